#!/usr/bin/python3
"""NumPy-vectorized baseline of the seeker LOS Monte Carlo (studies/los_seeker_wang2011.toml).

The same study as `poise run`: the model file's tolerances and distributions (read here with
tomllib), the same exact kinematic chain (src/models/seeker_los_chain.h: tilted axes by minimal
rotation, yaw frames x pitch LOS factorized over the grid), the same pointing-error definitions
and per-sample outputs, the same summary (per-output quantiles, per-grid-point p50/p95/p99.73
maps, pooled quantiles) and a samples.csv with the same 64 columns at 17 digits.
Design: plain Monte Carlo (numpy's PCG64); Poise's Sobol points are not reproduced, the
statistics agree to Monte Carlo error. --check SAMPLES_CSV recomputes the outputs from the
inputs Poise wrote and compares them (the two compute the same function).

Harmonic sums: by default the direct form, cos/sin of (n_h phi_k + psi_h) over (batch,
harmonic, angle) arrays, as a NumPy user writes it; --grouped uses the same grouping by order
as Poise (one phase factor per harmonic, tables of e^{i n phi} per order), for a like-for-like
algorithm.

--lean computes the same samples but keeps only the per-sample outputs and their summary
(quantiles, mean, std, the share meeting the requirement): no grid values, no maps, no
samples.csv; the counterpart of a Poise run with [output] samples_csv = false,
grid_values = false, maps = false (bench/baselines/compare.py times the two).

Usage: los_numpy.py [--samples N] [--batch B] [--grouped] [--out DIR] [--compute-only | --lean]
                    [--check SAMPLES_CSV]
Prints CPU seconds (time.process_time) of the compute and of the whole run.
"""
import argparse, os, sys, time, tomllib
import numpy as np
from scipy.special import ndtri

ARCSEC = np.pi / (180 * 3600)
UNITS = {"mm": 1e-3, "um": 1e-6, "m": 1.0, "deg": np.pi / 180, "arcsec": ARCSEC}
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SOURCES = ["radial_runout", "face_runout", "clearance", "bore_roundness", "ball_roundness", "seat_deformation"]
LOAD_SCALED = {"radial_runout", "face_runout", "clearance", "bore_roundness"}


def q(text):
    value, unit = text.split()
    return float(value) * UNITS[unit]


class Tol:
    """A tolerance table: centred quantile and magnitude quantile as sampling/distribution.cc."""
    def __init__(self, t):
        self.kind, self.t = t["distribution"], q(t["tolerance"]) if "tolerance" in t else None
        conv = t.get("tolerance_is", "bounds")
        self.sigma = self.t / {"1sigma": 1, "2sigma": 2, "3sigma": 3}.get(conv, 3) if self.kind == "normal" else None

    def centred(self, u):
        if self.kind == "normal": return self.sigma * ndtri(u)
        if self.kind == "uniform": return self.t * (2 * u - 1)
        if self.kind == "fixed": return np.full_like(u, self.t)
        raise ValueError(self.kind)

    def magnitude(self, u):
        return np.full_like(u, abs(self.t)) if self.kind == "fixed" else np.abs(self.centred(0.5 * (1 + u)))


def load(study_path):
    study = tomllib.load(open(study_path, "rb"))
    m = tomllib.load(open(os.path.join(os.path.dirname(study_path), study["study"]["model"]), "rb"))
    f = m["field_of_regard"]
    g = study["grid"]
    ld = m["load_deformation"]
    axes = {}
    for ax in ("yaw", "pitch"):
        a = m[ax]
        axes[ax] = dict(span=q(a["bearing_span"]), perp=Tol(a["perpendicularity"]),
                        sources=[(s, Tol(a[s]), float(a[s].get("order", 1))) for s in SOURCES if s in a])
    return dict(alpha=np.linspace(q(f["yaw_min"]), q(f["yaw_max"]), g["yaw_points"]),
                beta=np.linspace(q(f["pitch_min"]), q(f["pitch_max"]), g["pitch_points"]),
                ifov=q(f["pixel_ifov"]), k=(ld["min"], ld["max"]), axes=axes,
                barrel=q(m["optics"]["barrel_length"]), optics=Tol(m["optics"]["axis_error"]),
                requirement=q(study["requirement"]["los_error"].replace("px", "arcsec")) * q(f["pixel_ifov"]) / ARCSEC
                if study["requirement"]["los_error"].endswith("px") else q(study["requirement"]["los_error"]))


def draw(M, u):
    """Design points u (B, D) -> SI inputs (B, D) in Poise's column order, as SeekerSampler::draw."""
    v = np.empty_like(u)
    v[:, 0] = M["k"][0] + (M["k"][1] - M["k"][0]) * u[:, 0]
    v[:, 1] = M["axes"]["yaw"]["perp"].magnitude(u[:, 1]) / M["axes"]["yaw"]["span"]
    v[:, 2] = 2 * np.pi * u[:, 2]
    v[:, 3] = M["axes"]["pitch"]["perp"].centred(u[:, 3]) / M["axes"]["pitch"]["span"]
    v[:, 4] = M["optics"].centred(u[:, 4]) / M["barrel"]
    c = 5
    for ax in ("yaw", "pitch"):
        for _, tol, _ in M["axes"][ax]["sources"]:
            for _ in "AB":
                v[:, c] = tol.magnitude(u[:, c])
                v[:, c + 1] = 2 * np.pi * u[:, c + 1]
                c += 2
    return v


def harmonics(M, v, ax, first):
    """Amplitudes (B, H) in rad, orders (H,), phases (B, H) of one axis from the SI inputs."""
    a = M["axes"][ax]
    amp, order, phase = [], [], []
    c = first
    for name, _, n in a["sources"]:
        scale = (v[:, 0] if name in LOAD_SCALED else 1.0) / a["span"]
        for sign in (-1.0, 1.0):
            amp.append(sign * scale * v[:, c]), phase.append(v[:, c + 1]), order.append(n)
            c += 2
    return np.stack(amp, 1), np.array(order), np.stack(phase, 1), c


def tilt_sums(amp, order, phase, phi, grouped):
    """sum_h A_h (cos, sin)(n_h phi_k + psi_h) -> (B, K, 2)."""
    if not grouped:
        arg = order[None, :, None] * phi[None, None, :] + phase[:, :, None]
        return np.stack([(amp[:, :, None] * np.cos(arg)).sum(1), (amp[:, :, None] * np.sin(arg)).sum(1)], -1)
    cz = amp * np.exp(1j * phase)
    out = np.zeros((amp.shape[0], phi.size), complex)
    for n in np.unique(order):
        out += cz[:, order == n].sum(1)[:, None] * np.exp(1j * n * phi)[None, :]
    return np.stack([out.real, out.imag], -1)


def tilt_rotation(a, e1, e2, t):
    """T(a -> u), u = normalize(a + t1 e1 + t2 e2), for t (B, K, 2) -> (B, K, 3, 3)."""
    u = a + t[..., :1] * e1 + t[..., 1:] * e2
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    v = np.cross(a, u)
    c = u @ a
    vx = np.zeros(v.shape + (3,))
    vx[..., 0, 1], vx[..., 0, 2], vx[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    vx[..., 1, 0], vx[..., 2, 0], vx[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return np.eye(3) + vx + (vx @ vx) / (1 + c)[..., None, None]


def kernel(M, v, grouped=False):
    """SI inputs (B, D) -> outputs (B, 8) and total error per grid point (B, Ka * Kb) in arcsec."""
    al, be = M["alpha"], M["beta"]
    B = v.shape[0]
    X, Y, Z = np.eye(3)
    ya, yo, yp, c = harmonics(M, v, "yaw", 5)
    pa, po, pp, _ = harmonics(M, v, "pitch", c)
    ty = tilt_sums(ya, yo, yp, al, grouped)
    ty[..., 0] += (v[:, 1] * np.cos(v[:, 2]))[:, None]
    ty[..., 1] += (v[:, 1] * np.sin(v[:, 2]))[:, None]
    tp = tilt_sums(pa, po, pp, be, grouped)
    tp[..., 1] += v[:, 3][:, None]
    ca, sa, cb, sb = np.cos(al), np.sin(al), np.cos(be), np.sin(be)
    rz = np.zeros((al.size, 3, 3))
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1], rz[:, 2, 2] = ca, -sa, sa, ca, 1
    yaw_frames = tilt_rotation(Z, X, Y, ty) @ rz                          # (B, Ka, 3, 3)
    l = np.stack([np.ones(B), v[:, 4], np.zeros(B)], -1)
    l /= np.linalg.norm(l, axis=-1, keepdims=True)
    rl = np.stack([cb[None] * l[:, :1], np.broadcast_to(l[:, 1:2], (B, be.size)), sb[None] * l[:, :1]], -1)
    pitch_los = np.einsum("bkij,bkj->bki", tilt_rotation(-Y, X, Z, tp), rl)  # (B, Kb, 3)
    d = np.einsum("baij,bkj->baki", yaw_frames, pitch_los)               # (B, Ka, Kb, 3)
    n = np.stack(np.broadcast_arrays(cb[None, :] * ca[:, None], cb[None, :] * sa[:, None], sb[None, :]), -1)
    total = 2 * np.arcsin(0.5 * np.linalg.norm(d - n, axis=-1))
    along = d[..., 0] * ca[:, None] + d[..., 1] * sa[:, None]
    across = -d[..., 0] * sa[:, None] + d[..., 1] * ca[:, None]
    yaw = np.arctan2(across, along)
    pitch = np.arcsin(d[..., 2] * cb - np.hypot(d[..., 0], d[..., 1]) * sb)
    tot = total.reshape(B, -1)
    mt, my, mp = tot.max(1), np.abs(yaw).reshape(B, -1).max(1), np.abs(pitch).reshape(B, -1).max(1)
    out = np.stack([mt / ARCSEC, np.sqrt((tot ** 2).mean(1)) / ARCSEC, my / ARCSEC, mp / ARCSEC, mt / M["ifov"],
                    (tot <= M["requirement"]).mean(1), my / M["ifov"], mp / M["ifov"]], 1)
    return out, tot / ARCSEC


def display(M, v):
    """SI inputs -> Poise's display units (arcsec, deg, um)."""
    f = np.ones(v.shape[1])
    f[1], f[2], f[3], f[4] = ARCSEC, np.pi / 180, ARCSEC, ARCSEC
    f[5::2], f[6::2] = 1e-6, np.pi / 180
    return v / f


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--study", default=os.path.join(ROOT, "studies", "los_seeker_wang2011.toml"))
    ap.add_argument("--samples", type=int, default=16384)
    ap.add_argument("--batch", type=int, default=4096)
    ap.add_argument("--seed", type=int, default=20111101)
    ap.add_argument("--grouped", action="store_true")
    ap.add_argument("--compute-only", action="store_true", help="no results, no statistics")
    ap.add_argument("--lean", action="store_true",
                    help="per-sample outputs and their summary only (no grid values, maps or samples.csv)")
    ap.add_argument("--out", default=None, help="folder for samples.csv and summary.npz")
    ap.add_argument("--check", default=None, help="a Poise samples.csv of the same study: recompute, compare")
    a = ap.parse_args()
    M = load(a.study)
    D = 5 + 4 * sum(len(M["axes"][x]["sources"]) for x in ("yaw", "pitch"))
    if a.check:
        raw = np.genfromtxt(a.check, delimiter=",", names=True, dtype=None, encoding=None)
        cols = raw.dtype.names
        vin = np.stack([raw[c].astype(float) for c in cols[2:2 + D]], 1)
        f = display(M, np.ones((1, D)))[0]
        out, _ = kernel(M, vin / f, a.grouped)
        want = np.stack([raw[c].astype(float) for c in cols[2 + D:2 + D + 8]], 1)
        rel = np.abs(out - want) / np.maximum(np.abs(want), 1e-300)
        rel[:, 5] = np.abs(out[:, 5] - want[:, 5])  # field_ok_fraction: absolute
        print(f"check: {len(want)} samples, largest relative difference of the outputs {rel.max():.2e}")
        return 0 if rel.max() < 1e-9 else 1
    rng = np.random.default_rng(a.seed)
    t0 = time.process_time()
    compute = 0.0
    outs, grids, ins = [], [], []
    for start in range(0, a.samples, a.batch):
        b = min(a.batch, a.samples - start)
        c0 = time.process_time()
        v = draw(M, rng.random((b, D)))
        out, grid = kernel(M, v, a.grouped)
        compute += time.process_time() - c0
        if a.lean:
            outs.append(out)
        elif not a.compute_only:
            outs.append(out), grids.append(grid.astype(np.float32)), ins.append(display(M, v))
    if a.lean:
        out = np.concatenate(outs)
        probs = [0.5, 0.95, 0.9973]
        summary = dict(outputs=np.quantile(out, probs, axis=0), mean=out.mean(0), std=out.std(0, ddof=1),
                       ok=(out[:, 0] <= M["requirement"] / ARCSEC).mean())
        print(f"los_max_arcsec p50 {summary['outputs'][0, 0]:.3f} p95 {summary['outputs'][1, 0]:.3f}"
              f" p99.73 {summary['outputs'][2, 0]:.3f}; units meeting the requirement {summary['ok']:.3f} (lean)")
    elif not a.compute_only:
        out, grid, vin = np.concatenate(outs), np.concatenate(grids), np.concatenate(ins)
        probs = [0.5, 0.95, 0.9973]
        summary = dict(outputs=np.quantile(out, probs, axis=0), mean=out.mean(0), std=out.std(0, ddof=1),
                       maps=np.quantile(grid, probs, axis=0), pooled=np.quantile(grid, probs),
                       ok=(out[:, 0] <= M["requirement"] / ARCSEC).mean())
        if a.out:
            os.makedirs(a.out, exist_ok=True)
            table = np.column_stack([np.arange(a.samples), vin, out])
            np.savetxt(os.path.join(a.out, "samples.csv"), table, fmt=["%d"] + ["%.17g"] * (table.shape[1] - 1),
                       delimiter=",", comments="")
            np.savez(os.path.join(a.out, "summary.npz"), **summary)
        print(f"los_max_arcsec p50 {summary['outputs'][0, 0]:.3f} p95 {summary['outputs'][1, 0]:.3f}"
              f" p99.73 {summary['outputs'][2, 0]:.3f}; units meeting the requirement {summary['ok']:.3f}")
    total = time.process_time() - t0
    print(f"numpy: {a.samples} samples, compute {compute:.3f} CPU-s ({compute / a.samples * 1e6:.2f} us/sample),"
          f" whole run {total:.3f} CPU-s ({'grouped' if a.grouped else 'direct'} harmonic sums{', lean' if a.lean else ''})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
