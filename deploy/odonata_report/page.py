"""The HTML page a person reads top to bottom, and the report's files (summary.json, summary.md, index.html)."""
import html
import json
import os


from .common import fmt
from .verdicts import lead, summarise
from .tables import COLUMNS, TABLE_NOTE, markdown, table_rows
from .plots import make_plots

# --- page ------------------------------------------------------------------------------------

def page(summary, figures):
    """The report a person reads top to bottom: a contents list, then each experiment opening
    with its verdict, its compare plot (FIT in every legend) and its readable rules as a table;
    the full rules fold away, and the table of every figure is the appendix."""
    rows = table_rows(summary)
    h = ["<!doctype html><html><head><meta charset='utf-8'>"
         "<meta name='viewport' content='width=device-width, initial-scale=1'><title>odonata report</title>",
         "<style>body{font-family:sans-serif;max-width:1400px;margin:auto;padding:0 8px}"
         "table{border-collapse:collapse;font-size:13px}"
         "td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}th{background:#eee}"
         "td[data-key=verdict],td[data-key=experiment],td[data-key=headline],td.rule{text-align:left}"
         ".verdict{font-size:16px;background:#f4f4f4;padding:6px;border-left:4px solid #555}"
         "img{max-width:100%;height:auto;border:1px solid #ddd;margin:4px 0}"
         "details li{font-family:monospace;font-size:12px}"
         "@media (max-width:600px){h1{font-size:20px}h2{font-size:17px}.verdict{font-size:14px}}</style>"
         "</head><body>",
         "<h1>odonata — the paper's six identifications through the LCM pipeline</h1>",
         f"<p>Mode {html.escape(summary['mode'])}, {html.escape(summary['consequent'])} consequents, seed {summary['seed']}. "
         "Persistence (ŷ(k+1) = y(k)) and linear ARX on the same regressors are the baselines.</p>",
         # Names only: the verdicts open each section, and the first one's plot stays on the
         # first screen at 400 px too.
         "<nav><b>Contents:</b> " +
         " · ".join(f"<a href='#{html.escape(s['experiment'])}'>{html.escape(s['experiment'])}</a>"
                    for s in summary["experiments"]) +
         " · <a href='#appendix'>appendix: every figure</a></nav>"]
    for s in summary["experiments"]:
        name = s["experiment"]
        hl = s["headline"]
        h.append(f"<h2 id='{name}'>{html.escape(name)}: {html.escape(s['output'])} from {html.escape(', '.join(s['inputs']))}</h2>")
        h.append(f"<p class='verdict'><b>{html.escape(lead(s))}</b><br>"
                 f"Headline: validation {html.escape(hl['metric'])} {fmt(hl['fuzzy'])} (fuzzy) vs "
                 f"{fmt(hl['arx'])} (ARX), higher is better.</p>")
        shown = figures.get(name, {})
        if "output" in shown:
            h.append(f"<img src='{shown['output']}' alt='{name}: measured, the fuzzy model and ARX'>")
        rd = s.get("readable")
        if rd:
            fit = fmt(rd["validate_one_step_fit"])
            h.append(f"<h3>Rules, readable form ({rd['rules']} of {s['rules']}; validation one-step FIT "
                     f"{fit} % against the model's {fmt(s['validate']['one_step']['fit'])} %)</h3>")
            h.append("<table class='rules'>" + "".join(f"<tr><td class='rule'>{html.escape(t)}</td></tr>"
                                                        for t in rd["text"]) + "</table>")
        # The readable form's terms, which rule fires when, and how the rules' dynamics vary
        # across the operating range (or a static map's surface).
        for key, what in (("terms", "each signal's terms"), ("activation", "which rule fires when"),
                          ("gain_schedule", "gain schedule"), ("gain_surface", "gain surface"),
                          ("surface", "output surface")):
            if key in shown:
                h.append(f"<img src='{shown[key]}' alt='{name}: {what}'>")
        if s["notes"]:
            h.append("<ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in s["notes"]) + "</ul>")
        goals = ", ".join(f"{k}: {'met' if v else 'NOT met'}" for k, v in s["goals"].items())
        h.append(f"<p>Goals — {html.escape(goals)}</p>")
        for key in ("learning", "parameters", "membership", "sweep"):
            if key in shown:
                h.append(f"<img src='{shown[key]}' alt='{name} {key}'>")
        h.append(f"<details><summary>Every rule of the model ({s['rules']})</summary><ol>" +
                 "".join(f"<li>{html.escape(t)}</li>" for t in s["rule_text"]) + "</ol></details>")
    h.append("<h2 id='appendix'>Appendix: every figure</h2>")
    h.append(f"<p>{html.escape(TABLE_NOTE)}</p>")
    h.append("<div style='overflow-x:auto'><table id='summary'><tr>" +
             "".join(f"<th>{html.escape(hd)}</th>" for _, hd in COLUMNS) + "</tr>")
    for r in rows:
        h.append("<tr>" + "".join(f"<td data-key='{k}'>{html.escape(r[k])}</td>" for k, _ in COLUMNS) + "</tr>")
    h.append("</table></div>")
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
            figures[r["name"]] = make_plots(out, r, getattr(args, "build", None))
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write(page(summary, figures))
    return summary
