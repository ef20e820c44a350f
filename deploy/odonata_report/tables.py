"""The summary table: terminal, Markdown and the rows the HTML page and its test share."""
import textwrap


from .common import fmt
from .verdicts import _delta, lead

# --- tables ----------------------------------------------------------------------------------

# The verdict and the headline (validation FIT % in the headline mode, fuzzy beside ARX) come first,
# where a narrow screen shows them; the details follow.
COLUMNS = [("experiment", "experiment"), ("verdict", "verdict"), ("headline", "headline"),
           ("hl_fuzzy", "fuzzy"), ("hl_arx", "ARX"),
           ("delta", "fuzzy − ARX"), ("order", "ny/nu"), ("H", "H chosen"), ("rules", "rules"),
           ("paper_mfs", "paper MFs"), ("paper_h_fit", "paper H: val FIT (rules)"), ("train_fit", "train FIT"),
           ("train_fr", "train free-run"), ("val_fit", "val FIT"), ("val_vaf", "val VAF"), ("val_rmse", "val RMSE"),
           ("val_fr", "val free-run"), ("arx_fit", "ARX val FIT"), ("arx_fr", "ARX free-run"),
           ("avg", "beat-avg fuzzy / ARX free-run"), ("pers_fit", "persist. FIT"),
           ("ndei_ratio", "NDEI / persist."), ("paper_acc", "paper accuracy")]
# The terminal keeps what decides the verdict; VAF, RMSE, training and averaged-output scores are
# in summary.md and index.html.
TERMINAL_KEYS = ["experiment", "verdict", "headline", "hl_fuzzy", "hl_arx", "delta", "order", "rules",
                 "paper_mfs", "val_fit", "val_fr"]


def _averaged(s):
    a = s.get("averaged_output")
    if not a:
        return "–"
    f = (a["validate"].get("free_run") or a["validate"]["one_step"])["fit"]
    x = (a["arx_validate"].get("free_run") or a["arx_validate"]["one_step"])["fit"]
    return f"{fmt(f)} / {fmt(x)}"


def table_rows(summary, short=False):
    rows = []
    for s in summary["experiments"]:
        ndei = s["validate"]["one_step"]["ndei"]
        pn = s["persistence"]["one_step"]["ndei"]
        hl = s["headline"]
        rows.append({
            "experiment": s["experiment"],
            "headline": hl["metric"],
            "hl_fuzzy": fmt(hl["fuzzy"]),
            "hl_arx": fmt(hl["arx"]),
            "delta": _delta(s),
            "order": f"{s['ny']}/{s['nu']}",
            "H": f"{s['entropy_threshold']:.4g}",
            "rules": str(s["rules"]),
            "paper_mfs": str(s["paper"].get("mfs", "–")),
            "paper_h_fit": f"{s['paper_threshold_run']['entropy_threshold']:.4g}: "
                           f"{fmt(s['paper_threshold_run']['validate_one_step_fit'])} ({s['paper_threshold_run']['rules']} rules)",
            "train_fit": fmt(s["train"]["one_step"]["fit"]),
            "train_fr": fmt((s["train"]["free_run"] or {}).get("fit")),
            "val_fit": fmt(s["validate"]["one_step"]["fit"]),
            "val_vaf": fmt(s["validate"]["one_step"]["vaf"]),
            "val_rmse": fmt(s["validate"]["one_step"]["rmse"], 4),
            "val_fr": fmt((s["validate"]["free_run"] or {}).get("fit")),
            "arx_fit": fmt(s["arx"]["one_step"]["fit"]),
            "arx_fr": fmt((s["arx"].get("free_run") or {}).get("fit")),
            "avg": _averaged(s),
            "pers_fit": fmt(s["persistence"]["one_step"]["fit"]),
            "ndei_ratio": fmt(ndei / pn if ndei is not None and pn else None),
            "paper_acc": s["paper"].get("accuracy", "–"),
            "verdict": s["verdict_short"] if short else s["verdict"],
        })
    return rows


TABLE_NOTE = ("headline: validation FIT % (higher is better), free run unless the loop integrates or has "
              "no output lags; fuzzy − ARX in FIT points in that mode, |Δ| < 1 counts as equal. FIT/VAF in %, one-step unless 'free-run'; validation uses a different excitation.")


def terminal_table(summary):
    rows = table_rows(summary, short=True)
    cols = [(k, h) for k, h in COLUMNS if k in TERMINAL_KEYS]
    widths = {k: max(len(h), *(len(r[k]) for r in rows)) for k, h in cols}
    # Text columns read left-aligned, numbers right-aligned.
    just = {k: (str.ljust if k in ("experiment", "headline", "verdict") else str.rjust) for k, _ in cols}
    lines = ["  ".join(just[k](h, widths[k]) for k, h in cols).rstrip()]
    for r in rows:
        lines.append("  ".join(just[k](r[k], widths[k]) for k, _ in cols).rstrip())
    lines += textwrap.wrap(TABLE_NOTE + " VAF, RMSE, training and beat-averaged scores, persistence and the "
                           "paper's figures: summary.md.", width=max(100, len(lines[0])))
    return "\n".join(lines)


def markdown(summary):
    rows = table_rows(summary)
    md = ["# odonata — the paper's six identifications through the LCM pipeline", "",
          f"Mode: {summary['mode']}; consequents: {summary['consequent']}; seed {summary['seed']}.", ""]
    for s in summary["experiments"]:
        md.append(f"- **{s['experiment']}**: {lead(s)}")
    md += ["", TABLE_NOTE, "",
          "| " + " | ".join(h for _, h in COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for r in rows:
        md.append("| " + " | ".join(r[k] for k, _ in COLUMNS) + " |")
    md.append("")
    for s in summary["experiments"]:
        hl = s["headline"]
        md.append(f"## {s['experiment']}: {s['output']} from {', '.join(s['inputs'])}")
        md.append("")
        md.append(f"**{lead(s)}**")
        md.append("")
        md.append(f"- headline: validation {hl['metric']} {fmt(hl['fuzzy'])} (fuzzy) vs "
                  f"{fmt(hl['arx'])} (ARX), higher is better")
        for n in s["notes"]:
            md.append(f"- {n}")
        md.append(f"- goals: {', '.join(k + ('' if v else ' NOT MET') for k, v in s['goals'].items())}")
        md.append("")
        for i, t in enumerate(s["rule_text"], 1):
            md.append(f"{i}. {t}")
        md.append("")
    return "\n".join(md)
