"""The Python module against the command line and against physics it can be checked on.

Run by ctest (python_api) with PYTHONPATH=build/python, POISE_EXE=build/poise and
POISE_SOURCE_DIR=the repository. Small sample counts: the big runs belong to studies.
"""
import csv
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import poise

SRC = os.environ.get("POISE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
EXE = os.environ.get("POISE_EXE", os.path.join(SRC, "build", "poise"))
SEEKER = os.path.join(SRC, "studies", "los_seeker_wang2011.toml")
SHAFT = os.path.join(SRC, "studies", "shaft_sag_example.toml")
GIMBAL = os.path.join(SRC, "studies", "gimbal_unbalance_mc.toml")


def read_csv_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: [row[k] for row in body] for k, name in enumerate(header)}


def cli_run(study, out, *args):
    subprocess.run([EXE, "run", study, "--out", str(out), "-q", "--no-plots", *args], check=True,
                   stdout=subprocess.DEVNULL)
    return read_csv_columns(os.path.join(out, "samples.csv"))


def as_float(cells):
    return np.array([float(c) if c not in ("", "nan") else math.nan for c in cells])


@pytest.mark.parametrize("study", [SEEKER, SHAFT])
def test_run_equals_the_command_line_value_for_value(tmp_path, study):
    r = poise.run(study, samples=48, seed=5, threads=2, out=tmp_path / "py")
    cli = cli_run(study, tmp_path / "cli", "-n", "48", "-s", "5", "-j", "1")
    assert r.path == str(tmp_path / "py")
    assert len(r.sample) == 48 and list(r.sample) == [int(c) for c in cli["sample"]]
    for name, values in r.outputs.items():
        np.testing.assert_array_equal(values, as_float(cli[name]), err_msg=name)
    for name, values in r.inputs.items():
        np.testing.assert_array_equal(values, as_float(cli[name]), err_msg=name)
    # Both folders hold the same samples.csv, byte for byte.
    with open(tmp_path / "py" / "samples.csv") as a, open(tmp_path / "cli" / "samples.csv") as b:
        assert a.read() == b.read()
    with open(tmp_path / "cli" / "summary.json") as f:
        assert r.summary["answer"] == json.load(f)["answer"]
    assert r.units["los_max_arcsec" if study == SEEKER else "los_error_arcsec"] == "arcsec"


def test_run_without_out_keeps_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path))  # where the run's temporary folder goes
    r = poise.run(SHAFT, samples=16, seed=1)
    assert r.path is None
    assert len(r.outputs["tilt_urad"]) == 16 and np.all(np.isfinite(r.outputs["tilt_urad"]))
    assert os.listdir(tmp_path) == []


def test_overrides_reach_the_model_and_the_summary():
    base = poise.run(SEEKER, samples=32, seed=2, threads=1)
    longer = poise.run(SEEKER, samples=32, seed=2, threads=1, overrides={"yaw.bearing_span": "164 mm"})
    assert longer.summary["study"]["overrides"]["yaw.bearing_span"] == "164 mm"
    # A yaw axis twice as long tilts half as much for the same run-outs: less yaw error.
    assert np.mean(longer.outputs["yaw_max_arcsec"]) < np.mean(base.outputs["yaw_max_arcsec"])


@pytest.mark.parametrize("study", [SEEKER, SHAFT, os.path.join(SRC, "studies", "los_obstruction.toml"),
                                   os.path.join(SRC, "studies", "geometry_mass_properties.toml")])
def test_evaluate_at_a_runs_inputs_gives_its_outputs(study):
    r = poise.run(study, samples=64 if study in (SEEKER, SHAFT) else 3, seed=9, threads=2)
    s = poise.Study(study)
    assert s.evaluates and not s.has_own_randomness
    assert s.input_names == list(r.inputs)
    y = s.evaluate(r.inputs, threads=2)
    assert list(y) == s.output_names
    for name in s.output_names:
        ok = r.ok
        np.testing.assert_allclose(y[name][ok], r.outputs[name][ok], rtol=1e-12, atol=1e-12, err_msg=name)


def test_evaluate_takes_a_matrix_and_leaves_missing_inputs_nominal():
    s = poise.Study(SEEKER)
    nominal = s.nominal()
    y0 = s.evaluate(nominal)
    # A perfect seeker points exactly: no tolerance, no LOS error.
    assert y0["los_max_arcsec"][0] == pytest.approx(0.0, abs=1e-9)
    # Only the pitch axis leaning: the error at the boresight grows with it, linearly.
    tilt = np.array([0.0, 5.0, 10.0, 20.0])
    y = s.evaluate({"pitch_perpendicularity_arcsec": tilt})
    assert np.all(np.diff(y["los_max_arcsec"]) > 0)
    x = np.tile([nominal[n] for n in s.input_names], (4, 1))
    x[:, s.input_names.index("pitch_perpendicularity_arcsec")] = tilt
    np.testing.assert_array_equal(s.evaluate(x)["los_max_arcsec"], y["los_max_arcsec"])


def test_shaft_sag_evaluate_against_euler_bernoulli():
    s = poise.Study(SHAFT)
    nominal = s.nominal()
    y = s.evaluate(nominal)
    # Simply supported shaft, point load P at a from bearing A (b = L - a): slope at the load
    # P a b (b - a) / (3 E I L), deflection P a^2 b^2 / (3 E I L), I = pi d^4 / 64 (solid).
    L, a, d, E, m, g = 0.056, nominal["load_position_mm"] * 1e-3, nominal["diameter_mm"] * 1e-3, \
        nominal["youngs_modulus_GPa"] * 1e9, nominal["load_mass_g"] * 1e-3, 9.80665
    b, inertia = L - a, math.pi * d**4 / 64
    slope = m * g * a * b * (b - a) / (3 * E * inertia * L)
    deflection = m * g * a**2 * b**2 / (3 * E * inertia * L)
    assert y["tilt_urad"][0] == pytest.approx(slope * 1e6, rel=1e-9)
    assert y["deflection_um"][0] == pytest.approx(deflection * 1e6, rel=1e-9)
    assert y["los_error_arcsec"][0] == pytest.approx(2 * abs(slope) * 206264.80624709636, rel=1e-9)
    # A point without a physical answer fails alone, with its reason.
    y = s.evaluate({"load_position_mm": np.array([20.0, 80.0, 30.0])})
    assert np.isfinite(y["tilt_urad"][0]) and np.isnan(y["tilt_urad"][1]) and np.isfinite(y["tilt_urad"][2])
    assert s.failure_count == 1 and s.last_failures[0][0] == 1 and "load off the shaft" in s.last_failures[0][1]


def test_evaluate_refuses_unknown_inputs_with_a_suggestion():
    s = poise.Study(SEEKER)
    with pytest.raises(poise.InputError, match="did you mean 'pitch_perpendicularity_arcsec'"):
        s.evaluate({"pitch_perpendicularity_arcsek": [1.0]})


@pytest.mark.parametrize("study", ["gimbal_unbalance_from_geometry.toml", "platform_balancing_sequence.toml"])
def test_a_study_that_cannot_evaluate_says_why(study):
    s = poise.Study(os.path.join(SRC, "studies", study))
    assert not s.evaluates and "cannot be evaluated" in s.why_not
    assert s.has_own_randomness  # said for every kind, evaluable or not
    assert s.output_names
    with pytest.raises(poise.Error, match="cannot be evaluated"):
        s.evaluate({})


def test_balancing_evaluate_gives_sample_k_its_draws():
    # As the gimbal's, to the solver's reaction to the inputs' rounding in samples.csv (a
    # last-digit change moves the adaptive steps: about 1e-6 of an output here).
    study = os.path.join(SRC, "studies", "wang2014_balancing_mc.toml")
    r = poise.run(study, samples=3, seed=4, threads=2)
    s = poise.Study(study, seed=4)
    assert s.evaluates and s.has_own_randomness
    y = s.evaluate(r.inputs, threads=2)
    for name in s.output_names:
        np.testing.assert_allclose(y[name][r.ok], r.outputs[name][r.ok], rtol=1e-4, atol=1e-9, err_msg=name)
    assert not poise.Study(SHAFT).has_own_randomness


def test_gimbal_evaluate_gives_sample_k_its_draws():
    # The gimbal's samples draw per test (K_T drift, zeros) and add sensor noise: point k of
    # evaluate gets sample k's, so a run's inputs in order give its outputs back (to the
    # solver's reaction to the inputs' last-digit rounding in samples.csv).
    r = poise.run(GIMBAL, samples=3, seed=4, threads=2)
    s = poise.Study(GIMBAL, seed=4)
    assert s.evaluates and s.has_own_randomness
    y = s.evaluate(r.inputs, threads=2)
    for name in s.output_names:
        np.testing.assert_allclose(y[name][r.ok], r.outputs[name][r.ok], rtol=1e-6, atol=1e-9, err_msg=name)
    # The nominal rig measures the loads with the noise alone: small torque errors.
    nominal = s.evaluate(s.nominal())
    assert np.all(np.isfinite(nominal["g_rmse_torque_mNm"]))


def test_input_error_carries_file_line_and_key(tmp_path):
    text = open(SHAFT).read().replace('model = "../models/', 'model = "' + os.path.join(SRC, "models") + '/')
    bad = tmp_path / "bad.toml"
    assert "\nseed = 1\n" in text
    bad.write_text(text.replace("\nseed = 1\n", "\nseed = \"eleven\"\n", 1))
    with pytest.raises(poise.InputError) as e:
        poise.run(bad, samples=4)
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(bad) and e.value.line and e.value.key == "sampling.seed"
    with pytest.raises(poise.InputError):
        poise.Study(bad)
    with pytest.raises(poise.InputError, match="overrides"):
        poise.run(SHAFT, overrides=["x"])


def test_input_error_carries_every_refused_value(tmp_path):
    # Two refused values in one file: .errors holds both, each with its file, line and key, as
    # `poise validate` lists them; the error's own file, line and key are the first one's.
    text = open(SHAFT).read().replace('model = "../models/', 'model = "' + os.path.join(SRC, "models") + '/')
    assert "\nseed = 1\n" in text and "\nsamples = " in text
    text = text.replace("\nseed = 1\n", "\nseed = \"eleven\"\n", 1).replace("\nsamples = ", "\nsamples = -", 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    with pytest.raises(poise.InputError) as e:
        poise.run(bad, samples=4)
    keys = [r.key for r in e.value.errors]
    assert "sampling.seed" in keys and "sampling.samples" in keys, e.value.errors
    lines = text.splitlines()
    for r in e.value.errors:
        assert r.file == str(bad) and r.line and r.key.split(".")[-1] in lines[r.line - 1], r
        assert r.message and r.expected, r
    assert (e.value.file, e.value.line, e.value.key) == (e.value.errors[0].file, e.value.errors[0].line,
                                                         e.value.errors[0].key)
    cli = subprocess.run([EXE, "validate", str(bad)], capture_output=True, text=True)
    assert cli.returncode == 2
    for r in e.value.errors:
        assert f"{r.file}:{r.line}" in cli.stderr + cli.stdout
    # An error of a call's own argument: one entry, the error itself.
    with pytest.raises(poise.InputError) as e:
        poise.run(SHAFT, overrides=["x"])
    assert len(e.value.errors) == 1 and e.value.errors[0].message == str(e.value)


def test_input_units_are_the_declared_ones():
    # "residual_unbalance_g_mm" is in g*mm: its kind says so; a name's tail would say mm.
    r = poise.run(GIMBAL, samples=2, threads=1)
    assert r.units["residual_unbalance_g_mm"] == "g*mm" and r.units["axis_tilt_arcmin"] == "arcmin"
    assert r.units == {**r.summary["sampling"]["input_units"], **{k: r.units[k] for k in r.outputs}}
    s = poise.Study(SEEKER)
    assert s.input_units["yaw_perpendicularity_tilt_arcsec"] == "arcsec" and s.input_units["k_load"] == "1"


def test_validate_and_replay_are_the_command_lines():
    for study in (SEEKER, GIMBAL):
        cli = subprocess.run([EXE, "validate", study], check=True, capture_output=True, text=True).stdout.strip()
        assert poise.validate(study) == cli
        j = json.loads(subprocess.run([EXE, "replay", study, "-i", "3", "--samples", "16", "--seed", "5"], check=True,
                                      capture_output=True, text=True).stdout)
        s = poise.replay(study, 3, samples=16, seed=5)
        assert isinstance(s, poise.Sample)
        assert s.index == 3 and s.ok == (j["status"] == "ok") and s.inputs == j["inputs"] and s.outputs == j["outputs"]
        assert set(s.details) == set(j) - {"sample", "status", "message", "inputs", "outputs"}
    # The seeker's grid as arrays: its greatest total error is the sample's los_max_arcsec.
    s = poise.replay(SEEKER, 3, samples=16, seed=5)
    grid = s.details["grid"]
    assert isinstance(grid["total_arcsec"], np.ndarray) and grid["total_arcsec"].shape == grid["yaw_deg"].shape
    assert grid["total_arcsec"].max() == pytest.approx(s.outputs["los_max_arcsec"], rel=1e-12)
    with pytest.raises(poise.InputError, match="outside"):
        poise.replay(SEEKER, 16, samples=16)
    with pytest.raises(poise.InputError):
        poise.validate(os.path.join(SRC, "studies", "wang2011_budget.toml"))


def test_optimize_is_the_command_line(tmp_path):
    # A small bearing-span sizing of the LOS study: the same optimum, answer and verdict as
    # `poise optimize` at the same seed.
    opt = tmp_path / "spans.toml"
    opt.write_text(f"""[optimization]
name = "spans"
study = "{SEEKER}"
samples = 128
seed = 11
algorithm = "cobyla"
max_evaluations = 12

[[variable]]
parameter = "yaw.bearing_span"
lower = "60 mm"
upper = "160 mm"
start = "140 mm"

[objective]
variable_sum = ["yaw.bearing_span"]

[[constraint]]
output = "los_max_px"
statistic = "p95"
at_most = 1.9

[verification]
samples = 256
seed = 5
""")
    cli = subprocess.run([EXE, "optimize", str(opt), "-q", "--no-plots", "--threads", "2", "--out",
                          str(tmp_path / "cli")], capture_output=True, text=True)
    assert cli.returncode in (0, 3), cli.stderr
    cli_summary = json.load(open(tmp_path / "cli" / "summary.json"))
    r = poise.optimize(opt, threads=2)
    assert isinstance(r, poise.Optimization) and r.path is None
    assert r.exit_status == cli.returncode and r.verified == (cli.returncode == 0)
    assert r.answer == cli_summary["answer"] and f"answer: {r.answer}" in cli.stdout
    assert r.summary["optimum"] == cli_summary["optimum"] and r.summary["verification"] == cli_summary["verification"]
    with pytest.raises(poise.InputError):
        poise.optimize(SEEKER)


def cli_json(*args, cwd=None):
    return json.loads(subprocess.run([EXE, *args, "--json"], check=True, capture_output=True, text=True,
                                     cwd=cwd).stdout)


def test_fit_diagnose_record_error_mechanisms_and_sensitivity_are_the_command_lines(tmp_path):
    table = os.path.join(SRC, "data", "yang2015", "table1_loading_test_36pt.csv")
    j = cli_json("fit", table)
    f = poise.fit(table)
    assert isinstance(f, poise.SineFit)
    assert (f.amplitude, f.phase_deg, f.offset, f.unit, f.n_points) == (j["amplitude"], j["phase_deg"], j["offset"],
                                                                         j["unit"], j["n_points"])
    assert np.array_equal(f.residuals["residual"], [r["residual"] for r in j["residuals"]])
    # A real record (ODrive's holding-current map) with its own columns and units.
    folder = os.path.join(SRC, "tests", "data", "real", "odrive_gchenfc_coggingmap")
    j = cli_json("diagnose-record", "map.csv", "--column", "angle=count", "--unit", "angle=1/8192 rev", "--column",
                 "current=Iq_A", "--kt", "1 N*m/A", cwd=folder)
    d = poise.diagnose_record(os.path.join(folder, "map.csv"), kt="1 N*m/A",
                              columns={"angle": "count", "current": "Iq_A"}, units={"angle": "1/8192 rev"})
    assert isinstance(d, poise.RecordDiagnosis) and d.answer == j["answer"]
    assert {k: v for k, v in d.json.items() if k != "file"} == {k: v for k, v in j.items() if k != "file"}
    assert d.angle.shape == d.residual_before.shape == d.residual_after.shape and d.angle.size > 100
    assert np.sqrt(np.mean(d.residual_after ** 2)) < np.sqrt(np.mean(d.residual_before ** 2))
    with pytest.raises(poise.InputError, match="--unit angle=UNIT") as e:  # counts without their unit
        poise.diagnose_record(os.path.join(folder, "map.csv"), columns={"angle": "count", "current": "Iq_A"})
    assert e.value.file.endswith("map.csv") and e.value.line == 2
    # Which error mechanism the paper's tables support, with few draws.
    data = os.path.join(SRC, "data", "yang2015")
    j = cli_json("error-mechanisms", data, "--draws", "200")
    assert poise.error_mechanisms(data, draws=200) == j
    with pytest.raises(poise.InputError, match="no such table"):
        poise.error_mechanisms(data, calibrate="Table 99", draws=200)
    # Sobol indices: the command's summary.
    subprocess.run([EXE, "sensitivity", SHAFT, "--base", "64", "-q", "--no-plots", "--threads", "2", "--out",
                    str(tmp_path / "cli")], check=True, stdout=subprocess.DEVNULL)
    r = poise.sensitivity(SHAFT, base=64, threads=2)
    assert r.summary["sensitivity"] == json.load(open(tmp_path / "cli" / "summary.json"))["sensitivity"]


def test_budget_is_the_json_of_the_command_line():
    budget = os.path.join(SRC, "studies", "wang2011_budget.toml")
    j = poise.budget(budget)
    cli = json.loads(subprocess.run([EXE, "budget", budget, "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    assert j["answer"] == cli["answer"] and j["combined"] == cli["combined"]


def test_balance_is_the_json_of_the_command_line(tmp_path):
    campaign = os.path.join(SRC, "examples", "balance_campaign", "campaign.toml")
    j = poise.balance(campaign, out=tmp_path / "report")
    cli = json.loads(subprocess.run([EXE, "balance", campaign, "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    assert j == cli
    assert (tmp_path / "report" / "report.html").exists()
    with pytest.raises(poise.InputError) as e:
        poise.balance(os.path.join(SRC, "studies", "wang2011_budget.toml"))
    assert "campaign" in str(e.value)


def test_mass_properties_of_a_cube(tmp_path):
    # A 10 mm cube of 1000 kg/m^3: 1 g, centre at its middle, I = m a^2 / 6 about each axis.
    v = [(x, y, z) for x in (0, 10) for y in (0, 10) for z in (0, 10)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
             (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    lines = ["solid cube"]
    for f in faces:
        lines += ["facet normal 0 0 0", "outer loop"] + [f"vertex {v[i][0]} {v[i][1]} {v[i][2]}" for i in f] + \
                 ["endloop", "endfacet"]
    (tmp_path / "cube.stl").write_text("\n".join(lines + ["endsolid cube"]) + "\n")
    j = poise.mass_properties(tmp_path / "cube.stl", unit="mm", density="1000 kg/m^3")
    text = json.dumps(j)
    cli = json.loads(subprocess.run([EXE, "mass-properties", str(tmp_path / "cube.stl"), "--unit", "mm", "--density",
                                     "1000 kg/m^3", "--json"], check=True, capture_output=True, text=True).stdout)
    assert {k: v for k, v in j.items() if k != "warnings"} == cli, text
    assert j["mass_kg"] == pytest.approx(1e-3, rel=1e-12)
    with pytest.raises(poise.InputError, match="unit"):
        poise.mass_properties(tmp_path / "cube.stl", unit="furlong", density="1000 kg/m^3")


def test_diagnose_is_the_json_of_the_command_line():
    data = os.path.join(SRC, "data", "yang2015", "table1_loading_test_36pt.csv")
    j = poise.diagnose(data)
    cli = json.loads(subprocess.run([EXE, "diagnose", data, "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    assert j == cli
    # Not a table: its header (the first line that is not a comment) has no angle column.
    with pytest.raises(poise.InputError, match="theta_deg") as e:
        poise.diagnose(os.path.join(SRC, "README.md"))
    assert e.value.file == os.path.join(SRC, "README.md") and e.value.line >= 1


def test_evaluate_releases_the_gil():
    # evaluate holds before point 3000 (a test hook of the engine) until this thread sees the hold
    # and releases it. This thread needs the GIL to look: had evaluate kept it, the test could
    # never get past its first look (it would end at ctest's hang guard). No timing involved.
    from poise import _poise
    s = poise.Study(SEEKER)
    x = np.tile([v for v in s.nominal().values()], (6000, 1))
    _poise._test_hold_at_sample(3000)
    try:
        t = threading.Thread(target=lambda: s.evaluate(x, threads=1))
        t.start()
        while not _poise._test_hold_reached():
            time.sleep(0.001)
        assert t.is_alive()  # evaluate is inside its call, held, while this thread runs
        _poise._test_release_hold()
        t.join()
    finally:
        _poise._test_hold_at_sample(None)
    assert not t.is_alive()


def test_ctrl_c_stops_a_run():
    # The run holds at sample 5000 until its signal (POISE_INJECT_HOLD_AT_SAMPLE) and says so on
    # stderr: the signal is sent once the run is under way, and the run cannot end before it.
    code = ("import poise, sys\n"
            "try:\n"
            f"    poise.run({SEEKER!r}, samples=20000, seed=1, threads=1)\n"
            "except KeyboardInterrupt as e:\n"
            "    print('interrupted:', e); sys.exit(42)\n")
    env = dict(os.environ, POISE_INJECT_HOLD_AT_SAMPLE="5000")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env)
    seen = []
    for line in p.stderr:  # ends at the hook's line, or when the child ends without it
        seen.append(line)
        if "held until SIGINT" in line:
            break
    assert seen and "sample 5000 held" in seen[-1], "".join(seen)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate()
    assert p.returncode == 42, out + err
    assert "SIGINT" in out and "nothing was kept (out=None)" in out


def test_arguments_of_the_wrong_kind_are_input_errors(tmp_path):
    for bad in ({"samples": -5}, {"samples": 10.5}, {"seed": "abc"}, {"threads": -1}):
        with pytest.raises(poise.InputError, match=list(bad)[0]):
            poise.run(SHAFT, **bad)
    with pytest.raises(poise.InputError, match="density"):
        poise.mass_properties("x.stl", unit="mm", density=2700)
    s = poise.Study(SHAFT)
    with pytest.raises(poise.InputError, match="not text"):
        s.evaluate({"diameter_mm": "8 mm"})
    with pytest.raises(poise.InputError, match="2-D"):
        s.evaluate({"diameter_mm": np.ones((2, 2))})
    y = s.evaluate({"diameter_mm": [8.0, np.inf, np.nan]})
    assert np.isfinite(y["tilt_urad"][0]) and np.all(np.isnan(y["tilt_urad"][1:]))
    assert [k for k, _ in s.last_failures] == [1, 2] and "not a finite number" in s.last_failures[0][1]
    poise.run(SHAFT, samples=4, out=tmp_path / "r")
    with pytest.raises(poise.InputError, match="^out=") as e:
        poise.run(SHAFT, samples=4, out=tmp_path / "r")
    assert e.value.key == "out"
    with pytest.raises(poise.InputError, match="poise budget"):
        poise.run(os.path.join(SRC, "studies", "wang2011_budget.toml"))


def test_warnings_reach_python_as_poise_warnings():
    # A fresh interpreter: Poise says a study's warnings once per process.
    code = (
        "import warnings, poise\n"
        "with warnings.catch_warnings(record=True) as w:\n"
        "    warnings.simplefilter('always')\n"
        f"    poise.Study({os.path.join(SRC, 'studies', 'wang2014_balancing_mc.toml')!r})\n"
        "print(len(w), all(issubclass(x.category, poise.PoiseWarning) for x in w))\n"
        "print(w[0].message if w else '')\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ.copy(), timeout=600)
    assert r.returncode == 0, r.stderr
    first, message = r.stdout.splitlines()[:2]
    count, all_poise = first.split()
    assert int(count) >= 1 and all_poise == "True", r.stdout
    assert "above lead" in message or "outside the rotor" in message, r.stdout
    assert "poise: warning:" not in r.stderr  # not printed besides: Python has them


def test_diagnose_reads_a_labs_table_with_its_own_columns(tmp_path):
    """columns= and units= are the command line's --column and --unit."""
    path = tmp_path / "lab.csv"
    rows = ["# turntable log", "angle (deg);M"]
    with open(os.path.join(SRC, "data", "yang2015", "table1_loading_test_36pt.csv"), encoding="utf-8") as f:
        next(f)
        for line in f:
            theta, torque = line.strip().split(",")[:2]
            rows.append(f"{theta};{float(torque) * 1e-3!r}".replace(".", ","))
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    j = poise.diagnose(path, columns={"angle": "angle (deg)", "torque": "M"}, units={"torque": "N*m"})
    cli = json.loads(subprocess.run([EXE, "diagnose", str(path), "--column", "angle=angle (deg)", "--column",
                                     "torque=M", "--unit", "torque=N*m", "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    assert j == cli
    assert j["estimate_before"]["amplitude"] == pytest.approx(12.4747e-3, rel=1e-4)


# --- Your own mechanism: a Python function (kind = "python"), an external program ---------------

STACK_PARAMETERS = """
[parameters]
housing = "0.060 m"
bearing_a = "0.016 m"
spacer = "0.0276 m"
bearing_b = "0.016 m"
[tolerances.housing]
tolerance = "0.00005 m"
distribution = "normal"
tolerance_is = "3sigma"
[tolerances.bearing_a]
deviation = ["-0.00012 m", "0 m"]
distribution = "normal"
tolerance_is = "3sigma"
[tolerances.spacer]
tolerance = "0.00003 m"
distribution = "uniform"
tolerance_is = "bounds"
"""

STACK_PROGRAM = """import json, sys
for line in sys.stdin:
    r = json.loads(line)
    x = r["inputs"]
    print(json.dumps({"sample": r["sample"], "outputs": {"gap": x["housing"] - (x["bearing_a"] + x["spacer"] + x["bearing_b"])}}), flush=True)
"""


def stack_study(tmp_path, kind, model_keys=""):
    outputs = '[[output]]\nname = "gap"\nunit = "m"\n'
    if kind == "formula":
        outputs += 'formula = "housing - (bearing_a + spacer + bearing_b)"\n'
    (tmp_path / f"{kind}.toml").write_text(f'[model]\nkind = "{kind}"\nname = "stack"\n{model_keys}' +
                                           STACK_PARAMETERS + outputs)
    study = tmp_path / f"study_{kind}.toml"
    study.write_text(f'[study]\nname = "s"\nkind = "{kind}"\nmodel = "{kind}.toml"\n'
                     '[sampling]\nmethod = "monte_carlo"\nsamples = 300\nseed = 4\nmax_failure_share = 0.99\n')
    return str(study)


def stack_function(x):
    return {"gap": x["housing"] - (x["bearing_a"] + x["spacer"] + x["bearing_b"])}


def test_a_formula_a_program_and_a_python_function_give_the_same_samples(tmp_path):
    """The same arithmetic in SI units three ways: samples.csv the same byte for byte."""
    (tmp_path / "model.py").write_text(STACK_PROGRAM)
    runs = {
        "formula": poise.run(stack_study(tmp_path, "formula"), threads=2, out=tmp_path / "formula_run"),
        "python": poise.run(stack_study(tmp_path, "python", "batch = 64\n"), threads=2, out=tmp_path / "python_run",
                            model=stack_function),
        "external": poise.run(stack_study(tmp_path, "external", 'command = ["python3", "model.py"]\n'), threads=2,
                              out=tmp_path / "external_run", allow_programs=True),
    }
    texts = {k: (tmp_path / f"{k}_run" / "samples.csv").read_text() for k in runs}
    assert texts["python"] == texts["formula"]
    assert texts["external"] == texts["formula"]
    assert len(runs["python"].outputs["gap"]) == 300


def test_a_python_study_needs_its_function_and_a_program_its_permission(tmp_path):
    with pytest.raises(poise.Error, match=r"poise.run\(.*model=f"):
        poise.run(stack_study(tmp_path, "python"))
    (tmp_path / "model.py").write_text(STACK_PROGRAM)
    with pytest.raises(poise.Error, match="--allow-programs"):
        poise.run(stack_study(tmp_path, "external", 'command = ["python3", "model.py"]\n'))
    with pytest.raises(poise.InputError, match="expected a function"):
        poise.run(stack_study(tmp_path, "python"), model=42)


def test_a_python_function_that_fails_fails_its_samples_with_the_reason(tmp_path):
    def half_nan(x):
        gap = x["housing"] - (x["bearing_a"] + x["spacer"] + x["bearing_b"])
        gap[::2] = np.nan
        return {"gap": gap}

    def raising(x):
        raise ValueError("no such bearing")

    r = poise.run(stack_study(tmp_path, "python"), model=half_nan, out=tmp_path / "nan")
    assert r.summary["failures"]["count"] == 150
    assert "the model function gave no number for gap" in (tmp_path / "nan" / "samples.csv").read_text()
    with pytest.raises(poise.Error):
        poise.run(stack_study(tmp_path, "python"), model=raising, out=tmp_path / "raising")
    assert "the model function raised ValueError: no such bearing" in (tmp_path / "raising" / "samples.csv").read_text()


def test_the_shipped_python_study_gives_its_recorded_samples(tmp_path):
    """studies/bearing_stack_python.toml with models/bearing_stack_python.py at the plan's 2
    samples, seed 11 (tests/data/study_reference/record.sh records it this way)."""
    import runpy
    f = runpy.run_path(os.path.join(SRC, "models", "bearing_stack_python.py"))["model"]
    poise.run(os.path.join(SRC, "studies", "bearing_stack_python.toml"), samples=2, seed=11, threads=2,
              out=tmp_path / "run", model=f)
    recorded = os.path.join(SRC, "tests", "data", "study_reference", "bearing_stack_python.csv")
    assert (tmp_path / "run" / "samples.csv").read_text() == open(recorded).read()
