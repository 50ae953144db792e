#!/usr/bin/env python3
"""Third, independent generator of gimbal static-unbalance measurement data (tables and raw records).

Written from the physical description of the test (Yang et al. 2015) alone; it shares no code and
no formula source with Poise.  Deterministic: the same --seed gives the same files byte for byte.

PHYSICAL MODEL (SI units inside, mN*m in the files)
----------------------------------------------------
Turntable angle theta (locked at each position) sets the direction of gravity in the gimbal frame.
The gimbal angle phi (small, oscillating about 0) is driven by the gimbal's own motor.

  J phi'' = K_T(t) i - L(theta, phi) - F_f - C(phi)                                   (1)

  L(theta, phi) = U sin(theta + b + phi)                    rotor unbalance, U = m g e
                + U_a sin(theta + b_a + phi)                 bent shaft: axial mass offset of the rotor
                                                             times the tilt of the bent axis (a first
                                                             harmonic of another phase: a real torque,
                                                             not separable from U by any table)
                + M_2 sin(2(theta + phi) + b_2)              anisotropic shaft sag: the sag d = C_s m g
                                                             (compliance matrix C_s, principal values
                                                             c1 != c2) gives m (d x g) = m^2 g^2 (c1-c2)/2
                                                             * sin(2(theta - psi)): a 2nd harmonic
                + M_K + k_c phi                              cable spring/offset torque

  F_f: LuGre bristle friction with Stribeck effect (not a tanh/sign Coulomb law):
      z' = phi' - sigma0 |phi'| z / g(phi'),   g(v) = F_c,d + (F_s,d - F_c,d) exp(-(v/v_s)^2)
      F_f = sigma0 z + sigma1 exp(-(v/v_d)^2) z' + sigma2 phi'
      with direction-dependent levels F_c,d = F_c (1 + a_f sgn v), F_s,d = F_s (1 + a_f sgn v)
  C(phi) = A_c sin(N_c phi + c_c): motor cogging of order N_c per turn.

  Servo (discrete, at the sampling rate f_s, zero-order hold): the reference is
  phi_r = A sin(2 pi t / T); the encoder reads phi quantised to 2 pi / 2^bits; velocity from the
  difference of readings through a first-order filter; i = (J_n phi_r'' + K_p e + K_d (v_r - v_f)
  + K_i int e) / K_T0 (PID with inertia feed-forward, nominal K_T0).  The current loop is ideal.

  Current sensor: first-order low-pass (time constant tau_s, exact ZOH discretisation), its own
  offset i_0(t) (constant, or a ramp for the records' offset drift), white noise, and an ADC of
  `adc_bits` over +-adc_range.  Thermal torque constant: the motor warms as
      dT(t) = dT_inf (1 - exp(-t / tau_th)),   K_T(t) = K_T0 (1 - alpha dT(t))
  while the test converts with K_T0, so the torque of a position is multiplied by
  K_T0 / K_T(t) = 1 / (1 - alpha dT(t)).

  Integration: own fixed-step classical Runge-Kutta 4 on (phi, phi', z), all positions of the whole
  suite integrated at once as numpy vectors, one (tables) or two (records) steps per sample.

  The test's torque of a position (Eq. 21 of the paper):  M_meas = K_T0 * mean(i_ADC) over whole
  periods after one settling period.  Over a symmetric periodic oscillation J phi'', the friction,
  k_c phi and cogging average to (nearly) constants, so the closed-form limit (no friction, no
  noise, no effects) is
      M_meas = [U sin(theta + b) J0(A) + M_K] / (1 - alpha dT) + K_T0 i_0            (2)
  (J0 = Bessel function: the mean of sin(theta + b + A sin wt) is sin(theta + b) J0(A)).
  test_third_generator.py checks (2) against the integration.

  Table-level artifacts added to M_meas (measurement artifacts, not torques):
      position noise  e_k, white or AR(1) in time order  (e_k = rho e_{k-1} + sqrt(1-rho^2) sigma w_k)
      linear drift    d t / t_end;   saturating drift  d (1 - exp(-t/tau));  step  s [t >= t_s]
      cable hysteresis  +h/2 on sweep +1, -h/2 on sweep -1 (split sweep: out, then back)
      outlier  o at one row;  9th harmonic  a9 sin(9 theta + c9);  sawtooth in time
      a_s (frac(t / T_s) - 1/2)  (a sensor re-zeroed every T_s)

DETECTABILITY (this generator's own criterion, from the planted parameters and the known noise)
----------------------------------------------------------------------------------------------
Tables: s = the effect's noise-free contribution to the torque column (closed form), X0 = [1,
sin theta, cos theta]; r = (I - X0 X0^+) s is the part of the effect no re-fit of the base model
can absorb; z = ||r|| / sigma (the matched-filter signal-to-noise ratio of a known shape in white
noise of the known position sigma).  Detectable when z >= 3 for a shape Poise would know up to
its size (2nd harmonic, K_T drift, linear drift, direction offset), z >= 4 when a location or
time constant has to be scanned (step, outlier, saturating drift: look-elsewhere), z >= 5 for
shapes outside any candidate list (9th harmonic, sawtooth), found only by omnibus tests.
AR(1): detectable when rho sqrt(n) >= 3 (lag-1 autocorrelation at 3 of its null SEs).  A bent
shaft is a pure first harmonic: z = 0, never detectable (the estimate takes it, by physics).
Records: s = the effect's closed-form torque along the true motion of a clean twin integrated
with the same noise (cogging A_c sin(N phi + c); K_T0 times the offset ramp; for the friction
asymmetry the LuGre steady-state excess a g(v)), X0 = the base regressors [phi'', phi', sgn phi',
phi, 1] of that motion, sigma_eff = rms residual of the clean twin against X0 (sensor noise plus the misfit of LuGre/filter to the base model);
detectable when ||r|| / sigma_eff >= 4 (offset drift, a known ramp) or >= 5 (cogging, order
scanned) and, for cogging, at least one cycle of order N fits in the peak-to-peak swing
(N * 2A >= 2 pi): a fraction of a cycle is a smooth curvature in phi that a spring, an offset
or any other smooth law explains as well, so it is not identifiable *as cogging*.  A constant friction asymmetry is a constant at one position: z ~ 0.

Usage:  generate.py OUTDIR [--seed 3] [--small]
"""
import argparse
import json
import math
import os

import numpy as np

KT0 = 0.05  # N*m/A, nominal torque constant (the conversion the test uses)
G_MNM = 1e3  # N*m -> mN*m

# Rig defaults (SI).  Magnitudes follow Yang 2015 (U ~ 12.9 mN*m, M_K ~ 3.5 mN*m, residual
# ~0.2 mN*m) and the record Poise simulates (J ~ 1e-3 kg m^2, Coulomb ~1.4 mN*m).
RIG = dict(
    J=1.0e-3, Jn=1.0e-3,
    Fc=1.2e-3, Fs=1.8e-3, vs=0.02, vd=0.01, sigma0=8.0, sigma1=0.02, sigma2=4.0e-3, a_f=0.0,
    kc=1.0e-3,  # N*m/rad cable spring
    A_deg=2.0, T=1.0,
    Kp=9.0, Kd=0.13, Ki=80.0, vel_fc=60.0,
    enc_bits=20,
    sensor_tau=1.0 / (2 * math.pi * 300.0), adc_bits=12, adc_range=2.0,
    noise_i=2.0e-3,  # A rms sensor noise per sample
    i0=0.0,  # A constant sensor offset
    cog_amp=0.0, cog_N=1.0, cog_ph=0.0,
    Ua=0.0, ba=0.0, M2=0.0, b2=0.0,
    alpha=0.0015, dT_inf=0.0, tau_th=180.0,
)

THRESH = dict(sag_harmonic2=3.0, thermal_kt=3.0, linear_drift=3.0, direction_offset=3.0,
              step=4.0, outlier=4.0, saturating_drift=4.0, harmonic9=5.0, sawtooth=5.0,
              ar1=3.0, bent_shaft=float('inf'),
              cogging=5.0, offset_drift=4.0, friction_asymmetry=4.0)


# ----------------------------------------------------------------------------------------------
# The integrator: every oscillator (one per turntable position or record) as a numpy vector.
# ----------------------------------------------------------------------------------------------
def _rhs(p, th, KT, i_cmd, phi, om, z):
    """Right-hand side of (1) and the LuGre bristle state."""
    sgn = np.sign(om)
    fcd = p['Fc'] * (1.0 + p['a_f'] * sgn)
    fsd = p['Fs'] * (1.0 + p['a_f'] * sgn)
    g = np.maximum(fcd + (fsd - fcd) * np.exp(-(om / p['vs']) ** 2), 1e-12)
    dz = om - p['sigma0'] * np.abs(om) * z / g
    ff = p['sigma0'] * z + p['sigma1'] * np.exp(-(om / p['vd']) ** 2) * dz + p['sigma2'] * om
    load = (p['U'] * np.sin(th + p['b'] + phi) + p['Ua'] * np.sin(th + p['ba'] + phi)
            + p['M2'] * np.sin(2.0 * (th + phi) + p['b2']) + p['MK'] + p['kc'] * phi)
    cog = p['cog_amp'] * np.sin(p['cog_N'] * phi + p['cog_ph'])
    acc = (KT * i_cmd - load - ff - cog) / p['J']
    return om, acc, dz


def simulate(p, fs, substeps, settle_periods, meas_periods, noise_seeds=None, rng=None,
             offset_ramp=None, keep_series=False):
    """Integrates every oscillator of the parameter dict p (arrays of equal length P).

    Returns the mean ADC current over the measuring window (whole periods) and, with
    keep_series, (t, i_adc, phi_enc, phi_true, om_true, acc_true) over that window.
    Noise: per-oscillator generators seeded by noise_seeds (records: twins share noise), or
    one generator rng drawing a vector per sample (tables).
    offset_ramp: array (P,) of sensor offset change over the measuring window (A), or None.
    """
    P = len(p['theta'])
    T = p['T']
    A = np.deg2rad(p['A_deg'])
    w = 2 * np.pi / T
    n_settle = int(round(settle_periods * T[0] * fs))
    n_meas = int(round(meas_periods * T[0] * fs))
    n = n_settle + n_meas
    h = 1.0 / fs / substeps
    th = p['theta']
    KT = KT0 * (1.0 - p['alpha'] * p['dT'])
    q_enc = 2 * np.pi / 2.0 ** p['enc_bits']
    q_adc = 2 * p['adc_range'] / 2.0 ** p['adc_bits']
    a_v = 1.0 - np.exp(-2 * np.pi * p['vel_fc'] / fs)
    a_s = 1.0 - np.exp(-1.0 / (fs * p['sensor_tau']))
    if noise_seeds is not None:
        noise = np.stack([np.random.default_rng(int(s)).standard_normal(n) for s in noise_seeds], 1)
    phi = np.zeros(P)
    om = np.zeros(P)
    z = np.zeros(P)
    # The servo held the gimbal while the turntable moved: its integrator starts at the static load.
    integ = (p['U'] * np.sin(th + p['b']) + p['Ua'] * np.sin(th + p['ba'])
             + p['M2'] * np.sin(2 * th + p['b2']) + p['MK']) / p['Ki']
    vf = np.zeros(P)
    phim_prev = np.zeros(P)
    isens = integ * p['Ki'] / KT0
    acc_sum = np.zeros(P)
    if keep_series:
        ser = {k: np.zeros((n_meas, P)) for k in ('i', 'phim', 'phi', 'om', 'acc')}
    for k in range(n):
        t = k / fs
        phim = q_enc * np.round(phi / q_enc)
        vf = vf + a_v * ((phim - phim_prev) * fs - vf)
        phim_prev = phim
        s, c = np.sin(w * t), np.cos(w * t)
        e = A * s - phim
        integ = integ + e / fs
        u = p['Jn'] * (-A * w * w * s) + p['Kp'] * e + p['Kd'] * (A * w * c - vf) + p['Ki'] * integ
        i_cmd = u / KT0
        # ADC sample of the sensor at t (filter state), then the sensor filter advances.
        nz = noise[k] if noise_seeds is not None else rng.standard_normal(P)
        off = p['i0']
        if offset_ramp is not None and k >= n_settle:
            off = off + offset_ramp * (k - n_settle) / n_meas
        i_adc = q_adc * np.round((isens + off + p['noise_i'] * nz) / q_adc)
        if k >= n_settle:
            acc_sum += i_adc
            if keep_series:
                j = k - n_settle
                ser['i'][j] = i_adc
                ser['phim'][j] = phim
                ser['phi'][j] = phi
                ser['om'][j] = om
                ser['acc'][j] = _rhs(p, th, KT, i_cmd, phi, om, z)[1]
        isens = isens + a_s * (i_cmd - isens)
        for _ in range(substeps):
            k1 = _rhs(p, th, KT, i_cmd, phi, om, z)
            k2 = _rhs(p, th, KT, i_cmd, phi + 0.5 * h * k1[0], om + 0.5 * h * k1[1], z + 0.5 * h * k1[2])
            k3 = _rhs(p, th, KT, i_cmd, phi + 0.5 * h * k2[0], om + 0.5 * h * k2[1], z + 0.5 * h * k2[2])
            k4 = _rhs(p, th, KT, i_cmd, phi + h * k3[0], om + h * k3[1], z + h * k3[2])
            phi = phi + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            om = om + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            z = z + h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
    mean_i = acc_sum / n_meas
    if keep_series:
        tt = np.arange(n_meas) / fs
        return mean_i, (tt, ser)
    return mean_i


def bessel_j0(x):
    return float(np.real(np.mean(np.exp(1j * x * np.sin(np.linspace(0, 2 * np.pi, 4096, endpoint=False))))))


def closed_form_torque_mNm(U, b, MK, theta, A_deg, alpha=0.0, dT=0.0, i0=0.0):
    """Eq. (2): the no-friction, no-noise limit of the measured torque of a position."""
    return (G_MNM * (U * np.sin(theta + b) * bessel_j0(np.deg2rad(A_deg)) + MK) / (1 - alpha * dT)
            + G_MNM * KT0 * i0)


def param_vectors(rows):
    """rows: list of dicts of per-oscillator parameters over RIG -> dict of arrays."""
    keys = set(RIG) | {'theta', 'U', 'b', 'MK', 'dT'}
    out = {}
    for k in keys:
        out[k] = np.array([float(r.get(k, RIG.get(k, 0.0))) for r in rows])
    return out


# ----------------------------------------------------------------------------------------------
# Tables
# ----------------------------------------------------------------------------------------------
def design(kind):
    """Turntable positions (deg), sweep and time of each row.  12 s per position."""
    if kind == 'mono36':
        th = np.arange(36) * 10.0
        sw = np.ones(36)
    elif kind == 'mono18':
        th = np.arange(18) * 20.0
        sw = np.ones(18)
    elif kind == 'split36':  # out at 0, 20, ..., 340 then back at 350, 330, ..., 10
        th = np.concatenate([np.arange(18) * 20.0, 350.0 - np.arange(18) * 20.0])
        sw = np.concatenate([np.ones(18), -np.ones(18)])
    else:
        raise ValueError(kind)
    t = 6.0 + 12.0 * np.arange(len(th))
    return th, sw, t


def base_design_matrix(th_deg):
    r = np.deg2rad(th_deg)
    return np.column_stack([np.ones_like(r), np.sin(r), np.cos(r)])


def orth_norm(X, s):
    coef, *_ = np.linalg.lstsq(X, s, rcond=None)
    return float(np.linalg.norm(s - X @ coef))


def artifact_signal(fam, prm, th, sw, t):
    """Noise-free contribution (mN*m) of a measurement artifact to the torque column."""
    if fam == 'linear_drift':
        return prm['d_mNm'] * (t - t[0]) / (t[-1] - t[0])
    if fam == 'saturating_drift':
        return prm['d_mNm'] * (1 - np.exp(-(t - t[0]) / prm['tau_s']))
    if fam == 'step':
        return prm['s_mNm'] * (np.arange(len(t)) >= prm['row'])
    if fam == 'direction_offset':
        return 0.5 * prm['h_mNm'] * sw
    if fam == 'outlier':
        s = np.zeros(len(t))
        s[prm['row']] = prm['o_mNm']
        return s
    if fam == 'harmonic9':
        return prm['a_mNm'] * np.sin(9 * np.deg2rad(th) + prm['phase_rad'])
    if fam == 'sawtooth':
        return prm['a_mNm'] * (np.mod(t / prm['period_s'], 1.0) - 0.5)
    return np.zeros(len(t))


def physics_signal(fam, prm, spec, th, t):
    """Closed-form noise-free contribution (mN*m) of a physical effect (for detectability)."""
    r = np.deg2rad(th)
    if fam == 'sag_harmonic2':
        return prm['M2_mNm'] * np.sin(2 * r + prm['b2_rad'])
    if fam == 'thermal_kt':
        dT = prm['dT_inf_K'] * (1 - np.exp(-t / prm['tau_th_s']))
        m = spec['U_mNm'] * np.sin(r + np.deg2rad(spec['b_deg'])) + spec['MK_mNm']
        return m * (1 / (1 - prm['alpha_per_K'] * dT) - 1)
    if fam == 'bent_shaft':
        return prm['Ua_mNm'] * np.sin(r + prm['ba_rad'])
    return np.zeros(len(t))


PHYSICAL = {'sag_harmonic2', 'thermal_kt', 'bent_shaft'}


def effect_signal(fam, prm, spec, th, sw, t):
    """Noise-free contribution (mN*m) of any deterministic effect, physical or artifact."""
    return physics_signal(fam, prm, spec, th, t) if fam in PHYSICAL else artifact_signal(fam, prm, th, sw, t)


def effect_z(fam, prm, spec, th, sw, t):
    X = base_design_matrix(th)
    if fam == 'ar1':
        return prm['rho'] * math.sqrt(len(th))
    return orth_norm(X, effect_signal(fam, prm, spec, th, sw, t)) / spec['sigma_mNm']


SIZE_KEY = dict(sag_harmonic2='M2_mNm', thermal_kt='dT_inf_K', linear_drift='d_mNm',
                saturating_drift='d_mNm', step='s_mNm', direction_offset='h_mNm', outlier='o_mNm',
                harmonic9='a_mNm', sawtooth='a_mNm', bent_shaft='Ua_mNm')


def sized(fam, prm, spec, target_z):
    """Scales the family's size parameter so that its z reaches target_z (z is ~linear in size)."""
    th, sw, t = design(spec['design'])
    key = SIZE_KEY[fam]
    prm = dict(prm)
    prm[key] = 1.0
    z1 = effect_z(fam, prm, spec, th, sw, t)
    prm[key] = target_z / z1
    for _ in range(3):  # the thermal law is slightly non-linear
        z = effect_z(fam, prm, spec, th, sw, t)
        prm[key] *= target_z / z
    prm[key] = float(round(prm[key], 5))
    return prm


def table_specs(seed, small=False):
    rng = np.random.default_rng(seed)
    specs = []

    def base(name, design_kind, sigma=0.2):
        return dict(name=name, design=design_kind, U_mNm=float(round(rng.uniform(7.0, 16.0), 3)),
                    b_deg=float(round(rng.uniform(0, 360), 2)), MK_mNm=float(round(rng.uniform(2.0, 4.0), 3)),
                    sigma_mNm=sigma, noise_seed=int(rng.integers(1 << 30)), effects=[])

    n_clean = 10 if small else 16
    designs = ['mono36', 'split36', 'mono18', 'mono36']
    for k in range(n_clean):
        specs.append(base(f'table_clean_{k:02d}', designs[k % 4], sigma=[0.2, 0.1, 0.25][k % 3]))
    zs = [2.0, 4.5, 8.0] if small else [2.0, 3.5, 6.0, 12.0]

    def add(fam, design_kind, prm, targets):
        for j, zt in enumerate(targets):
            sp = base(f'table_{fam}_{j}', design_kind)
            sp['effects'].append(dict(family=fam, params=sized(fam, prm, sp, zt)))
            specs.append(sp)

    add('sag_harmonic2', 'mono36', dict(b2_rad=float(rng.uniform(0, 2 * np.pi))), zs)
    add('thermal_kt', 'split36', dict(alpha_per_K=0.0015, tau_th_s=180.0), zs)
    add('linear_drift', 'split36', {}, zs[:3] if not small else zs[:2])
    add('saturating_drift', 'split36', dict(tau_s=90.0), zs[:3] if not small else zs[:2])
    add('step', 'split36', dict(row=23), zs[:3] if not small else zs[:2])
    add('direction_offset', 'split36', {}, zs[:3] if not small else zs[:2])
    add('outlier', 'mono36', dict(row=13), zs[1:] if not small else zs[1:])
    add('harmonic9', 'mono36', dict(phase_rad=0.7), [3.0, 9.0] if not small else [9.0])
    add('sawtooth', 'split36', dict(period_s=120.0), [3.0, 9.0] if not small else [9.0])
    for j, rho in enumerate([0.3, 0.6, 0.85] if not small else [0.3, 0.85]):
        sp = base(f'table_ar1_{j}', 'mono36')
        sp['effects'].append(dict(family='ar1', params=dict(rho=rho)))
        specs.append(sp)
    for j, ua in enumerate([1.0, 3.0] if not small else [3.0]):
        sp = base(f'table_bent_shaft_{j}', 'mono36')
        sp['effects'].append(dict(family='bent_shaft', params=dict(Ua_mNm=ua, ba_rad=1.9)))
        specs.append(sp)
    for sp in specs:
        th, sw, t = design(sp['design'])
        for e in sp['effects']:
            e['z'] = float(round(effect_z(e['family'], e['params'], sp, th, sw, t), 3))
            e['threshold'] = THRESH[e['family']]
            e['detectable'] = bool(e['z'] >= THRESH[e['family']])
    return specs


def generate_tables(specs, outdir, seed, rig_overrides=None):
    rows, owner = [], []
    for si, sp in enumerate(specs):
        th, sw, t = design(sp['design'])
        eff = {e['family']: e['params'] for e in sp['effects']}
        for k in range(len(th)):
            r = dict(RIG)
            r.update(rig_overrides or {})
            r.update(sp.get('rig', {}))
            r.update(theta=np.deg2rad(th[k]), U=sp['U_mNm'] / G_MNM, b=np.deg2rad(sp['b_deg']),
                     MK=sp['MK_mNm'] / G_MNM, dT=0.0)
            if 'sag_harmonic2' in eff:
                r.update(M2=eff['sag_harmonic2']['M2_mNm'] / G_MNM, b2=eff['sag_harmonic2']['b2_rad'])
            if 'thermal_kt' in eff:
                q = eff['thermal_kt']
                r.update(alpha=q['alpha_per_K'], dT=q['dT_inf_K'] * (1 - math.exp(-t[k] / q['tau_th_s'])))
            if 'bent_shaft' in eff:
                r.update(Ua=eff['bent_shaft']['Ua_mNm'] / G_MNM, ba=eff['bent_shaft']['ba_rad'])
            rows.append(r)
            owner.append(si)
    p = param_vectors(rows)
    mean_i = simulate(p, fs=2000.0, substeps=1, settle_periods=1, meas_periods=3,
                      rng=np.random.default_rng(seed + 1000))
    owner = np.array(owner)
    entries = []
    for si, sp in enumerate(specs):
        th, sw, t = design(sp['design'])
        m = G_MNM * KT0 * mean_i[owner == si]
        rng = np.random.default_rng(sp['noise_seed'])
        w = rng.standard_normal(len(th))
        eff = {e['family']: e['params'] for e in sp['effects']}
        if 'ar1' in eff:
            rho = eff['ar1']['rho']
            e = np.zeros(len(th))
            e[0] = w[0]
            for k in range(1, len(th)):
                e[k] = rho * e[k - 1] + math.sqrt(1 - rho * rho) * w[k]
            w = e
        m = m + sp['sigma_mNm'] * w
        for fam, prm in eff.items():
            if fam not in PHYSICAL:
                m = m + artifact_signal(fam, prm, th, sw, t)
        fn = sp['name'] + '.csv'
        with open(os.path.join(outdir, fn), 'w') as f:
            f.write('theta_deg,torque_mNm,time_s,sweep\n')
            for k in range(len(th)):
                f.write(f'{th[k]:.2f},{m[k]:.4f},{t[k]:.1f},{int(sw[k])}\n')
        entries.append(dict(file=fn, kind='table', design=sp['design'], n_points=len(th),
                            U_mNm=sp['U_mNm'], b_deg=sp['b_deg'], MK_mNm=sp['MK_mNm'],
                            noise_sigma_mNm=sp['sigma_mNm'], effects=sp['effects'],
                            clean=not sp['effects']))
    return entries


# ----------------------------------------------------------------------------------------------
# Records
# ----------------------------------------------------------------------------------------------
RECORD_FS = 2000.0
RECORD_PERIODS = 3


def record_specs(seed, small=False):
    rng = np.random.default_rng(seed + 7)
    specs = []

    def base(name):
        return dict(name=name, theta_deg=float(round(rng.uniform(0, 360), 1)),
                    U_mNm=float(round(rng.uniform(8.0, 15.0), 3)), b_deg=float(round(rng.uniform(0, 360), 2)),
                    MK_mNm=float(round(rng.uniform(2.0, 4.0), 3)), noise_seed=int(rng.integers(1 << 30)),
                    effects=[])

    for k in range(3 if small else 6):
        specs.append(base(f'record_clean_{k:02d}'))
    cog = ([(24, 0.3), (120, 0.05), (180, 0.3), (300, 0.1)] if small else
           [(24, 0.3), (36, 0.2), (120, 0.03), (120, 0.1), (180, 0.3), (240, 0.05), (300, 0.15), (450, 0.4)])
    for j, (N, a) in enumerate(cog):
        sp = base(f'record_cogging_{j}')
        sp['effects'].append(dict(family='cogging', params=dict(order=N, amplitude_mNm=a, phase_rad=0.4)))
        specs.append(sp)
    for j, d in enumerate([0.3, 1.0, 3.0] if small else [0.2, 0.5, 1.0, 3.0]):
        sp = base(f'record_offset_drift_{j}')
        sp['effects'].append(dict(family='offset_drift', params=dict(drift_mA=d)))
        specs.append(sp)
    for j, a in enumerate([0.2] if small else [0.1, 0.3]):
        sp = base(f'record_friction_asymmetry_{j}')
        sp['effects'].append(dict(family='friction_asymmetry', params=dict(a_f=a)))
        specs.append(sp)
    if not small:
        sp = base('record_cogging_and_drift')
        sp['effects'].append(dict(family='cogging', params=dict(order=200, amplitude_mNm=0.2, phase_rad=1.0)))
        sp['effects'].append(dict(family='offset_drift', params=dict(drift_mA=1.5)))
        specs.append(sp)
    return specs


def generate_records(specs, outdir):
    rows, ramps, seeds = [], [], []
    for twin in (0, 1):  # 0: with the planted effects, 1: clean twin with the same noise
        for sp in specs:
            r = dict(RIG)
            r.update(theta=np.deg2rad(sp['theta_deg']), U=sp['U_mNm'] / G_MNM, b=np.deg2rad(sp['b_deg']),
                     MK=sp['MK_mNm'] / G_MNM, dT=0.0)
            ramp = 0.0
            if twin == 0:
                for e in sp['effects']:
                    q = e['params']
                    if e['family'] == 'cogging':
                        r.update(cog_amp=q['amplitude_mNm'] / G_MNM, cog_N=q['order'], cog_ph=q['phase_rad'])
                    elif e['family'] == 'offset_drift':
                        ramp = q['drift_mA'] * 1e-3
                    elif e['family'] == 'friction_asymmetry':
                        r.update(a_f=q['a_f'])
            rows.append(r)
            ramps.append(ramp)
            seeds.append(sp['noise_seed'])
    p = param_vectors(rows)
    _, (tt, ser) = simulate(p, fs=RECORD_FS, substeps=2, settle_periods=1, meas_periods=RECORD_PERIODS,
                            noise_seeds=seeds, offset_ramp=np.array(ramps), keep_series=True)
    n = len(specs)
    A = np.deg2rad(RIG['A_deg'])
    entries = []
    for j, sp in enumerate(specs):
        i_w, i_c = ser['i'][:, j], ser['i'][:, n + j]
        X = np.column_stack([ser['acc'][:, n + j], ser['om'][:, n + j], np.sign(ser['om'][:, n + j]),
                             ser['phi'][:, n + j], np.ones(len(tt))])
        yc = G_MNM * KT0 * i_c
        coef, *_ = np.linalg.lstsq(X, yc, rcond=None)
        sig_eff = float(np.sqrt(np.mean((yc - X @ coef) ** 2)))
        phi_c, om_c = ser['phi'][:, n + j], ser['om'][:, n + j]
        for e in sp['effects']:  # each effect's closed-form torque along the clean twin's motion
            q = e['params']
            if e['family'] == 'cogging':
                s1 = q['amplitude_mNm'] * np.sin(q['order'] * phi_c + q['phase_rad'])
            elif e['family'] == 'offset_drift':
                s1 = G_MNM * KT0 * q['drift_mA'] * 1e-3 * np.arange(len(tt)) / len(tt)
            else:  # LuGre steady state g(v) sgn v with F_c,F_s scaled by (1 + a sgn v): + a g(v)
                s1 = G_MNM * q['a_f'] * (RIG['Fc'] + (RIG['Fs'] - RIG['Fc']) * np.exp(-(om_c / RIG['vs']) ** 2))
            e['z'] = float(round(orth_norm(X, s1) / sig_eff, 3))
            e['threshold'] = THRESH[e['family']]
            e['detectable'] = bool(e['z'] >= e['threshold'])
            if e['family'] == 'cogging':  # a cycle must fit in the swing, whatever the size
                e['cycles_over_swing'] = float(round(e['params']['order'] * 2 * A / (2 * np.pi), 3))
                e['detectable'] = e['detectable'] and e['cycles_over_swing'] >= 1.0
        fn = sp['name'] + '.csv'
        with open(os.path.join(outdir, fn), 'w') as f:
            f.write('time_s,current_A,phi_deg\n')
            phid = np.rad2deg(ser['phim'][:, j])
            for k in range(len(tt)):
                f.write(f'{tt[k]:.6f},{i_w[k]:.9f},{phid[k]:.9f}\n')
        th = np.deg2rad(sp['theta_deg'])
        true_t = G_MNM * (sp['U_mNm'] / G_MNM * math.sin(th + np.deg2rad(sp['b_deg'])) * bessel_j0(A)
                          + sp['MK_mNm'] / G_MNM)
        entries.append(dict(file=fn, kind='record', theta_deg=sp['theta_deg'], U_mNm=sp['U_mNm'],
                            b_deg=sp['b_deg'], MK_mNm=sp['MK_mNm'], kt_N_m_per_A=KT0,
                            true_torque_mNm=float(round(true_t, 6)),
                            eq21_clean_twin_mNm=float(round(float(np.mean(yc)), 6)),
                            sigma_eff_mNm=float(round(sig_eff, 5)), fs_Hz=RECORD_FS,
                            effects=sp['effects'], clean=not sp['effects']))
    return entries


def generate(outdir, seed=3, small=False):
    os.makedirs(outdir, exist_ok=True)
    tables = generate_tables(table_specs(seed, small), outdir, seed)
    records = generate_records(record_specs(seed, small), outdir)
    man = dict(generator='tests/third_gimbal_data/generate.py', seed=seed, small=small,
               rig=RIG, thresholds={k: (v if math.isfinite(v) else None) for k, v in THRESH.items()},
               files=tables + records)
    with open(os.path.join(outdir, 'manifest.json'), 'w') as f:
        json.dump(man, f, indent=1)
    return man


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('outdir')
    ap.add_argument('--seed', type=int, default=3)
    ap.add_argument('--small', action='store_true', help='fewer files (quick runs)')
    a = ap.parse_args()
    man = generate(a.outdir, a.seed, a.small)
    print(f"wrote {len(man['files'])} files and manifest.json to {a.outdir}")


if __name__ == '__main__':
    main()
