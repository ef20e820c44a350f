"""The verdict of one odonata-fit run (fit_report.py's page opens with it): per output, the model's
FIT in the mode the fit is scored by, beside ARX and persistence, worded as the main job's verdicts."""
import math

from .verdicts import _compare

# A FIT this large in size is a run-away prediction's number (−3·10²⁴ %), not a score.
HUGE_FIT = 1e6
# What each mode is called, after "fuzzy beats ARX by … FIT points".
WHERE = {"free_run": "in free run", "one_step": "in one-step prediction", "k_step": "{k} steps ahead"}


def scored_mode(scores):
    """K steps ahead with --horizon, else free run (output lags), else one step: what odonata-fit
    chooses the model by unless told otherwise."""
    return next((m for m in ("k_step", "free_run") if m in scores), "one_step")


def fit_of(block):
    """A score block's FIT, or None where it diverged: flagged, null, not finite or huge."""
    if not isinstance(block, dict) or block.get("diverged"):
        return None
    f = block.get("fit")
    if isinstance(f, bool) or not isinstance(f, (int, float)) or not math.isfinite(f) or abs(f) > HUGE_FIT:
        return None
    return float(f)


def percent(block):
    """'97.20 %', 'diverges', or '–' where there is no such score (a baseline without the mode)."""
    if not isinstance(block, dict):
        return "–"
    f = fit_of(block)
    return "diverges" if f is None else f"{round(f, 2) or 0.0:.2f} %"  # or 0.0: no "-0.00"


def legend(block):
    """The same score as the compare plot's legend prints it."""
    f = fit_of(block)
    return "diverges" if f is None else f"FIT {f:.1f} %"


def outputs(report):
    """[(output, its block)]: the report itself for one output, per_output's block for several."""
    names = report.get("outputs") or [report.get("output")]
    per = report.get("per_output") or {}
    return [(name, per.get(name, report)) for name in names]


def judge(f, a, mode, rules, where):
    """fuzzy against ARX, each FIT or None (diverged)."""
    if f is None and a is None:
        return f"both diverge {where}"
    if f is None:
        return f"fuzzy loses to ARX: its prediction diverges {where}"
    if a is None:
        return f"fuzzy beats ARX: ARX diverges {where}"
    return _compare(f, a, mode, rules, where)[0]


def verdict(report, output, block):
    """{output, set, mode, where, fit, arx, persistence, text} for one output; the scores as
    printed ("49.80 %", "diverges" or "–")."""
    data = "validate" if block.get("validate") else "train"
    scores = block.get(data) or {}
    mode = scored_mode(scores)
    where = WHERE[mode].format(k=(scores.get(mode) or {}).get("horizon", "K"))
    base = block.get("baselines") or {}
    model = scores.get(mode)
    arx = ((base.get("arx") or {}).get(data) or {}).get(mode)
    pers = ((base.get("persistence") or {}).get(data) or {}).get(mode)
    rules = block.get("rules", report.get("rules"))
    f, p = fit_of(model), fit_of(pers)
    said = judge(f, fit_of(arx), mode, rules, where)
    on = "on the validation file" if data == "validate" else "on the training file (no validation file given)"
    v = {"output": output, "set": data, "mode": mode, "where": where, "fit": percent(model),
         "arx": percent(arx), "persistence": percent(pers)}
    inputs = report.get("inputs") or []
    text = (f"{output}{' from ' + ', '.join(inputs) if inputs else ''} "
            f"({rules} rule{'' if rules == 1 else 's'}), {on}: {said} "
            f"(the model's FIT {v['fit']}, ARX {v['arx']}, persistence {v['persistence']})")
    flags = (report.get("verdict") or {}).get("flags", []) if output == outputs(report)[0][0] else []
    if "constant" in flags:
        text += "; the model is a constant: it has identified nothing"
    if p is not None and (f is None or f < p):
        text += "; below persistence: holding the last value predicts better"
    v["text"] = text + "."
    return v
