#!/usr/bin/python3
"""odonata-fit's time and peak memory against the record's length (issue 22).

A Narendra-type plant, y(k+1) = y(k)/(1+y(k)^2) + u(k)^3, driven by a random input held for 1-10
samples (so it has both fast and slow stretches), one input and one output; odonata-fit's defaults
on 1k, 10k, 100k and 360k training rows (an hour at 100 Hz), scored on a separate 5 000-row
record. Prints a Markdown table (rows, wall time, peak memory, rules, validation FIT % one-step /
free run) and, with --plot, draws time and memory against rows on log-log axes.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time


def write_record(path, rows, seed):
    rng = random.Random(seed)
    u = []
    while len(u) < rows:
        u.extend([rng.uniform(-2, 2)] * rng.randint(1, 10))
    u = u[:rows]
    y = 0.0
    with open(path, "w") as f:
        f.write("u,y\n")
        for k in range(rows):
            f.write(f"{u[k]:.10g},{y:.10g}\n")
            y = y / (1 + y * y) + u[k] ** 3


def run(cmd):
    """Wall time and peak resident memory (MB) of one child process."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdout=out, stderr=err, text=True)
        # wait4: this child's own peak memory (getrusage would give the largest child so far).
        _, status, usage = os.wait4(p.pid, 0)
        secs = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return secs, usage.ru_maxrss / 1024.0, p.returncode, out.read(), err.read()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--fit", default=os.path.join(root, "build", "services", "fit", "odonata-fit"))
    ap.add_argument("--rows", type=int, nargs="+", default=[1000, 10000, 100000, 360000])
    ap.add_argument("--plot", help="write a log-log plot of time and memory to this PNG")
    ap.add_argument("--json", help="also write the figures to this file")
    ap.add_argument("extra", nargs="*", help="more odonata-fit options (after --)")
    args = ap.parse_args()
    if not os.access(args.fit, os.X_OK):
        sys.exit(f"fit_scaling: {args.fit} is not built (cmake --build build)")
    results = []
    with tempfile.TemporaryDirectory(prefix="odonata-fit-scaling-") as tmp:
        validate = os.path.join(tmp, "validate.csv")
        write_record(validate, 5000, seed=2)
        print("| training rows | time | peak memory | rules | validation FIT % one-step / free run |")
        print("|---|---|---|---|---|")
        for rows in args.rows:
            train = os.path.join(tmp, f"train_{rows}.csv")
            write_record(train, rows, seed=1)
            print(f"{rows} rows …", file=sys.stderr, flush=True)
            secs, mb, rc, out, err = run([args.fit, "--train", train, "--validate", validate,
                                          "--input", "u", "--output", "y", "--json", *args.extra])
            os.remove(train)
            if rc != 0:
                sys.exit(f"fit_scaling: odonata-fit failed on {rows} rows: {err.strip()}")
            j = json.loads(out)
            v = j["validate"]
            r = {"rows": rows, "seconds": secs, "peak_mb": mb, "rules": j["rules"],
                 "one_step_fit": v["one_step"]["fit"], "free_run_fit": v["free_run"]["fit"],
                 "searched_rows": j.get("selection", {}).get("searched_rows")}
            results.append(r)
            print(f"| {rows:,} | {secs:.1f} s | {mb:.0f} MB | {r['rules']} | "
                  f"{r['one_step_fit']:.2f} / {r['free_run_fit']:.2f} |", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rows = [r["rows"] for r in results]
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        ax.loglog(rows, [r["seconds"] for r in results], "o-", label="time (s)")
        ax.loglog(rows, [r["peak_mb"] for r in results], "s-", label="peak memory (MB)")
        # Linear cost through the largest record, for reference.
        ref = results[-1]["seconds"]
        ax.loglog(rows, [ref * n / rows[-1] for n in rows], ":", color="grey",
                  label="linear in rows")
        ax.set_xlabel("training rows")
        ax.set_title("odonata-fit defaults, 1 input, 1 output, 2 cores")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print(f"plot: {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
