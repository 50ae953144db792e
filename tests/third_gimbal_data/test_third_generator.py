"""ctest third_generator_scores: Poise's diagnosis scored on the third, independent generator.

Generates the seeded suite (generate.py) into a temporary folder, scores it with the built poise
(POISE_EXE, as tests/reports does) and asserts the scores stay at or above the floors below.
The floors are what the current poise achieves on this seeded suite (measured, see README.md);
raise them as the diagnosis improves (one line each).
"""
import json
import math
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate  # noqa: E402
import oracle  # noqa: E402
import score  # noqa: E402

FLOORS = {
    # measured on poise after the periodogram test of the residual (seed 3, full suite: 78 %,
    # 78 %, 0, 0, 0 %, 0 %); after the diagnosis round 4 (local noise level for cogging; seed 3:
    # 72 %, 78 %, 0, 0, 0 %, 0 %; seeds 5 and 11 records: 78 % and 89 % found,
    # 0 % false positives; round 3: 72 %, 56 %, 0, 0, 0 %, 17 %); the friction asymmetry scored
    # by its own target ("not identifiable", nothing invented) and cogging orders by their stated
    # resolution (seed 3: 78 %, 100 %, 0, 0, 0 %, 0 %, 2 of 2; seeds 5 and 11 records: 88 %, 100 %)
    #                                                           # the targets
    'table_found_pct_min': 77.0,                                # >= 90 % of detectable effects found
    'record_found_pct_min': 87.0,                               # >= 90 %
    'table_worse_max': 0,                                       # 0 estimates made worse
    'record_worse_max': 0,                                      # 0
    'table_false_positive_pct_max': 0.0,                        # <= 5 % on clean tables
    'record_false_positive_pct_max': 0.0,                       # <= 5 % on clean records
    # tables: at most this many detectable effects fewer than the oracle that knows each effect's
    # shape (noise estimated, the same 12 candidates at alpha 0.05; oracle.py); seed 3: 14 vs 16
    'table_below_oracle_max': 2,
}

SEED = 3


def poise_exe():
    exe = os.environ.get('POISE_EXE')
    if not exe:
        src = os.environ.get('POISE_SOURCE_DIR', os.path.join(HERE, '..', '..'))
        exe = os.path.join(src, 'build', 'poise')
    if not os.path.exists(exe):
        pytest.skip(f'no poise executable at {exe} (set POISE_EXE)')
    return exe


@pytest.fixture(scope='module')
def scored(tmp_path_factory):
    d = str(tmp_path_factory.mktemp('third_suite'))
    generate.generate(d, seed=SEED)
    res = score.score(d, poise_exe(), jobs=1)
    with open(os.path.join(d, 'scores.json'), 'w') as f:
        json.dump(res, f, indent=1)
    print(score.format_table(res['summary']))
    return d, res


def test_scores_not_below_floors(scored):
    _, res = scored
    t, r = res['summary']['table'], res['summary']['record']
    assert t['detectable'] >= 10 and r['detectable'] >= 5, 'suite lost its detectable effects'
    assert t['found_pct'] >= FLOORS['table_found_pct_min'], score.format_table(res['summary'])
    assert r['found_pct'] >= FLOORS['record_found_pct_min'], score.format_table(res['summary'])
    assert t['worse'] <= FLOORS['table_worse_max'], t['worse_files']
    assert r['worse'] <= FLOORS['record_worse_max'], r['worse_files']
    assert t['false_positive_pct'] <= FLOORS['table_false_positive_pct_max'], t['false_positive_files']
    assert r['false_positive_pct'] <= FLOORS['record_false_positive_pct_max'], r['false_positive_files']
    assert r['not_identifiable_target'] >= 1, 'suite lost its friction asymmetry'
    assert r['not_identifiable_said'] == r['not_identifiable_target'], score.format_table(res['summary'])
    o = res['summary']['oracle_noise_estimated']
    assert o['detectable'] == t['detectable']
    assert o['found'] - t['found'] <= FLOORS['table_below_oracle_max'], (o['missed'], t)


def test_oracle_z_on_noise_free_tables_is_the_planted_z(scored):
    """The oracle's matched filter, on a table with the planted effect and no noise, reads the
    generator's own z (its criterion) for every deterministic family."""
    d, _ = scored
    man = json.load(open(os.path.join(d, 'manifest.json')))
    checked = set()
    for entry in man['files']:
        if entry['kind'] != 'table':
            continue
        th, sw, t, _ = oracle.read_table(os.path.join(d, entry['file']))
        spec = dict(U_mNm=entry['U_mNm'], b_deg=entry['b_deg'], MK_mNm=entry['MK_mNm'])
        for eff in entry['effects']:
            fam, prm = eff['family'], eff['params']
            if fam == 'ar1':
                continue
            y = (2.0 + entry['U_mNm'] * np.sin(np.deg2rad(th + entry['b_deg']))
                 + generate.effect_signal(fam, prm, spec, th, sw, t))
            z = oracle.oracle_effect(entry, eff, th, sw, t, y, 0.05, 12, False)['z']
            assert abs(abs(z) - eff['z']) <= 1e-3 * max(1.0, eff['z']), (entry['file'], z, eff['z'])
            checked.add(fam)
    assert len(checked) >= 8, checked


def test_oracle_false_positive_rate_is_its_level():
    """On noise alone (split sweep, the planted sigma) the oracle's test of a step, a drift and
    the AR(1) test reject in alpha of tables (binomial 3-sigma band over 400)."""
    th, sw, t = generate.design('split36')
    entry = dict(U_mNm=10.0, b_deg=30.0, MK_mNm=3.0, noise_sigma_mNm=0.2)
    rng = np.random.default_rng(7)
    effects = [dict(family='linear_drift', params=dict(d_mNm=1.0)),
               dict(family='step', params=dict(s_mNm=1.0, row=20))]
    alpha, runs = 0.05, 400
    for eff in effects:
        for estimate_sigma in (False, True):
            hits = sum(oracle.oracle_effect(entry, eff, th, sw, t, 0.2 * rng.standard_normal(len(th)),
                                            alpha, 1, estimate_sigma)['found'] for _ in range(runs))
            band = 3.0 * math.sqrt(alpha * (1 - alpha) * runs)
            assert abs(hits - alpha * runs) <= band, (eff['family'], estimate_sigma, hits)
    ar = dict(family='ar1', params=dict(rho=0.5))
    hits = sum(oracle.oracle_effect(entry, ar, th, sw, t, 0.2 * rng.standard_normal(len(th)), alpha, 1,
                                    False)['found'] for _ in range(100))
    assert hits <= alpha * 100 + 3.0 * math.sqrt(alpha * (1 - alpha) * 100), hits


def test_cogging_orders_lie_within_their_stated_resolution(scored):
    """A cogging Poise reports on a record with one planted is within its stated resolution
    (order_resolution, half a cycle over the swing) of the planted order."""
    _, res = scored
    checked = 0
    for f in res['files']:
        if f['kind'] != 'record' or len(f.get('planted_orders', [])) != 1:
            continue
        for order, resolution in zip(f['orders'], f['order_resolutions']):
            assert resolution is not None and resolution > 0, f['file']
            assert abs(order - f['planted_orders'][0]) <= resolution, (f['file'], order, resolution)
            checked += 1
    assert checked >= 4, 'the suite lost its found cogging'


def test_manifest_lists_every_file_with_its_truth(scored):
    d, _ = scored
    man = json.load(open(os.path.join(d, 'manifest.json')))
    for e in man['files']:
        assert os.path.exists(os.path.join(d, e['file']))
        for eff in e['effects']:
            assert {'family', 'params', 'z', 'detectable'} <= set(eff)
        if e['kind'] == 'table':
            assert e['U_mNm'] > 0 and 'b_deg' in e
        else:
            assert math.isfinite(e['true_torque_mNm'])


def test_closed_form_limit():
    """No friction, no sensor noise: the integrated mean torque of a position is Eq. (2),
    [U sin(theta + b) J0(A) + M_K] / (1 - alpha dT) + K_T0 i0, to within the ADC quantum."""
    U, b, MK = 12.9e-3, 0.8, 3.0e-3
    th = np.deg2rad(np.arange(0.0, 360.0, 30.0))
    cases = [dict(), dict(alpha=0.0015, dT=8.0, i0=2e-3)]
    rows = []
    for c in cases:
        for x in th:
            r = dict(generate.RIG)
            r.update(theta=x, U=U, b=b, MK=MK, dT=0.0, Fc=0.0, Fs=0.0, sigma0=0.0, sigma1=0.0,
                     sigma2=0.0, noise_i=0.0)
            r.update(c)
            rows.append(r)
    p = generate.param_vectors(rows)
    m = generate.simulate(p, fs=2000.0, substeps=1, settle_periods=1, meas_periods=3,
                          rng=np.random.default_rng(0))
    m = generate.G_MNM * generate.KT0 * m
    quantum = generate.G_MNM * generate.KT0 * 2 * generate.RIG['adc_range'] / 2 ** generate.RIG['adc_bits']
    for k, c in enumerate(cases):
        cf = generate.closed_form_torque_mNm(U, b, MK, th, generate.RIG['A_deg'], c.get('alpha', 0.0),
                                             c.get('dT', 0.0), c.get('i0', 0.0))
        err = np.abs(m[k * len(th):(k + 1) * len(th)] - cf)
        assert err.max() < 0.25 * quantum, (c, err.max(), quantum)
