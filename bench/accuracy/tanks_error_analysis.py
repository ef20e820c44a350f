#!/usr/bin/python3
"""Where the cascaded tanks' free-run error lies, and what the regressor allows (README, On
measured records).

Two figures, for the explanation only; nothing here chooses a setting:
- with --predictions (odonata-fit's --predictions file of a run validated on the tanks' test
  record): the share of the fuzzy model's and ARX's squared free-run error within N samples after
  a sample where the lower tank is full (10 V), where its lags say nothing of the unmeasured upper
  tank, and the RMSE elsewhere;
- polynomial NARX models (degree 2 and 3) on the same regressor (ny 2, nu 2) trained on the
  simulation error (Levenberg–Marquardt from one-step least squares fits): trained on the test
  record itself, what the regressor can represent there (an in-sample figure); trained on the
  training record, what these models reach on the test record.
"""
import argparse
import csv
import os
import sys

import numpy as np
from scipy.optimize import least_squares

from real_records import load, monomials

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


def polynomial_narx(train, test, degree):
    """Trains a polynomial NARX (2, 2) on the simulation error of `train` and scores its free run
    on `train` and `test` (the same file for the in-sample figure)."""
    y, u = load(train, "y", ["u"])
    yv, uv = load(test, "y", ["u"])
    u, uv = u[:, 0], uv[:, 0]
    terms = monomials(4, degree)
    # Each term as `degree` indices into [regressor…, 1]: one product per term, one call per step.
    index = np.array([list(c) + [4] * (degree - len(c)) for c in terms])
    ym, ys, um, us = y.mean(), y.std(), u.mean(), u.std()

    def regressor(yy, uu, k):
        return np.array([(yy[k - 1] - ym) / ys, (yy[k - 2] - ym) / ys, (uu[k - 1] - um) / us,
                         (uu[k - 2] - um) / us, 1.0])

    def simulate(theta, uu, yy0):
        yy = np.empty(len(yy0))
        yy[:2] = yy0[:2]
        for k in range(2, len(yy0)):
            v = ym + ys * (np.prod(regressor(yy, uu, k)[index], axis=1) @ theta)
            yy[k] = v if np.isfinite(v) and abs(v) < 1e3 else 1e3  # a diverged run stays large
        return yy

    def rmse(theta, uu, yy):
        return np.sqrt(np.mean((simulate(theta, uu, yy) - yy) ** 2))

    x = np.array([np.prod(regressor(y, u, k)[index], axis=1) for k in range(2, len(y))])
    target = (y[2:] - ym) / ys
    one_step = np.linalg.lstsq(x, target, rcond=None)[0]
    # The simulation error has several minima: start from the one-step fit of every term, and
    # from that of the linear terms alone; keep the better fit of the training file.
    linear = np.zeros(len(terms))
    first_order = [i for i, c in enumerate(terms) if len(c) <= 1]
    linear[first_order] = np.linalg.lstsq(x[:, first_order], target, rcond=None)[0]
    fits = [least_squares(lambda th: simulate(th, u, y) - y, start, method="lm", max_nfev=3000).x
            for start in (one_step, linear)]
    best = min(fits, key=lambda th: rmse(th, u, y))
    where = "on it" if train == test else f"on {os.path.basename(train)}"
    print(f"degree-{degree} polynomial NARX (2, 2), {len(terms)} terms, trained {where}: free-run RMSE "
          f"{rmse(best, u, y):.3f} V there, {rmse(best, uv, yv):.3f} V on {os.path.basename(test)} "
          f"({rmse(one_step, uv, yv):.3f} V by one-step least squares)")


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--test", default=os.path.join(root, "..", "shared", "realdata", "cascaded_tanks_test.csv"),
                    help="the tanks' test record (columns u, y)")
    ap.add_argument("--train", default=os.path.join(root, "..", "shared", "realdata", "cascaded_tanks_train.csv"),
                    help="the tanks' training record (columns u, y)")
    ap.add_argument("--predictions", help="odonata-fit --predictions file of a run validated on it")
    ap.add_argument("--after", type=int, default=100, help="samples after a full tank (default 100)")
    ap.add_argument("--degrees", type=int, nargs="+", default=[2, 3],
                    help="polynomial degrees (default 2 3)")
    args = ap.parse_args()
    if not os.path.exists(args.test):
        sys.exit(f"tanks_error_analysis: no test record at {args.test}")
    if args.predictions:
        error_shares(args.predictions, args.after)
    for degree in args.degrees:
        polynomial_narx(args.test, args.test, degree)
        if os.path.exists(args.train):
            polynomial_narx(args.train, args.test, degree)


if __name__ == "__main__":
    main()
