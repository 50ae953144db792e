#!/usr/bin/python3
"""SciPy LSODA baseline of one 36-point static-unbalance measurement (bench/gimbal_bench.cc).

The same measurement as poise_gimbal_bench's BM_Measurement36By: the rig of
models/gimbal_simulator_yang2015.toml (read here with tomllib) with the bench's load (25.81 g at
51 mm, 45.5 deg), the full 7-state disk rotor on elastic supports (models/disk_rotor.h: phi, y, z
and their rates, Lagrange's equations with y'', z'' eliminated in closed form), the PID servo with
acceleration feed-forward and its clipped, conditionally integrated current, and at each
turntable position: settle, lead-in, then N whole periods over which the drive current is
integrated as a state (Eq. 21), the acquisition's white noise, ADC step and offsets drawn in
distribution (one normal draw per window); then the least-squares sine fit (Eq. 22).
Each position is integrated piecewise ([0, t0], [t0, t1], [t1, t2]: the reference's corner and
the window's start are not stepped across) by scipy.integrate.odeint (LSODA).

Accuracy: the script first runs at --tight-rtol (1e-9) and then at each --rtol given, and
prints |MT_s - MT_s(tight)| / load for each: the same noise draws (same seed) in all runs, so
the difference is the solver's. Timing: CPU seconds (time.process_time) per measurement.

With --sweep, each rtol's line also gives the worst |dMT_s|/load over the bench's accuracy sweep (4
rotors x 3 noise seeds, each against its own run at --sweep-tight-rtol), the rule by which
compare.py picks Poise's setting; compare.py then picks LSODA's by the same rule.

Usage: gimbal_scipy.py [--rtol 1e-5 1e-6 ...] [--repeat N] [--sweep]
Prints one line per rtol: "lsoda rtol R: MT_s X mN*m, |dMT_s|/load D, cpu S s per measurement, steps K,
rhs_evals E" (LSODA's steps and right-hand-side calls over the 36 positions).
"""
import argparse, os, sys, time, tomllib
import numpy as np
from scipy.integrate import odeint

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
UNITS = {"kg": 1, "kg*m^2": 1, "N/m": 1, "N*s/m": 1, "N*m*s/rad": 1, "mN*m": 1e-3, "N*m": 1, "rad/s": 1,
         "N*m/rad": 1, "deg": np.pi / 180, "N*m/A": 1, "A": 1, "mA": 1e-3, "Hz": 1, "deg/s": np.pi / 180,
         "s": 1, "rad": 1, "arcsec": np.pi / 648000, "m/s^2": 1, "mm": 1e-3, "m": 1}


def q(text):
    v, u = text.split()
    return float(v) * UNITS[u]


CLUMP, RADIUS, ANGLE = 25.81e-3, 0.051, 45.5 * np.pi / 180  # the bench's load


def load(path, clump=CLUMP, angle=ANGLE):
    m = tomllib.load(open(path, "rb"))
    r, mo, sv, osc, acq, tt = m["rotor"], m["motor"], m["servo"], m["oscillation"], m["acquisition"], m["turntable"]
    P = dict(m=q(r["mass"]) + clump, J=q(r["inertia"]) + clump * RADIUS ** 2, k=q(r["support_stiffness"]),
             c=q(r["support_damping"]), kf=q(r["viscous_friction"]), tc=q(r["coulomb_friction"]),
             ws=q(r["coulomb_smoothing"]), kcr=q(r["torsion_stiffness"]), phi0=q(r["torsion_zero"]),
             kt=q(mo["kt_nominal"]), imax=q(mo["current_limit"]), bw=q(sv["bandwidth"]), zeta=float(sv["damping"]),
             ratio=float(sv["integral_ratio"]), jhat=q(sv["inertia_estimate"]), A=q(osc["rate_amplitude"]),
             T=q(osc["period"]), N=int(osc["periods"]), lead=q(osc["lead_in"]), settle=q(osc["settle_time"]),
             centre=q(osc["centre"]), rate=q(acq["rate"]), noise=q(acq["noise_rms"]), offset=q(acq["offset"]),
             drift=q(acq["offset_drift"]), onoise=q(acq["offset_noise"]), bits=int(acq["adc_bits"]),
             fs=q(acq["adc_full_scale"]), pos_err=q(tt["positioning_error"]), g=q(tt["gravity"]),
             rtol=float(m["solver"]["rtol"]), atol_angle=q(m["solver"]["atol_angle"]),
             atol_length=q(m["solver"]["atol_length"]))
    P["e"], P["eps"] = clump * RADIUS / P["m"], angle
    return P


def rhs(y, t, P, gy, gz, wc):
    phi, w, yy, yd, z, zd, integ = y[:7]
    om = 2 * np.pi / P["T"]
    a = P["A"] / om
    if t < P["settle"]:
        pr, rr, ar = P["centre"] - a, 0.0, 0.0
    else:
        s = om * (t - P["settle"])
        pr, rr, ar = P["centre"] - a * np.cos(s), P["A"] * np.sin(s), P["A"] * om * np.cos(s)
    kp = P["jhat"] * wc * wc
    cmd = (kp * (pr - phi) + 2 * P["zeta"] * P["jhat"] * wc * (rr - w) + kp * wc * P["ratio"] * integ
           + P["jhat"] * ar) / P["kt"]
    i = min(max(cmd, -P["imax"]), P["imax"])
    m, e = P["m"], P["e"]
    p = phi + P["eps"]
    sp, cp = np.sin(p), np.cos(p)
    qphi = (P["kt"] * i - P["kf"] * w - P["tc"] * np.tanh(w / P["ws"]) - P["kcr"] * (phi - P["phi0"])
            + m * e * (-gy * sp + gz * cp))
    fy = m * e * cp * w * w - P["k"] * yy - P["c"] * yd + m * gy
    fz = m * e * sp * w * w - P["k"] * z - P["c"] * zd + m * gz
    pdd = (qphi + e * (sp * fy - cp * fz)) / P["J"]
    inwin = t >= P["settle"] + P["lead"]
    err = pr - phi
    return [w, pdd, yd, (fy + m * e * sp * pdd) / m, zd, (fz - m * e * cp * pdd) / m,
            0.0 if i != cmd else err, i if inwin else 0.0, err * err if inwin else 0.0]


def measure(P, rtol, seed=2015):
    rng = np.random.default_rng(seed)
    wc = 2 * np.pi * P["bw"]
    atol = np.array([P["atol_angle"], 10 * P["atol_angle"], P["atol_length"], 1e3 * P["atol_length"],
                     P["atol_length"], 1e3 * P["atol_length"], 0.1 * P["atol_angle"], 1e-3 * P["rtol"], 1e30])
    atol *= rtol / P["rtol"]
    t0, t1 = P["settle"], P["settle"] + P["lead"]
    t2 = t1 + P["N"] * P["T"]
    n = round(P["N"] * P["T"] * P["rate"])
    lsb = 2 * P["fs"] / 2 ** P["bits"]
    thetas = 2 * np.pi * np.arange(36) / 36
    offset, torques = P["offset"], []
    counts = [0, 0]  # LSODA's steps and RHS evaluations (finite-difference Jacobians included)
    a = P["A"] * P["T"] / (2 * np.pi)
    for th in thetas:
        th_true = th + P["pos_err"] * rng.standard_normal()
        offset += P["drift"] * rng.standard_normal()
        window_offset = offset + P["onoise"] * rng.standard_normal()
        gy, gz = P["g"] * np.cos(th_true), -P["g"] * np.sin(th_true)
        y = np.array([P["centre"] - a, 0, P["m"] * gy / P["k"], 0, P["m"] * gz / P["k"], 0, 0, 0, 0], float)
        for ta, tb in ((0.0, t0), (t0, t1), (t1, t2)):
            sol, info = odeint(rhs, y, [ta, tb], args=(P, gy, gz, wc), rtol=rtol, atol=atol, mxstep=100000,
                               full_output=True)
            y = sol[-1]
            counts[0] += int(info["nst"][-1])
            counts[1] += int(info["nfe"][-1])
        i_mean = y[7] / (t2 - t1) + window_offset + np.sqrt((P["noise"] ** 2 + lsb ** 2 / 12) / n) * rng.standard_normal()
        torques.append(P["kt"] * i_mean)
    # Eq. 22: M = a sin(theta) + b cos(theta) + c by least squares.
    X = np.column_stack([np.sin(thetas), np.cos(thetas), np.ones_like(thetas)])
    coef = np.linalg.lstsq(X, np.array(torques), rcond=None)[0]
    return np.hypot(coef[0], coef[1]), counts


def sweep_cases(path):
    """The bench's accuracy sweep (bench/gimbal_bench.cc accuracy_sweep): clumps of 25.81, 10, 50
    and 5 g at 51 mm and 45.5 + 70 k deg, each with noise seeds 1, 2 and 3 (NumPy's draws here)."""
    return [(load(path, mass, (45.5 + 70.0 * k) * np.pi / 180), seed)
            for k, mass in enumerate((CLUMP, 10e-3, 50e-3, 5e-3)) for seed in (1, 2, 3)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", default=os.path.join(ROOT, "models", "gimbal_simulator_yang2015.toml"))
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-4, 1e-5, 1e-6])
    ap.add_argument("--tight-rtol", type=float, default=1e-9)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--sweep", action="store_true",
                    help="also the worst |dMT_s|/load over the bench's accuracy sweep (4 rotors x 3 noise seeds, "
                         "each against its own run at --sweep-tight-rtol), as Poise's setting is judged")
    ap.add_argument("--sweep-tight-rtol", type=float, default=1e-5)
    a = ap.parse_args()
    P = load(a.model)
    load_torque = CLUMP * RADIUS * P["g"]
    c0 = time.process_time()
    tight, _ = measure(P, a.tight_rtol)
    print(f"lsoda tight rtol {a.tight_rtol:g}: MT_s {tight * 1e3:.6f} mN*m ({time.process_time() - c0:.2f} CPU-s)")
    cases = sweep_cases(a.model) if a.sweep else []
    references = [measure(Pc, a.sweep_tight_rtol, seed)[0] for Pc, seed in cases]
    for rtol in a.rtol:
        c0 = time.process_time()
        for _ in range(a.repeat):
            mt, counts = measure(P, rtol)
        cpu = (time.process_time() - c0) / a.repeat
        worst = ""
        if cases:
            w = max(abs(measure(Pc, rtol, seed)[0] - ref) for (Pc, seed), ref in zip(cases, references))
            worst = f", worst of {len(cases)} cases {w / load_torque:.2e}"
        print(f"lsoda rtol {rtol:g}: MT_s {mt * 1e3:.6f} mN*m, |dMT_s|/load {abs(mt - tight) / load_torque:.2e},"
              f" cpu {cpu:.3f} s per measurement, steps {counts[0]}, rhs_evals {counts[1]}{worst}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
