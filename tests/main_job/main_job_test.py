#!/usr/bin/python3
"""A short version of the main job (4 s per phase, every experiment): the report is produced,
accuracy stays above a floor, and the numbers in index.html and summary.md equal summary.json's."""
import html
import html.parser
import json
import os
import re
import subprocess
import sys
import tempfile

SRC, BUILD = os.environ["ODONATA_SOURCE"], os.environ["ODONATA_BUILD"]
sys.path.insert(0, os.path.join(SRC, "deploy"))
import odonata_report  # noqa: E402

FLOOR = {"roll": 85, "pitch": 85, "yaw": 85}  # validation one-step FIT %, short runs
DEFAULT_FLOOR = 60


class Cells(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.rows, self._key = [], None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr":
            self.rows.append({})
        if tag == "td" and "data-key" in a:
            self._key = a["data-key"]

    def handle_data(self, data):
        if self._key:
            self.rows[-1][self._key] = self.rows[-1].get(self._key, "") + data

    def handle_endtag(self, tag):
        if tag == "td":
            self._key = None


# Says, once the page has loaded, where the first experiment's verdict and plot lie.
WHERE = """<script>window.addEventListener('load', () => {
  const v = document.querySelector('.verdict').getBoundingClientRect();
  const i = document.querySelector('h2 ~ img').getBoundingClientRect();
  document.body.setAttribute('data-first-screen', JSON.stringify(
      {verdict_bottom: v.bottom, plot_top: i.top, height: innerHeight}));
});</script>"""


def first_screen(out):
    """The report read in Chromium at 1400 px and at phone width: the first screen holds the first
    verdict and the top of its plot (issue 49 point 5). Screenshots are written beside it."""
    failures = []
    page = open(os.path.join(out, "index.html")).read().replace("</body>", WHERE + "</body>")
    probe = os.path.join(out, "probe.html")
    with open(probe, "w") as f:
        f.write(page)
    for width, height in ((1400, 900), (400, 800)):
        common = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                  f"--window-size={width},{height}"]
        r = subprocess.run(common + ["--virtual-time-budget=5000", "--dump-dom", "file://" + probe],
                           capture_output=True, text=True, timeout=120)
        found = re.search(r'data-first-screen="([^"]*)"', r.stdout)
        if not found:
            failures.append(f"{width} px: Chromium gave no layout ({r.stderr.strip()[-300:]})")
            continue
        where = json.loads(html.unescape(found.group(1)))
        if not (where["verdict_bottom"] <= where["height"] and where["plot_top"] < where["height"]):
            failures.append(f"{width} px: the first verdict or plot is below the first screen: {where}")
        shot = os.path.join(out, f"report-{width}px.png")
        subprocess.run(common + [f"--screenshot={shot}", "file://" + probe], capture_output=True,
                       timeout=120)
        if not os.path.exists(shot) or os.path.getsize(shot) < 10000:
            failures.append(f"{width} px: no screenshot")
    return failures


def main():
    failures = []
    with tempfile.TemporaryDirectory() as out:
        r = subprocess.run([os.path.join(SRC, "deploy/run-experiments"), "--out", out, "--build", BUILD,
                            "--duration", "4", "--experiments", "actuator_fz,actuator_fx,vertical_velocity,roll,pitch,yaw"],
                           capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            print(r.stdout, r.stderr)
            sys.exit("FAIL: the main job failed")
        summary = json.load(open(os.path.join(out, "summary.json")))
        names = [e["experiment"] for e in summary["experiments"]]
        if names != ["actuator_fz", "actuator_fx", "vertical_velocity", "roll", "pitch", "yaw"]:
            failures.append(f"experiments {names}")
        for e in summary["experiments"]:
            n = e["experiment"]
            fit = e["validate"]["one_step"]["fit"]
            if fit is None or fit < FLOOR.get(n, DEFAULT_FLOOR):
                failures.append(f"{n}: validation FIT {fit} below the floor")
            if e["rules"] < 1 or not e["rule_text"]:
                failures.append(f"{n}: no rules")
            # odonata-fit --plot's pictures (issue 49 point 4): the readable terms and which rule
            # fires when, on the page and on disk.
            html_page = open(os.path.join(out, "index.html")).read()
            for kind in ("terms", "activation"):
                png = f"{n}-{kind}.png"
                if not os.path.exists(os.path.join(out, png)) or f"src='{png}'" not in html_page:
                    failures.append(f"{n}: no {kind} picture in the report")
            if not any(os.path.exists(os.path.join(out, f"{n}-{k}.png")) for k in ("gain_schedule", "surface")):
                # one rule has no schedule to draw: only a model of several rules must have one
                if e["rules"] > 1 and e.get("consequent", "linear") == "linear":
                    failures.append(f"{n}: neither a gain schedule nor a surface")
            live = e["validate_live"]["one_step"]["fit"]
            if abs(live - fit) > 1e-6:
                failures.append(f"{n}: live pipeline FIT {live} != frozen-model FIT {fit}")
            for plot in ("output", "learning", "parameters", "membership", "sweep"):
                if not os.path.getsize(os.path.join(out, f"{n}-{plot}.png")):
                    failures.append(f"{n}: empty {plot} plot")
        expected = odonata_report.table_rows(summary)
        parser = Cells()
        parser.feed(open(os.path.join(out, "index.html")).read())
        shown = [row for row in parser.rows if row]
        if shown != expected:
            failures.append(f"index.html table differs from summary.json:\n{shown}\n{expected}")
        md = open(os.path.join(out, "summary.md")).read()
        for row in expected:
            line = "| " + " | ".join(row[k] for k, _ in odonata_report.COLUMNS) + " |"
            if line not in md:
                failures.append(f"summary.md lacks the row {line}")
        # Spot-check the formatting itself against the raw JSON numbers.
        for row, e in zip(expected, summary["experiments"]):
            if row["val_fit"] != f"{e['validate']['one_step']['fit']:.2f}":
                failures.append(f"{e['experiment']}: table FIT {row['val_fit']} vs JSON {e['validate']['one_step']['fit']}")
            if row["rules"] != str(e["rules"]):
                failures.append(f"{e['experiment']}: table rules {row['rules']} vs JSON {e['rules']}")
            # The readable form (odonata-fit --rules) is in the report, with its score.
            rd = e.get("readable")
            if not rd or not rd["text"] or rd["validate_one_step_fit"] is None:
                failures.append(f"{e['experiment']}: no readable form with a score")
        failures += first_screen(out)
    if failures:
        print("\n".join("FAIL: " + f for f in failures))
        sys.exit(1)
    print(f"PASS: main job report for {len(names)} experiments; numbers consistent")


if __name__ == "__main__":
    main()
