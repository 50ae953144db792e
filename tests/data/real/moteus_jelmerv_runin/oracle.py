#!/usr/bin/env python3
"""Oracle for a real public record kept under tests/data/real (see SOURCE).
Reads the excerpt exactly as stored, converts to SI (s, A or N*m, rad), and
prints a JSON object with an ordinary least-squares ripple/friction fit.
Needs only Python 3 and numpy (Debian python3-numpy: /usr/bin/python3)."""
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# The common core: ../oracle_fit.py (the fit, the periodogram, the direction and time rules).
sys.path.insert(0, os.path.dirname(HERE))
from oracle_fit import _lstsq, _rms, direction_from_position, periodogram, ripple_fit, time_stats  # noqa: E402,F401

FILE = "07-04_11-34-18_run-in_split_0.5rps.csv"


def main():
    path = os.path.join(HERE, FILE)
    with open(path) as f:
        header = f.readline().strip().split(";")
    raw = np.loadtxt(path, delimiter=";", skiprows=1, dtype=float)
    col = {name: raw[:, i] for i, name in enumerate(header)}
    # TIME is time.time_ns() (integer ns since epoch); as float64 it keeps ~0.3 us
    # resolution, so subtract the first stamp using the exact integers.
    with open(path) as f:
        f.readline()
        tns = np.array([int(line.split(";", 1)[0]) for line in f if line.strip()], dtype=np.int64)
    t = (tns - tns[0]).astype(float) * 1e-9                 # s
    theta = col["POSITION"] * 2.0 * np.pi                   # rev (output) -> rad
    iq = col["Q_CURRENT"]                                   # A
    torque = col["TORQUE"]                                  # N*m (moteus, output side)
    direction = direction_from_position(theta, half_window=10)
    fit = ripple_fit(theta, iq, direction=direction, max_order=400)
    fit_t = ripple_fit(theta, torque, direction=direction, max_order=400)
    out = {
        "record": "moteus_jelmerv_runin",
        "signal": "Q_CURRENT [A], angle = POSITION [output rev] * 2*pi",
        "files": [FILE],
        "columns": header,
        "time": time_stats(t),
        "angle_span_turns": float((theta.max() - theta.min()) / (2 * np.pi)),
        "mean_speed_turns_per_s": float((theta[-1] - theta[0]) / (2 * np.pi) / t[-1]),
        "direction_rule": "sign of POSITION change over +-10 rows",
        "rows_torque_exactly_zero": int(np.sum(torque == 0.0)),
        "fit": fit,
        "secondary_fit_TORQUE_Nm": fit_t,
    }
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
