#!/usr/bin/env python3
"""Writes the Narendra–Parthasarathy benchmark y(k+1) = y(k)/(1+y(k)^2) + u(k)^3 as CSV:
train.csv (u uniform in [-2, 2], seeded) and validate.csv (u(k) = sin(2 pi k / 100))."""
import random, math, sys, os

def simulate(u):
    y = [0.0]
    for k in range(len(u) - 1):
        y.append(y[k] / (1 + y[k] ** 2) + u[k] ** 3)
    return y

def write(path, u, y):
    with open(path, "w") as f:
        f.write("k,u,y\n")
        for k, (a, b) in enumerate(zip(u, y)):
            f.write(f"{k},{a:.17g},{b:.17g}\n")

out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
rng = random.Random(7)
u_train = [rng.uniform(-2, 2) for _ in range(5000)]
u_val = [math.sin(2 * math.pi * k / 100) for k in range(1000)]
write(os.path.join(out, "train.csv"), u_train, simulate(u_train))
write(os.path.join(out, "validate.csv"), u_val, simulate(u_val))
