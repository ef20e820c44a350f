#!/usr/bin/python3
"""One line of run_fleet_bench.sh's table from the producers' outputs on stdin.

Usage: fleet_summary.py LAYOUT N IDENTIFIER_CPU_TICKS TICKS_PER_S WALL_S
"""
import math
import re
import statistics
import sys

layout, n = sys.argv[1], int(sys.argv[2])
ticks, hz, secs = int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
runs = [tuple(float(x) for x in m.groups()) for m in re.finditer(
    r"paced \S+ Hz: (\d+) of (\d+) predictions .*?p50 ([\d.]+) us, p99 ([\d.]+) us", sys.stdin.read())]
got = sum(r[0] for r in runs)
want = n * (runs[0][1] if runs else 0)
p50 = [r[2] for r in runs]
p99 = [r[3] for r in runs]


def med(v):
    return statistics.median(v) if v else math.nan


line = (f"{layout:8} N={n:<3d} dropped {int(want - got):6d} of {int(want):7d}"
        f"  latency p50 {med(p50):7.0f} us (worst {max(p50, default=math.nan):7.0f})"
        f"  p99 {med(p99):8.0f} us (worst {max(p99, default=math.nan):8.0f})"
        f"  identifier CPU {100 * ticks / hz / secs / n:5.2f} % of a core per vehicle")
if len(runs) < n:
    line += f"  ({n - len(runs)} producers reported nothing: counted as all dropped)"
print(line)
