#!/usr/bin/python3
"""Draws what `odonata-fit --plot DIR` wrote into DIR (common/fit/fit_plot_data.hpp):

  membership.png     each signal's shared, named terms of the readable form (the premises an
                     operator reads), or the full model's rules when there is no readable form
  activation.png     measured and predicted over the validation run, and under them which rule
                     of the readable form fires when (a strip, one row per rule)
  surface.png        a static map's output over its two most influential inputs
  gain_surface.png   a dynamic model's steady-state gain over the two signals its rules spread
                     over most (the rules' local models blended by their firing at each point)
  gain_schedule.png  a dynamic model's steady-state gain and slowest time constant, rule by rule,
                     along the signal its rules are spread over (how they vary across the range)
  plot_notes.json    {picture: what it states instead of curves}: "linear: one rule" for a model
                     of one rule, a constant gain where the rules' local models coincide (no
                     surface or schedule drawn from round-off); fit_report.py shows them

    python3 fit_plots.py DIR

The firing strengths come from odonata-fit (activation.csv), not from a copy of its rules here.
"""
import csv
import json
import math
import os
import re
import sys
import textwrap

TERM_NAMES = {1: ["medium"], 2: ["low", "high"], 3: ["low", "medium", "high"],
              4: ["very low", "low", "high", "very high"],
              5: ["very low", "low", "medium", "high", "very high"]}
# A quantity whose range over a surface or across the rules is below this share of its magnitude
# is one value: what varies is round-off (and the CSVs' ten digits), which a colour bar would
# blow up into a picture with "1e-11" over its title.
CONSTANT_RELATIVE = 1e-9
ONE_RULE = "linear: one rule"


def fit_percent(y, yhat):
    """FIT = 100 (1 − ‖y − ŷ‖ / ‖y − ȳ‖), the figure odonata-fit reports."""
    mean = sum(y) / len(y)
    den = math.sqrt(sum((v - mean) ** 2 for v in y))
    num = math.sqrt(sum((a - b) ** 2 for a, b in zip(y, yhat)))
    return 100.0 * (1.0 - num / den) if den > 0 else float("nan")


def read_columns(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    return {h: [float(r[i]) for r in body] for i, h in enumerate(head)}


def signal_of(regressor):
    """'pitch_deg(k-1)' → 'pitch_deg': a regressor's signal, whose lags share the readable terms."""
    return re.sub(r"\(k[-+0-9]*\)$", "", regressor)


def terms(model, regressors):
    """Per signal: its distinct (centre, width) pairs in raw units, over the rules' premises at
    the signal's first regressor (the readable form gives a signal's lags one term)."""
    sc = model["scaling"]
    out = {}
    for i, reg in enumerate(regressors):
        sig = signal_of(reg)
        if sig in out:
            continue
        pairs = set()
        for rule in model["models"][0]["rules"]:
            c = sc["regressor_mid"][i] + sc["regressor_half"][i] * rule["centre"][i]
            s = sc["regressor_half"][i] * rule["sigma"][i]
            pairs.add((round(c, 12), round(s, 12)))
        out[sig] = (i, sorted(pairs))
    return out


def constant(values):
    """(True, value) when the finite `values` are one number up to CONSTANT_RELATIVE."""
    finite = [v for v in values if math.isfinite(v)]
    if not finite:
        return False, float("nan")
    lo, hi = min(finite), max(finite)
    return hi - lo <= CONSTANT_RELATIVE * max(abs(lo), abs(hi)), 0.5 * (lo + hi)


def reads_linear(report):
    """The model, or its readable form, is one rule: the rules' local models coincide."""
    return report.get("rules") == 1 or (report.get("readable") or {}).get("rules") == 1


def one_rule_statement(report):
    return ONE_RULE if report.get("consequent", "linear") == "linear" else "one rule: a constant output"


def plot_statement(plt, d, kind, title, statement, detail=""):
    """A picture that says what there is to see in words: nothing varies, so no curves."""
    fig, ax = plt.subplots(figsize=(7.5, 2.0))
    ax.axis("off")
    ax.text(0.5, 0.68, statement, ha="center", va="center", fontsize=18, weight="bold",
            transform=ax.transAxes)
    if detail:
        ax.text(0.5, 0.22, textwrap.fill(detail, 95), ha="center", va="center", fontsize=8,
                transform=ax.transAxes)
    ax.set_title(title, fontsize=10)
    return save(plt, fig, d, kind)


def remove_stale(d, kind):
    """A picture this run decided not to draw must not survive from an earlier run into DIR."""
    path = os.path.join(d, f"{kind}.png")
    if os.path.exists(path):
        os.remove(path)


def plot_membership(plt, d, report, notes):
    readable = os.path.exists(os.path.join(d, "readable_model.json"))
    model = json.load(open(os.path.join(d, "readable_model.json" if readable else "model.json")))
    if len(model["models"][0]["rules"]) == 1:
        # One rule fires everywhere: its terms are flat lines at 1 with widths of 10⁴, which say
        # less than the words.
        statement = one_rule_statement(report)
        text = (report.get("readable") or {}).get("text") or report.get("rule_text") or [""]
        rule = text[0][len(ONE_RULE) + 2:] if text[0].startswith(ONE_RULE + ": ") else text[0]
        detail = "one rule fires everywhere: no membership functions to draw. " + rule
        notes["membership.png"] = statement
        return plot_statement(plt, d, "membership", f"{report['output']}: the rules' premises",
                              statement, detail)
    per = terms(model, report["regressors"])
    sc = model["scaling"]
    fig, axes = plt.subplots(len(per), 1, figsize=(7.5, 1.7 * len(per) + 0.8), squeeze=False)
    for ax, (sig, (i, pairs)) in zip(axes[:, 0], per.items()):
        lo = sc["regressor_mid"][i] - 1.2 * sc["regressor_half"][i]
        hi = sc["regressor_mid"][i] + 1.2 * sc["regressor_half"][i]
        xs = [lo + (hi - lo) * k / 300 for k in range(301)]
        names = TERM_NAMES.get(len(pairs), [f"term {k + 1}" for k in range(len(pairs))])
        for k, (c, s) in enumerate(pairs):
            s = max(abs(s), 1e-12)
            ys = [math.exp(-0.5 * ((x - c) / s) ** 2) for x in xs]
            ax.plot(xs, ys, lw=1.5, label=f"{names[k]} ({c:.3g} ± {s:.2g})" if readable else None)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel(sig, fontsize=9)
        if readable:
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    what = "readable form: each signal's terms" if readable else "the rules' membership functions"
    axes[0][0].set_title(f"{report['output']}: {what}")
    return save(plt, fig, d, "membership")


def timed(report):
    """Whether odonata-fit knew the data's rate (a time column or a ULog): t_s is then seconds."""
    data = report.get("data") or {}
    return any(isinstance(v, dict) and "rate_hz" in v for v in data.values())


def plot_activation(plt, d, report):
    a = read_columns(os.path.join(d, "activation.csv"))
    rules = sorted((k for k in a if k.startswith("rule_")), key=lambda k: int(k[5:]))
    t, y = a["t_s"], a["measured"]
    fig, axes = plt.subplots(2 if rules else 1, 1, figsize=(9, 5.2 if rules else 3.2), sharex=True,
                             squeeze=False, gridspec_kw={"height_ratios": [3, 2] if rules else [1]})
    ax = axes[0][0]
    ax.plot(t, a["one_step"], color="C0", lw=1.0, label=f"one step (FIT {fit_percent(y, a['one_step']):.1f} %)")
    ax.plot(t, a["free_run"], color="C1", lw=1.0, label=f"free run (FIT {fit_percent(y, a['free_run']):.1f} %)")
    ax.plot(t, y, "k", lw=0.7, label="measured")
    ax.set_ylabel(report["output"])
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"{report['output']}: the {report.get('validate') and 'validation' or 'training'} run, "
                 "and which rule of the readable form fires when")
    if rules:
        strip = axes[1][0]
        firing = [a[r] for r in rules]
        step = (t[1] - t[0]) if len(t) > 1 else 1.0
        strip.imshow(firing, aspect="auto", cmap="Greens", vmin=0, vmax=1, interpolation="nearest",
                     extent=[t[0] - step / 2, t[-1] + step / 2, len(rules) - 0.5, -0.5])
        # At most about ten labels: a readable form of many rules would print them on each other.
        every = max(1, math.ceil(len(rules) / 10))
        ticks = list(range(0, len(rules), every))
        strip.set_yticks(ticks)
        strip.set_yticklabels([f"rule {rules[k][5:]}" for k in ticks], fontsize=8)
        strip.set_ylabel("firing (0 … 1)", fontsize=8)
    axes[-1][0].set_xlabel("time (s)" if timed(report) else "sample")
    return save(plt, fig, d, "activation")


def plot_surface(plt, d, report):
    with open(os.path.join(d, "surface.csv")) as f:
        rows = list(csv.reader(f))
    xa, xb, out = rows[0]
    pts = [[float(v) for v in r] for r in rows[1:]]
    n = int(round(math.sqrt(len(pts))))
    grid_a = [pts[i * n][0] for i in range(n)]
    grid_b = [pts[j][1] for j in range(n)]
    z = [[pts[i * n + j][2] for i in range(n)] for j in range(n)]
    fig, ax = plt.subplots(figsize=(6.5, 5))
    mesh = ax.contourf(grid_a, grid_b, z, levels=20, cmap="viridis")
    ax.contour(grid_a, grid_b, z, levels=10, colors="k", linewidths=0.4)
    fig.colorbar(mesh, ax=ax, label=out)
    ax.set_xlabel(xa)
    ax.set_ylabel(xb)
    ax.set_title(f"{out} over its two most influential inputs (the others at their mean)")
    return save(plt, fig, d, "surface")


def plot_gain_surface(plt, d, report, notes):
    """A dynamic model's steady-state gain from its first input over the two signals its rules
    spread over most: at each point the rules' local models blended as the model blends them.
    A gain that is one value over the surface is stated in `notes`, not painted."""
    path = os.path.join(d, "gain_surface.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = list(csv.reader(f))
    head, pts = rows[0], [[float(v) for v in r] for r in rows[1:]]
    n = int(round(math.sqrt(len(pts))))
    grid_a = [pts[i * n][0] for i in range(n)]
    grid_b = [pts[j][1] for j in range(n)]
    gains, flat = [], []
    for k, name in enumerate(head[2:4]):
        same, value = constant([p[2 + k] for p in pts])
        (flat if same else gains).append((k, name, value))
    if flat:
        why = f": {ONE_RULE}" if reads_linear(report) else " over the surface"
        said = [f"gain {v:.4g} from {name[10:]}" if name.startswith("gain from ") else f"{name} {v:.4g}"
                for _, name, v in flat]
        notes["gain_surface.png"] = "constant " + "; ".join(said) + why
    if not gains:
        remove_stale(d, "gain_surface")
        return None
    fig, axes = plt.subplots(1, len(gains), figsize=(6.2 * len(gains), 4.8), squeeze=False)
    for ax, (k, name, _) in zip(axes[0], gains):
        z = [[pts[i * n + j][2 + k] for i in range(n)] for j in range(n)]
        mesh = ax.contourf(grid_a, grid_b, z, levels=20, cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=name)
        ax.set_xlabel(head[0])
        ax.set_ylabel(head[1])
        ax.set_title(f"{report['output']}: steady-state {name}", fontsize=10)
    return save(plt, fig, d, "gain_surface")


def plot_gain_schedule(plt, d, report, notes):
    local = report.get("local_models") or []
    model = json.load(open(os.path.join(d, "model.json")))
    rules = model["models"][0]["rules"]
    if len(local) < 2 or len(local) != len(rules):
        return None
    sc = model["scaling"]
    regs = report["regressors"]
    # The signal the rules are spread over most (in units of its range): their operating points.
    spread = [max(r["centre"][i] for r in rules) - min(r["centre"][i] for r in rules) for i in range(len(regs))]
    i = max(range(len(regs)), key=lambda k: spread[k])
    x = [sc["regressor_mid"][i] + sc["regressor_half"][i] * r["centre"][i] for r in rules]
    order = sorted(range(len(rules)), key=lambda j: x[j])
    xs = [x[j] for j in order]
    inputs = sorted({k for m in local for k in m.get("dc_gain", {})})
    seconds = "time_constants_s" in local[0]
    tau_key = "time_constants_s" if seconds else "time_constants_samples"
    unit = "s" if seconds else "samples"
    # (label, values, what a constant row is called); constant consequents have no dynamics of
    # their own: each rule's output level instead.
    if report.get("consequent") == "singleton":
        series = [(f"rule output ({report['output']})",
                   [local[j].get("equilibrium", float("nan")) for j in order], "output {v:.4g}")]
    else:
        series = [(f"gain from {u}", [local[j]["dc_gain"].get(u, float("nan")) for j in order],
                   f"gain {{v:.4g}} from {u}") for u in inputs]
        series.append((f"slowest τ ({unit})", [max(local[j].get(tau_key) or [float("nan")]) for j in order],
                       f"slowest τ {{v:.3g}} {unit}"))
    flat = [constant(values) for _, values, _ in series]
    if all(same for same, _ in flat):
        # The rules' local models coincide: a schedule of one value, drawn, is round-off.
        why = ONE_RULE if reads_linear(report) else "the rules' local models coincide"
        notes["gain_schedule.png"] = ("constant " + " and ".join(
            what.format(v=v) for (_, _, what), (_, v) in zip(series, flat)) + f" in every rule: {why}")
        remove_stale(d, "gain_schedule")
        return None
    if report.get("consequent") == "singleton":
        fig, ax = plt.subplots(figsize=(7, 3.2))
        draw_row(ax, xs, series[0][1])
        ax.set_xlabel(f"each rule's operating point in {regs[i]}")
        ax.set_ylabel(series[0][0], fontsize=8)
        ax.set_title(f"{report['output']}: each rule's constant output along its operating point")
        return save(plt, fig, d, "gain_schedule")
    fig, axes = plt.subplots(len(inputs) + 1, 1, figsize=(7, 2.2 * (len(inputs) + 1) + 0.6), sharex=True,
                             squeeze=False)
    for row, u in enumerate(inputs):
        ax = axes[row][0]
        draw_row(ax, xs, series[row][1])
        ax.set_ylabel(series[row][0], fontsize=8)
        glob = (report.get("global_linear") or {}).get("dc_gain", {}).get(u)
        if glob is not None:
            ax.axhline(glob, color="0.5", ls="--", lw=0.8, label="global linear model")
            ax.legend(fontsize=7)
    ax = axes[-1][0]
    taus = series[-1][1]
    stable = [local[j].get("stable", True) for j in order]
    draw_row(ax, xs, taus)
    for xv, tv, ok in zip(xs, taus, stable):
        if not ok:
            ax.plot([xv], [tv], "rx", ms=9)
    ax.set_ylabel(series[-1][0], fontsize=8)
    ax.set_xlabel(f"each rule's operating point in {regs[i]}")
    axes[0][0].set_title(f"{report['output']}: gain schedule, one point per rule (x: unstable)")
    return save(plt, fig, d, "gain_schedule")


def draw_row(ax, xs, values):
    """One row of the schedule; a row of one value is drawn at that value, on an axis without the
    offset ("1e-12 + 4.99") that round-off would put over it."""
    same, v = constant(values)
    if same:
        values = [v] * len(values)
        pad = 0.05 * abs(v) or 1.0
        ax.set_ylim(v - pad, v + pad)
        ax.ticklabel_format(axis="y", useOffset=False)
    ax.plot(xs, values, "o-", lw=1)


def save(plt, fig, d, kind):
    fig.tight_layout()
    path = os.path.join(d, f"{kind}.png")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    d = argv[1]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("fit_plots.py: matplotlib is missing (apt-get install python3-matplotlib)", file=sys.stderr)
        return 1
    report = json.load(open(os.path.join(d, "report.json")))
    notes = {}
    written = [plot_membership(plt, d, report, notes), plot_activation(plt, d, report)]
    if os.path.exists(os.path.join(d, "surface.csv")):
        written.append(plot_surface(plt, d, report))
    else:
        written.append(plot_gain_schedule(plt, d, report, notes))
        written.append(plot_gain_surface(plt, d, report, notes))
    with open(os.path.join(d, "plot_notes.json"), "w") as f:
        json.dump(notes, f, indent=1, ensure_ascii=False)
    for w in written:
        if w:
            print(w)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
