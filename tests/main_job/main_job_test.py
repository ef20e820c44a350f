#!/usr/bin/python3
"""A short version of the main job (4 s per phase, every experiment): the report is produced,
accuracy stays above a floor, and the numbers in index.html and summary.md equal summary.json's."""
import html.parser
import json
import os
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
    if failures:
        print("\n".join("FAIL: " + f for f in failures))
        sys.exit(1)
    print(f"PASS: main job report for {len(names)} experiments; numbers consistent")


if __name__ == "__main__":
    main()
