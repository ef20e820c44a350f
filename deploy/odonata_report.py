"""Report of the main job: summary table (terminal, Markdown, JSON), plots and one HTML page."""
import csv
import html
import json
import math
import os

import numpy as np


def _scores(y, yhat):
    y = np.asarray(y, float)
    yhat = np.asarray(yhat, float)
    e = y - yhat
    spread = np.linalg.norm(y - y.mean())
    rmse = float(np.sqrt(np.mean(e ** 2)))
    if spread == 0:
        return {"fit": None, "vaf": None, "rmse": rmse, "ndei": None, "samples": int(len(y))}
    return {"fit": float(100 * (1 - np.linalg.norm(e) / spread)),
            "vaf": float(100 * (1 - np.var(e) / np.var(y))),
            "rmse": rmse, "ndei": float(rmse / np.std(y)), "samples": int(len(y))}


def read_predictions(path, output):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0].keys()} if rows else {}
    return cols


def live_scores(path, output):
    """Accuracy of the frozen identifier's live predictions in the last run (validation)."""
    p = read_predictions(path, output)
    last = p["run"] == p["run"].max()
    y = p[f"{output}_measured"][last]
    return {"one_step": _scores(y, p[f"{output}_predicted"][last]),
            "free_run": _scores(y, p[f"{output}_free_run"][last])}


def fmt(v, digits=2):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if v < -999:
        return "diverges"  # a FIT below −999 % only says the simulation ran away
    return f"{v:.{digits}f}"


def summarise(r):
    v, b = r["validate"], r["baselines"]
    ndei = v["one_step"]["ndei"]
    pers_ndei = b["persistence"]["validate"]["one_step"]["ndei"]
    arx_fit = b["arx"]["validate"]["one_step"]["fit"]
    notes = []
    if r["rules"] == 1:
        notes.append("one rule: the model is a single local linear model (ARX-like); within the selection's "
                     "tolerance the training hold-out does not call for more rules at these amplitudes")
    if r["integrator"]:
        notes.append("integrating loop: free run drifts with any bias, one-step is the meaningful score")
    if v["one_step"]["fit"] is not None and arx_fit is not None and v["one_step"]["fit"] < arx_fit:
        notes.append(f"does not beat linear ARX one-step ({fmt(v['one_step']['fit'])} % vs {fmt(arx_fit)} %)")
    if v.get("free_run", {}).get("fit") is not None and b["arx"]["validate"].get("free_run", {}).get("fit") is not None \
            and v["free_run"]["fit"] < b["arx"]["validate"]["free_run"]["fit"]:
        notes.append("free run worse than ARX's")
    paper_mfs = r["paper"].get("mfs")
    goal_rules = paper_mfs is None or r["rules"] <= paper_mfs
    return {
        "experiment": r["name"],
        "output": r["preset"]["output"],
        "inputs": r["preset"]["inputs"],
        "entropy_threshold": r["chosen_entropy_threshold"],
        "kappa": r["config"]["kappa"],
        "ny": r["config"]["ny"],
        "nu": r["config"]["nu"],
        "rules": r["rules"],
        "paper": r["paper"],
        "paper_threshold_run": {"entropy_threshold": r["paper_entropy_threshold_run"]["entropy_threshold"],
                                "rules": r["paper_entropy_threshold_run"]["rules"],
                                "validate_one_step_fit": r["paper_entropy_threshold_run"]["validate"]["one_step"]["fit"]},
        "train": {"one_step": r["train"]["one_step"], "free_run": r["train"].get("free_run")},
        "validate": {"one_step": v["one_step"], "free_run": v.get("free_run")},
        "validate_live": r["validate_live"],
        "averaged_output": r.get("averaged_output"),
        "arx": b["arx"]["validate"],
        "persistence": b["persistence"]["validate"],
        "integrator": r["integrator"],
        "goals": {
            "ndei_at_most_half_of_persistence": bool(ndei is not None and pers_ndei is not None and ndei <= 0.5 * pers_ndei),
            "rules_not_more_than_paper": bool(goal_rules),
            "validation_fit_at_least_90": bool(v["one_step"]["fit"] is not None and v["one_step"]["fit"] >= 90),
        },
        "notes": notes,
        "rule_text": r["rule_text"],
    }


COLUMNS = [("experiment", "experiment"), ("order", "ny/nu"), ("H", "H chosen"), ("rules", "rules"), ("paper_mfs", "paper MFs"),
           ("paper_h_fit", "paper H: val FIT (MFs)"), ("train_fit", "train FIT"), ("train_fr", "train free-run"),
           ("val_fit", "val FIT"), ("val_vaf", "val VAF"), ("val_rmse", "val RMSE"), ("val_fr", "val free-run"),
           ("arx_fit", "ARX val FIT"), ("arx_fr", "ARX free-run"), ("delta", "fuzzy − ARX"),
           ("avg", "beat-avg fuzzy / ARX free-run"), ("pers_fit", "persist. FIT"),
           ("ndei_ratio", "NDEI / persist."), ("paper_acc", "paper accuracy")]


def _delta(s):
    """fuzzy − ARX in the headline mode: free run unless the loop integrates (one-step there)."""
    mode = "one_step" if s.get("integrator") or not (s["validate"].get("free_run") or {}).get("fit") else "free_run"
    f, a = (s["validate"].get(mode) or {}).get("fit"), (s["arx"].get(mode) or {}).get("fit")
    if f is None or a is None or not math.isfinite(f) or not math.isfinite(a) or min(f, a) < -999:
        return "–"
    return f"{f - a:+.2f} ({mode.replace('_', '-')})"


def _averaged(s):
    a = s.get("averaged_output")
    if not a:
        return "–"
    f = (a["validate"].get("free_run") or a["validate"]["one_step"])["fit"]
    x = (a["arx_validate"].get("free_run") or a["arx_validate"]["one_step"])["fit"]
    return f"{fmt(f)} / {fmt(x)}"


def table_rows(summary):
    rows = []
    for s in summary["experiments"]:
        ndei = s["validate"]["one_step"]["ndei"]
        pn = s["persistence"]["one_step"]["ndei"]
        rows.append({
            "experiment": s["experiment"],
            "order": f"{s['ny']}/{s['nu']}",
            "H": f"{s['entropy_threshold']:.4g}",
            "rules": str(s["rules"]),
            "paper_mfs": str(s["paper"].get("mfs", "–")),
            "paper_h_fit": f"{s['paper_threshold_run']['entropy_threshold']:.4g}: "
                           f"{fmt(s['paper_threshold_run']['validate_one_step_fit'])} ({s['paper_threshold_run']['rules']} MFs)",
            "train_fit": fmt(s["train"]["one_step"]["fit"]),
            "train_fr": fmt((s["train"]["free_run"] or {}).get("fit")),
            "val_fit": fmt(s["validate"]["one_step"]["fit"]),
            "val_vaf": fmt(s["validate"]["one_step"]["vaf"]),
            "val_rmse": fmt(s["validate"]["one_step"]["rmse"], 4),
            "val_fr": fmt((s["validate"]["free_run"] or {}).get("fit")),
            "arx_fit": fmt(s["arx"]["one_step"]["fit"]),
            "arx_fr": fmt(s["arx"].get("free_run", {}).get("fit")),
            "delta": _delta(s),
            "avg": _averaged(s),
            "pers_fit": fmt(s["persistence"]["one_step"]["fit"]),
            "ndei_ratio": fmt(ndei / pn if ndei is not None and pn else None),
            "paper_acc": s["paper"].get("accuracy", "–"),
        })
    return rows


def terminal_table(summary):
    rows = table_rows(summary)
    widths = {k: max(len(h), *(len(r[k]) for r in rows)) for k, h in COLUMNS}
    lines = ["  ".join(h.rjust(widths[k]) for k, h in COLUMNS)]
    for r in rows:
        lines.append("  ".join(r[k].rjust(widths[k]) for k, _ in COLUMNS))
    lines.append("FIT/VAF in %, one-step unless 'free-run'; validation uses a different excitation.")
    return "\n".join(lines)


def markdown(summary):
    rows = table_rows(summary)
    md = ["# odonata — the paper's six identifications through the LCM pipeline", "",
          f"Mode: {summary['mode']}; consequents: {summary['consequent']}; seed {summary['seed']}.", "",
          "| " + " | ".join(h for _, h in COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for r in rows:
        md.append("| " + " | ".join(r[k] for k, _ in COLUMNS) + " |")
    md.append("")
    for s in summary["experiments"]:
        md.append(f"## {s['experiment']}: {s['output']} from {', '.join(s['inputs'])}")
        for n in s["notes"]:
            md.append(f"- {n}")
        md.append(f"- goals: {', '.join(k + ('' if v else ' NOT MET') for k, v in s['goals'].items())}")
        md.append("")
        for i, t in enumerate(s["rule_text"], 1):
            md.append(f"{i}. {t}")
        md.append("")
    return "\n".join(md)


def make_plots(out, r):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    d = r["dir"]
    out_name = r["preset"]["output"]
    p = read_predictions(os.path.join(d, "pipeline", "predictions.csv"), out_name)
    files = {}
    dt = 0.01
    runs = sorted(set(p["run"].astype(int)))
    fig, axes = plt.subplots(2, len(runs), figsize=(6 * len(runs), 6), sharex="col", squeeze=False)
    for c, run in enumerate(runs):
        m = p["run"] == run
        t = p["sample"][m] * dt
        y, yh, fr = p[f"{out_name}_measured"][m], p[f"{out_name}_predicted"][m], p[f"{out_name}_free_run"][m]
        title = "training (learning online)" if c == 0 and len(runs) > 1 else "validation (frozen model)"
        axes[0][c].plot(t, y, "k", lw=1, label="measured")
        axes[0][c].plot(t, yh, "C0", lw=0.8, label="one-step")
        axes[0][c].plot(t, fr, "C1", lw=0.8, alpha=0.8, label="free run")
        axes[0][c].set_title(f"{r['name']}: {title}")
        axes[0][c].set_ylabel(out_name)
        axes[0][c].legend(loc="upper right", fontsize=8)
        axes[1][c].plot(t, y - yh, "C0", lw=0.8, label="one-step error")
        axes[1][c].plot(t, y - fr, "C1", lw=0.8, alpha=0.6, label="free-run error")
        axes[1][c].set_xlabel("time (s)")
        axes[1][c].set_ylabel("error")
        axes[1][c].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    files["output"] = f"{r['name']}-output.png"
    fig.savefig(os.path.join(out, files["output"]), dpi=90)
    plt.close(fig)

    m = p["run"] == runs[0]
    fig, ax = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
    ax[0].step(p["sample"][m] * dt, p[f"{out_name}_rules"][m], where="post")
    ax[0].set_ylabel("rules (MFs)")
    ax[0].set_title(f"{r['name']}: structure learning (H = {r['chosen_entropy_threshold']:.4g})")
    ax[1].plot(p["sample"][m] * dt, p[f"{out_name}_max_entropy"][m], lw=0.6)
    ax[1].axhline(r["chosen_entropy_threshold"], color="r", ls="--", lw=0.8, label="H threshold")
    ax[1].set_ylabel("H_max")
    ax[1].set_xlabel("time (s)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    files["learning"] = f"{r['name']}-learning.png"
    fig.savefig(os.path.join(out, files["learning"]), dpi=90)
    plt.close(fig)

    snaps = json.load(open(os.path.join(d, "pipeline", "snapshots.json")))
    snaps = [s for s in snaps if s["model"]["models"]]
    if snaps:
        fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
        for s_idx, key, label in ((0, "centre", "centres (raw units)"), (1, "sigma", "widths (raw units)")):
            series = {}
            for s in snaps:
                sc = s["model"]["scaling"]
                for j, rule in enumerate(s["model"]["models"][0]["rules"]):
                    for i, v in enumerate(rule[key]):
                        raw = sc["regressor_mid"][i] + sc["regressor_half"][i] * v if key == "centre" \
                            else sc["regressor_half"][i] * v
                        series.setdefault((j, i), ([], []))
                        series[(j, i)][0].append(s["samples_learned"] * dt)
                        series[(j, i)][1].append(raw)
            for (j, i), (t, v) in series.items():
                ax[s_idx].plot(t, v, lw=0.8, color=f"C{i % 10}")
            ax[s_idx].set_ylabel(label)
        series = {}
        for s in snaps:
            sc = s["model"]["scaling"]
            cons = s["model"]["models"][0]["consequent"]
            vals = cons["centres"] if cons["kind"] == "singleton" else [c[0] for c in cons["coefficients"]]
            for j, v in enumerate(vals):
                series.setdefault(j, ([], []))
                series[j][0].append(s["samples_learned"] * dt)
                series[j][1].append(sc["output_mean"][0] + sc["output_std"][0] * v)
        for j, (t, v) in series.items():
            ax[2].plot(t, v, lw=0.8)
        ax[2].set_ylabel("consequent b / a0")
        ax[2].set_xlabel("training time (s)")
        ax[0].set_title(f"{r['name']}: parameters over time (colour = input)")
        fig.tight_layout()
        files["parameters"] = f"{r['name']}-parameters.png"
        fig.savefig(os.path.join(out, files["parameters"]), dpi=90)
        plt.close(fig)

    model = json.load(open(os.path.join(d, "pipeline", "model.json")))
    sc = model["scaling"]
    spec = model["regressor"]
    regs = []
    for o in spec["outputs"]:
        for l in range(spec["output_lags"]):
            regs.append(f"{o} lag {l + 1}")
    for u in spec["inputs"]:
        for l in range(spec["input_lags"]):
            regs.append(f"{u} lag {l}")
    rules = model["models"][0]["rules"]
    n = len(regs)
    fig, ax = plt.subplots(n, 1, figsize=(7, 1.6 * n + 0.5), squeeze=False)
    for i in range(n):
        lo = sc["regressor_mid"][i] - 1.3 * sc["regressor_half"][i]
        hi = sc["regressor_mid"][i] + 1.3 * sc["regressor_half"][i]
        x = np.linspace(lo, hi, 400)
        for j, rule in enumerate(rules):
            c = sc["regressor_mid"][i] + sc["regressor_half"][i] * rule["centre"][i]
            s = sc["regressor_half"][i] * math.sqrt(rule["sigma"][i] ** 2 + 1e-6)
            ax[i][0].plot(x, np.exp(-0.5 * ((x - c) / s) ** 2), lw=1)
        ax[i][0].set_ylabel(regs[i], fontsize=8)
        ax[i][0].set_ylim(0, 1.05)
    ax[0][0].set_title(f"{r['name']}: membership functions at the end ({len(rules)} rules)")
    fig.tight_layout()
    files["membership"] = f"{r['name']}-membership.png"
    fig.savefig(os.path.join(out, files["membership"]), dpi=90)
    plt.close(fig)

    pts = r["sweep"]["points"]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for key in sorted(set((q.get("ny", 0), q.get("nu", 0), q["kappa"]) for q in pts)):
        sel = sorted([q for q in pts if (q.get("ny", 0), q.get("nu", 0), q["kappa"]) == key and q["score"] is not None],
                     key=lambda q: q["entropy_threshold"])
        ax.plot([q["rules"] for q in sel], [q["score"] for q in sel], "o-", ms=3,
                label=f"ny/nu {key[0]}/{key[1]}, κ {key[2]:g}")
    ch = pts[r["sweep"]["chosen_index"]]
    ax.plot([ch["rules"]], [ch["score"]], "r*", ms=12, label=f"chosen (H={ch['entropy_threshold']:.3g})")
    ax.set_xlabel("rules")
    ax.set_ylabel(f"hold-out {r['sweep']['criterion'].replace('_', '-')} NDEI")
    ax.set_yscale("log")
    ax.set_title(f"{r['name']}: model selection on the training hold-out")
    ax.legend(fontsize=7)
    fig.tight_layout()
    files["sweep"] = f"{r['name']}-sweep.png"
    fig.savefig(os.path.join(out, files["sweep"]), dpi=90)
    plt.close(fig)
    return files


def page(summary, figures):
    rows = table_rows(summary)
    h = ["<!doctype html><html><head><meta charset='utf-8'><title>odonata report</title>",
         "<style>body{font-family:sans-serif;max-width:1400px;margin:auto}table{border-collapse:collapse;font-size:13px}"
         "td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}th{background:#eee}"
         "img{max-width:100%;border:1px solid #ddd;margin:4px}li{font-family:monospace;font-size:12px}</style></head><body>",
         "<h1>odonata — the paper's six identifications through the LCM pipeline</h1>",
         f"<p>Mode {html.escape(summary['mode'])}, {html.escape(summary['consequent'])} consequents, seed {summary['seed']}. "
         "FIT/VAF in %, one-step unless marked free-run; validation always uses a different excitation. "
         "Persistence (ŷ(k+1) = y(k)) and linear ARX on the same regressors are the baselines.</p>",
         "<table id='summary'><tr>" + "".join(f"<th>{html.escape(hd)}</th>" for _, hd in COLUMNS) + "</tr>"]
    for r in rows:
        h.append("<tr>" + "".join(f"<td data-key='{k}'>{html.escape(r[k])}</td>" for k, _ in COLUMNS) + "</tr>")
    h.append("</table>")
    for s in summary["experiments"]:
        name = s["experiment"]
        h.append(f"<h2 id='{name}'>{html.escape(name)}: {html.escape(s['output'])} from {html.escape(', '.join(s['inputs']))}</h2>")
        if s["notes"]:
            h.append("<ul>" + "".join(f"<li style='font-family:sans-serif'>{html.escape(n)}</li>" for n in s["notes"]) + "</ul>")
        goals = ", ".join(f"{k}: {'met' if v else 'NOT met'}" for k, v in s["goals"].items())
        h.append(f"<p>Goals — {html.escape(goals)}</p>")
        for key in ("output", "learning", "parameters", "membership", "sweep"):
            if key in figures.get(name, {}):
                h.append(f"<img src='{figures[name][key]}' alt='{name} {key}'>")
        h.append("<h3>Rules</h3><ol>" + "".join(f"<li>{html.escape(t)}</li>" for t in s["rule_text"]) + "</ol>")
    h.append("</body></html>")
    return "\n".join(h)


def write_report(out, results, args, plots=True):
    summary = {"mode": args.mode, "consequent": args.consequent, "seed": args.seed,
               "experiments": [summarise(r) for r in results]}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(markdown(summary))
    figures = {}
    if plots:
        for r in results:
            figures[r["name"]] = make_plots(out, r)
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write(page(summary, figures))
    return summary
