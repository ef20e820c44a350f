"""odonata-compare's drawing (MATLAB's `compare` for odonata-fit): measured against the fuzzy
model and ARX, one-step, k-step and free run, FIT % in each legend, the training file beside the
validation file and a zoom where the signal moves fastest. A free run that leaves the measured
range is clipped to the view and labelled "diverges" instead of a FIT of −10²⁴ %."""
import csv
import math

MODES = (("one_step", "one step"), ("k_step", "{k} steps ahead"), ("free_run", "free run"))
SETS = ("train", "validate")
FUZZY, ARX = "tab:blue", "tab:orange"


# Below −100 % FIT (errors over twice the spread of the data: worse than predicting the mean,
# twice over) a simulation has left the data; its digits (−3e24 %) say nothing more. One cut for
# every place that prints "diverges": this plot, the report, odonata-run and odonata-monitor.
DIVERGED_FIT = -100.0  # the C++ tools' metrics::kDivergedFitPercent: one cut everywhere


def fit_label(fit):
    """FIT % as a legend shows it; below DIVERGED_FIT or not finite: "diverges"."""
    if fit is None or not isinstance(fit, (int, float)) or not math.isfinite(fit) or fit < DIVERGED_FIT:
        return "diverges"
    return f"FIT {fit:.1f} %"


def read_predictions(path):
    """Columns of odonata-fit --predictions as lists of floats."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    return {name: [float(r[i]) for r in body] for i, name in enumerate(head)}


def y_window(y):
    """The measured range plus a margin: a diverging prediction cannot squash the data flat."""
    finite = [v for v in y if math.isfinite(v)]
    lo, hi = (min(finite), max(finite)) if finite else (-1.0, 1.0)
    span = (hi - lo) or max(abs(hi), 1e-9)
    return lo - 0.15 * span, hi + 0.15 * span, span


def leaves(v, window):
    lo, hi, span = window
    return any(not math.isfinite(x) or x > hi + span or x < lo - span for x in v)


def fastest_window(y, width):
    """Start of the `width`-sample stretch of `y` with the largest summed |Δy|: where a plot of
    the whole record shows least."""
    if len(y) <= width:
        return 0
    d = [abs(y[i + 1] - y[i]) if math.isfinite(y[i + 1] - y[i]) else 0.0 for i in range(len(y) - 1)]
    run = sum(d[:width - 1])
    best, best_start = run, 0
    for s in range(1, len(y) - width + 1):
        run += d[s + width - 2] - d[s - 1]
        if run > best:
            best, best_start = run, s
    return best_start


def scores(report, output):
    """{(set, model, mode): fit} from odonata-fit's JSON, for one output."""
    block = report.get("per_output", {}).get(output, report)
    out = {}
    for s in SETS:
        for mode, _ in MODES:
            out[(s, "fuzzy", mode)] = block.get(s, {}).get(mode, {}).get("fit")
            arx = block.get("baselines", {}).get("arx", {}).get(s, {}).get(mode, {})
            out[(s, "arx", mode)] = arx.get("fit")
    return out


def interval_label(report, output, set_name, mode):
    """The prediction interval's legend: its level, and on the validation file its coverage
    (odonata-fit's validate.<mode>.interval); None when odonata-fit gave none."""
    block = report.get("per_output", {}).get(output, report)
    interval = block.get("validate", {}).get(mode, {}).get("interval")
    if not interval:
        return None
    text = f"{100 * interval['level']:.0f} % interval"
    if set_name == "validate":
        text += f" (covers {100 * interval['coverage']:.1f} %)"
    return text


def draw(plt, pred, report, output, several, horizon, path, only_modes=None, only_sets=None, labels=None):
    """One figure: a row per mode; columns the training file, its fastest stretch, the validation
    file and its fastest stretch. Returns the legend of every panel, as text (what the user reads without the PNG).
    `only_modes` (mode keys) and `only_sets` (0 train, 1 validate) keep some of them (fit_report.py
    draws the scored mode on one file); `labels` {(set, model, mode): text} replaces fit_label's."""
    sfx = f"_{output}" if several else ""
    sets = sorted(set(int(v) for v in pred["set"]))
    sets = [s for s in sets if only_sets is None or s in only_sets]
    names = {0: "training file", 1: "validation file"}
    modes = [(m, w.format(k=horizon)) for m, w in MODES
             if f"fuzzy_{m}{sfx}" in pred and (m != "free_run" or report.get("ny", 1) > 0)
             and (only_modes is None or m in only_modes)]
    cols = [(s, zoom) for s in sets for zoom in (False, True)]
    fig, axes = plt.subplots(len(modes), len(cols), figsize=(4.6 * len(cols), 2.9 * len(modes)),
                             squeeze=False)
    fits = scores(report, output)
    legends = []
    for c, (s, zoom) in enumerate(cols):
        idx = [i for i, v in enumerate(pred["set"]) if int(v) == s]
        t = [pred["sample"][i] for i in idx]
        y = [pred[f"measured{sfx}"][i] for i in idx]
        if zoom:
            width = max(50, min(len(y), len(y) // 10))
            start = fastest_window(y, width)
            sl = slice(start, start + width)
            t, y, idx = t[sl], y[sl], idx[sl]
        window = y_window(y)
        set_name = SETS[s] if s < len(SETS) else str(s)
        for r, (mode, what) in enumerate(modes):
            ax = axes[r][c]
            panel = [f"{names.get(s, s)}{' (fastest stretch)' if zoom else ''}, {what}:"]
            for model, colour, label in (("fuzzy", FUZZY, "fuzzy"), ("arx", ARX, "ARX")):
                v = [pred[f"{model}_{mode}{sfx}"][i] for i in idx]
                key = (set_name, model, mode)
                text = labels[key] if labels and key in labels else fit_label(fits.get(key))
                if text != "diverges" and leaves(v, window):
                    text += ", diverges"
                lo, hi, span = window
                shown = [min(max(x, lo - 10 * span), hi + 10 * span) if math.isfinite(x)
                         else float("nan") for x in v]
                ax.plot(t, shown, color=colour, lw=1.6, alpha=0.8, label=f"{label} ({text})")
                panel.append(f"{label} ({text})")
            ax.plot(t, y, "k", lw=0.8, label="measured")
            panel.append("measured")
            band = interval_label(report, output, set_name, mode)
            if band and f"fuzzy_{mode}_lower{sfx}" in pred:
                lower = [pred[f"fuzzy_{mode}_lower{sfx}"][i] for i in idx]
                upper = [pred[f"fuzzy_{mode}_upper{sfx}"][i] for i in idx]
                ax.fill_between(t, lower, upper, color=FUZZY, alpha=0.18, lw=0, label=band)
                panel.append(band)
            ax.set_ylim(window[0], window[1])
            ax.set_title(panel[0].rstrip(":"), fontsize=9)
            ax.legend(fontsize=7, loc="upper right")
            ax.grid(alpha=0.3)
            if r == len(modes) - 1:
                ax.set_xlabel("sample")
            if c == 0:
                ax.set_ylabel(output)
            legends.append(" | ".join(panel))
    fig.suptitle(f"odonata-fit: {output}, measured against the fuzzy model and ARX", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return legends
