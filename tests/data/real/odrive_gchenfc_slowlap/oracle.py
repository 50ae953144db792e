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

COUNTS_PER_REV = 8192          # encoder cpr (CUI AMT102, 2048 lines x 4), see SOURCE


def main():
    data = np.load(os.path.join(HERE, "nocomp_0.npy"))
    assert data.shape[0] == 3
    t = data[0]                               # s, time.time() - start (host clock)
    pos = data[1]                             # counts (encoder.pos_estimate)
    iq = data[2]                              # A (motor.current_control.Iq_measured)
    theta = pos * (2.0 * np.pi / COUNTS_PER_REV)
    direction = direction_from_position(theta, half_window=25)
    fit = ripple_fit(theta, iq, direction=direction, max_order=400)
    v = np.gradient(theta, t)
    out = {
        "record": "odrive_gchenfc_slowlap",
        "signal": "Iq_measured [A], angle = pos_estimate/8192 turn",
        "files": ["nocomp_0.npy"],
        "time": time_stats(t),
        "angle_span_turns": float((theta.max() - theta.min()) / (2 * np.pi)),
        "mean_speed_turns_per_s": float((theta[-1] - theta[0]) / (2 * np.pi) / (t[-1] - t[0])),
        "raw_velocity_rows_negative": int(np.sum(v < 0)),
        "direction_rule": "sign of pos change over +-25 rows",
        "fit": fit,
    }
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
