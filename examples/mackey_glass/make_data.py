#!/usr/bin/python3
"""Mackey–Glass time series in Jang's ANFIS setup (IEEE SMC 1993), the field's standard benchmark.

dx/dt = 0.2 x(t−τ) / (1 + x(t−τ)^10) − 0.1 x(t), τ = 17, x(0) = 1.2, x(t) = 0 for t < 0,
integrated by 4th-order Runge–Kutta with step 0.1 (the delayed value at the half step is the mean
of its neighbours). Sampled at integer t: inputs x(t−18), x(t−12), x(t−6), x(t), target x(t+6),
for t = 118 … 1117; the first 500 rows are training data, the last 500 test data.
Writes train.csv and validate.csv beside this script (or in --out)."""
import argparse
import os


def series(t_end, dt=0.1, tau=17.0, x0=1.2):
    lag = int(round(tau / dt))
    n = int(round(t_end / dt)) + 1
    x = [0.0] * n
    x[0] = x0

    def delayed(k):
        return x[k - lag] if k - lag >= 0 else 0.0

    def f(xt, xd):
        return 0.2 * xd / (1.0 + xd ** 10) - 0.1 * xt

    for k in range(n - 1):
        xd0, xd1 = delayed(k), delayed(k + 1)
        xdh = 0.5 * (xd0 + xd1)
        k1 = f(x[k], xd0)
        k2 = f(x[k] + 0.5 * dt * k1, xdh)
        k3 = f(x[k] + 0.5 * dt * k2, xdh)
        k4 = f(x[k] + dt * k3, xd1)
        x[k + 1] = x[k] + dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0
    step = int(round(1.0 / dt))
    return [x[i * step] for i in range(int(t_end) + 1)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    args = ap.parse_args()
    x = series(1124)
    rows = [(x[t - 18], x[t - 12], x[t - 6], x[t], x[t + 6]) for t in range(118, 1118)]
    header = "x_t_minus_18,x_t_minus_12,x_t_minus_6,x_t,x_t_plus_6\n"
    for name, part in (("train.csv", rows[:500]), ("validate.csv", rows[500:])):
        with open(os.path.join(args.out, name), "w") as f:
            f.write(header)
            for r in part:
                f.write(",".join(f"{v:.10f}" for v in r) + "\n")


if __name__ == "__main__":
    main()
