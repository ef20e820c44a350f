"""The page of one odonata-fit run (fit_report.py writes it as DIR/index.html), top to bottom: the
verdict, the warnings and the training data's excitation, the compare plot, the rules with their
time constants and gains, the pictures, the data, the command. HTML and CSS only: no script and
nothing from elsewhere, so it opens offline; every text from the report is escaped."""
import html
import math

from . import fit_verdict

# 1400 px and a 400 px phone alike: pictures shrink to the width, a wide table scrolls in its own
# box (never the page), and long signal names and paths break anywhere.
STYLE = ("body{font-family:sans-serif;max-width:1400px;margin:auto;padding:0 10px;overflow-wrap:anywhere}"
         ".verdict{font-size:17px;background:#f4f4f4;padding:8px;border-left:4px solid #555;margin:6px 0}"
         ".settings{color:#444;font-size:14px}.warnings li{color:#8a4b00}"
         ".scroll{overflow-x:auto;max-width:100%}table{border-collapse:collapse;font-size:13px}"
         "td,th{border:1px solid #ccc;padding:3px 6px;text-align:right;overflow-wrap:normal}"
         "th{background:#eee}td.text,th.text{text-align:left}"
         "ul.rules li,ol.rules li{font-family:monospace;font-size:13px;margin:3px 0}"
         "img{max-width:100%;height:auto;border:1px solid #ddd}figure{margin:10px 0}"
         "figcaption{font-size:13px;color:#333}.note{font-weight:bold}"
         "pre{white-space:pre-wrap;overflow-wrap:anywhere;background:#f4f4f4;padding:8px;font-size:13px}"
         "h3{font-size:16px}"
         "@media (max-width:600px){h1{font-size:20px}h2{font-size:17px}.verdict{font-size:15px}}")

# The pictures odonata-fit --plot draws (fit_plots.py), in the order the page shows them.
PICTURES = (("membership.png", "each signal's terms: the premises the rules read"),
            ("activation.png", "measured and predicted, and which rule fires when"),
            ("gain_schedule.png",
             "each rule's steady-state gain and slowest time constant along its operating point"),
            ("gain_surface.png", "the steady-state gain over the two signals the rules spread over most"),
            ("surface.png", "the output over its two most influential inputs"))
MODE_NAMES = {"one_step": "one step", "free_run": "free run", "k_step": "K steps ahead"}


def esc(v):
    return html.escape(str(v))


def shown(v):
    """A JSON value as a cell shows it."""
    if v is None:
        return "–"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.6g}" if math.isfinite(v) else str(v)
    if isinstance(v, list):
        return ", ".join(shown(x) for x in v)
    if isinstance(v, dict):
        return ", ".join(f"{k}: {shown(x)}" for k, x in v.items())
    return str(v)


def table(head, rows, text_columns=1):
    """A table in its own scrolling box; the first `text_columns` columns are text, left-aligned."""
    def cell(tag, k, v):
        cls = " class='text'" if k < text_columns else ""
        return f"<{tag}{cls}>{esc(v)}</{tag}>"
    h = ["<div class='scroll'><table><tr>" + "".join(cell("th", k, v) for k, v in enumerate(head)) + "</tr>"]
    for r in rows:
        h.append("<tr>" + "".join(cell("td", k, v) for k, v in enumerate(r)) + "</tr>")
    return "".join(h) + "</table></div>"


def title(report):
    outs = ", ".join(report.get("outputs") or [report.get("output", "?")])
    inputs = ", ".join(report.get("inputs") or [])
    return f"odonata-fit: {outs}" + (f" from {inputs}" if inputs else "")


def verdict_section(report, verdicts):
    h = ["<section id='verdict'>"]
    for v in verdicts:
        # The figures as attributes too: a test reads them without parsing the sentence.
        data = " ".join(f"data-{k}='{esc(v[k])}'"
                        for k in ("output", "set", "mode", "fit", "arx", "persistence"))
        h.append(f"<p class='verdict' {data}>{esc(v['text'])}</p>")
    keys = [("consequent", "{} consequents"), ("ny", "ny {}"), ("nu", "nu {}"), ("delay", "delay {}"),
            ("entropy_threshold", "entropy threshold H̄ {}"), ("kappa", "κ {}"), ("epochs", "{} epochs")]
    said = [w.format(shown(report[k])) for k, w in keys if k in report]
    if said:
        h.append(f"<p class='settings'>{esc(', '.join(said))}. FIT % = 100 (1 − ‖y − ŷ‖/‖y − ȳ‖): "
                 "100 % a perfect fit, 0 % no better than the mean.</p>")
    return "".join(h) + "</section>"


def warnings_section(report):
    w = report.get("warnings") or []
    body = ("<ul class='warnings'>" + "".join(f"<li>{esc(x)}</li>" for x in w) + "</ul>"
            if w else "<p>None.</p>")
    return f"<h2 id='warnings'>Warnings</h2>{body}"


def excitation_section(report):
    """The training data's excitation, as odonata-fit reports it, whatever its keys: plain values
    as a list, a block of one entry per signal as a table."""
    ex = report.get("excitation")
    if not isinstance(ex, dict):
        return ""
    h = ["<h2 id='excitation'>Excitation of the training data</h2>"]
    plain = [(k, v) for k, v in ex.items() if not isinstance(v, dict)]
    if plain:
        h.append("<ul>" + "".join(f"<li>{esc(k)}: {esc(shown(v))}</li>" for k, v in plain) + "</ul>")
    for k, block in ex.items():
        if not isinstance(block, dict):
            continue
        rows = [(name, v) for name, v in block.items()]
        if all(isinstance(v, dict) for _, v in rows):
            cols = list(dict.fromkeys(c for _, v in rows for c in v))
            h.append(table([k.rstrip("s")] + cols,
                           [[name] + [shown(v.get(c)) for c in cols] for name, v in rows]))
        else:
            h.append(table([k, "value"], [[n, shown(v)] for n, v in rows]))
    return "".join(h)


def compare_section(compares):
    """compares: [(output, png or None, caption)]."""
    h = ["<h2 id='compare'>Measured against the model and ARX</h2>"]
    for output, png, caption in compares:
        if png:
            h.append(f"<figure><img src='{esc(png)}' alt='{esc(output)}: measured, the model and ARX'>"
                     f"<figcaption>{esc(caption)}</figcaption></figure>")
        else:
            h.append(f"<p class='note'>{esc(output)}: {esc(caption)}</p>")
    return "".join(h)


def dynamics_table(block):
    """Each rule of the full model: stability, slowest time constant, damping, steady-state gains."""
    local = block.get("local_models") or []
    if not local:
        return ""
    seconds = all("time_constants_s" in m for m in local)
    tau_key = "time_constants_s" if seconds else "time_constants_samples"
    inputs = list(dict.fromkeys(u for m in local for u in (m.get("dc_gain") or {})))
    head = ["rule", "stable", f"slowest τ ({'s' if seconds else 'samples'})", "least damping"] + \
        [f"gain from {u}" for u in inputs] + ["equilibrium"]
    rows = []
    for j, m in enumerate(local, 1):
        taus, damping = m.get(tau_key) or [], m.get("damping") or []
        rows.append([str(j), shown(m.get("stable")), shown(max(taus)) if taus else "–",
                     shown(min(damping)) if damping else "–"] +
                    [shown((m.get("dc_gain") or {}).get(u)) for u in inputs] + [shown(m.get("equilibrium"))])
    g = block.get("global_linear")
    if isinstance(g, dict):
        rows.append(["global linear model", shown(g.get("stable")), "–", "–"] +
                    [shown((g.get("dc_gain") or {}).get(u)) for u in inputs] + [shown(g.get("equilibrium"))])
    unit = "seconds" if seconds else "samples (the data's rate is unknown: give --time or --rate)"
    return (f"<p>Each rule of the full model on its own, time constants in {esc(unit)}:</p>"
            + table(head, rows))


def rules_section(report, verdicts):
    h = ["<h2 id='rules'>Rules</h2>"]
    several = len(verdicts) > 1
    for (output, block), v in zip(fit_verdict.outputs(report), verdicts):
        if several:
            h.append(f"<h3>{esc(output)}</h3>")
        rd = block.get("readable") or {}
        full = block.get("rule_text") or []
        if rd.get("text"):
            score = ((block.get("baselines") or {}).get("readable") or {}).get(v["set"], {}).get(v["mode"])
            n = rd.get("rules")
            h.append(f"<p>The readable form: {esc(n)} rule{'' if n == 1 else 's'} "
                     f"of the model's {esc(len(full))}; {esc(MODE_NAMES[v['mode']])} FIT "
                     f"{esc(fit_verdict.percent(score))} against the model's {esc(v['fit'])} "
                     f"({'validation' if v['set'] == 'validate' else 'training'} file).</p>")
            h.append("<ul class='rules'>" + "".join(f"<li>{esc(t)}</li>" for t in rd["text"]) + "</ul>")
        h.append(dynamics_table(block))
        if full:
            items = "<ol class='rules'>" + "".join(f"<li>{esc(t)}</li>" for t in full) + "</ol>"
            # Beside a readable form the full rules fold away; without one they are the rules.
            h.append(f"<details><summary>Every rule of the full model ({len(full)})</summary>"
                     f"{items}</details>" if rd.get("text") else items)
    return "".join(h)


def pictures_section(present, notes):
    """present: the picture files that exist; notes: fit_plots.py's {picture: statement}."""
    h = ["<h2 id='pictures'>Pictures of the model</h2>"]
    for name, what in PICTURES:
        note = notes.get(name)
        if name in present:
            said = f"{what}" + (f" — {note}" if note else "")
            h.append(f"<figure><img src='{esc(name)}' alt='{esc(what)}'><figcaption>{esc(said)}"
                     "</figcaption></figure>")
        elif note:
            h.append(f"<p class='note'>{esc(name[:-4].replace('_', ' '))}: {esc(note)}</p>")
    return "".join(h) if len(h) > 1 else ""


# The data's keys, in the order and words the page uses; any other key follows under its own name.
DATA_KEYS = (("rows", "rows read"), ("samples", "samples used"), ("segments", "segments"),
             ("rate_hz", "rate (Hz)"), ("bridged", "missing values bridged"),
             ("missing", "samples dropped in longer gaps"), ("dropped_segments", "segments dropped"),
             ("window_s", "window (s)"), ("outside_window", "samples outside the window"),
             ("keep_when", "kept when"), ("cut_by_condition", "samples cut by the condition"),
             ("time_column", "time column"), ("time_unit_s", "its unit (s)"), ("first_s", "first time (s)"),
             ("last_s", "last time (s)"), ("signal_rates_hz", "each signal's rate (Hz)"),
             ("rate_from", "rate taken from (the slowest signal)"))


def data_section(report, roles):
    """Each file the fit read, a column each; roles: {path: 'training', …} from the command."""
    data = {k: v for k, v in (report.get("data") or {}).items() if isinstance(v, dict)}
    if not data:
        return ""
    files = list(data)
    known = [k for k, _ in DATA_KEYS]
    rest = list(dict.fromkeys(k for f in files for k in data[f] if k not in known and k != "file"))
    rows = [[word] + [shown(data[f].get(k)) for f in files] for k, word in DATA_KEYS
            if any(k in data[f] for f in files)]
    rows += [[k] + [shown(data[f].get(k)) for f in files] for k in rest]
    head = [""] + [f"{roles[f]}: {f}" if f in roles else f for f in files]
    return "<h2 id='data'>Data</h2>" + table(head, rows)


def command_section(command):
    if not command:
        return "<h2 id='command'>Command</h2><p>No command.txt beside the report.</p>"
    return ("<h2 id='command'>The command that made this page</h2>"
            f"<pre class='command'>{esc(command)}</pre>")


def page(report, verdicts, compares, present, notes, roles, command):
    name = title(report)
    return "\n".join([
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<title>{esc(name)}</title><style>{STYLE}</style></head><body>",
        f"<h1>{esc(name)}</h1>",
        verdict_section(report, verdicts),
        warnings_section(report),
        excitation_section(report),
        compare_section(compares),
        rules_section(report, verdicts),
        pictures_section(present, notes),
        data_section(report, roles),
        command_section(command),
        "</body></html>"])
