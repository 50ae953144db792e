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
NOMINAL_WAIT_S = 3.0           # find_cog(..., waittime=3) default, see SOURCE


def main():
    fwd = np.load(os.path.join(HERE, "cogging_measure_final_c_16.npy"))
    rev = np.load(os.path.join(HERE, "cogging_measure_final_e_16r.npy"))
    assert fwd.shape == (8192,) and rev.shape == (8192,)
    # find_cog(step=16): forward visits index i = 0,16,...,8176;
    # reverse (reverse=True) visits index 8191-i = 8191,8175,...,15 (in that order).
    idx_f = np.arange(0, 8192, 16)
    idx_r = (8191 - np.arange(0, 8192, 16))          # measurement order of the reverse sweep
    yf = fwd[idx_f]
    yr = rev[idx_r]
    unvisited_nonzero = int(np.count_nonzero(np.delete(fwd, idx_f)) +
                            np.count_nonzero(np.delete(rev, idx_r)))
    theta = np.concatenate([idx_f, idx_r]) * (2.0 * np.pi / COUNTS_PER_REV)   # rad
    y = np.concatenate([yf, yr])                                            # A (Iq_measured)
    direction = np.concatenate([np.ones(yf.size), -np.ones(yr.size)])
    fit = ripple_fit(theta, y, direction=direction, max_order=255)
    # the same orders fitted per direction (constant + harmonics), for comparison
    orders = sorted(o["order"] for o in fit["orders"])
    per_dir = {}
    for name, th, yy in (("forward_c_16", theta[:yf.size], yf), ("reverse_e_16r", theta[yf.size:], yr)):
        X = [np.ones(yy.size)] + [f(k * th) for k in orders for f in (np.sin, np.cos)]
        X = np.column_stack(X)
        coef, res = _lstsq(X, yy)
        od = []
        for j, k in enumerate(orders):
            bs, bc = coef[1 + 2 * j], coef[2 + 2 * j]
            od.append({"order": k, "amplitude": float(np.hypot(bs, bc)), "phase_rad": float(np.arctan2(bc, bs))})
        per_dir[name] = {"rows": int(yy.size), "constant": float(coef[0]),
                         "rms_residual_constant_only": _rms(yy - yy.mean()),
                         "rms_residual_fit": _rms(res), "orders": od}
    out = {
        "record": "odrive_gchenfc_coggingmap",
        "signal": "Iq_measured [A] (holding current), angle = index/8192 turn",
        "angle_unit_in_file": "array index = encoder count (8192 per turn)",
        "files": ["cogging_measure_final_c_16.npy", "cogging_measure_final_e_16r.npy"],
        "unvisited_entries_nonzero": unvisited_nonzero,
        "zero_valued_visited_entries": int(np.sum(yf == 0) + np.sum(yr == 0)),
        "time": {"time_recorded": False,
                 "nominal_time_step_s": NOMINAL_WAIT_S,
                 "note": "no time column; each point was held ~3 s (script default) before sampling",
                 "angle_step_counts": 16,
                 "angle_step_rad": 16 * 2.0 * np.pi / COUNTS_PER_REV},
        "fit": fit,
        "per_direction_same_orders": per_dir,
    }
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
