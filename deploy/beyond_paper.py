"""The main job's experiments beyond the paper's six (docs/identifier.md §10):

- where the physics is nonlinear (vertical_wide, force_map_fz, roll_coupled): offline, with
  odonata-fit's defaults (every setting chosen on the selection excitation), at the preset's
  decimated rate, fuzzy against ARX and ARX with squared inputs on the validation excitation;
- the damage scenarios (wing_damage, battery_sag): the vehicle changes halfway through the
  validation run; the model keeps learning, beside a frozen copy and ARX fitted before the change,
  with the accuracy alarm. Both run through the LCM pipeline at the preset's rate (battery_sag:
  the identifier decimates to 20 Hz), odonata-monitor raising the alarm live; odonata-fit --track
  replays the same learner offline, bit for bit, beside a frozen copy and ARX.

Targets are issue 9's; each result says whether it met them.
"""
import csv
import json
import math
import os
import statistics
import subprocess
import sys

from fit_tools import fit_json, signal_flags, simulate_phases

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NONLINEAR = ["vertical_wide", "force_map_fz", "roll_coupled"]
DAMAGE = ["wing_damage", "battery_sag"]
# Issue 9's floors on the validation excitation (free run; a static map's one-step is its free run).
TARGETS = {
    "vertical_wide": {"fit": 94.0, "above_arx": 5.0},
    "force_map_fz": {"fit": 98.0},
    "roll_coupled": {"fit": 94.0},
}
DAMAGE_TARGETS = {"alarm_s": 1.0, "recovery_s": 10.0, "frozen_gap": 5.0, "recover_points": 1.0}


def _headline(block):
    """Free run where there is one (ny > 0), else one-step (a static map: the same thing)."""
    return block.get("free_run") or block["one_step"]


def rule_budget(preset, train_csv):
    """At most one linear-consequent parameter per ten training rows (and 5–100 rules): more is
    not identifiable from the data, and a 100-rule candidate of 17 regressors costs minutes of
    least squares for nothing. Depends only on the training file's length and the regressor
    count, never on a score."""
    with open(train_csv) as f:
        rows = sum(1 for _ in f) - 1
    regressors = preset["ny"] + preset["nu"] * len(preset["inputs"])
    return max(5, min(100, rows // (10 * (regressors + 1))))


def nonlinear(name, preset, args, out):
    """odonata-fit with its defaults (but the rule budget): train, choose on selection, score on
    validation."""
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    files = simulate_phases(args.build, name, args.seed, args.duration, d)
    budget = rule_budget(preset, files["train"])
    fit = fit_json(args.build, ["--train", files["train"], "--select", files["select"], "--validate",
                                 files["validate"], *signal_flags(preset), "--max-rules", str(budget), "--predictions",
                                 os.path.join(d, "predictions.csv"), "--save-model", os.path.join(d, "model.json")])
    b = fit["baselines"]
    result = {
        "kind": "nonlinear", "name": name, "dir": d, "preset": preset,
        "rules": fit["rules"], "entropy_threshold": fit["entropy_threshold"], "kappa": fit["kappa"],
        "epochs": fit["epochs"], "consequent": fit["consequent"], "regressors": fit["regressors"],
        "max_rules": budget,
        "decimate": preset["decimate"], "rate_hz": 100.0 / preset["decimate"],
        "fuzzy": _headline(fit["validate"])["fit"],
        "fuzzy_ndei": _headline(fit["validate"])["ndei"],
        "fuzzy_one_step": fit["validate"]["one_step"]["fit"],
        "arx": _headline(b["arx"]["validate"])["fit"],
        "arx_ndei": _headline(b["arx"]["validate"])["ndei"],
        "arx_squared": _headline(b["arx_squared_inputs"]["validate"])["fit"] if "arx_squared_inputs" in b else None,
        "persistence_one_step": b["persistence"]["validate"]["one_step"]["fit"],
        "mode": "free run" if "free_run" in fit["validate"] else "static map (one-step = free run)",
        "warnings": fit["warnings"], "rule_text": fit["rule_text"],
    }
    result["online"] = online(name, preset, args, d, files["train"], budget)
    t = TARGETS.get(name, {})
    met = result["fuzzy"] >= t.get("fit", -math.inf)
    if "above_arx" in t:
        met = met and result["fuzzy"] - result["arx"] >= t["above_arx"]
    result["target"] = t
    result["target_met"] = bool(met)
    return result


def online(name, preset, args, d, train_csv, budget):
    """The same experiment learned online, through the LCM pipeline (plant, generator, identifier,
    monitor, logger): the identifier with scheduled refits (docs/identifier.md §6.3) from a quarter
    of the training record, doubling, on every sample kept, closing at the freeze; it has no
    selection excitation, so it chooses on its training hold-out. Scored live by odonata-monitor on
    the validation run, beside the identifier's live ARX (§6.4). Fixed in advance, not tuned."""
    with open(train_csv) as f:
        rows = sum(1 for _ in f) - 1
    pipe = os.path.join(d, "online")
    os.makedirs(pipe, exist_ok=True)
    cfg_path = os.path.join(pipe, "identifier.json")
    duration = ["--duration", str(args.duration)] if args.duration > 0 else []
    subprocess.run([sys.executable, os.path.join(ROOT, "deploy/make-identifier-config"), "--preset", name,
                    "--seed", str(args.seed), "--build", args.build, "--output", cfg_path,
                    "--consequent", args.consequent, "--max-rules", str(budget),
                    "--refit-first", str(max(50, rows // 4)), "--refit-every", str(10 * rows + 1000), *duration],
                   check=True)
    cfg = json.load(open(cfg_path))
    cfg["refit_buffer"] = rows + 1000  # every training sample: the closing refit sees them all
    json.dump(cfg, open(cfg_path, "w"), indent=1)
    subprocess.run([sys.executable, os.path.join(ROOT, "deploy/odonata-run"), "--preset", name, "--mode", args.mode,
                    "--identifier-config", cfg_path, "--seed", str(args.seed), "--out", pipe, "--build", args.build,
                    *duration], check=True, stderr=open(os.path.join(pipe, "pipeline.stderr.txt"), "wb"))
    o = json.load(open(os.path.join(pipe, "monitor-summary.json")))["outputs"][preset["output"]]
    free = preset["ny"] > 0  # a static map's one-step is its free run
    pick = (lambda b: b["free_run"]["fit"]) if free else (lambda b: b["one_step"]["fit"])
    arx = o.get("arx")
    return {"fit": pick(o), "one_step": o["one_step"]["fit"], "rules": o["rules"],
            "arx": pick(arx) if arx else None, "refit_first": cfg["refit_first"], "dir": pipe}


def _read_track(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    col = {k: [float(r[k]) for r in rows] for k in rows[0]}
    col["sample"] = [int(v) for v in col["sample"]]
    return col


def damage_metrics(track, change, rate, alarm_events, frozen_events=()):
    """Recovery figures from a --track CSV (tracking FIT per model) and the alarm's events."""
    s, on, fr, ax = track["sample"], track["online_window_fit"], track["frozen_window_fit"], track["arx_window_fit"]
    idx = {v: i for i, v in enumerate(s)}
    w = int(round(rate))
    pre = [on[idx[k]] for k in range(change - 10 * w, change) if k in idx and math.isfinite(on[idx[k]])]
    pre_level = statistics.mean(pre) if pre else float("nan")
    floor = pre_level - DAMAGE_TARGETS["recover_points"]
    recovery = None
    for k in range(change, s[-1] - w + 2):
        window = [on[idx[j]] for j in range(k, k + w) if j in idx]
        if window and min(window) >= floor:
            recovery = (k - change) / rate
            break
    late = [i for i, k in enumerate(s) if k >= change + 5 * w]
    gap = lambda other: statistics.mean(on[i] - other[i] for i in late) if late else float("nan")  # noqa: E731
    # An alarm more than 10 s after the change answers something else (a dip of the excitation).
    after = [e for e in alarm_events if e["kind"] == "alarm" and change <= e["sample"] < change + 10 * w]
    before = [e for e in alarm_events if e["kind"] == "alarm" and e["sample"] < change]
    alarm_s = (after[0]["sample"] - change) / rate if after else None
    frozen_after = [e for e in frozen_events if e["kind"] == "alarm" and change <= e["sample"] < change + 10 * w]
    m = {"pre_level": pre_level, "recovery_s": recovery, "alarm_s": alarm_s, "false_alarms_before": len(before),
         # The same alarm on the frozen copy: it sees a change the learner has already absorbed.
         "frozen_alarm_s": (frozen_after[0]["sample"] - change) / rate if frozen_after else None,
         "frozen_gap": gap(fr), "arx_gap": gap(ax),
         "online_after": statistics.mean(on[i] for i in late) if late else float("nan"),
         "frozen_after": statistics.mean(fr[i] for i in late) if late else float("nan"),
         "arx_after": statistics.mean(ax[i] for i in late) if late else float("nan")}
    m["targets"] = {
        "alarm_within_1_s": alarm_s is not None and alarm_s <= DAMAGE_TARGETS["alarm_s"],
        "recovered_within_10_s": recovery is not None and recovery <= DAMAGE_TARGETS["recovery_s"],
        "frozen_5_points_below": m["frozen_gap"] >= DAMAGE_TARGETS["frozen_gap"],
    }
    return m


def damage(name, preset, args, out, learner_flags):
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    rate = 100.0 / preset["decimate"]
    # Forget in about one second of data, whatever the rate: fixed in advance, not tuned.
    forgetting = 1.0 - 1.0 / rate
    change = int(round(preset["damage_at_s"] * rate))
    duration = ["--duration", str(args.duration)] if args.duration > 0 else []
    files = simulate_phases(args.build, name, args.seed, args.duration, d)
    track_csv = os.path.join(d, "track.csv")
    result = {"kind": "damage", "name": name, "dir": d, "preset": preset, "rate_hz": rate,
              "forgetting": forgetting, "change_s": preset["damage_at_s"], "track_csv": track_csv}
    # Through the pipeline: H and kappa chosen on the selection excitation with the online
    # learner's settings (as for the paper's six), then the identifier learns on through the
    # damaged validation run with forgetting, at the preset's rate; the monitor's alarm is the
    # live one. odonata-fit --track replays the same learner offline beside a frozen copy and ARX.
    cfg_path = os.path.join(d, "identifier.json")
    ranges = os.path.join(d, "ranges.json")
    subprocess.run([sys.executable, os.path.join(ROOT, "deploy/make-identifier-config"), "--preset", name,
                    "--seed", str(args.seed), "--build", args.build, "--output", cfg_path,
                    "--ranges-output", ranges, "--consequent", args.consequent, *duration], check=True)
    cfg = json.load(open(cfg_path))
    sweep = fit_json(args.build, ["--train", files["train"], "--select", files["select"], "--ranges", ranges,
                                   *signal_flags(preset), *learner_flags(cfg)])
    cfg["entropy_threshold"], cfg["kappa"] = sweep["entropy_threshold"], sweep["kappa"]
    json.dump(cfg, open(cfg_path, "w"), indent=1)
    pipe = os.path.join(d, "pipeline")
    subprocess.run([sys.executable, os.path.join(ROOT, "deploy/odonata-run"), "--preset", name, "--mode", args.mode,
                    "--identifier-config", cfg_path, "--seed", str(args.seed), "--out", pipe, "--build", args.build,
                    "--keep-learning", "--forgetting", repr(forgetting), *duration],
                   check=True, stderr=open(os.path.join(d, "pipeline.stderr.txt"), "wb"))
    track = fit_json(args.build, ["--load-model", os.path.join(pipe, "models", "model-trained.json"), "--train",
                                   os.path.join(pipe, "train.csv"), "--track", os.path.join(pipe, "validate.csv"),
                                   "--track-forgetting", repr(forgetting), "--track-window", str(int(rate)),
                                   "--track-output", track_csv])
    monitor = json.load(open(os.path.join(pipe, "monitor-summary.json")))
    events = monitor["outputs"][preset["output"]]["alarm_events"]
    result.update(where=f"pipeline at {rate:g} Hz (odonata-monitor's live alarm)", rules=track["rules"],
                  entropy_threshold=cfg["entropy_threshold"], kappa=cfg["kappa"], alarm_events=events,
                  pipeline_equals_offline=_same_online(os.path.join(pipe, "predictions.csv"), track_csv,
                                                       preset["output"]))
    result["one_step"] = {m: track["track"][m]["one_step"]["fit"] for m in ("online", "frozen", "arx")}
    result["rules_after"] = track["track"]["rules_after"]
    result["metrics"] = damage_metrics(_read_track(track_csv), change, rate, events,
                                       track["track"]["frozen"]["events"])
    return result


def _same_online(predictions, track_csv, output):
    """True when the pipeline's live one-step predictions equal the offline online learner's."""
    with open(predictions) as f:
        rows = list(csv.DictReader(f))
    last = max(int(r["run"]) for r in rows)
    live = {int(r["sample"]): float(r[f"{output}_predicted"]) for r in rows if int(r["run"]) == last}
    track = _read_track(track_csv)
    pairs = [(live[k], v) for k, v in zip(track["sample"], track["online"]) if k in live]
    return bool(pairs) and all(a == b for a, b in pairs)


# ---- report -------------------------------------------------------------------------------------

def _f(v, digits=1):
    return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.{digits}f}"


def nonlinear_verdict(r):
    delta = r["fuzzy"] - r["arx"]
    if abs(delta) < 1.0:
        return f"fuzzy equals ARX ({delta:+.1f} points): linear enough at this range"
    sq = r["arx_squared"]
    sq_text = f"; ARX with squared inputs {_f(sq)} %" if sq is not None else ""
    return (f"fuzzy {'beats' if delta > 0 else 'loses to'} ARX by {delta:+.1f} FIT points in {r['mode']}"
            f"{sq_text}")


def damage_verdict(r):
    m = r["metrics"]
    ok = m["targets"]
    alarm = (f"alarm {_f(m['alarm_s'], 2)} s after the change" if m["alarm_s"] is not None else
             "no alarm within 10 s: the learner absorbed the change within its memory (the frozen copy's "
             f"alarm: {_f(m['frozen_alarm_s'], 2)} s)")
    back = (f"never a whole second below 1 point under its pre-damage {_f(m['pre_level'])} %"
            if m["recovery_s"] == 0 else
            f"back within 1 point of {_f(m['pre_level'])} % after {_f(m['recovery_s'], 1)} s")
    return (f"{alarm} ({'met' if ok['alarm_within_1_s'] else 'NOT met'}); {back} "
            f"({'met' if ok['recovered_within_10_s'] else 'NOT met'}); frozen {_f(m['frozen_gap'])} points below "
            f"from 5 s after the change on ({'met' if ok['frozen_5_points_below'] else 'NOT met'})")


def summary(results):
    out = {"nonlinear": [], "damage": []}
    for r in results:
        if r["kind"] == "nonlinear":
            out["nonlinear"].append({k: r[k] for k in (
                "name", "rules", "max_rules", "entropy_threshold", "kappa", "epochs", "consequent", "decimate",
                "rate_hz", "mode",
                "fuzzy", "fuzzy_ndei", "fuzzy_one_step", "arx", "arx_ndei", "arx_squared", "persistence_one_step",
                "target", "target_met", "warnings", "rule_text", "online")} | {"verdict": nonlinear_verdict(r),
                                                                      "output": r["preset"]["output"],
                                                                      "inputs": r["preset"]["inputs"]})
        else:
            out["damage"].append({k: r.get(k) for k in (
                "name", "where", "rate_hz", "forgetting", "change_s", "rules", "rules_after", "entropy_threshold",
                "kappa", "one_step", "metrics", "alarm_events", "pipeline_equals_offline")} |
                {"verdict": damage_verdict(r), "output": r["preset"]["output"], "inputs": r["preset"]["inputs"],
                 "description": r["preset"]["description"]})
    return out


def markdown(s):
    md = []
    if s["nonlinear"]:
        md += ["## Beyond the paper: where the physics is nonlinear", "",
               "Offline (`odonata-fit` with its defaults: H̄, κ, consequent and epochs chosen on the selection "
               "excitation), at the preset's decimated rate; validation excitation, free run (a static map's "
               "one-step is its free run).", "",
               "Online: the same training run through the LCM pipeline, the identifier refitting from a quarter "
               "of it on, scored live on the validation run by odonata-monitor beside the identifier's live ARX.",
               "",
               "| experiment | rate | rules | fuzzy FIT | ARX | ARX + u² | fuzzy − ARX | online fuzzy (rules) | "
               "online live ARX | target | verdict |",
               "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in s["nonlinear"]:
            t = r["target"]
            target = f"≥ {t['fit']:g} %" + (f", ≥ ARX + {t['above_arx']:g}" if "above_arx" in t else "")
            md.append(f"| {r['name']} | {r['rate_hz']:.3g} Hz | {r['rules']} | {_f(r['fuzzy'], 2)} | {_f(r['arx'], 2)} | "
                      f"{_f(r['arx_squared'], 2)} | {r['fuzzy'] - r['arx']:+.2f} | "
                      f"{_f(r['online']['fit'], 2)} ({r['online']['rules']}) | {_f(r['online']['arx'], 2)} | {target}: "
                      f"{'met' if r['target_met'] else 'NOT met'} | {r['verdict']} |")
        md.append("")
    if s["damage"]:
        md += ["## Damage in flight: online learning against a frozen model", "",
               "Tracking FIT: one-second window error against the output's spread over ten seconds. The model keeps "
               "learning with forgetting 1 − 1/(samples per second), fixed in advance.", "",
               "| scenario | where | alarm after | false alarms before | recovered after | online / frozen / ARX "
               "from +5 s | verdict |", "|---|---|---|---|---|---|---|"]
        for r in s["damage"]:
            m = r["metrics"]
            md.append(f"| {r['name']} | {r['where']} | {_f(m['alarm_s'], 2)} s | {m['false_alarms_before']} | "
                      f"{_f(m['recovery_s'], 1)} s | {_f(m['online_after'])} / {_f(m['frozen_after'])} / "
                      f"{_f(m['arx_after'])} % | {r['verdict']} |")
        md.append("")
    return "\n".join(md)


def terminal(s):
    lines = []
    for r in s["nonlinear"]:
        lines.append(f"{r['name']:>14}: fuzzy {_f(r['fuzzy'], 2)} % ({r['rules']} rules) vs ARX {_f(r['arx'], 2)} %, "
                     f"ARX+u² {_f(r['arx_squared'], 2)} %; online {_f(r['online']['fit'], 2)} % "
                     f"({r['online']['rules']} rules, live ARX {_f(r['online']['arx'], 2)} %) — target "
                     f"{'met' if r['target_met'] else 'NOT met'}")
    for r in s["damage"]:
        lines.append(f"{r['name']:>14}: {r['verdict']}")
    return "\n".join(lines)


def plots(out, results):
    """A recovery timeline per damage scenario and a validation trace per nonlinear experiment."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figures = {}
    for r in results:
        path = os.path.join(out, f"{r['name']}-{'recovery' if r['kind'] == 'damage' else 'output'}.png")
        if r["kind"] == "damage":
            t = _read_track(r["track_csv"])
            time_s = [k / r["rate_hz"] for k in t["sample"]]
            m = r["metrics"]
            fig, ax = plt.subplots(figsize=(11, 4.5))
            ax.plot(time_s, t["arx_window_fit"], "C1", lw=1, label="ARX fitted before the change")
            ax.plot(time_s, t["frozen_window_fit"], "C7", lw=1.2, label="fuzzy, frozen after training")
            ax.plot(time_s, t["online_window_fit"], "C0", lw=1.6, label="fuzzy, learning online")
            ax.axvline(r["change_s"], color="k", ls="--", lw=1, label="damage")
            if math.isfinite(m["pre_level"]):
                ax.axhline(m["pre_level"] - 1, color="C2", ls=":", lw=1, label="pre-damage level − 1 point")
            for e in r["alarm_events"]:
                ax.axvline(e["sample"] / r["rate_hz"], color="C3" if e["kind"] == "alarm" else "C2", lw=0.6,
                           alpha=0.6)
            ax.plot([], [], color="C3", lw=0.6, label="alarm raised / (green) cleared")
            lo = min(v for v in t["online_window_fit"] + t["frozen_window_fit"] if math.isfinite(v))
            ax.set_ylim(max(lo - 2, 50), 100.5)
            ax.set_xlabel("time in the validation run (s)")
            ax.set_ylabel("tracking FIT (%), 1 s window")
            ax.set_title(f"{r['name']}: {r['preset']['description']}"[:140], fontsize=9)
            ax.legend(loc="lower left", fontsize=8)
        else:
            with open(os.path.join(r["dir"], "predictions.csv")) as f:
                rows = [x for x in csv.DictReader(f) if x["set"] == "1"]
            k = [int(x["sample"]) / r["rate_hz"] for x in rows]
            fig, ax = plt.subplots(figsize=(11, 4))
            ax.plot(k, [float(x["arx_free_run"]) for x in rows], "C1", lw=1.6, label=f"ARX free run ({_f(r['arx'])} %)")
            ax.plot(k, [float(x["fuzzy_free_run"]) for x in rows], "C0", lw=1.6,
                    label=f"fuzzy free run ({_f(r['fuzzy'])} %, {r['rules']} rules)")
            ax.plot(k, [float(x["measured"]) for x in rows], "k", lw=0.8, label="measured", zorder=3)
            ax.set_xlabel("time in the validation run (s)")
            ax.set_ylabel(r["preset"]["output"])
            ax.set_title(f"{r['name']}: validation excitation, {r['mode']} at {r['rate_hz']:g} Hz", fontsize=10)
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(path, dpi=90)
        plt.close(fig)
        figures[r["name"]] = os.path.basename(path)
    return figures


def html_section(s, figures):
    import html
    h = []
    md = markdown(s).splitlines()
    # The two tables as HTML, then the figures.
    table = []
    for line in md + [""]:
        if line.startswith("## "):
            h.append(f"<h2>{html.escape(line[3:])}</h2>")
        elif line.startswith("|"):
            if set(line) <= set("|-"):
                continue
            table.append("<tr>" + "".join(f"<td>{html.escape(c.strip())}</td>" for c in line.strip("|").split("|"))
                         + "</tr>")
        else:
            if table:
                h.append("<table>" + "".join(table) + "</table>")
                table = []
            if line:
                h.append(f"<p>{html.escape(line)}</p>")
    for name, fig in figures.items():
        h.append(f"<h3>{html.escape(name)}</h3><img src='{fig}' alt='{html.escape(name)}'>")
    return "\n".join(h)
