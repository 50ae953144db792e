#!/usr/bin/env python3
"""What poise.Study.evaluate costs on top of Poise's own computation (issue 31: at most 1.2x).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_evaluate.py [--points 100000] [--repeats 5]

Both sides in one run, on one thread, CPU time (time.process_time), median of the repeats:
  C++    the extension's evaluate on a ready points x inputs array (one call: the chunked C++
         loop over the points, nothing per point in Python)
  Python Study.evaluate with a dict of input arrays, as a user calls it (the arrays checked and
         read in place by the C++ loop, the outputs split into a dict of views)
The points are the nominal seeker's inputs with every toleranced input drawn at random around it.
Exit status 1 when the ratio exceeds --limit (default 1.2).
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

import poise

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def cpu_seconds(f, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        f()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--study", default=os.path.join(ROOT, "studies", "los_seeker_wang2011.toml"))
    p.add_argument("--points", type=int, default=100000)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--limit", type=float, default=1.2)
    a = p.parse_args()
    s = poise.Study(a.study)
    names = s.input_names
    rng = np.random.default_rng(1)
    nominal = s.nominal()
    inputs = {n: nominal[n] + rng.normal(0.0, 1.0, a.points) for n in names}
    matrix = np.column_stack([inputs[n] for n in names])
    native = cpu_seconds(lambda: s._s.evaluate_matrix(matrix, 1), a.repeats)
    python = cpu_seconds(lambda: s.evaluate(inputs, threads=1), a.repeats)
    ratio = python / native
    print(f"{os.path.basename(a.study)}: {a.points} points, {len(names)} inputs, 1 thread, CPU s (median of "
          f"{a.repeats})")
    print(f"  C++ evaluate          {native:8.3f} s  ({1e6 * native / a.points:.2f} us/point)")
    print(f"  Study.evaluate (dict) {python:8.3f} s  ratio {ratio:.3f} (target <= {a.limit})")
    return 0 if ratio <= a.limit else 1


if __name__ == "__main__":
    sys.exit(main())
