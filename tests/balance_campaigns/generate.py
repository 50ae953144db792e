#!/usr/bin/env python3
r"""Simulated two-plane field-balancing campaigns from a physical rigid-rotor model.

Independent test-data generator for Poise's influence-coefficient estimator.
Python 3 standard library + numpy only.

    python3 generate.py --out DIR --count N --seed S \
        --effect none|nonlinear|crosstalk|offset|lead_phase|none_two_speeds [--check-runs K] \
        [--mount-angles with|against]
    python3 generate.py --self-check

Every convention below is derived from the model and verified by --self-check
(time-domain RK4 integration of the equations of motion, peak picking, fits).

1. Frame and rotation
---------------------
Right-handed lab frame: z along the shaft from bearing b1 (z = 0) to bearing b2
(z = L); x and y transverse.  The rotor spins at +Omega about +z, i.e. a point
of the rotor moves from +x toward +y ("direction of rotation" = from x to y).
A notch on the rotor (rotor angle 0) triggers the keyphasor, mounted at lab
angle 0 (+x): the once-per-revolution event happens at t = 2 pi n / Omega.  At
time t the notch is at lab angle Omega t, and a rotor point at angle theta
counted WITH rotation from the notch is at lab angle Omega t + theta.

2. Equations of motion (4 DOF, rigid rotor)
-------------------------------------------
q = [xG, yG, a, b]: translation of the centre of mass G (axial position zG) and
the slopes a = dx/dz, b = dy/dz of the shaft line, so the shaft at axial
position z is at  x(z) = Tx(z) q,  y(z) = Ty(z) q  with
    Tx(z) = [1, 0, z - zG, 0],   Ty(z) = [0, 1, 0, z - zG].
Small rotations: theta_y = a, theta_x = -b; the spin axis is n = (a, b, 1).
Angular momentum H = It (theta_x', theta_y') + Ip Omega n; dH/dt = moment
about G.  A force (Fx, Fy) at z gives the moment ((zG - z) Fy, (z - zG) Fx),
and, rewriting in (a, b):
    M xG''                = sum Fx
    M yG''                = sum Fy
    It a'' + Ip Omega b'  = sum (z - zG) Fx
    It b'' - Ip Omega a'  = sum (z - zG) Fy
i.e.  Mm q'' + (C + Omega G) q' + K q = Q(t),  Mm = diag(M, M, It, It),
G[2,3] = +Ip, G[3,2] = -Ip (skew, gyroscopic).  The generalised force of a
force at z is Q = Tx(z)^T Fx + Ty(z)^T Fy (virtual work).  Bearing j (axial
position zb_j) pushes back with  Fx = -kx_j x(zb_j) - cx_j x'(zb_j) and the
same in y, so K = sum_j kx_j Tx^T Tx + ky_j Ty^T Ty and C likewise.
(Check: the forward conical whirl frequency rises with Omega - gyroscopic
stiffening - as it must for rotation from x to y; verified in --self-check.)
Nonlinear variant: hardening support, Fx = -kx x - k3x x^3 (same in y).

3. Unbalance forcing and steady state
-------------------------------------
Mass m at radius r, axial position z, rotor angle theta (with rotation):
    F = m r Omega^2 [cos(Omega t + theta), sin(Omega t + theta)]
      = Re( Omega^2 U [1, -i] e^{i Omega t} ),   U = m r e^{i theta}.
With q = Re(qh e^{i Omega t}):
    D(Omega) qh = Omega^2 sum_planes U_p (Tx(z_p) - i Ty(z_p))^T,
    D(Omega) = K - Omega^2 Mm + i Omega (C + Omega G).
qh is complex-LINEAR in the U_p (a real linear system with phasor forcing);
anisotropic supports give elliptical (forward + backward) orbits, nothing
else changes.

4. Probe reading, phase lag, peak-to-peak
-----------------------------------------
A probe at mounting angle alpha (counted from +x in the direction of
rotation) at bearing j reads the projection of the shaft displacement on its
axis: s(t) = cos(alpha) x(zb_j) + sin(alpha) y(zb_j) = Re(S e^{i Omega t})
with S = cos(alpha) Xh_j + sin(alpha) Yh_j.  Hence
    s(t) = |S| cos(Omega t + arg S):
the positive peak comes at Omega t = -arg S (mod 360 deg) after the keyphasor
event, so the PHASE LAG (rotation angle from the keyphasor to the positive
peak) is  lag = -arg S,  and the 1X amplitude is  pp = 2 |S|  (peak-to-peak).
The instrument phasor  P = pp e^{-i lag} = 2 S  is complex-linear in U.
Each probe measures its own direction: the x probe (alpha = 0) sees x only,
the y probe (alpha = 90 deg) sees y only; for a forward circular orbit the y
probe peaks a quarter turn after the x probe, lag_y = lag_x + 90 deg
(verified by peak picking on the time-domain signals in --self-check).

5. What the tool's rule requires (derived)
------------------------------------------
Poise forms  R = pp e^{i(lag + alpha_decl)} = conj(P) e^{i alpha_decl}.
conj(P) is linear in conj(U) = m r e^{-i theta}.  So R is linear in
mass * e^{i angle} exactly when  angle = -theta:

    WEIGHT ANGLES ARE COUNTED AGAINST ROTATION from the keyphasor notch
    (the same sense as the phase lag).  campaign.toml, truth.json: all
    weight angles follow this rule.

Counted with rotation the data would be anti-linear (the fit fails exactly as
for a reversed phase sign); --self-check demonstrates both.  Physically:
for a stiff rotor at low speed (high spot = heavy spot) a weight at angle beta
(against rotation) gives an x-probe lag of beta and a y-probe lag of
beta + 90 deg.

Mounting angles: any constant declared angle keeps R linear (it is a constant
factor per sensor).  By default the probes are declared with their physical
angle counted WITH rotation (x "0 deg", y "90 deg").  Under the tool's
lag + angle rule that gives, for an isotropic machine, h(y) = -h(x) (the two
rotations add instead of cancelling).  Declaring mounting angles AGAINST
rotation (--mount-angles against: y probe "270 deg") makes lag + angle the
high-spot angle on the rotor counted against rotation, identical for every
probe of an isotropic machine (h(y) = h(x)); both are verified.  Influence
coefficients per sensor are the same physics either way; only the constant
e^{i alpha_decl} factor in the "tool" form of truth.json changes.

6. Effects (--effect)
---------------------
none        linear physics + noise.
nonlinear   cubic hardening supports, Fx = -k x - k3 x^3; one-term harmonic
            balance: the fundamental of x^3 for x = Re(X e^{i Omega t}) is
            (3/4)|X|^2 x, so each support acts as k_eff = k + 3/4 k3 |X|^2,
            solved per run by Newton's method (analytic Jacobian).  k3 is
            tuned so the tool's noise-free linear fit leaves 3-10 % relative
            residual, with at most 30 % stiffening at the as-found amplitude
            (machines where that cannot show are redrawn); a 3-rung mass
            ladder (same plane and angle, x1, x2, x3) is included.
crosstalk   each y probe reads y + c x at its bearing, c in [0.05, 0.20].
none_two_speeds  clean physics read at two speeds, as offset's campaigns (a control for
            the runout test: no runout planted).
offset      a constant runout phasor per probe (pp um, random lag) added to
            every reading; every run is read at two speeds (speed_rpm column).
lead_phase  the instrument reports phase LEAD = -lag (mod 360) while the
            campaign declares "lag"; >= 2 trial angles in one plane.
Noise: independent circular complex Gaussian added to each reading's phasor
P (pp um): re and im each sd/sqrt(2), E|n|^2 = sd^2 (truth.json noise_sd_um),
sd = 1-5 % of the RMS as-found reading.
"""
from __future__ import annotations

import argparse
import cmath
import json
import math
import os
import sys
import time

import numpy as np

RHO_STEEL = 7850.0
EFFECTS = ("none", "nonlinear", "crosstalk", "offset", "lead_phase", "none_two_speeds")
PLANES = ("left", "right")
# name, bearing index, physical mounting angle in deg counted WITH rotation from +x
SENSORS = (("b1_x", 0, 0.0), ("b1_y", 0, 90.0), ("b2_x", 1, 0.0), ("b2_y", 1, 90.0))
STREAM_ROTOR, STREAM_STRUCT, STREAM_EFFECT, STREAM_NOISE = 1, 2, 3, 4
TWO_PI = 2.0 * math.pi
GENERATOR_VERSION = 1


# --------------------------------------------------------------------------
# physics
# --------------------------------------------------------------------------
class Rotor:
    """Rigid rotor on two flexible damped (anisotropic) supports, 4 DOF."""

    def __init__(self, M, It, Ip, zG, zb, kx, ky, cx, cy, zp, rp):
        self.M, self.It, self.Ip, self.zG = float(M), float(It), float(Ip), float(zG)
        self.zb = np.asarray(zb, float)
        self.zp = np.asarray(zp, float)
        self.rp = np.asarray(rp, float)          # plane radii, m
        self.klin = np.array([kx[0], ky[0], kx[1], ky[1]], float)   # x1 y1 x2 y2
        self.clin = np.array([cx[0], cy[0], cx[1], cy[1]], float)
        self.Mm = np.diag([M, M, It, It]).astype(float)
        self.G = np.zeros((4, 4))
        self.G[2, 3], self.G[3, 2] = Ip, -Ip
        self.Tb = np.array([self.Tx(zb[0]), self.Ty(zb[0]), self.Tx(zb[1]), self.Ty(zb[1])])
        self.K = self.Tb.T @ np.diag(self.klin) @ self.Tb
        self.C = self.Tb.T @ np.diag(self.clin) @ self.Tb
        # generalised force of a unit forward unbalance (U = 1 kg m, theta = 0), / Omega^2
        self.Bp = np.array([self.Tx(z) - 1j * self.Ty(z) for z in self.zp])
        # bearing stiffness "shape" matrices E_j = T_j^T T_j
        self.E = np.einsum("ja,jb->jab", self.Tb, self.Tb)

    def Tx(self, z):
        return np.array([1.0, 0.0, z - self.zG, 0.0])

    def Ty(self, z):
        return np.array([0.0, 1.0, 0.0, z - self.zG])

    def dyn(self, Om):
        return self.K - Om * Om * self.Mm + 1j * Om * (self.C + Om * self.G)

    def forcing(self, Om, U):
        """U: (n, 2) complex plane unbalances (kg m, theta counted with rotation)."""
        return Om * Om * (np.asarray(U, complex) @ self.Bp)

    def bearing_disp_linear(self, Om, U):
        """(n, 4) complex bearing displacement phasors [X1, Y1, X2, Y2] (m, 0-pk)."""
        F = self.forcing(Om, U)
        q = np.linalg.solve(self.dyn(Om), F.T).T
        return q @ self.Tb.T

    def bearing_disp_hb(self, Om, U, k3, tol=1e-12, maxit=80):
        """One-term harmonic balance with cubic hardening supports.

        k_eff = k + 3/4 k3 |d|^2 per support direction; unknown dk = k_eff - k;
        Newton on r(dk) = dk - 3/4 k3 |d(dk)|^2 with the analytic Jacobian
        d|d_i|^2/d dk_j = -2 Re(conj(d_i) W_ij d_j), W = Tb D^-1 Tb^T.
        Returns (d (n,4), converged bool array)."""
        F = self.forcing(Om, U)
        n = F.shape[0]
        D0 = self.dyn(Om)
        k3 = np.asarray(k3, float)
        dk = np.zeros((n, 4))
        conv = np.zeros(n, bool)
        d = None
        for _ in range(maxit):
            D = D0[None] + np.einsum("nj,jab->nab", dk, self.E)
            Dinv = np.linalg.inv(D)
            q = np.einsum("nab,nb->na", Dinv, F)
            d = q @ self.Tb.T
            r = dk - 0.75 * k3 * np.abs(d) ** 2
            rel = np.max(np.abs(r) / self.klin, axis=1)
            conv = rel < tol
            if conv.all():
                break
            W = np.einsum("ia,nab,jb->nij", self.Tb, Dinv, self.Tb)
            dd2 = -2.0 * np.real(np.conj(d)[:, :, None] * W * d[:, None, :])
            J = np.eye(4)[None] - 0.75 * k3[None, :, None] * dd2
            step = np.linalg.solve(J, -r[:, :, None])[:, :, 0]
            # keep the step bounded (hardening: dk >= 0)
            lim = 0.5 * (self.klin + dk)
            step = np.clip(step, -lim, lim)
            dk = np.maximum(dk + step, 0.0)
        return d, conv

    def state_matrix(self, Om):
        Minv = np.linalg.inv(self.Mm)
        Z, I = np.zeros((4, 4)), np.eye(4)
        return np.block([[Z, I], [-Minv @ self.K, -Minv @ (self.C + Om * self.G)]])

    def whirl(self, Om):
        """Damped whirl frequencies (rad/s, >0) at speed Om and slowest decay rate."""
        lam = np.linalg.eigvals(self.state_matrix(Om))
        w = np.sort(lam.imag[lam.imag > 1e-9])
        return w, float(np.min(-lam.real))

    def to_json(self):
        return {
            "mass_kg": self.M, "transverse_inertia_kg_m2": self.It,
            "polar_inertia_kg_m2": self.Ip, "cg_z_m": self.zG,
            "bearing_z_m": self.zb.tolist(), "plane_z_m": self.zp.tolist(),
            "plane_radius_mm": (self.rp * 1000).tolist(),
            "kx_N_per_m": self.klin[[0, 2]].tolist(), "ky_N_per_m": self.klin[[1, 3]].tolist(),
            "cx_N_s_per_m": self.clin[[0, 2]].tolist(), "cy_N_s_per_m": self.clin[[1, 3]].tolist(),
            "rotation": "from +x toward +y (positive about +z, b1 at z=0 -> b2 at z=L)",
        }


def projection(crosstalk=(0.0, 0.0)):
    """(4 sensors x 4 bearing dofs) projection; crosstalk c_j adds c_j x_j to y probe j."""
    P = np.zeros((4, 4))
    for i, (_, j, ang) in enumerate(SENSORS):
        c, s = math.cos(math.radians(ang)), math.sin(math.radians(ang))
        P[i, 2 * j] = c if abs(c) > 1e-12 else 0.0
        P[i, 2 * j + 1] = s if abs(s) > 1e-12 else 0.0
        if ang == 90.0:
            P[i, 2 * j] += crosstalk[j]
    return P


def instrument(d, proj):
    """Instrument phasor P = pp * exp(-i lag) in um from bearing phasors d (m, 0-pk)."""
    return 2e6 * (d @ proj.T)


def declared_angles(mount):
    return np.array([ang if mount == "with" else (-ang) % 360.0 for _, _, ang in SENSORS])


def tool_reading(P, mount="with", reported="lag"):
    """What Poise forms from the instrument output: amp*exp(i(phase + alpha_decl))."""
    amp, lag = np.abs(P), -np.angle(P)
    phase = lag if reported == "lag" else -lag
    return amp * np.exp(1j * (phase + np.radians(declared_angles(mount))))


def mass_unbalance(rot, masses):
    """masses: list of (plane, grams, angle_deg counted AGAINST rotation) -> U (2,) kg m."""
    U = np.zeros(2, complex)
    for p, g, beta in masses:
        U[p] += g * 1e-3 * rot.rp[p] * cmath.exp(-1j * math.radians(beta))
    return U


def mass_vector(masses):
    """Tool-side regressors: sum over masses of grams * exp(i angle), per plane."""
    w = np.zeros(2, complex)
    for p, g, beta in masses:
        w[p] += g * cmath.exp(1j * math.radians(beta))
    return w


def influence_inst(rot, Om, proj=None):
    """(4, 2) instrument phasors per gram at angle 0, pp um."""
    proj = projection() if proj is None else proj
    U = np.diag(1e-3 * rot.rp).astype(complex)
    return instrument(rot.bearing_disp_linear(Om, U), proj).T


def fit_tool(W, R):
    """Complex LS of R (n,4) = a + W (n,2) h; returns a (4,), h (2,4), rel residual."""
    X = np.hstack([np.ones((W.shape[0], 1)), W])
    coef, *_ = np.linalg.lstsq(X, R, rcond=None)
    res = R - X @ coef
    return coef[0], coef[1:], float(np.linalg.norm(res) / np.linalg.norm(R))


def rpm2rad(n):
    return TWO_PI * n / 60.0


# --------------------------------------------------------------------------
# formatting
# --------------------------------------------------------------------------
def fmt_sig(x, sig):
    if x == 0:
        return "0"
    d = max(0, sig - 1 - int(math.floor(math.log10(abs(x)))))
    return f"{x:.{d}f}"


def fmt_phase(deg):
    s = f"{deg % 360.0:.4f}"
    return "0.0000" if s == "360.0000" else s


def deg(z):
    return float(math.degrees(cmath.phase(z)) % 360.0)


# --------------------------------------------------------------------------
# campaign generation
# --------------------------------------------------------------------------
def rng_for(seed, idx, stream):
    return np.random.default_rng([int(seed), int(idx), stream])


def loguniform(rs, a, b):
    return float(math.exp(rs.uniform(math.log(a), math.log(b))))


def draw_rotor(rs):
    M = loguniform(rs, 50.0, 500.0)
    L = rs.uniform(0.4, 2.0)
    ell = L * rs.uniform(0.6, 1.0)
    R = math.sqrt(M / (RHO_STEEL * math.pi * ell)) * rs.uniform(1.0, 1.6)
    It = M * (3 * R * R + ell * ell) / 12.0 * rs.uniform(0.8, 1.2)
    Ip = M * R * R / 2.0 * rs.uniform(0.8, 1.2)
    zG = L * rs.uniform(0.35, 0.65)
    zp = [L * rs.uniform(-0.15, 0.25), L * rs.uniform(0.75, 1.15)]
    r1 = min(max(5 * round(R * rs.uniform(0.6, 1.0) * 200), 30), 400)
    r2 = r1 if rs.random() < 0.6 else min(max(5 * round(R * rs.uniform(0.6, 1.0) * 200), 30), 400)
    kx1 = loguniform(rs, 1e7, 1e9)
    kx2 = min(max(kx1 * loguniform(rs, 0.5, 2.0), 1e7), 1e9)
    aniso = rs.random() < 0.7
    kx = [kx1, kx2]
    ky = [min(max(k * loguniform(rs, 0.4, 2.5), 1e7), 1e9) if aniso else k for k in kx]
    zx = [rs.uniform(0.03, 0.2) for _ in range(2)]
    zy = [rs.uniform(0.03, 0.2) for _ in range(2)] if aniso else zx
    cx = [2 * zx[j] * math.sqrt(kx[j] * M / 2) for j in range(2)]
    cy = [2 * zy[j] * math.sqrt(ky[j] * M / 2) for j in range(2)]
    return Rotor(M, It, Ip, zG, [0.0, L], kx, ky, cx, cy, zp, [r1 / 1000.0, r2 / 1000.0])


def margin(rot, n_rpm):
    Om = rpm2rad(n_rpm)
    w, _ = rot.whirl(Om)
    return float(np.min(np.abs(w - Om)) / Om) if w.size else 1.0


def draw_machine(rs, two_speeds):
    """Rotor + speed(s); 80 % of machines keep a >= 20 % separation margin."""
    separated = rs.random() < 0.8
    while True:
        rot = draw_rotor(rs)
        for _ in range(200):
            lo = 2000.0 if two_speeds else 1000.0
            n1 = int(round(loguniform(rs, lo, 12000.0)))
            speeds = [n1]
            if two_speeds:
                speeds.append(max(1000, int(round(n1 * rs.uniform(0.3, 0.7)))))
            ms = [margin(rot, n) for n in speeds]
            if separated and min(ms) >= 0.2:
                return rot, speeds, separated, ms
            if not separated and 0.02 <= ms[0] < 0.2:
                return rot, speeds, separated, ms


def build_runs(rs, effect, h1, P0, check_runs):
    nP0 = np.linalg.norm(P0)
    nh = np.linalg.norm(h1, axis=0)

    def size(p, rho):
        return float(fmt_sig(rho * nP0 / nh[p], 3))

    runs = [{"name": "as found", "masses": [], "check": False}]
    first_angle = {}
    for p in (0, 1):
        a = int(rs.integers(0, 360))
        first_angle[p] = a
        runs.append({"name": f"{PLANES[p]} trial", "check": False,
                     "masses": [(p, size(p, rs.uniform(0.2, 1.0)), a)]})
    if effect == "lead_phase" or rs.random() < 0.5:
        p = int(rs.integers(0, 2))
        a = (first_angle[p] + int(rs.integers(60, 301))) % 360
        runs.append({"name": f"{PLANES[p]} trial 2", "check": False,
                     "masses": [(p, size(p, rs.uniform(0.2, 1.0)), a)]})
    if rs.random() < 0.5:
        runs.append({"name": "both trial", "check": False,
                     "masses": [(p, size(p, rs.uniform(0.2, 0.7)), int(rs.integers(0, 360)))
                                for p in (0, 1)]})
    if effect == "nonlinear" or rs.random() < 0.3:
        p = int(rs.integers(0, 2))
        a = int(rs.integers(0, 360))
        base = size(p, rs.uniform(0.25, 0.35))
        n = 3 if (effect == "nonlinear" or rs.random() < 0.5) else 2
        for k in range(1, n + 1):
            runs.append({"name": f"{PLANES[p]} ladder {k}", "check": False,
                         "masses": [(p, float(fmt_sig(base * k, 3)), a)]})
    used = {m for r in runs for m in r["masses"]}
    K = int(rs.integers(1, 5)) if check_runs is None else check_runs
    for c in range(K):
        while True:
            if rs.random() < 0.5:
                p = int(rs.integers(0, 2))
                ms = [(p, size(p, rs.uniform(0.2, 1.0)), int(rs.integers(0, 360)))]
            else:
                ms = [(p, size(p, rs.uniform(0.2, 0.7)), int(rs.integers(0, 360))) for p in (0, 1)]
            if not any(m in used for m in ms):
                break
        used.update(ms)
        runs.append({"name": f"check {c + 1}", "check": True, "masses": ms})
    return runs


def nonlinear_metric(rot, Om, U_runs, W_runs, k3, proj, mount):
    d, conv = rot.bearing_disp_hb(Om, U_runs, k3)
    if not conv.all():
        return None
    R = tool_reading(instrument(d, proj), mount)
    return fit_tool(W_runs, R)[2]


NL_MAX_STIFFENING = 0.3     # 3/4 k3 A^2 / k at the as-found amplitude, at most


def calibrate_k3(rot, Om, U0, U_runs, W_runs, proj, mount, tgt):
    """k3 = s k / A^2 (A: as-found 0-pk amplitude at the bearing) with s chosen so that
    the tool's linear fit of the noise-free campaign leaves ~tgt relative residual.
    Returns (k3, s, residual) or None if unreachable with 3/4 s <= NL_MAX_STIFFENING."""
    dlin = rot.bearing_disp_linear(Om, U0[None])[0]
    A = np.repeat(np.maximum(np.abs(dlin[0::2]), np.abs(dlin[1::2])), 2)
    unit = rot.klin / A ** 2
    s_max = NL_MAX_STIFFENING / 0.75
    m_max = nonlinear_metric(rot, Om, U_runs, W_runs, s_max * unit, proj, mount)
    if m_max is None or m_max < 0.85 * tgt:
        return None
    lo, hi = 0.0, s_max
    s, m = s_max, m_max
    for _ in range(60):
        if m is not None and 0.85 * tgt <= m <= 1.15 * tgt:
            return s * unit, s, m
        if m is None or m > tgt:
            hi = s
        else:
            lo = s
        s = math.sqrt(lo * hi) if lo > 0 else hi / 4.0
        m = nonlinear_metric(rot, Om, U_runs, W_runs, s * unit, proj, mount)
    return None


def draw_as_found(rs_rot, two, proj0):
    """Machine, speed(s) and initial unbalance U0 (2,) kg m (theta counted with rotation)."""
    while True:
        rot, speeds, separated, margins = draw_machine(rs_rot, two)
        Oms = [rpm2rad(n) for n in speeds]
        # ISO 1940 grade G (mm/s): (|U_left| + |U_right|) / M * Omega = G, random split
        # and angles.  Grade drawn in 2.5-63; if the RMS as-found reading falls outside
        # 3-200 um pp the grade is moved to that window within 1-250 mm/s, else the
        # machine is redrawn.
        u_shape = np.array([rs_rot.uniform(0.3, 1.0) * cmath.exp(1j * rs_rot.uniform(0, TWO_PI))
                            for _ in range(2)])
        u_shape /= np.sum(np.abs(u_shape))
        grade = loguniform(rs_rot, 2.5, 63.0)
        P = instrument(rot.bearing_disp_linear(Oms[0], u_shape[None]), proj0)[0]
        rms_unit = np.linalg.norm(P) / 2.0              # per kg m of total unbalance
        rms = rms_unit * rot.M * grade * 1e-3 / Oms[0]
        if rms < 3.0:
            grade *= 3.0 / rms
        elif rms > 200.0:
            grade *= 200.0 / rms
        if 1.0 <= grade <= 250.0:
            return rot, speeds, separated, margins, Oms, u_shape * rot.M * grade * 1e-3 / Oms[0]


def make_campaign(seed, idx, effect, check_runs=None, mount="with", noise=True):
    """Build one campaign in memory: dict with rendered texts and truth."""
    rs_rot = rng_for(seed, idx, STREAM_ROTOR)
    rs_st = rng_for(seed, idx, STREAM_STRUCT)
    rs_eff = rng_for(seed, idx, STREAM_EFFECT)
    rs_noise = rng_for(seed, idx, STREAM_NOISE)
    two = effect in ("offset", "none_two_speeds")
    proj0 = projection()
    nl_target = float(rs_eff.uniform(0.03, 0.10))
    while True:
        rot, speeds, separated, margins, Oms, U0 = draw_as_found(rs_rot, two, proj0)
        h_inst = [influence_inst(rot, Om) for Om in Oms]       # (4,2) per speed
        P0 = instrument(rot.bearing_disp_linear(Oms[0], U0[None]), proj0)[0]
        runs = build_runs(rs_st, effect, h_inst[0], P0, check_runs)
        n_runs = len(runs)
        U_runs = np.array([U0 + mass_unbalance(rot, r["masses"]) for r in runs])
        W_runs = np.array([mass_vector(r["masses"]) for r in runs])
        if effect != "nonlinear":
            break
        # nonlinear: machines on which a realistic hardening cannot show are redrawn
        nl = calibrate_k3(rot, Oms[0], U0, U_runs, W_runs, proj0, mount, nl_target)
        if nl is not None:
            break

    # repeats
    reps = [1] * n_runs
    if rs_st.random() < 0.35:
        reps = [int(rs_st.choice([1, 2, 3], p=[0.3, 0.45, 0.25])) for _ in range(n_runs)]
        if max(reps) == 1:
            reps[int(rs_st.integers(0, n_runs))] = 2

    rms0 = float(np.linalg.norm(P0) / 2.0)
    noise_rel = float(rs_noise.uniform(0.01, 0.05))
    sd = noise_rel * rms0 if noise else 0.0

    # effect parameters
    eff = {}
    proj = proj0
    k3 = None
    runout = np.zeros(4, complex)
    if effect == "crosstalk":
        ct = (float(rs_eff.uniform(0.05, 0.2)), float(rs_eff.uniform(0.05, 0.2)))
        proj = projection(ct)
        eff["crosstalk_fraction"] = {"b1_y": ct[0], "b2_y": ct[1]}
        eff["model"] = "y probe at bearing j reads y_j + c_j * x_j"
    elif effect == "offset":
        amps = rs_eff.uniform(0.1, 0.5, 4) * rms0
        lags = rs_eff.uniform(0.0, 360.0, 4)
        runout = amps * np.exp(-1j * np.radians(lags))
        eff["runout"] = {s[0]: {"amplitude_um_pp": float(a), "phase_lag_deg": float(l)}
                         for s, a, l in zip(SENSORS, amps, lags)}
        eff["model"] = "constant phasor added to every reading at every speed"
    elif effect == "nonlinear":
        k3, sfac, val = nl
        eff["k3_N_per_m3"] = {"x": [float(k3[0]), float(k3[2])], "y": [float(k3[1]), float(k3[3])]}
        eff["stiffening_at_as_found"] = float(0.75 * sfac)
        eff["linear_fit_rel_residual_noise_free"] = float(val)
        eff["model"] = ("F = -k x - k3 x^3 per support direction, one-term harmonic balance; "
                        "stiffening = 3/4 k3 A^2 / k at the as-found amplitude A")
    elif effect == "lead_phase":
        eff["model"] = "instrument reports -lag (lead) while campaign declares lag"

    # noise-free readings (clean = linear, effect-free; eff = with effect)
    clean, witheff = [], []
    for Om in Oms:
        d_lin = rot.bearing_disp_linear(Om, U_runs)
        clean.append(instrument(d_lin, proj0))
        if k3 is not None:
            d, conv = rot.bearing_disp_hb(Om, U_runs, k3)
            assert conv.all()
        else:
            d = d_lin
        witheff.append(instrument(d, proj) + runout[None, :])

    # rows
    rows = []
    for i in range(n_runs):
        for si, n in enumerate(speeds):
            for _ in range(reps[i]):
                nz = rs_noise.normal(size=4) + 1j * rs_noise.normal(size=4)
                Pm = witheff[si][i] + sd / math.sqrt(2.0) * nz
                amp, lag = np.abs(Pm), np.degrees(-np.angle(Pm))
                ph = -lag if effect == "lead_phase" else lag
                rows.append((i + 1, n if two else None, amp, ph))

    camp = {"seed": seed, "index": idx, "effect": effect, "mount": mount, "rot": rot,
            "speeds": speeds, "runs": runs, "rows": rows, "reps": reps}
    camp["toml"] = render_toml(camp)
    camp["csv"] = render_csv(camp)
    camp["truth"] = build_truth(camp, U0, h_inst, clean, witheff, sd, noise_rel, eff,
                                separated, margins, Oms, proj)
    return camp


def masses_json(ms):
    return [{"plane": PLANES[p], "mass_g": g, "angle_deg": a} for p, g, a in ms]


def readings_json(P):
    return {s[0]: {"amplitude_um_pp": float(abs(z)), "phase_lag_deg": deg(np.conj(z))}
            for s, z in zip(SENSORS, P)}


def h_json(h, mount):
    alpha = declared_angles(mount)
    out = {}
    for i, s in enumerate(SENSORS):
        out[s[0]] = {}
        for p in (0, 1):
            z = h[i, p]
            zt = np.conj(z) * cmath.exp(1j * math.radians(alpha[i]))
            out[s[0]][PLANES[p]] = {
                "amplitude_um_per_g": float(abs(z)), "phase_lag_deg": deg(np.conj(z)),
                "tool_re": float(zt.real), "tool_im": float(zt.imag), "tool_angle_deg": deg(zt)}
    return out


def build_truth(c, U0, h_inst, clean, witheff, sd, noise_rel, eff, separated, margins, Oms, proj):
    rot = c["rot"]
    init = {}
    for p in (0, 1):
        u = U0[p]
        init[PLANES[p]] = {"mass_g": float(abs(u) / rot.rp[p] * 1e3),
                           "angle_deg": deg(np.conj(u)),
                           "radius_mm": float(rot.rp[p] * 1e3),
                           "unbalance_g_mm": float(abs(u) * 1e6)}
    ecc = (abs(U0[0]) + abs(U0[1])) / rot.M
    t = {
        "generator": "tests/balance_campaigns/generate.py", "generator_version": GENERATOR_VERSION,
        "seed": c["seed"], "campaign": c["index"], "effect": c["effect"],
        "conventions": {
            "mass_angle": "degrees on the rotor from the keyphasor notch, counted AGAINST rotation",
            "phase": "lag: rotation angle from keyphasor event to the probe's positive peak",
            "mounting_angle": ("declared WITH rotation from +x (y probe 90 deg)" if c["mount"] == "with"
                               else "declared AGAINST rotation (y probe, 90 deg ahead in rotation, = 270 deg)"),
            "tool_form": "tool_re/im = amplitude*exp(i(phase_lag + declared mounting angle)) per gram at 0 deg",
            "amplitudes": "1X peak-to-peak micrometres",
            "noise": "circular complex Gaussian on each reading phasor; re, im sd = noise_sd_um/sqrt(2)",
        },
        "speeds_rpm": c["speeds"],
        "noise_sd_um": sd, "noise_rel_to_rms_as_found": noise_rel,
        "initial_unbalance": init,
        "initial_unbalance_G_grade_mm_per_s": float(ecc * Oms[0] * 1e3),
        "check_runs": [{"run": i + 1, "name": r["name"], "masses": masses_json(r["masses"]),
                        "added_clean_readings": [readings_json(clean[s][i] - clean[s][0])
                                                 for s in range(len(Oms))]}
                       for i, r in enumerate(c["runs"]) if r["check"]],
        "influence_coefficients": [{"speed_rpm": n, "sensors": h_json(h_inst[s], c["mount"])}
                                   for s, n in enumerate(c["speeds"])],
        "effect_parameters": eff,
        "runs": [{"run": i + 1, "name": r["name"], "check": r["check"], "masses": masses_json(r["masses"]),
                  "rows": c["reps"][i] * len(Oms),
                  "clean_readings": [{"speed_rpm": n, "sensors": readings_json(clean[s][i])}
                                     for s, n in enumerate(c["speeds"])],
                  "effect_readings_noise_free": [{"speed_rpm": n, "sensors": readings_json(witheff[s][i])}
                                                 for s, n in enumerate(c["speeds"])]}
                 for i, r in enumerate(c["runs"])],
        "critical_speeds": {
            "whirl_frequencies_rpm_at_speed": [[float(w * 60 / TWO_PI) for w in rot.whirl(Om)[0]]
                                               for Om in Oms],
            "separation_margin": margins, "separated_by_20_percent": separated},
        "rotor": rot.to_json(),
    }
    if c["effect"] == "crosstalk":
        t["apparent_influence_coefficients"] = [
            {"speed_rpm": n, "sensors": h_json(influence_inst(rot, Om, proj), c["mount"])}
            for n, Om in zip(c["speeds"], Oms)]
    return t


def render_toml(c):
    rot = c["rot"]
    alpha = declared_angles(c["mount"])
    mount_txt = ("probe mounting angles counted from the x probe WITH rotation (y probe 90 deg ahead)"
                 if c["mount"] == "with" else
                 "probe mounting angles counted AGAINST rotation (y probe, 90 deg ahead in rotation, is 270 deg)")
    sp = ", ".join(f"{n} rpm" for n in c["speeds"])
    L = [
        "# Simulated two-plane field-balancing campaign: rigid rotor on flexible damped supports.",
        f"# generated by tests/balance_campaigns/generate.py (seed {c['seed']}, campaign {c['index']});"
        " known truth in truth.json",
        "# conventions: phase = LAG, rotation angle from the keyphasor to the probe's positive peak;",
        "#   weight angles are counted AGAINST rotation from the keyphasor notch (same sense as the lag);",
        f"#   {mount_txt};",
        "#   amplitudes are 1X peak-to-peak micrometres.",
        f"# speed: {sp}",
        "",
        "[campaign]",
        f'name = "simulated rigid rotor, campaign {c["index"]}"',
        'readings = "readings.csv"',
        'amplitude_unit = "um"',
        'phase = "lag"',
        "",
    ]
    for (name, _, _), a in zip(SENSORS, alpha):
        L += ["[[sensor]]", f'name = "{name}"', f'amplitude = "{name}_um"', f'phase = "{name}_deg"',
              f'angle = "{a:g} deg"']
    L.append("")
    for p in (0, 1):
        L += ["[[plane]]", f'name = "{PLANES[p]}"', f'radius = "{rot.rp[p] * 1000:.0f} mm"']
    L.append("")
    for r in c["runs"]:
        L += ["[[run]]", f'name = "{r["name"]}"']
        if r["check"]:
            L.append("check = true")
        ms = ", ".join(f'{{plane = "{PLANES[p]}", mass = "{fmt_sig(g, 3)} g", angle = "{a} deg"}}'
                       for p, g, a in r["masses"])
        L.append(f"masses = [{ms}]")
    return "\n".join(L) + "\n"


def render_csv(c):
    two = len(c["speeds"]) > 1
    L = ["# simulated field-balancing readings: 1X amplitude (um peak-to-peak) and phase (deg)",
         "# run = 1-based index of the [[run]] table in campaign.toml; repeated rows = repeated readings"]
    hdr = ["run"] + (["speed_rpm"] if two else [])
    for name, _, _ in SENSORS:
        hdr += [f"{name}_um", f"{name}_deg"]
    L.append(",".join(hdr))
    for run, n, amp, ph in c["rows"]:
        f = [str(run)] + ([str(n)] if two else [])
        for a, p in zip(amp, ph):
            f += [fmt_sig(float(a), 7), fmt_phase(float(p))]
        L.append(",".join(f))
    return "\n".join(L) + "\n"


def write_campaign(c, outdir):
    d = os.path.join(outdir, f"campaign_{c['index']:03d}")
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "campaign.toml"), "w") as f:
        f.write(c["toml"])
    with open(os.path.join(d, "readings.csv"), "w") as f:
        f.write(c["csv"])
    with open(os.path.join(d, "truth.json"), "w") as f:
        json.dump(c["truth"], f, indent=1)
        f.write("\n")


# --------------------------------------------------------------------------
# self-check
# --------------------------------------------------------------------------
def simulate(rot, Om, U, k3=None, n_rev=300, spr=256, n_fit=20):
    """RK4 from rest; returns (nc, 4) complex bearing phasors of the 1X component
    (fitted by DFT over the last n_fit revolutions) and the last revolution's samples."""
    Minv = np.linalg.inv(rot.Mm)
    Kq = (Minv @ rot.K).T
    Cq = (Minv @ (rot.C + Om * rot.G)).T
    Fm = rot.forcing(Om, U) @ Minv.T
    TbM = rot.Tb @ Minv.T
    nc = Fm.shape[0]
    h = TWO_PI / (Om * spr)
    E = np.exp(1j * np.pi * np.arange(2 * spr) / spr)   # e^{i Omega t} at half steps

    def acc(q, v, e):
        a = (Fm * e).real - q @ Kq - v @ Cq
        if k3 is not None:
            d = q @ rot.Tb.T
            a -= (k3 * d ** 3) @ TbM
        return a

    q = np.zeros((nc, 4))
    v = np.zeros((nc, 4))
    n_steps = n_rev * spr
    first = n_steps - n_fit * spr
    acc_c = np.zeros((nc, 4), complex)
    last = []
    for n in range(n_steps):
        k = n % spr
        if n >= first:
            d = q @ rot.Tb.T
            acc_c += d * np.conj(E[2 * k])
            if n >= n_steps - spr:
                last.append(d)
        e0, eh, e1 = E[2 * k], E[(2 * k + 1) % (2 * spr)], E[(2 * k + 2) % (2 * spr)]
        a1 = acc(q, v, e0)
        q2, v2 = q + 0.5 * h * v, v + 0.5 * h * a1
        a2 = acc(q2, v2, eh)
        q3, v3 = q + 0.5 * h * v2, v + 0.5 * h * a2
        a3 = acc(q3, v3, eh)
        q4, v4 = q + h * v3, v + h * a3
        a4 = acc(q4, v4, e1)
        q = q + h / 6.0 * (v + 2 * v2 + 2 * v3 + v4)
        v = v + h / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)
    # s = A cos + B sin  ->  phasor A - iB = (2/N) sum s e^{-i Omega t}
    return 2.0 * acc_c / (n_fit * spr), np.array(last)


class Checker:
    def __init__(self):
        self.failed = 0

    def __call__(self, ok, name, detail):
        print(f"{'PASS' if ok else 'FAIL'}  {name}: {detail}")
        if not ok:
            self.failed += 1


def test_rotor():
    return Rotor(M=120.0, It=9.0, Ip=1.6, zG=0.42, zb=[0.0, 0.9],
                 kx=[4e7, 6e7], ky=[2.5e7, 3.5e7], cx=[2.2e4, 2.6e4], cy=[1.6e4, 2.0e4],
                 zp=[-0.06, 1.02], rp=[0.12, 0.10])


def parse_campaign(toml_text, csv_text):
    import tomllib
    cfg = tomllib.loads(toml_text)
    alpha = [float(s["angle"].split()[0]) for s in cfg["sensor"]]
    planes = [p["name"] for p in cfg["plane"]]
    W = []
    for r in cfg["run"]:
        w = np.zeros(2, complex)
        for m in r["masses"]:
            w[planes.index(m["plane"])] += float(m["mass"].split()[0]) * cmath.exp(
                1j * math.radians(float(m["angle"].split()[0])))
        W.append(w)
    sign = 1.0 if cfg["campaign"]["phase"] == "lag" else -1.0
    lines = [ln for ln in csv_text.splitlines() if ln and not ln.startswith("#")]
    hdr = lines[0].split(",")
    rows = []
    for ln in lines[1:]:
        f = dict(zip(hdr, ln.split(",")))
        R = [float(f[s["amplitude"]]) * cmath.exp(1j * math.radians(sign * float(f[s["phase"]]) + a))
             for s, a in zip(cfg["sensor"], alpha)]
        rows.append((int(f["run"]), float(f.get("speed_rpm", "nan")), np.array(R)))
    checks = [i for i, r in enumerate(cfg["run"]) if r.get("check", False)]
    return cfg, np.array(W), rows, checks


def truth_h(truth, si=0):
    ic = truth["influence_coefficients"][si]["sensors"]
    return np.array([[ic[s[0]][p]["tool_re"] + 1j * ic[s[0]][p]["tool_im"] for s in SENSORS]
                     for p in PLANES])


def self_check():
    ck = Checker()
    rot = test_rotor()
    Om = rpm2rad(3000.0)
    w, sig = rot.whirl(Om)
    print(f"test rotor: whirl frequencies at 3000 rpm = "
          f"{', '.join(f'{x * 60 / TWO_PI:.0f}' for x in w)} rpm, slowest decay {sig:.1f} 1/s")

    # 1. gyroscopic sign: forward conical whirl stiffens with speed (isotropic rotor)
    iso = Rotor(100.0, 6.0, 4.0, 0.5, [0.0, 1.0], [3e7, 3e7], [3e7, 3e7], [1e3, 1e3], [1e3, 1e3],
                [0.1, 0.9], [0.1, 0.1])

    def conical(Om_):
        lam, V = np.linalg.eig(iso.state_matrix(Om_))
        fw, bw = [], []
        for l, vv in zip(lam, V.T):
            if l.imag <= 0:
                continue
            a, b = vv[2], vv[3]
            if abs(a) < 1e-6 * np.linalg.norm(vv[:4]):
                continue
            (fw if abs(a + 1j * b) > abs(a - 1j * b) else bw).append(l.imag)
        return max(fw), min(bw)

    f0, b0 = conical(1e-3)
    f1, b1 = conical(rpm2rad(6000))
    ck(f1 > f0 * 1.05 and b1 < b0 * 0.95, "gyroscopic sign (forward conical whirl stiffens)",
       f"forward {f0:.1f}->{f1:.1f} rad/s, backward {b0:.1f}->{b1:.1f} rad/s")

    # 2. time domain vs complex steady state (anisotropic, gyroscopic, overhung planes)
    U = np.array([[0.8e-3 * cmath.exp(0.7j), 1.1e-3 * cmath.exp(-2.1j)],
                  [1.0e-3, 0.0], [0.0, 1.0e-3 * cmath.exp(1.3j)]])
    n_rev = 300
    t0 = time.time()
    d_td, last = simulate(rot, Om, U, n_rev=n_rev)
    t_td = time.time() - t0
    decay = math.exp(-sig * (n_rev - 20) * TWO_PI / Om)
    d_ss = rot.bearing_disp_linear(Om, U)
    proj = projection()
    P_td, P_ss = instrument(d_td, proj), instrument(d_ss, proj)
    err = float(np.max(np.abs(P_td - P_ss)) / np.max(np.abs(P_ss)))
    ck(err < 1e-6 and decay < 1e-9, "RK4 time domain (300 rev, 256 steps/rev) vs complex steady state",
       f"max rel diff {err:.2e} (tol 1e-6), transient left {decay:.1e}, {t_td:.1f} s")

    # 3. phase lag = rotation angle from keyphasor to positive peak, by peak picking
    spr = last.shape[0]
    sig_last = np.einsum("kna,sa->kns", last, proj)           # (samples, configs, sensors)
    worst = 0.0
    for c in range(U.shape[0]):
        for s in range(4):
            x = sig_last[:, c, s]
            k = int(np.argmax(x))
            y0, y1, y2 = x[(k - 1) % spr], x[k], x[(k + 1) % spr]
            frac = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
            ang_peak = (k + frac) * 360.0 / spr
            lag = math.degrees(-cmath.phase(P_ss[c, s])) % 360.0
            worst = max(worst, abs((ang_peak - lag + 180.0) % 360.0 - 180.0))
    ck(worst < 0.05, "lag = -arg(S) equals the peak angle after the keyphasor (peak picking, x and y probes)",
       f"worst difference {worst:.4f} deg")

    # 4. high spot = heavy spot for a stiff rotor at low speed; y probe lags x by 90 deg
    stiff = Rotor(80.0, 4.0, 0.5, 0.5, [0.0, 1.0], [1e9, 1e9], [1e9, 1e9], [1e3, 1e3], [1e3, 1e3],
                  [0.5, 0.5], [0.1, 0.1])
    beta = 40.0
    Pst = instrument(stiff.bearing_disp_linear(rpm2rad(600), mass_unbalance(stiff, [(0, 10.0, beta)])[None]),
                     proj)[0]
    lags = [math.degrees(-cmath.phase(z)) % 360 for z in Pst]
    ok = abs(lags[0] - beta) < 0.5 and abs(lags[1] - (beta + 90)) < 0.5
    ck(ok, "stiff rotor, weight at 40 deg against rotation", f"x lag {lags[0]:.2f}, y lag {lags[1]:.2f} deg "
       f"(expect 40, 130): weight angle against rotation = x-probe lag")

    # 5. tool rule: readings linear in mass*exp(i angle) with angles AGAINST rotation
    rs = np.random.default_rng(12345)
    r6 = draw_rotor(rs)
    Om6 = rpm2rad(4321.0)
    U0 = np.array([2e-3 * cmath.exp(0.4j), 1.5e-3 * cmath.exp(2.5j)])
    runs6 = [[], [(0, 12.3, 30)], [(1, 8.7, 200)], [(0, 5.1, 275), (1, 9.9, 95)],
             [(0, 20.0, 150)], [(1, 4.4, 10), (0, 3.3, 333)]]
    for mount in ("with", "against"):
        Uruns = np.array([U0 + mass_unbalance(r6, m) for m in runs6])
        P6 = instrument(r6.bearing_disp_linear(Om6, Uruns), proj)
        W6 = np.array([mass_vector(m) for m in runs6])
        a, h, res = fit_tool(W6, tool_reading(P6, mount))
        ht = np.array([[np.conj(z) * cmath.exp(1j * math.radians(al))
                        for z, al in zip(influence_inst(r6, Om6)[:, p], declared_angles(mount))] for p in (0, 1)])
        herr = float(np.max(np.abs(h - ht)) / np.max(np.abs(ht)))
        ck(res < 1e-9 and herr < 1e-9, f"clean linear fit of 6 runs (mount angles {mount} rotation)",
           f"rel residual {res:.1e}, fitted vs exact h {herr:.1e} (tol 1e-9)")
    Wwrong = np.array([mass_vector([(p, g, -b) for p, g, b in m]) for m in runs6])
    res_w = fit_tool(Wwrong, tool_reading(P6))[2]
    res_l = fit_tool(W6, tool_reading(P6, reported="lead"))[2]
    ck(res_w > 1e-2 and res_l > 1e-2, "negative controls: weight angles WITH rotation / phase lead",
       f"rel residual {res_w:.3f} / {res_l:.3f} (must be large)")

    # 6. isotropic machine: h(y) = -h(x) with 'with' angles, h(y) = h(x) with 'against'
    hi = influence_inst(iso, rpm2rad(2500))
    for mount, sgn in (("with", -1.0), ("against", 1.0)):
        ht = np.conj(hi) * np.exp(1j * np.radians(declared_angles(mount)))[:, None]
        e = float(np.max(np.abs(ht[[1, 3]] - sgn * ht[[0, 2]])) / np.max(np.abs(ht)))
        ck(e < 1e-12, f"isotropic supports, mount angles {mount} rotation: h_y = {'+' if sgn > 0 else '-'}h_x",
           f"max deviation {e:.1e}")

    # 7. harmonic balance vs time domain with cubic supports
    dl = rot.bearing_disp_linear(Om, U[:1])[0]
    A = np.repeat(np.maximum(np.abs(dl[0::2]), np.abs(dl[1::2])), 2)
    k3 = 0.3 * rot.klin / A ** 2
    d_hb, conv = rot.bearing_disp_hb(Om, U[:1], k3)
    d_nl, _ = simulate(rot, Om, U[:1], k3=k3, n_rev=200)
    e_hb = float(np.max(np.abs(d_nl - d_hb)) / np.max(np.abs(d_hb)))
    e_lin = float(np.max(np.abs(d_nl - dl[None])) / np.max(np.abs(d_hb)))
    ck(conv.all() and e_hb < 0.02 and e_hb < 0.2 * e_lin,
       "one-term harmonic balance vs RK4 (cubic supports, ~22% stiffening)",
       f"1X rel diff {e_hb:.2e} (tol 2e-2; linear model would be off by {e_lin:.2e})")

    # 8. generated campaigns round-trip through the declared format
    for eff in EFFECTS:
        c = make_campaign(7, 3, eff, noise=False)
        cfg, W, rows, checks = parse_campaign(c["toml"], c["csv"])
        tr = c["truth"]
        speeds = [float(n) for n in tr["speeds_rpm"]] if eff == "offset" else [float("nan")]
        fits = []
        for si, spd in enumerate(speeds):
            sel = [r for r in rows if (eff != "offset" or r[1] == spd) and (r[0] - 1) not in checks]
            Wr = np.array([W[r[0] - 1] for r in sel])
            Rr = np.array([r[2] for r in sel])
            a, h, res = fit_tool(Wr, Rr)
            fits.append((a, h, res))
        a, h, res = fits[0]
        ht = truth_h(tr)
        herr = float(np.max(np.abs(h - ht)) / np.max(np.abs(ht)))
        if eff in ("none", "offset"):
            msg = f"fit residual {res:.1e}, h vs truth {herr:.1e}"
            ok = res < 2e-6 and herr < 2e-5
            if eff == "none":
                # predict check runs
                Rall = {r[0] - 1: r[2] for r in rows}
                perr = max(float(np.max(np.abs(a + W[i] @ h - Rall[i])) / np.max(np.abs(Rall[i])))
                           for i in checks)
                ok = ok and perr < 2e-5
                msg += f", check-run prediction {perr:.1e}"
            else:
                (a1, h1, _), (a2, h2, _) = fits
                ht2 = truth_h(tr, 1)
                herr2 = float(np.max(np.abs(h2 - ht2)) / np.max(np.abs(ht2)))
                # a_s = runout + h_s w0 at both speeds -> w0 (tool form) by least squares
                w0, *_ = np.linalg.lstsq((h1 - h2).T, a1 - a2, rcond=None)
                iu = tr["initial_unbalance"]
                w0t = np.array([iu[p]["mass_g"] * cmath.exp(1j * math.radians(iu[p]["angle_deg"]))
                                for p in PLANES])
                uerr = float(np.max(np.abs(w0 - w0t)) / np.max(np.abs(w0t)))
                ok = ok and herr2 < 2e-5 and uerr < 1e-4
                msg += f", 2nd speed h {herr2:.1e}, unbalance recovered from 2 speeds {uerr:.1e}"
        elif eff == "crosstalk":
            ha = truth_h({"influence_coefficients": tr["apparent_influence_coefficients"]})
            aerr = float(np.max(np.abs(h - ha)) / np.max(np.abs(ha)))
            ok = res < 2e-6 and aerr < 2e-5 and herr > 1e-2
            msg = f"fit residual {res:.1e} (linear), h vs apparent {aerr:.1e}, vs physical truth {herr:.2f}"
        elif eff == "nonlinear":
            tgt = tr["effect_parameters"]["linear_fit_rel_residual_noise_free"]
            ok = res > 0.02
            msg = f"fit residual {res:.3f} without check runs (tuned {tgt:.3f} on all runs)"
        else:
            ok = res > 0.02
            msg = f"fit residual {res:.3f} (lead read as lag: not linear)"
        ck(ok, f"campaign round trip, effect={eff} (noise-free)", msg)

    # 9. noise level sanity: residual of the 'none' campaign with noise ~ noise sd
    c = make_campaign(11, 0, "none")
    cfg, W, rows, checks = parse_campaign(c["toml"], c["csv"])
    sel = [r for r in rows if (r[0] - 1) not in checks]
    a, h, _ = fit_tool(np.array([W[r[0] - 1] for r in sel]), np.array([r[2] for r in sel]))
    res = np.array([r[2] - a - W[r[0] - 1] @ h for r in sel])
    dof = len(sel) - 3
    est = float(np.sqrt(np.sum(np.abs(res) ** 2) / (4 * dof))) if dof > 0 else float("nan")
    sd = c["truth"]["noise_sd_um"]
    ck(dof <= 0 or 0.3 < est / sd < 3.0, "noise level (campaign 11/0, effect none)",
       f"residual rms {est:.3f} um vs noise sd {sd:.3f} um ({len(sel)} rows)")

    # 10. determinism and speed
    a1 = make_campaign(5, 9, "offset")
    a2 = make_campaign(5, 9, "offset")
    b1 = make_campaign(6, 9, "offset")
    same = all(a1[k] == a2[k] for k in ("toml", "csv")) and json.dumps(a1["truth"]) == json.dumps(a2["truth"])
    ck(same and b1["csv"] != a1["csv"], "deterministic per seed", "identical texts for equal seeds")
    for eff in EFFECTS:
        t0 = time.time()
        for i in range(100):
            cc = make_campaign(1, i, eff)
            json.dumps(cc["truth"])
        dt = time.time() - t0
        ck(dt < 10.0, f"speed, 100 campaigns effect={eff}", f"{dt:.2f} s (in memory)")

    print("self-check:", "OK" if ck.failed == 0 else f"{ck.failed} FAILED")
    return 0 if ck.failed == 0 else 1


# --------------------------------------------------------------------------
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out")
    ap.add_argument("--count", type=int)
    ap.add_argument("--seed", type=int)
    ap.add_argument("--effect", choices=EFFECTS)
    ap.add_argument("--check-runs", type=int, choices=(1, 2, 3, 4))
    ap.add_argument("--mount-angles", choices=("with", "against"), default="with",
                    help="declare probe mounting angles counted with (default: y = 90 deg) "
                         "or against (y = 270 deg) rotation")
    ap.add_argument("--self-check", action="store_true")
    a = ap.parse_args(argv)
    if a.self_check:
        return self_check()
    if a.out is None or a.count is None or a.seed is None or a.effect is None:
        ap.error("--out, --count, --seed and --effect are required (or --self-check)")
    if a.count < 0 or a.seed < 0:
        ap.error("--count and --seed must be non-negative")
    os.makedirs(a.out, exist_ok=True)
    for i in range(a.count):
        write_campaign(make_campaign(a.seed, i, a.effect, a.check_runs, a.mount_angles), a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
