#!/usr/bin/env python3
"""How right odonata-fit's time-left estimate is (issue 59 point 4).

Runs odonata-fit with its stderr on a pseudo-terminal (so it draws its progress bar), stamps
every redraw, and compares each "~N s left" with the time the fit actually still took. Prints the
worst ratio either way (estimate / actual or actual / estimate) over the redraws with at least
--min-left seconds still to go; 2.0 is issue 59's bound.

  bench/fit/progress_estimate.py -- --train examples/narendra/train.csv \\
      --validate examples/narendra/validate.csv --output y --input u
"""
import argparse
import os
import pty
import re
import subprocess
import sys
import time

LEFT = re.compile(r"~(\d+) (s|min) left")


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fit", default=os.path.join(root, "build", "bin", "odonata-fit"))
    ap.add_argument("--min-left", type=float, default=2.0,
                    help="judge only redraws with at least this many seconds still to go")
    ap.add_argument("--all", action="store_true", help="print every judged estimate, not eight")
    ap.add_argument("args", nargs=argparse.REMAINDER, help="odonata-fit's arguments, after --")
    a = ap.parse_args()
    args = a.args[1:] if a.args[:1] == ["--"] else a.args
    if not args:
        ap.error("give odonata-fit's arguments after --")
    master, slave = pty.openpty()
    env = dict(os.environ)  # the bar stays quiet for its first 2 s, as users see it
    start = time.monotonic()
    proc = subprocess.Popen([a.fit] + args, stdout=subprocess.DEVNULL, stderr=slave, env=env)
    os.close(slave)
    stamps, buf = [], b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        now = time.monotonic() - start
        buf += chunk
        *parts, buf = buf.split(b"\r")
        for p in parts:
            m = LEFT.search(p.decode("utf-8", "replace"))
            if m:
                left = float(m.group(1)) * (60 if m.group(2) == "min" else 1)
                stamps.append((now, left, p.decode("utf-8", "replace").strip()[:40]))
    rc = proc.wait()
    end = time.monotonic() - start
    if rc != 0:
        sys.exit(f"odonata-fit exited {rc}")
    judged = [(t, left, end - t, label) for t, left, label in stamps if end - t >= a.min_left]
    print(f"fit took {end:.1f} s; {len(stamps)} estimates, {len(judged)} with "
          f">= {a.min_left:g} s to go")
    worst = None
    for t, left, actual, label in judged:
        ratio = max(left / actual, actual / left) if left > 0 else float("inf")
        if worst is None or ratio > worst[0]:
            worst = (ratio, t, left, actual, label)
    if worst:
        r, t, left, actual, label = worst
        print(f"worst: x{r:.2f} at {t:.1f} s ('{label}'): said ~{left:.0f} s, took {actual:.1f} s")
    step = 1 if a.all else max(1, len(judged) // 8)
    for t, left, actual, label in judged[::step]:
        print(f"  {t:6.1f} s  said {left:5.0f} s  took {actual:6.1f} s  {label}")


if __name__ == "__main__":
    main()
