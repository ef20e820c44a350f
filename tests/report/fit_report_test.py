#!/usr/bin/python3
"""odonata-fit --report DIR (deploy/fit_report.py): the page for a user's own fit. On the Narendra
example and on a linear plant (one rule, and two rules whose local models coincide), the page
opens with the verdict, whose figures are report.json's, shows the command that made it and only
pictures that exist, reads at 1400 px and at phone width without scrolling sideways, and a model of
one rule is stated as "linear: one rule", not drawn as flat lines or a surface of round-off."""
import html
import html.parser
import json
import math
import os
import random
import re
import shlex
import subprocess
import sys
import tempfile

SRC, BUILD = os.environ["ODONATA_SOURCE"], os.environ["ODONATA_BUILD"]
FIT = os.path.join(BUILD, "bin", "odonata-fit")
NARENDRA = ["--train", "examples/narendra/train.csv", "--validate", "examples/narendra/validate.csv",
            "--output", "y", "--input", "u", "--no-select", "--epochs", "2"]
SCREENS = ((1400, 900), (400, 800))

# Says, once the page has loaded, where the verdicts end, how wide the page is, and which
# pictures did not load: to the frame around it (below).
PROBE = """<script>window.addEventListener('load', () => {
  const bottoms = [...document.querySelectorAll('.verdict')].map(e => e.getBoundingClientRect().bottom);
  const broken = [...document.images].filter(i => !i.complete || i.naturalWidth === 0)
                                      .map(i => i.getAttribute('src'));
  parent.postMessage(JSON.stringify({verdicts: bottoms.length, verdict_bottom: Math.max(...bottoms),
      height: innerHeight, width: innerWidth, scroll_width: document.documentElement.scrollWidth,
      broken: broken}), '*');
});</script>"""
# Headless Chromium lays a window narrower than 500 px out at 500 px (its screenshots are cut to
# the size asked for): the page is read in a frame of the screen's exact size instead, which is
# its viewport, media queries included, and the frame's answer lands on the outer page's body.
FRAME = """<html><body style="margin:0"><iframe src="probe.html" style="width:{w}px;height:{h}px;border:0">
</iframe><script>addEventListener('message', e => document.body.setAttribute('data-layout', e.data));
</script></body></html>"""


class Page(html.parser.HTMLParser):
    """The verdict paragraphs (attributes and text), the pictures and the command of index.html."""

    def __init__(self):
        super().__init__()
        self.verdicts, self.images, self.command, self._in = [], [], "", None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "p" and a.get("class") == "verdict":
            self.verdicts.append(dict(a, text=""))
            self._in = "verdict"
        elif tag == "pre" and a.get("class") == "command":
            self._in = "command"
        elif tag == "img":
            self.images.append(a["src"])

    def handle_data(self, data):
        if self._in == "verdict":
            self.verdicts[-1]["text"] += data
        elif self._in == "command":
            self.command += data

    def handle_endtag(self, tag):
        if tag in ("p", "pre"):
            self._in = None


def linear_plant(path, seed, n=3000):
    """y(k+1) = 0.9 y(k) + 0.5 u(k), u a random staircase, 50 Hz with a time column: one rule
    explains it, and time constants come out in seconds (τ = 0.19 s)."""
    rng = random.Random(seed)
    y = u = 0.0
    with open(path, "w") as f:
        f.write("t_s,u,y\n")
        for k in range(n):
            if k % 25 == 0:
                u = rng.uniform(-1, 1)
            f.write(f"{0.02 * k:.3f},{u:.6f},{y + 0.01 * rng.gauss(0, 1):.6f}\n")
            y = 0.9 * y + 0.5 * u


def expected_verdict(report):
    """(set, mode, {model, arx, persistence: FIT or None where it diverges or is absent}) as the
    report gives them for its first output."""
    data = "validate" if report.get("validate") else "train"
    mode = next((m for m in ("k_step", "free_run") if m in report[data]), "one_step")
    base = report["baselines"]
    blocks = {"fit": report[data][mode], "arx": base["arx"][data].get(mode),
              "persistence": base["persistence"][data].get(mode)}
    return data, mode, blocks


def check_figure(name, block, shown):
    """The page's figure equals the report's to its two decimals, or says diverges / –."""
    if block is None:
        return [] if shown == "–" else [f"{name}: '{shown}' where the report has no score"]
    f = block.get("fit")
    diverged = block.get("diverged") or f is None or not math.isfinite(f) or abs(f) > 1e6
    if diverged:
        return [] if shown == "diverges" else [f"{name}: '{shown}', the report's {f} diverges"]
    m = re.fullmatch(r"(-?[0-9]+\.[0-9]{2}) %", shown)
    if not m or abs(float(m.group(1)) - f) > 0.0051:
        return [f"{name}: the page says '{shown}', report.json {f}"]
    return []


def check_page(case, out, args):
    failures = []
    report = json.load(open(os.path.join(out, "report.json")))
    text = open(os.path.join(out, "index.html")).read()
    page = Page()
    page.feed(text)
    data, mode, blocks = expected_verdict(report)
    if not page.verdicts:
        return [f"{case}: no verdict on the page"]
    v = page.verdicts[0]
    if (v.get("data-set"), v.get("data-mode")) != (data, mode):
        failures.append(f"{case}: verdict on {v.get('data-set')} {v.get('data-mode')}, expected {data} {mode}")
    for key, block in blocks.items():
        shown = v.get(f"data-{key}", "")
        failures += [f"{case}: {f}" for f in check_figure(key, block, shown)]
        if shown not in v["text"]:
            failures.append(f"{case}: the verdict's text lacks {key} '{shown}': {v['text']}")
    if "ARX" not in v["text"] or "persistence" not in v["text"]:
        failures.append(f"{case}: the verdict names neither ARX nor persistence: {v['text']}")
    # The command, one line, exactly what ran; on the page as written.
    command = open(os.path.join(out, "command.txt")).read()
    if command.count("\n") != 1 or shlex.split(command)[1:] != args:
        failures.append(f"{case}: command.txt is {command!r}, ran {args}")
    if page.command.strip() != command.strip():
        failures.append(f"{case}: the page's command {page.command!r} is not command.txt's")
    for src in page.images:
        if not os.path.isfile(os.path.join(out, html.unescape(src))):
            failures.append(f"{case}: the page shows {src}, which is not in {out}")
    if "compare.png" not in page.images:
        failures.append(f"{case}: no compare plot on the page")
    for w in report.get("warnings", []):
        if html.escape(w) not in text:
            failures.append(f"{case}: the warning '{w}' is not on the page")
    return failures + screens(case, out, text)


def screens(case, out, text):
    """The page in Chromium at 1400 px and at phone width: every verdict on the first screen, no
    sideways scrolling, every picture loaded; a screenshot of each."""
    failures = []
    probe = os.path.join(out, "probe.html")
    with open(probe, "w") as f:
        f.write(text.replace("</body>", PROBE + "</body>"))
    for width, height in SCREENS:
        frame = os.path.join(out, f"frame-{width}px.html")
        with open(frame, "w") as f:
            f.write(FRAME.format(w=width, h=height))
        common = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                  f"--window-size={width},{height}"]
        r = subprocess.run(common + ["--virtual-time-budget=5000", "--dump-dom", "file://" + frame],
                           capture_output=True, text=True, timeout=120)
        found = re.search(r'data-layout="([^"]*)"', r.stdout)
        if not found:
            failures.append(f"{case} {width} px: Chromium gave no layout ({r.stderr.strip()[-300:]})")
            continue
        at = json.loads(html.unescape(found.group(1)))
        if not at["verdicts"] or at["verdict_bottom"] > at["height"]:
            failures.append(f"{case} {width} px: the verdict is not on the first screen: {at}")
        if at["scroll_width"] > at["width"]:
            failures.append(f"{case} {width} px: the page scrolls sideways: {at}")
        if at["broken"]:
            failures.append(f"{case} {width} px: pictures that do not load: {at['broken']}")
        shot = os.path.join(out, f"page-{width}px.png")
        subprocess.run(common + [f"--screenshot={shot}", "file://" + os.path.join(out, "index.html")],
                       capture_output=True, timeout=120)
        if not os.path.exists(shot) or os.path.getsize(shot) < 10000:
            failures.append(f"{case} {width} px: no screenshot")
    return failures


def check_one_rule(case, out, seconds, roundoff):
    """One rule (or rules that read as one) is said in words: the membership picture states
    "linear: one rule"; no gain schedule or surface is drawn from round-off."""
    failures = []
    notes = json.load(open(os.path.join(out, "plot_notes.json")))
    text = open(os.path.join(out, "index.html")).read()
    if notes.get("membership.png") != "linear: one rule":
        failures.append(f"{case}: the membership picture does not state 'linear: one rule': {notes}")
    if not re.search(r"<img src='membership.png'[^>]*><figcaption>[^<]*linear: one rule</figcaption>", text):
        failures.append(f"{case}: the page does not say the membership picture is 'linear: one rule'")
    surface = os.path.join(out, "gain_surface.csv")
    if roundoff and not os.path.exists(surface):
        failures.append(f"{case}: odonata-fit wrote no gain surface: the round-off case is not tested")
    if os.path.exists(surface):
        gains = [float(r.split(",")[2]) for r in open(surface).read().split("\n")[1:] if r]
        if max(gains) - min(gains) > 1e-9 * max(abs(g) for g in gains):
            failures.append(f"{case}: the gain varies over the surface: not the round-off case")
        if not notes.get("gain_surface.png", "").startswith("constant gain"):
            failures.append(f"{case}: no 'constant gain' said for the surface: {notes}")
    for picture in ("gain_surface.png", "gain_schedule.png"):
        if os.path.exists(os.path.join(out, picture)):
            failures.append(f"{case}: {picture} drawn for a model that reads as one rule")
    if seconds and "slowest τ (s)" not in text:
        failures.append(f"{case}: time constants not in seconds though the data's rate is known")
    return failures


def check_diverges():
    """The page's "diverges": flagged by odonata-fit, null, not finite, or a FIT of size > 1e6;
    "–" where there is no such score."""
    sys.path.insert(0, os.path.join(SRC, "deploy"))
    from odonata_report import fit_verdict
    said = {97.234: "97.23 %", -0.001: "0.00 %", -999.0: "-999.00 %", -3.4e24: "diverges",
            float("nan"): "diverges", float("inf"): "diverges", None: "diverges"}
    failures = [f"FIT {f} printed '{fit_verdict.percent({'fit': f})}', not '{w}'"
                for f, w in said.items() if fit_verdict.percent({"fit": f}) != w]
    if fit_verdict.percent({"fit": 12.0, "diverged": True}) != "diverges" or fit_verdict.percent(None) != "–":
        failures.append("a flagged divergence or a missing score is misprinted")
    return failures


def fit(case, out, args):
    """odonata-fit ARGS --report OUT, with this tree's scripts; its arguments as run."""
    args = args + ["--report", out]
    env = dict(os.environ, ODONATA_PYTHON_DIR=os.path.join(SRC, "deploy"))
    r = subprocess.run([FIT, *args], cwd=SRC, env=env, capture_output=True, text=True, timeout=120)
    if r.returncode != 0 or not os.path.exists(os.path.join(out, "index.html")):
        print(r.stdout[-2000:], r.stderr[-2000:])
        sys.exit(f"FAIL: {case}: odonata-fit --report failed ({r.returncode}) or wrote no index.html")
    return args


def main():
    failures = check_diverges()
    with tempfile.TemporaryDirectory(prefix="fit-report-") as tmp:
        train, validate = os.path.join(tmp, "train.csv"), os.path.join(tmp, "validate.csv")
        linear_plant(train, 1)
        linear_plant(validate, 2)
        plant = ["--train", train, "--validate", validate, "--time", "t_s", "--output", "y", "--input", "u",
                 "--no-select", "--epochs", "2"]
        cases = (("narendra", NARENDRA, False),
                 ("one rule", plant + ["--max-rules", "1"], True),
                 # A ridge this strong pulls every rule onto ARX: two rules, one local model,
                 # whose gain differs across the surface by round-off alone.
                 ("rules that coincide", plant + ["--deviation-ridge", "1e9"], True))
        for k, (case, args, linear) in enumerate(cases):
            out = os.path.join(tmp, f"report{k}")
            ran = fit(case, out, args)
            failures += check_page(case, out, ran)
            if linear:
                failures += check_one_rule(case, out, seconds=True, roundoff=case == "rules that coincide")
            elif "slowest τ (samples)" not in open(os.path.join(out, "index.html")).read():
                failures.append(f"{case}: time constants not in samples though the data has no rate")
    if failures:
        print("\n".join("FAIL: " + f for f in failures))
        sys.exit(1)
    print(f"PASS: odonata-fit --report for {len(cases)} fits: the verdict first with report.json's "
          "figures, the command, pictures that exist, 1400 px and 400 px without sideways scrolling, "
          "one rule said as 'linear: one rule'")


if __name__ == "__main__":
    main()
