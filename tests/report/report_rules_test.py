#!/usr/bin/python3
"""The report's membership plot of a many-rule model (issue 23 point 4): each rule's share of the
firing over the training samples is computed from the model and the CSV, the rules carrying most
of it are picked, and the plot draws them in colour with the rest behind."""
import csv
import json
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.environ["ODONATA_SOURCE"], "deploy"))
import odonata_report  # noqa: E402


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def model_with_rules(centres):
    return {
        "regressor": {"delay": 1, "input_lags": 1, "inputs": ["u"], "output_lags": 1, "outputs": ["y"]},
        "scaling": {"regressor_mid": [0.0, 0.0], "regressor_half": [1.0, 1.0],
                    "output_mean": [0.0], "output_std": [1.0]},
        "models": [{"rules": [{"centre": list(c), "sigma": [0.2, 0.2]} for c in centres]}],
    }


def main():
    # 12 rules on a grid; the data sit around rules 0 (70 % of samples) and 5 (30 %).
    centres = [(-1 + 0.4 * (j % 4), -1 + 0.6 * (j // 4)) for j in range(12)]
    model = model_with_rules(centres)
    rng = np.random.default_rng(1)
    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "exp", "pipeline"))
        path = os.path.join(d, "exp", "pipeline", "train.csv")
        # Row k's regressor is (y(k-1), u(k-1)): consecutive rows share their place.
        ys, us = [], []
        for k in range(1000):
            c = centres[0] if (k // 50) % 10 < 7 else centres[5]
            ys.append(c[0] + 0.02 * rng.standard_normal())
            us.append(c[1] + 0.02 * rng.standard_normal())
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["t_s", "u", "y"])
            for k in range(1000):
                w.writerow([0.01 * k, us[k], ys[k]])
        shares = odonata_report.rule_shares(model, path)
        if shares is None or abs(shares.sum() - 1) > 1e-9:
            fail(f"shares {shares} do not sum to 1")
        top = odonata_report.dominant_rules(shares)
        if top[:2] != [0, 5]:
            fail(f"dominant rules {top} (shares {np.round(shares, 3)}), expected 0 then 5 first")
        if not 0.6 < shares[0] < 0.8 or not 0.2 < shares[5] < 0.4:
            fail(f"shares of rules 1 and 6: {shares[0]:.2f}, {shares[5]:.2f}")
        if odonata_report.rule_shares(model, os.path.join(d, "missing.csv")) is not None:
            fail("a missing file gave shares")
        with open(os.path.join(d, "exp", "pipeline", "model.json"), "w") as f:
            json.dump(model, f)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        name = odonata_report.plot_membership(plt, d, {"dir": os.path.join(d, "exp"), "name": "exp"})
        if os.path.getsize(os.path.join(d, name)) < 1000:
            fail("empty membership plot")
    print(f"PASS: rules 1 and 6 carry {100 * shares[0]:.0f} % and {100 * shares[5]:.0f} % of the firing; "
          f"the plot shows {len(top)} of 12 in colour")


if __name__ == "__main__":
    main()
