#!/usr/bin/python3
"""The own-vehicle example in Python, with the standard library only (odonata_signals.py): the
same climbing quadrotor as vehicle.cpp (thrust grows with the square of the throttle, drag with
the square of the speed), publishing vz_mps, throttle and battery_v on VEHICLE_SIGNALS once per
step. Run it where odonata_signals.py is importable (PYTHONPATH=python in the source tree;
installed: share/odonata/python).

    vehicle.py [--rate HZ] [--samples N] [--seed S] [--lcm-url URL]
"""
import argparse
import random
import sys
import time

from odonata_signals import SignalsPublisher


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rate", type=float, default=100.0, help="steps per second (default 100)")
    ap.add_argument("--samples", type=int, default=3000, help="steps to run (default 3000)")
    ap.add_argument("--seed", type=int, default=1, help="excitation seed (default 1)")
    ap.add_argument("--lcm-url", help="LCM URL (default: LCM_DEFAULT_URL, else udpm ttl=0)")
    ap.add_argument("--key", help="the system's shared key file: sign every message, for an identifier "
                    "started with the same --key (docs/lcm.md §15)")
    a = ap.parse_args()
    if a.rate <= 0 or a.samples < 0:
        ap.error("--rate must be positive and --samples not negative")
    pub = SignalsPublisher(a.lcm_url, source="python-vehicle", key_path=a.key)
    rng = random.Random(a.seed)
    dt, mass, g, k_thrust, k_drag = 0.01, 0.5, 9.81, 9.0, 0.08
    vz, battery, throttle, held = 0.0, 12.6, 0.6, 0
    names = ["vz_mps", "throttle", "battery_v"]
    period = 1.0 / a.rate
    next_t = time.monotonic()
    for k in range(a.samples):
        if held <= 0:
            throttle = rng.uniform(0.35, 0.95)
            held = rng.randint(20, 80)
        held -= 1
        # Sample k: the speed measured at k and the throttle applied from k on.
        pub.publish(k, names, [vz, throttle, battery])
        thrust = k_thrust * throttle * throttle
        vz += dt * (thrust - mass * g - k_drag * vz * abs(vz)) / mass
        battery -= 1e-5 * throttle
        next_t += period
        time.sleep(max(0.0, next_t - time.monotonic()))
    print(f"vehicle.py: {a.samples} samples published", file=sys.stderr)


if __name__ == "__main__":
    main()
