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

# ---- common oracle core (identical in every oracle.py under tests/data/real) ----
# Ordinary least squares of a signal y (SI: A or N*m) against the shaft angle
# theta (rad, may be unwrapped): y = c0 [+ c1*sign(v)] + sum_k a_k*sin(k*theta + phi_k)
# Orders k are whole cycles per turn, picked from a least-squares periodogram of
# the residual after the constant (+ Coulomb) fit.

def _lstsq(X, y):
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    return coef, y - X @ coef


def _rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def direction_from_position(theta, half_window):
    """Sign of the position change over a centred window of 2*half_window+1 rows
    (robust against the short backward slips that cogging causes); 0 where the
    change is below 1e-3 rad."""
    n = theta.size
    i = np.arange(n)
    lo = np.clip(i - half_window, 0, n - 1)
    hi = np.clip(i + half_window, 0, n - 1)
    d = theta[hi] - theta[lo]
    s = np.sign(d)
    s[np.abs(d) < 1e-3] = 0.0
    return s


def periodogram(theta, r, max_order):
    """Amplitude of the LS fit of r on [sin(k theta), cos(k theta)] for k=1..max_order."""
    amps = np.zeros(max_order)
    for k in range(1, max_order + 1):
        X = np.column_stack([np.sin(k * theta), np.cos(k * theta)])
        c, _ = _lstsq(X, r)
        amps[k - 1] = np.hypot(c[0], c[1])
    return amps


def ripple_fit(theta, y, direction=None, max_order=64, kmax=8, peak_factor=3.0,
               min_dir_fraction=0.10):
    theta = np.asarray(theta, float)
    y = np.asarray(y, float)
    n = y.size
    out = {"rows": int(n)}
    out["rms_signal"] = _rms(y)
    out["mean_signal"] = float(np.mean(y))
    out["rms_residual_constant_only"] = _rms(y - np.mean(y))
    cols = [np.ones(n)]
    use_coulomb = False
    if direction is not None:
        fpos = float(np.mean(direction > 0))
        fneg = float(np.mean(direction < 0))
        out["direction_fraction_positive"] = fpos
        out["direction_fraction_negative"] = fneg
        use_coulomb = fpos >= min_dir_fraction and fneg >= min_dir_fraction
        if use_coulomb:
            cols.append(np.asarray(direction, float))
    base = np.column_stack(cols)
    _, r0 = _lstsq(base, y)
    out["rms_residual_base"] = _rms(r0)
    # Greedy periodogram selection: take the largest order of the current
    # residual's periodogram, refit everything, repeat (at most kmax orders; an
    # order is taken only if its amplitude exceeds peak_factor x the median of
    # that periodogram).  The first periodogram (residual of the constant
    # [+ Coulomb] fit) is reported as "top12".
    chosen = []
    r = r0
    first = None
    for _ in range(kmax):
        amps = periodogram(theta, r, max_order)
        if first is None:
            first = amps
        amps_free = amps.copy()
        for k in chosen:
            amps_free[k - 1] = -1.0
        k = int(np.argmax(amps_free))
        if amps_free[k] <= peak_factor * float(np.median(amps)):
            break
        chosen.append(k + 1)
        X = [base] + [np.column_stack([np.sin(q * theta), np.cos(q * theta)]) for q in chosen]
        _, r = _lstsq(np.column_stack(X), y)
    chosen.sort()
    order_rank = np.argsort(-first)
    out["periodogram"] = {
        "max_order_searched": int(max_order),
        "selection": "greedy: largest order of the current residual, refit, repeat",
        "median_amplitude_first": float(np.median(first)),
        "peak_factor": peak_factor,
        "top12": [{"order": int(k + 1), "amplitude": float(first[k])} for k in order_rank[:12]],
    }
    X = [base]
    for k in chosen:
        X.append(np.column_stack([np.sin(k * theta), np.cos(k * theta)]))
    X = np.column_stack(X)
    coef, res = _lstsq(X, y)
    nb = base.shape[1]
    orders = []
    for j, k in enumerate(chosen):
        bs, bc = coef[nb + 2 * j], coef[nb + 2 * j + 1]
        orders.append({"order": k, "amplitude": float(np.hypot(bs, bc)),
                       "phase_rad": float(np.arctan2(bc, bs))})
    orders.sort(key=lambda o: -o["amplitude"])
    out["orders"] = orders
    out["constant"] = float(coef[0])
    if use_coulomb:
        c0, c1 = float(coef[0]), float(coef[1])
        out["coulomb"] = {
            "identifiable": True,
            "model": "c0 + c1*sign(v)",
            "c0_offset": c0,
            "c1_coulomb_half_difference": c1,
            "level_positive_direction": c0 + c1,
            "level_negative_direction": c0 - c1,
        }
    else:
        out["coulomb"] = {"identifiable": False,
                          "reason": "motion in one direction only (or too little of the other)"}
    out["rms_residual_full_fit"] = _rms(res)
    return out


def time_stats(t):
    t = np.asarray(t, float)
    dt = np.diff(t)
    med = float(np.median(dt))
    return {
        "time_recorded": True,
        "time_span_s": float(t[-1] - t[0]),
        "median_time_step_s": med,
        "steps_off_median_by_more_than_1pct": int(np.sum(np.abs(dt - med) > 0.01 * med)),
        "min_time_step_s": float(dt.min()),
        "max_time_step_s": float(dt.max()),
        "non_increasing_steps": int(np.sum(dt <= 0)),
    }
# ---- end of common core ----

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
