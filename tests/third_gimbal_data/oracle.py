#!/usr/bin/env python3
"""An upper bound for any diagnosis on a suite written by generate.py: the oracle.

The oracle knows what the diagnosis cannot: which effect is planted, its exact noise-free shape
and the noise level. On each table with a detectable planted effect it makes the most powerful
test of that one shape (Neyman-Pearson), at the multiplicity a diagnosis pays for not knowing
which of its candidates is there:

    deterministic effects  s = the effect's noise-free contribution (generate.py), projected off
                           the base model [1, sin, cos]: s' = (I - H) s; r = (I - H) y, the
                           residual of the table; z = s'.r / (sigma ||s'||) ~ N(0, 1) under no
                           effect (sigma the planted noise level, known to the oracle), N(z_plan,
                           1) with it; found when |z| > Phi^-1(1 - alpha / (2 m)).
                           With --estimate-sigma the oracle estimates sigma from the residual
                           off the base model and the shape (n - 4 dof) and makes the t test.
    AR(1) noise            the lag-1 autocorrelation of r in time order, one-sided (rho > 0), its
                           p from 4000 Monte Carlo draws r = (I - H) e, e ~ N(0, I); found when
                           p < alpha / m.

m is the number of candidates the diagnosis tests in its first round (12 for Poise: harmonics 2
to 6, time drift, K_T drift, direction offset, step, exponential settling, outlier, AR(1)); with
m = 1 the oracle is also told the family. A diagnosis that controls its false positives over m
candidates at alpha cannot expect to find more than this oracle on the same realisations: it
does not know the shape (a scanned step, a periodic shape, a period), and it estimates sigma.
The oracle's z on a realisation differs from the generator's planted z by the noise (sd 1).

Usage: oracle.py SUITE_DIR [--alpha 0.05] [--candidates 12]
"""
import argparse
import json
import os
import sys

import numpy as np
from scipy.stats import norm
from scipy.stats import t as student_t

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate  # noqa: E402


def read_table(path):
    d = np.genfromtxt(path, delimiter=',', names=True)
    order = np.argsort(d['time_s'], kind='stable')
    return d['theta_deg'][order], d['sweep'][order], d['time_s'][order], d['torque_mNm'][order]


def residual_maker(th):
    X = generate.base_design_matrix(th)
    return np.eye(len(th)) - X @ np.linalg.pinv(X)


def lag1(r):
    return float(r[1:] @ r[:-1] / (r @ r))


def ar1_p(M, r, draws=4000, seed=20261128):
    rng = np.random.default_rng(seed)
    sims = rng.standard_normal((draws, len(r))) @ M.T
    lag1_sims = np.sum(sims[:, 1:] * sims[:, :-1], axis=1) / np.sum(sims * sims, axis=1)
    return (1 + np.sum(lag1_sims >= lag1(r))) / (draws + 1)


def oracle_effect(entry, eff, th, sw, t, y, alpha, candidates, estimate_sigma):
    """(statistic, found) of the oracle's test of one planted effect."""
    M = residual_maker(th)
    r = M @ y
    fam, prm = eff['family'], eff['params']
    if fam == 'ar1':
        p = ar1_p(M, r)
        return dict(p=float(p), found=bool(p < alpha / candidates))
    spec = dict(U_mNm=entry['U_mNm'], b_deg=entry['b_deg'], MK_mNm=entry['MK_mNm'])
    s = M @ generate.effect_signal(fam, prm, spec, th, sw, t)
    along = float(s @ r / np.linalg.norm(s))
    if not estimate_sigma:
        z = along / entry['noise_sigma_mNm']
        return dict(z=z, found=bool(abs(z) > norm.ppf(1 - alpha / (2 * candidates))))
    dof = len(y) - 4
    z = along / np.sqrt((r @ r - along * along) / dof)
    return dict(z=z, found=bool(abs(z) > student_t.ppf(1 - alpha / (2 * candidates), dof)))


def oracle(suite, alpha=0.05, candidates=12, estimate_sigma=False):
    with open(os.path.join(suite, 'manifest.json')) as f:
        manifest = json.load(f)
    files = manifest['files'] if isinstance(manifest, dict) else manifest
    rows = []
    for entry in files:
        if entry['kind'] != 'table':
            continue
        th, sw, t, y = read_table(os.path.join(suite, entry['file']))
        for eff in entry['effects']:
            if not eff['detectable']:
                continue
            row = dict(file=entry['file'], family=eff['family'], planted_z=eff['z'])
            row.update(oracle_effect(entry, eff, th, sw, t, y, alpha, candidates, estimate_sigma))
            rows.append(row)
    found = sum(r['found'] for r in rows)
    return dict(alpha=alpha, candidates=candidates, estimate_sigma=estimate_sigma, detectable=len(rows), found=found,
                found_pct=100.0 * found / len(rows) if rows else float('nan'), effects=rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('suite')
    ap.add_argument('--alpha', type=float, default=0.05)
    ap.add_argument('--candidates', type=int, default=12)
    ap.add_argument('--estimate-sigma', action='store_true',
                    help='the oracle estimates the noise level from the residual (t test)')
    a = ap.parse_args()
    res = oracle(a.suite, a.alpha, a.candidates, a.estimate_sigma)
    for r in res['effects']:
        stat = f"z {r['z']:+.2f}" if 'z' in r else f"p {r['p']:.4f}"
        print(f"{r['file']:32s} {r['family']:18s} planted z {r['planted_z']:5.2f}  oracle {stat:10s}"
              f" {'found' if r['found'] else 'MISSED'}")
    known = 'shape known, noise estimated' if a.estimate_sigma else 'shape and noise known'
    print(f"oracle ({known}, {res['candidates']} candidates at alpha "
          f"{res['alpha']}): {res['found']}/{res['detectable']} ({res['found_pct']:.0f}%)")


if __name__ == '__main__':
    main()
