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
import score  # noqa: E402

FLOORS = {
    # measured on poise after the periodogram test of the residual (seed 3, full suite: 78 %,
    # 78 %, 0, 0, 0 %, 0 %); after the diagnosis round 4 (local noise level for cogging; seed 3:
    # 72 %, 78 %, 0, 0, 0 %, 0 %; seeds 5 and 11 records: 78 % and 89 % found,
    # 0 % false positives; round 3: 72 %, 56 %, 0, 0, 0 %, 17 %)
    #                                                           # the targets
    'table_found_pct_min': 77.0,                                # >= 90 % of detectable effects found
    'record_found_pct_min': 77.0,                               # >= 90 %
    'table_worse_max': 0,                                       # 0 estimates made worse
    'record_worse_max': 0,                                      # 0
    'table_false_positive_pct_max': 0.0,                        # <= 5 % on clean tables
    'record_false_positive_pct_max': 0.0,                       # <= 5 % on clean records
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
