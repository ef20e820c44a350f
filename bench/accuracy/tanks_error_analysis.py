#!/usr/bin/python3
"""Where the cascaded tanks' free-run error lies, and what the regressor allows (README, On
measured records).

Two figures, for the explanation only; nothing here chooses a setting:
- with --predictions (odonata-fit's --predictions file of a run validated on the tanks' test
  record): the share of the fuzzy model's and ARX's squared free-run error within N samples after
  a sample where the lower tank is full (10 V), where its lags say nothing of the unmeasured upper
  tank, and the RMSE elsewhere;
- an in-sample bound: a degree-2 polynomial NARX on the same regressor (ny 2, nu 2) trained on
  the simulation error of the test record itself (Levenberg–Marquardt from its one-step least
  squares fit), scored on that same record. A model trained on the training record is unlikely to
  do much better on the test record than this.
"""
import argparse
import csv
import itertools
import os
import sys

import numpy as np
from scipy.optimize import least_squares

FULL = 10.0  # V: the lower tank's level sensor at overflow


def read_columns(path, names):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [np.array([float(r[n]) for r in rows]) for n in names]


def after_full_mask(y, n):
    mask = np.zeros(len(y), bool)
    for i in np.flatnonzero(y >= FULL - 1e-9):
        mask[i:i + n] = True
    return mask


def error_shares(predictions, n):
    s, y, fuzzy, arx = read_columns(predictions, ["set", "measured", "fuzzy_free_run", "arx_free_run"])
    v = s == 1
    y, fuzzy, arx = y[v], fuzzy[v], arx[v]
    m = after_full_mask(y, n)
    print(f"{v.sum()} validation samples; {m.sum()} ({100 * m.mean():.0f} %) lie within {n} samples "
          f"after one at {FULL:g} V")
    for name, yh in (("fuzzy", fuzzy), ("ARX", arx)):
        e2 = (y - yh) ** 2
        print(f"  {name}: RMSE {np.sqrt(e2.mean()):.3f} V; {100 * e2[m].sum() / e2.sum():.0f} % of the "
              f"squared error there (RMSE {np.sqrt(e2[m].mean()):.3f} V), RMSE elsewhere "
              f"{np.sqrt(e2[~m].mean()):.3f} V")


def in_sample_bound(test):
    u, y = read_columns(test, ["u", "y"])
    terms = [c for d in range(3) for c in itertools.combinations_with_replacement(range(4), d)]
    ym, ys, um, us = y.mean(), y.std(), u.mean(), u.std()

    def regressor(yy, k):
        return np.array([(yy[k - 1] - ym) / ys, (yy[k - 2] - ym) / ys, (u[k - 1] - um) / us,
                         (u[k - 2] - um) / us])

    def features(r):
        return np.array([np.prod(r[list(c)]) for c in terms])

    def simulate(theta):
        yy = np.empty(len(y))
        yy[:2] = y[:2]
        for k in range(2, len(y)):
            v = ym + ys * (features(regressor(yy, k)) @ theta)
            yy[k] = v if np.isfinite(v) and abs(v) < 1e3 else 1e3  # a diverged run stays large
        return yy

    x = np.array([features(regressor(y, k)) for k in range(2, len(y))])
    theta0 = np.linalg.lstsq(x, (y[2:] - ym) / ys, rcond=None)[0]
    rmse0 = np.sqrt(np.mean((simulate(theta0) - y) ** 2))
    fit = least_squares(lambda th: simulate(th) - y, theta0, method="lm", max_nfev=4000)
    rmse = np.sqrt(np.mean((simulate(fit.x) - y) ** 2))
    print(f"degree-2 polynomial NARX (2, 2), {len(terms)} terms, trained and scored on {os.path.basename(test)}: "
          f"free-run RMSE {rmse0:.3f} V from one-step least squares, {rmse:.3f} V trained on the "
          f"simulation error")


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--test", default=os.path.join(root, "..", "shared", "realdata", "cascaded_tanks_test.csv"),
                    help="the tanks' test record (columns u, y)")
    ap.add_argument("--predictions", help="odonata-fit --predictions file of a run validated on it")
    ap.add_argument("--after", type=int, default=100, help="samples after a full tank (default 100)")
    args = ap.parse_args()
    if not os.path.exists(args.test):
        sys.exit(f"tanks_error_analysis: no test record at {args.test}")
    if args.predictions:
        error_shares(args.predictions, args.after)
    in_sample_bound(args.test)


if __name__ == "__main__":
    main()
