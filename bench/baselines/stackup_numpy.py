#!/usr/bin/python3
"""The Drake motor-assembly stack-up (tests/data/stackups/drake_motor_assembly/) in NumPy: the
baseline of Poise's formula kind (bench/baselines/compare.py, "Stack-up"). 10^6 samples of the
eleven normal dimensions (each tolerance read as 3 sigma, asymmetric ones about their centre),
the gap, and the statistics the Poise run reports of it: mean, sd, p0.135, p50, p99.865 and the
share outside [0.04, 0.08] in. Vectorised, one thread (OPENBLAS_NUM_THREADS=1).

Usage: stackup_numpy.py [--samples 1000000] [--seed 1]
"""
import argparse
import json

import numpy as np

# (sign, nominal, lower deviation, upper deviation) in inches: Drake, ch. 9.
DIMENSIONS = [(-1, 0.375, -0.031, 0.0), (1, 0.032, -0.002, 0.002), (1, 0.060, -0.003, 0.003),
              (1, 0.438, -0.015, 0.0), (1, 0.120, -0.005, 0.005), (1, 1.500, -0.004, 0.010),
              (1, 0.120, -0.005, 0.005), (1, 0.438, -0.015, 0.0), (1, 0.450, -0.007, 0.007),
              (-1, 3.019, 0.0, 0.012), (1, 0.300, -0.030, 0.030)]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--samples", type=int, default=1000000)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    rng = np.random.default_rng(a.seed)
    gap = np.zeros(a.samples)
    for sign, nominal, lo, hi in DIMENSIONS:
        centre, half = nominal + 0.5 * (lo + hi), 0.5 * (hi - lo)
        gap += sign * (centre + (half / 3.0) * rng.standard_normal(a.samples))
    q = np.quantile(gap, [0.00135, 0.5, 0.99865], method="median_unbiased")
    outside = np.count_nonzero((gap < 0.04) | (gap > 0.08)) / a.samples
    print(json.dumps({"samples": a.samples, "mean": gap.mean(), "sd": gap.std(ddof=1), "p0_135": q[0], "p50": q[1],
                      "p99_865": q[2], "outside": outside}))


if __name__ == "__main__":
    main()
