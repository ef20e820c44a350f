#!/usr/bin/python3
"""Writes the page of one odonata-fit run into DIR, from what `odonata-fit --report DIR` left there
(report.json, predictions.csv, command.txt and the pictures of --plot):

  index.html   the verdict first (the model's FIT beside ARX and persistence, in the mode the fit
               is scored by), the warnings and the training data's excitation, the compare plot,
               the readable rules with time constants and gains, the pictures, the data, the
               command that made it; one file that needs only the PNGs beside it
  compare.png  measured against the model and ARX in that mode, on the validation file (the
               training file without one), FIT in the legend; compare_OUTPUT.png for each further
               output

    fit_report.py DIR

It reads only DIR: run again, it draws the page again.
"""
import json
import os
import re
import shlex
import sys

# The helpers sit beside this script, in the source tree's deploy/ and in share/odonata/python.
sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import odonata_compare  # noqa: E402
from odonata_report import fit_page, fit_verdict  # noqa: E402

ROLES = {"--train": "training", "--validate": "validation", "--select": "selection", "--track": "tracking"}


def file_roles(command):
    """{path: 'training', …} from the command's --train/--validate/--select/--track."""
    roles = {}
    try:
        words = shlex.split(command)
    except ValueError:
        return roles
    for k, w in enumerate(words):
        flag, _, value = w.partition("=")
        if flag in ROLES:
            path = value or (words[k + 1] if k + 1 < len(words) else "")
            roles[path] = ROLES[flag]
    return roles


def draw_compares(d, report, verdicts):
    """compare.png per output: [(output, file name or None, caption)]."""
    pred_path = os.path.join(d, "predictions.csv")
    if not os.path.exists(pred_path):
        return [(v["output"], None, "no predictions.csv to draw") for v in verdicts]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return [(v["output"], None, "no compare plot: matplotlib is missing "
                 "(apt-get install python3-matplotlib)") for v in verdicts]
    pred = odonata_compare.read_predictions(pred_path)
    out = []
    for k, ((output, block), v) in enumerate(zip(fit_verdict.outputs(report), verdicts)):
        name = "compare.png" if k == 0 else f"compare_{re.sub(r'[^A-Za-z0-9_.-]', '_', output)}.png"
        data, mode = v["set"], v["mode"]
        # The legend says what the verdict says: the same FIT, or "diverges" by the same rule.
        labels = {(data, "fuzzy", mode): fit_verdict.legend((block.get(data) or {}).get(mode)),
                  (data, "arx", mode): fit_verdict.legend(
                      ((block.get("baselines") or {}).get("arx") or {}).get(data, {}).get(mode))}
        horizon = (block.get(data) or {}).get("k_step", {}).get("horizon", 0)
        odonata_compare.draw(plt, pred, report, output, len(verdicts) > 1, horizon, os.path.join(d, name),
                             only_modes=[mode], only_sets=[1 if data == "validate" else 0], labels=labels)
        file = "validation file" if data == "validate" else "training file (no validation file given)"
        out.append((output, name, f"{output}: the {file}, {v['where']}, and its fastest-moving stretch"))
    return out


def read_text(path):
    try:
        with open(path) as f:
            return f.read().strip()
    except OSError:
        return ""


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    d = argv[1]
    try:
        with open(os.path.join(d, "report.json")) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        print(f"fit_report.py: {d}: no report.json to read ({e})", file=sys.stderr)
        return 1
    verdicts = [fit_verdict.verdict(report, o, b) for o, b in fit_verdict.outputs(report)]
    compares = draw_compares(d, report, verdicts)
    notes_text = read_text(os.path.join(d, "plot_notes.json"))
    notes = json.loads(notes_text) if notes_text else {}
    present = {name for name, _ in fit_page.PICTURES if os.path.exists(os.path.join(d, name))}
    command = read_text(os.path.join(d, "command.txt"))
    html = fit_page.page(report, verdicts, compares, present, notes, file_roles(command), command)
    page = os.path.join(d, "index.html")
    with open(page, "w") as f:
        f.write(html)
    for _, png, caption in compares:
        if not png:
            print(f"fit_report.py: {caption}", file=sys.stderr)
    print(page)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
