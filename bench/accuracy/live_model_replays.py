#!/usr/bin/python3
"""The online identifier's *live* model on measured training files: what a user has mid-run.

Each replay pushes part of a training file through the identifier's learner with its default
refits (odonata-fit --refit-*, the same class) and stops without a freeze (--replay-unfrozen: no
closing refit, the refit in flight never lands), then scores that model on rows of the training
files the replay did not see. Only training files are read (docs/identifier.md §6.3: the
steady-state refits' check was decided on these replays); the test files play no part. With
--frozen each replay also runs with the closing refit, as a frozen identifier ends.

The records are read where they are (default ../shared/realdata from the project's root); the
parts are written to a temporary directory, never into the repository. A missing record is
skipped with a message.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

from real_records import ONLINE, fit_command  # the identifier's defaults, one command

# name, training file, rows replayed [from, to), scored on (file, rows [from, to)), output,
# inputs, ny, nu, horizon (0: free run)
SILVERBOX = "silverbox_train.csv"
REPLAYS = [(f"Silverbox 0–{cut}", SILVERBOX, (0, cut), (SILVERBOX, (52000, None)), "y", ["u"], 3, 3, 0)
           for cut in (14000, 23000, 35000, 41000, 47000, 52000)] + [
    ("Silverbox 13062–end", SILVERBOX, (13062, None), (SILVERBOX, (0, 13062)), "y", ["u"], 3, 3, 0),
    ("Silverbox 20000–end", SILVERBOX, (20000, None), (SILVERBOX, (0, 13062)), "y", ["u"], 3, 3, 0),
    ("tail-sitter v_z, train → select", "tailsitter_train.csv", (0, None),
     ("tailsitter_select.csv", (0, None)), "vz", ["ctl_thrust"], 2, 2, 50),
    ("tail-sitter v_z, select → train", "tailsitter_select.csv", (0, None),
     ("tailsitter_train.csv", (0, None)), "vz", ["ctl_thrust"], 2, 2, 50),
]


def write_part(src, rows, dst):
    with open(src) as f:
        lines = f.read().splitlines()
    header, body = lines[0], lines[1:]
    a, b = rows
    with open(dst, "w") as f:
        f.write("\n".join([header] + body[a:b]) + "\n")


def run(fit, train, test, output, inputs, ny, nu, horizon, frozen):
    extra = ONLINE if frozen else [*ONLINE, "--replay-unfrozen"]
    cmd = fit_command(fit, train, test, output, inputs, ny, nu, horizon, extra)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"odonata-fit failed: {r.stderr.strip()}")
    j = json.loads(r.stdout)
    key = "k_step" if horizon else "free_run"
    fit_of = lambda v: v[key]["fit"]  # noqa: E731
    return {"fit": fit_of(j["validate"]), "arx": fit_of(j["baselines"]["arx"]["validate"]),
            "rules": j["rules"], "refused": j["refits"]["steady_state_refused"],
            "linear": j["refits"]["linear_landed"],
            "landed": j["refits"]["landed"]}


def cell(x):
    return "ran away" if x is None else f"{x:.1f} %"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", nargs="?", default=os.path.join(root, "..", "shared", "realdata"))
    ap.add_argument("--fit", default=os.path.join(root, "build", "services", "fit", "odonata-fit"))
    ap.add_argument("--frozen", action="store_true", help="also replay with the closing refit")
    ap.add_argument("--only", help="run only the replays whose name contains this")
    ap.add_argument("--jobs", type=int, default=2, help="replays run at once (default 2)")
    args = ap.parse_args()
    if not os.access(args.fit, os.X_OK):
        sys.exit(f"live_model_replays: no odonata-fit at {args.fit} (build first, or --fit PATH)")
    replays = [r for r in REPLAYS if not args.only or args.only in r[0]]
    jobs = []
    # The parts go away with the directory, whatever ends the run.
    with tempfile.TemporaryDirectory(prefix="odonata-live-") as tmp, \
            concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for n, (name, train, rows, (test, test_rows), out, ins, ny, nu, h) in enumerate(replays):
            src, tst = os.path.join(args.dir, train), os.path.join(args.dir, test)
            if not (os.path.exists(src) and os.path.exists(tst)):
                print(f"{name}: skipped ({train} or {test} is not in {args.dir})", file=sys.stderr)
                continue
            a, b = os.path.join(tmp, f"{n}-train.csv"), os.path.join(tmp, f"{n}-score.csv")
            write_part(src, rows, a)
            write_part(tst, test_rows, b)
            modes = [False, True] if args.frozen else [False]
            futures = {m: pool.submit(run, args.fit, a, b, out, ins, ny, nu, h, m) for m in modes}
            jobs.append((name, h, futures))
        print("| replay (training files only) | scored | live model | ARX | rules "
              "| steady-state refits refused | linear models landed | frozen model |")
        print("|---|---|---|---|---|---|---|---|")
        for name, h, futures in jobs:
            live = futures[False].result()
            frozen = cell(futures[True].result()["fit"]) if True in futures else "–"
            scored = f"{h} steps ahead" if h else "free run"
            print(f"| {name} | {scored} | {cell(live['fit'])} | {cell(live['arx'])} "
                  f"| {live['rules']} | {live['refused']} of {live['landed']} | {live['linear']} "
                  f"| {frozen} |",
                  flush=True)


if __name__ == "__main__":
    main()
