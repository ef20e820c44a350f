"""The report's figures: measured against the fuzzy model and ARX, learning, parameters, membership, sweep, and odonata-fit --plot's pictures."""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

from .common import DIVERGED_FIT, DIVERGED_NDEI, DT, ROOT, read_predictions

# --- plots -----------------------------------------------------------------------------------

UNITS = {"n": "N", "rad": "rad", "mps": "m/s", "hz": "Hz", "radps": "rad/s", "m": "m", "s": "s"}


def _with_unit(signal):
    """'fz1_n' → 'fz1_n (N)': the unit is the signal name's last suffix (ignoring _avg)."""
    parts = [p for p in signal.split("_") if p != "avg"]
    unit = UNITS.get(parts[-1].lower()) if len(parts) > 1 else None
    return f"{signal} ({unit})" if unit else signal


def _regressors(model):
    """(signal, lag) of each regressor, in the model's order: output lags from 1, input lags from
    the delay (RegressorSpec::Fill)."""
    spec = model["regressor"]
    delay = spec.get("delay", 0)
    return [(o, l + 1) for o in spec["outputs"] for l in range(spec["output_lags"])] + \
        [(u, delay + l) for u in spec["inputs"] for l in range(spec["input_lags"])]


def rule_shares(model, csv_path):
    """Each rule's share of the normalised firing strength over the samples of `csv_path` (the
    model's first output), or None when the file lacks a regressor's column."""
    try:
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
        cols = {sig: np.array([float(r[sig]) for r in rows]) for sig, _ in _regressors(model)}
    except (OSError, KeyError, ValueError):
        return None
    regs = _regressors(model)
    first = max(lag for _, lag in regs) if regs else 0
    n = len(rows)
    if n <= first:
        return None
    x = np.stack([cols[sig][first - lag:n - lag] for sig, lag in regs], axis=1)
    sc = model["scaling"]
    xs = (x - np.array(sc["regressor_mid"])) / np.array(sc["regressor_half"])
    rules = model["models"][0]["rules"]
    c = np.array([r["centre"] for r in rules])
    sig = np.sqrt(np.array([r["sigma"] for r in rules]) ** 2 + 1e-12)
    d2 = (((xs[:, None, :] - c[None]) / sig[None]) ** 2).sum(axis=2)
    # Relative to each sample's nearest rule, so far samples do not underflow to 0 / 0.
    w = np.exp(-0.5 * (d2 - d2.min(axis=1, keepdims=True)))
    return (w / w.sum(axis=1, keepdims=True)).mean(axis=0)


def dominant_rules(shares, cover=0.8, most=6):
    """Rule indices by share, largest first, until they carry `cover` of the firing (at most
    `most`, at least one)."""
    order = sorted(range(len(shares)), key=lambda j: -shares[j])
    picked, total = [], 0.0
    for j in order:
        if len(picked) == most or (picked and total >= cover):
            break
        picked.append(j)
        total += shares[j]
    return picked


def _save(plt, fig, out, r, kind):
    fig.tight_layout()
    name = f"{r['name']}-{kind}.png"
    fig.savefig(os.path.join(out, name), dpi=90)
    plt.close(fig)
    return name


def arx_predictions(r, build):
    """ARX one-step and free-run predictions on the pipeline's recorded samples, from odonata-fit
    (the live pipeline runs only the fuzzy model). {set: columns}, set 0 training and 1 validation;
    None when the tool is missing or fails, so the report still comes out."""
    d = r["dir"]
    pipe = os.path.join(d, "pipeline")
    dest = os.path.join(d, "fit-predictions.csv")
    exe = os.path.join(build, "services/fit/odonata-fit")
    try:
        # --plot: the readable terms, the rule-activation strip and the gain schedule (or a
        # static map's surface) of the same model, drawn by odonata-fit (fit_plots.py).
        subprocess.run([exe, "--load-model", os.path.join(pipe, "model.json"), "--train", os.path.join(pipe, "train.csv"),
                        "--validate", os.path.join(pipe, "validate.csv"), "--predictions", dest,
                        "--plot", os.path.join(d, "fit-plots")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        p = read_predictions(dest)
    except (OSError, ValueError, subprocess.CalledProcessError) as e:
        print(f"odonata_report: {r['name']}: no ARX traces ({e})", file=sys.stderr)
        return None
    missing = {"set", "sample", "arx_one_step", "arx_free_run"} - set(p)
    if missing:
        print(f"odonata_report: {r['name']}: no ARX traces ({dest} lacks {', '.join(sorted(missing))})",
              file=sys.stderr)
        return None
    return {k: {c: v[p["set"] == k] for c, v in p.items()} for k in (0, 1)}


def _aligned(arx_set, sample, column):
    """ARX column at the given sample indices (NaN where odonata-fit has no prediction)."""
    out = np.full(len(sample), np.nan)
    index = {int(s): i for i, s in enumerate(arx_set["sample"])}
    for j, s in enumerate(sample):
        i = index.get(int(s))
        if i is not None:
            out[j] = arx_set[column][i]
    return out


def _y_window(y):
    """Measured range plus a margin: the y-limits of the output panels, so a diverging free run
    cannot squash the measured signal into a flat line."""
    lo, hi = float(np.nanmin(y)), float(np.nanmax(y))
    span = hi - lo or max(abs(hi), 1e-9)
    return lo - 0.15 * span, hi + 0.15 * span, span


def _diverges(v, lo, hi, span):
    """Leaves the measured range by more than the range itself, or overflows. NaN is a sample
    odonata-fit did not predict (alignment), not a divergence."""
    v = v[~np.isnan(v)]
    return bool(len(v)) and bool(np.isinf(v).any() or v.max() > hi + span or v.min() < lo - span)


def _trace(ax, t, v, colour, label, window):
    lo, hi, span = window
    if _diverges(v, lo, hi, span):
        label += " (diverges)"
    # Clipped just outside the view: Agg mishandles coordinates like 1e100, and the view is clipped anyway.
    v = np.clip(np.where(np.isfinite(v), v, np.nan), lo - 10 * span, hi + 10 * span)
    ax.plot(t, v, color=colour, lw=1.8, alpha=0.75, label=label, zorder=2)


FUZZY, ARX = "tab:blue", "tab:orange"


def _legend_measured_first(ax):
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: labels[i] != "measured")
    ax.legend([handles[i] for i in order], [labels[i] for i in order], loc="upper right", fontsize=8)


def _clip_spikes(ax, errors):
    """Limit the error axis to the bulk of the errors: one start-up spike of the online learner
    (or a rare outlier) otherwise flattens everything else. True when something was cut off."""
    e = np.concatenate([np.abs(v[np.isfinite(v)]) for v in errors])
    if not len(e):
        return False
    lim = 2 * float(np.percentile(e, 99.9))
    if lim <= 0 or e.max() <= lim:
        return False
    ax.set_ylim(-lim, lim)
    return True


def _fit_label(y, yhat):
    """"FIT 98.2 %" of a trace against the measured y, for its legend (MATLAB compare's figure)."""
    y, yhat = np.asarray(y, float), np.asarray(yhat, float)
    ok = np.isfinite(yhat)
    if ok.sum() < 2:
        return "no FIT"
    spread = np.linalg.norm(y[ok] - y[ok].mean())
    fit = 100 * (1 - np.linalg.norm(y[ok] - yhat[ok]) / spread) if spread > 0 else float("nan")
    return "diverges" if not np.isfinite(fit) or fit < DIVERGED_FIT else f"FIT {fit:.1f} %"


def plot_output(plt, out, r, p, arx):
    """Per run: one-step and free-run predictions (fuzzy and ARX) under the measured signal, and the
    one-step errors. Measured is drawn last and thin, in black, so it stays visible on top of
    predictions that match it; wide coloured traces show around it where they differ."""
    out_name = r["preset"]["output"]
    runs = sorted(set(p["run"].astype(int)))
    free_title = "free run (simulation)" if r["config"].get("ny", 1) else \
        "free run (same as one-step: a static map has no output lags)"
    fig, axes = plt.subplots(3, len(runs), figsize=(6.5 * len(runs), 9), sharex="col", squeeze=False)
    for c, run in enumerate(runs):
        m = p["run"] == run
        training = c == 0 and len(runs) > 1
        t, sample = p["sample"][m] * DT, p["sample"][m]
        y = p[f"{out_name}_measured"][m]
        fuzzy = {"one_step": p[f"{out_name}_predicted"][m], "free_run": p[f"{out_name}_free_run"][m]}
        # The last run is validation (set 1 in odonata-fit's file), the one before it training.
        a_set = arx[0 if training else 1] if arx else None
        a = {mode: _aligned(a_set, sample, f"arx_{mode}") for mode in fuzzy} if a_set else None
        window = _y_window(y)
        phase = ("training (fuzzy learning online; ARX fitted on these data)" if training
                 else "validation (frozen models, a different excitation)")
        for row, (mode, what) in enumerate((("one_step", "one-step"), ("free_run", "free run"))):
            ax = axes[row][c]
            _trace(ax, t, fuzzy[mode], FUZZY, f"fuzzy {what} ({_fit_label(y, fuzzy[mode])})", window)
            if a:
                _trace(ax, t, a[mode], ARX, f"ARX {what} ({_fit_label(y, a[mode])})", window)
            ax.plot(t, y, "k", lw=0.8, label="measured", zorder=3)
            ax.set_ylim(window[0], window[1])
            ax.set_ylabel(_with_unit(out_name))
            ax.set_title(f"{r['name']}: {phase}\none-step prediction" if row == 0 else free_title, fontsize=10)
            _legend_measured_first(ax)
        errors = [y - fuzzy["one_step"]] + ([y - a["one_step"]] if a else [])
        ax = axes[2][c]
        ax.plot(t, errors[0], color=FUZZY, lw=0.8, label="fuzzy")
        if a:
            ax.plot(t, errors[1], color=ARX, lw=0.8, alpha=0.8, label="ARX")
        clipped = _clip_spikes(ax, errors)
        ax.set_title("one-step error (measured − predicted)" + (", rare spikes clipped" if clipped else ""),
                     fontsize=10)
        ax.set_ylabel(_with_unit(out_name))
        ax.set_xlabel("time (s)")
        ax.legend(loc="upper right", fontsize=8)
    return _save(plt, fig, out, r, "output")


def plot_learning(plt, out, r, p):
    out_name = r["preset"]["output"]
    m = p["run"] == min(p["run"])
    fig, ax = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
    ax[0].step(p["sample"][m] * DT, p[f"{out_name}_rules"][m], where="post")
    ax[0].set_ylabel("rules")
    ax[0].set_title(f"{r['name']}: structure learning (H = {r['chosen_entropy_threshold']:.4g})")
    ax[1].plot(p["sample"][m] * DT, p[f"{out_name}_max_entropy"][m], lw=0.6)
    ax[1].axhline(r["chosen_entropy_threshold"], color="r", ls="--", lw=0.8, label="H threshold")
    ax[1].set_ylabel("H_max")
    ax[1].set_xlabel("time (s)")
    ax[1].legend(fontsize=8)
    return _save(plt, fig, out, r, "learning")


def plot_parameters(plt, out, r):
    """Antecedent centres and widths and each rule's consequent over training. Colour = signal: the
    lags of one signal share a colour (their centres nearly coincide, and with ten or more regressors
    a colour per regressor would repeat)."""
    from matplotlib.lines import Line2D
    snaps = json.load(open(os.path.join(r["dir"], "pipeline", "snapshots.json")))
    snaps = [s for s in snaps if s["model"]["models"]]
    if not snaps:
        return None
    regs = _regressors(snaps[-1]["model"])
    signals = list(dict.fromkeys(sig for sig, _ in regs))
    colour = [f"C{signals.index(sig) % 10}" for sig, _ in regs]
    fig, ax = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    for s_idx, key, label in ((0, "centre", "centres (raw units)"), (1, "sigma", "widths (raw units)")):
        series = {}
        for s in snaps:
            sc = s["model"]["scaling"]
            for j, rule in enumerate(s["model"]["models"][0]["rules"]):
                for i, v in enumerate(rule[key]):
                    raw = sc["regressor_mid"][i] + sc["regressor_half"][i] * v if key == "centre" \
                        else sc["regressor_half"][i] * v
                    series.setdefault((j, i), ([], []))
                    series[(j, i)][0].append(s["samples_learned"] * DT)
                    series[(j, i)][1].append(raw)
        for (j, i), (t, v) in series.items():
            ax[s_idx].plot(t, v, lw=0.8, color=colour[i])
        ax[s_idx].set_ylabel(label)
    # One legend entry per signal, not per line: there is a line per rule and regressor.
    lags = {sig: [l for q, l in regs if q == sig] for sig in signals}
    ax[0].legend([Line2D([], [], color=f"C{k % 10}") for k in range(len(signals))],
                 [f"{_with_unit(sig)}\nlags {lags[sig][0]}–{lags[sig][-1]}" for sig in signals], title="signal",
                 fontsize=7, title_fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    series = {}
    cons = snaps[-1]["model"]["models"][0]["consequent"]
    for s in snaps:
        sc = s["model"]["scaling"]
        cons = s["model"]["models"][0]["consequent"]
        vals = cons["centres"] if cons["kind"] == "singleton" else [c[0] for c in cons["coefficients"]]
        for j, v in enumerate(vals):
            series.setdefault(j, ([], []))
            series[j][0].append(s["samples_learned"] * DT)
            series[j][1].append(sc["output_mean"][0] + sc["output_std"][0] * v)
    for j, (t, v) in series.items():
        ax[2].plot(t, v, lw=0.8, color=f"C{j % 10}", label=f"rule {j + 1}")
    what = "singleton b" if cons["kind"] == "singleton" else "offset a0"
    ax[2].set_ylabel(f"consequent {what}\n{_with_unit(r['preset']['output'])}")
    ax[2].set_xlabel("training time (s)")
    if len(series) <= 10:  # beyond ten the colours repeat and a list of rules says nothing
        ax[2].legend(title="rule", fontsize=7, title_fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax[2].legend([Line2D([], [], color="grey")], [f"one line per rule\n({len(series)} rules)"],
                     fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax[0].set_title(f"{r['name']}: parameters over time (colour = signal, one line per rule and lag)")
    return _save(plt, fig, out, r, "parameters")


def plot_membership(plt, out, r):
    model = json.load(open(os.path.join(r["dir"], "pipeline", "model.json")))
    sc = model["scaling"]
    regs = [f"{sig} lag {lag}" for sig, lag in _regressors(model)]
    rules = model["models"][0]["rules"]
    # A model of many rules is a tangle of curves: draw the few that carry most of the firing over
    # the training samples in colour, with their share, and the rest thin and grey behind them.
    shares = rule_shares(model, os.path.join(r["dir"], "pipeline", "train.csv"))
    shown = dominant_rules(shares) if shares is not None and len(rules) > 6 else list(range(len(rules)))
    n = len(regs)
    fig, ax = plt.subplots(n, 1, figsize=(7.8, 1.6 * n + 0.7), squeeze=False)
    for i in range(n):
        lo = sc["regressor_mid"][i] - 1.3 * sc["regressor_half"][i]
        hi = sc["regressor_mid"][i] + 1.3 * sc["regressor_half"][i]
        x = np.linspace(lo, hi, 400)
        for j in [k for k in range(len(rules)) if k not in shown] + shown:
            rule = rules[j]
            c = sc["regressor_mid"][i] + sc["regressor_half"][i] * rule["centre"][i]
            s = sc["regressor_half"][i] * math.sqrt(rule["sigma"][i] ** 2 + 1e-6)
            label = None
            if i == 0 and j in shown:
                label = f"rule {j + 1}" + (f" ({100 * shares[j]:.0f} % of firing)" if shares is not None else "")
            if j in shown:
                ax[i][0].plot(x, np.exp(-0.5 * ((x - c) / s) ** 2), lw=1.4, color=f"C{shown.index(j) % 10}",
                              label=label)
            else:
                ax[i][0].plot(x, np.exp(-0.5 * ((x - c) / s) ** 2), lw=0.5, color="0.75", zorder=0)
        ax[i][0].set_ylabel(regs[i], fontsize=8)
        ax[i][0].set_ylim(0, 1.05)
    others = len(rules) - len(shown)
    if others:
        rest = 100 * (1 - sum(shares[j] for j in shown))
        ax[0][0].plot([], [], lw=0.5, color="0.75", label=f"{others} other rules ({rest:.0f} % of firing)")
    if len(shown) <= 10:
        ax[0][0].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    what = "membership functions"
    if others:
        what = "the rule carrying most of the firing" if len(shown) == 1 else \
            f"the {len(shown)} rules carrying most of the firing"
    ax[0][0].set_title(f"{r['name']}: {what} at the end ({len(rules)} rules)")
    return _save(plt, fig, out, r, "membership")


def _label_where_legible(fig, ax, points, texts):
    """Annotate points, dropping any label that would overlap one already placed or leave the axes."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    placed = []
    for (x, y), text in zip(points, texts):
        a = ax.annotate(text, (x, y), xytext=(4, 3), textcoords="offset points", fontsize=6.5, color="0.25")
        box = a.get_window_extent(renderer).expanded(1.05, 1.1)
        inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        if not inside or any(box.overlaps(b) for b in placed):
            a.remove()
        else:
            placed.append(box)


def _plain_log_ticks(axis, values):
    """Log axis ticked at 1-2-5 steps (finer within one decade, decades only beyond three)
    and labelled in plain numbers: 0.2 reads faster than 2×10⁻¹."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter
    lo, hi = min(values), max(values)
    decades = math.log10(hi / lo) if lo > 0 else 0
    steps = (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8) if decades < 0.5 else (1, 1.5, 2, 3, 5, 7) if decades < 1 \
        else (1, 2, 5) if decades <= 3 else (1,)
    ticks = [m * 10.0 ** e for e in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1)
             for m in steps if lo / 1.3 <= m * 10.0 ** e <= hi * 1.3]
    axis.set_major_locator(FixedLocator(ticks))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def plot_sweep(plt, out, r):
    """Selection scores: colour = model order, marker = κ, each curve runs over H; H is written
    next to a point wherever it fits. Diverged scores sit on the top edge instead of stretching
    the log axis over a hundred decades."""
    from matplotlib.lines import Line2D
    pts = [q for q in r["sweep"]["points"] if q["score"] is not None]
    chosen = r["sweep"]["points"][r["sweep"]["chosen_index"]]
    crit = r["sweep"]["criterion"].replace("_", "-")
    orders = sorted(set((q.get("ny", 0), q.get("nu", 0)) for q in pts))
    kappas = sorted(set(q["kappa"] for q in pts))
    markers = "osD^v<>p"
    top = min(max(q["score"] for q in pts), DIVERGED_NDEI)
    shown = lambda q: min(q["score"], top)  # noqa: E731
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for oi, order in enumerate(orders):
        for ki, kappa in enumerate(kappas):
            sel = sorted((q for q in pts if (q.get("ny", 0), q.get("nu", 0)) == order and q["kappa"] == kappa),
                         key=lambda q: q["entropy_threshold"])
            if sel:
                ax.plot([q["rules"] for q in sel], [shown(q) for q in sel], "-", color=f"C{oi}",
                        marker=markers[ki % len(markers)], ms=4.5, lw=0.9, alpha=0.85)
    ax.plot([chosen["rules"]], [shown(chosen)], "r*", ms=14, zorder=4)
    off = [q for q in pts if q["score"] > top]
    if off:
        ax.axhline(top, color="0.5", ls=":", lw=0.8)
        ax.annotate("diverged (off scale)", (0.01, top), xycoords=("axes fraction", "data"), xytext=(0, -9),
                    textcoords="offset points", fontsize=7, color="0.4")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _plain_log_ticks(ax.xaxis, [q["rules"] for q in pts])
    _plain_log_ticks(ax.yaxis, [shown(q) for q in pts])
    ax.set_xlabel("rules (count, log scale)")
    ax.set_ylabel(f"{crit} NDEI on the selection data\n(dimensionless, lower is better)")
    ax.set_title(f"{r['name']}: choice of H, κ and order — {crit} NDEI on the SELECTION excitation\n"
                 "(a third excitation; validation takes no part in the choice)", fontsize=10)
    handles = [Line2D([], [], color=f"C{i}", lw=2) for i in range(len(orders))] + \
              [Line2D([], [], color="0.3", ls="", marker=markers[i % len(markers)]) for i in range(len(kappas))] + \
              [Line2D([], [], color="r", ls="", marker="*", ms=10)]
    labels = [f"ny/nu {o[0]}/{o[1]}" for o in orders] + [f"κ {k:g}" for k in kappas] + \
             [f"chosen: ny/nu {chosen.get('ny', 0)}/{chosen.get('nu', 0)}, κ {chosen['kappa']:g}, "
              f"H {chosen['entropy_threshold']:.3g}, {chosen['rules']} rules"]
    if off:
        labels[-1] += f"\n{len(off)} diverged point(s) drawn on the top edge"
    ax.legend(handles, labels, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    # The chosen point's H first, so it is never the one dropped for lack of room.
    ordered = [chosen] + [q for q in pts if q is not chosen]
    _label_where_legible(fig, ax, [(q["rules"], shown(q)) for q in ordered],
                         [f"H {q['entropy_threshold']:.2g}" for q in ordered])
    return _save(plt, fig, out, r, "sweep")


def make_plots(out, r, build=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    p = read_predictions(os.path.join(r["dir"], "pipeline", "predictions.csv"))
    arx = arx_predictions(r, build or os.path.join(ROOT, "build"))
    files = {"output": plot_output(plt, out, r, p, arx), "learning": plot_learning(plt, out, r, p)}
    parameters = plot_parameters(plt, out, r)
    if parameters:
        files["parameters"] = parameters
    files["membership"] = plot_membership(plt, out, r)
    files["sweep"] = plot_sweep(plt, out, r)
    files.update(fit_pictures(out, r))
    return files


def fit_pictures(out, r):
    """odonata-fit --plot's pictures of the model (drawn with the ARX traces, arx_predictions),
    copied beside the report's: terms, activation, and gain_schedule or surface."""
    found = {}
    src = os.path.join(r["dir"], "fit-plots")
    for kind, png in (("terms", "membership.png"), ("activation", "activation.png"),
                      ("gain_schedule", "gain_schedule.png"), ("gain_surface", "gain_surface.png"),
                      ("surface", "surface.png")):
        path = os.path.join(src, png)
        if os.path.exists(path):
            name = f"{r['name']}-{kind}.png"
            shutil.copyfile(path, os.path.join(out, name))
            found[kind] = name
    return found
