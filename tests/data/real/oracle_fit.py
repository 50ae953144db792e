"""The common core of the real records' oracles (tests/data/real/*/oracle.py): an ordinary
least-squares fit, written independently of Poise. Needs only Python 3 and numpy (Debian
python3-numpy: /usr/bin/python3)."""
import numpy as np

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
