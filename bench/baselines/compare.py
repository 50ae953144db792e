#!/usr/bin/python3
"""Poise against its NumPy / SciPy baselines, in one run, by CPU time per core (issue 19).

  LOS compute      poise_bench BM_SampleCompute (one sample: design point, draw, 13 x 13 grid,
                   outputs; CPU time) against los_numpy.py's compute time per sample (direct
                   and grouped harmonic sums).                          Target >= 10x.
  LOS whole run    `poise run` of studies/los_seeker_wang2011.toml without its sweeps and
                   contribution reruns,
                   --threads 1 (results, summary and report written, no plots; user + sys CPU
                   of the process) against los_numpy.py with its samples.csv and summary
                   written; 5 pairs (1 with --quick) run in turn, the median pair's ratio
                   quoted with the range; then one pair at each of --scales (200000 and
                   10^6 samples).                                       Target >= 5x.
  LOS lean run     the same with [output] samples_csv, grid_values, maps and plots false
                   (per-sample outputs and their quantiles only) against los_numpy.py --lean,
                   at the same scales.                                  Target >= 5x.
  Cost per sample  Poise's CPU per sample at 16384 over that at each larger scale, whole
                   and lean (1 = flat).                                 Target >= 0.83.
  Stack-up         `poise run` of Drake's motor assembly (formula kind, 10^6 samples, no
                   samples.csv or plots) against stackup_numpy.py computing the same statistics;
                   3 pairs (1 with --quick), the median pair's ratio.        Target >= 1x.
  Gimbal           poise_gimbal_bench BM_Measurement36By (36-point measurement, CPU time) by
                   formulation and tolerance, each with its worst torque error over 4 rotors
                   x 3 noise seeds against their tight values, against gimbal_scipy.py --sweep
                   (LSODA) at the loosest rtol whose worst error over the same sweep is
                   within 1e-4 of the load.
                                                                        Target >= 50x.
The load average is printed beside the figures: on a loaded machine CPU times still grow
(shared caches, frequency), so compare runs at similar load.

--json FILE writes every printed figure in machine form (schema poise-baselines/1: each ratio
with its two CPU figures and their units, its target, the load average before and after, the
sample count, the quick flag), atomically (FILE.tmp, then renamed). bench/nightly embeds it in
its run file and compares the ratios (bench/NIGHTLY.md).

Usage: compare.py [--build build] [--samples 16384] [--scales 200000,1000000] [--quick] [--json FILE]
"""
import argparse, shutil, datetime, json, math, os, re, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ENV = dict(os.environ, POISE_SOURCE_DIR=ROOT, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, env=ENV, **kw).stdout


def gbench(exe, flt, min_time):
    out = run([exe, f"--benchmark_filter={flt}", f"--benchmark_min_time={min_time}", "--benchmark_format=json"])
    return {b["name"]: b for b in json.loads(out)["benchmarks"]}


def cpu_seconds(b):
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
    return b["cpu_time"] * scale


def child_cpu(cmd):
    before = os.times()
    subprocess.run(cmd, check=True, capture_output=True, env=ENV, cwd=ROOT)
    after = os.times()
    return (after.children_user - before.children_user) + (after.children_system - before.children_system)


def utc_now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def finite(x):
    """A JSON-safe number: NaN and infinities (a benchmark without its counter) become null."""
    return x if isinstance(x, (int, float)) and math.isfinite(x) else None


def figure(value, unit, what):
    return {"value": finite(value), "unit": unit, "what": what}


def ratio_entry(description, baseline, poise, target_min):
    """One ratio of CPU times: baseline / Poise (higher = Poise faster), with both figures."""
    value = baseline["value"] / poise["value"] if baseline["value"] and poise["value"] else None
    return {"description": description, "value": finite(value), "unit": "x", "better": "higher",
            "target": {"min": target_min}, "poise": poise, "baseline": baseline}


def write_json_atomic(path, doc):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def study_text(lean):
    """The study's Monte Carlo alone, as the NumPy script: its [[sweep]] runs and per-tolerance
    contribution reruns left out, the model by absolute path; lean: nothing per point and no
    samples.csv either ([output] keys), as los_numpy.py --lean."""
    text = open(os.path.join(ROOT, "studies", "los_seeker_wang2011.toml")).read().split("[[sweep]]")[0]
    text = text.replace('"../models/', '"' + os.path.join(ROOT, "models") + "/")
    text += "\n[output]\ncontribution_samples = 0  # no per-tolerance reruns: the Monte Carlo alone\n"
    if lean:
        text += "samples_csv = false\ngrid_values = false\nmaps = false\nplots = false\n"
    return text


def whole_run_pairs(build, n, lean, count):
    """Pairs, Poise then NumPy, each pair's ratio taken by itself: a neighbour's load that
    drifts during the minute acts on both sides of a pair alike. Sorted by ratio."""
    pairs = []
    with tempfile.TemporaryDirectory() as tmp:
        study = os.path.join(tmp, "los_seeker_wang2011.toml")
        open(study, "w").write(study_text(lean))
        for k in range(count):
            p_cpu = child_cpu([os.path.join(build, "poise"), "run", study, "--samples", str(n), "--threads",
                               "1", "--out", os.path.join(tmp, f"poise{k}"), "--quiet", "--no-plots"])
            n_cpu = child_cpu([sys.executable, os.path.join(HERE, "los_numpy.py"), "--samples", str(n)]
                              + (["--lean"] if lean else ["--out", os.path.join(tmp, f"numpy{k}")]))
            pairs.append((n_cpu / p_cpu, p_cpu, n_cpu))
            shutil.rmtree(os.path.join(tmp, f"poise{k}"), ignore_errors=True)
            shutil.rmtree(os.path.join(tmp, f"numpy{k}"), ignore_errors=True)
    return sorted(pairs)


STACKUP_STUDY = """[study]
name = "drake_stackup"
kind = "formula"
model = "{model}"
[sampling]
method = "monte_carlo"
samples = {samples}
seed = 1
[output]
plots = false
samples_csv = false
[[requirement]]
output = "gap"
within = ["0.04 in", "0.08 in"]
yield_at_least = 0.5
"""


def stackup_pairs(build, samples, count):
    """The formula kind on Drake's stack-up (its statistics, the share outside and the summary;
    no samples.csv, no plots) against stackup_numpy.py, pair by pair. Sorted by ratio."""
    pairs = []
    with tempfile.TemporaryDirectory() as tmp:
        study = os.path.join(tmp, "drake.toml")
        model = os.path.join(ROOT, "tests", "data", "stackups", "drake_motor_assembly", "model.toml")
        open(study, "w").write(STACKUP_STUDY.format(model=model, samples=samples))
        for k in range(count):
            p_cpu = child_cpu([os.path.join(build, "poise"), "run", study, "--threads", "1", "--out",
                               os.path.join(tmp, f"poise{k}"), "--quiet", "--no-plots"])
            n_cpu = child_cpu([sys.executable, os.path.join(HERE, "stackup_numpy.py"), "--samples", str(samples)])
            pairs.append((n_cpu / p_cpu, p_cpu, n_cpu))
            shutil.rmtree(os.path.join(tmp, f"poise{k}"), ignore_errors=True)
    return sorted(pairs)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--samples", type=int, default=16384, help="the first scale: 5 pairs of runs")
    ap.add_argument("--scales", type=lambda t: [int(x) for x in t.split(",") if x], default=[200000, 1000000],
                    help="larger sample counts of the whole and lean runs, one pair each (default 200000,1000000; "
                         "--quick: none)")
    ap.add_argument("--quick", action="store_true", help="shorter timings, LSODA at one tolerance")
    ap.add_argument("--json", metavar="FILE", help="also write every figure to FILE (JSON, written atomically)")
    a = ap.parse_args()
    mt = "0.2" if a.quick else "1"
    load_start = [round(x, 2) for x in os.getloadavg()]
    started = utc_now()
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    doc = {"schema": "poise-baselines/1", "started_utc": started, "quick": a.quick, "samples": a.samples,
           "min_time_s": float(mt), "figure": "CPU time per core (process time; Google Benchmark cpu_time)",
           "load_avg_start": load_start, "ratios": {}, "gimbal_lsoda": [], "gimbal_poise": []}

    # LOS compute.
    b = gbench(os.path.join(a.build, "bench", "poise_bench"), "BM_SampleCompute", mt)["BM_SampleCompute"]
    poise_us = cpu_seconds(b) * 1e6
    numpy_us = {}
    for mode in ("direct", "grouped"):
        out = run([sys.executable, os.path.join(HERE, "los_numpy.py"), "--samples", str(a.samples), "--compute-only"]
                  + (["--grouped"] if mode == "grouped" else []))
        numpy_us[mode] = float(re.search(r"\(([\d.]+) us/sample\)", out).group(1))
    print(f"LOS compute: poise {poise_us:.2f} us/sample; numpy {numpy_us['direct']:.2f} (direct sums), "
          f"{numpy_us['grouped']:.2f} (grouped) -> {numpy_us['direct'] / poise_us:.1f}x, "
          f"{numpy_us['grouped'] / poise_us:.1f}x (target >= 10x)")
    poise_fig = figure(poise_us, "us/sample", "poise_bench BM_SampleCompute, CPU time")
    for mode, key in (("direct", "los_compute"), ("grouped", "los_compute_grouped")):
        doc["ratios"][key] = ratio_entry(
            f"LOS compute per sample, NumPy {mode} harmonic sums over Poise", poise=poise_fig,
            baseline=figure(numpy_us[mode], "us/sample", f"los_numpy.py --compute-only{' --grouped' if mode == 'grouped' else ''}, "
                            f"{a.samples} samples, CPU time"), target_min=10.0)

    # LOS whole run, full and lean, at each scale (issue 34: the cost per sample flat from
    # 16384 to 10^6 samples; >= 5x the script, also when only the per-sample outputs and their
    # quantiles are wanted).
    scales = [a.samples] if a.quick else sorted({a.samples, *a.scales})
    per_sample = {}  # (mode, n) -> Poise CPU-s per sample
    for n in scales:
        for lean in (False, True):
            pairs = whole_run_pairs(a.build, n, lean, 1 if a.quick or n != a.samples else 5)
            ratio, poise_cpu, numpy_cpu = pairs[len(pairs) // 2]
            mode = "lean" if lean else "whole"
            per_sample[(mode, n)] = poise_cpu / n
            print(f"LOS {'lean' if lean else 'whole'} run ({n} samples, 1 thread{', outputs and quantiles only' if lean else ', results written'}): "
                  f"poise {poise_cpu:.2f} CPU-s ({poise_cpu / n * 1e6:.1f} us/sample), numpy {numpy_cpu:.2f} CPU-s "
                  f"-> {ratio:.1f}x (target >= 5x); median of {len(pairs)} pairs, {pairs[0][0]:.2f}x to {pairs[-1][0]:.2f}x")
            key = f"los_{mode}_run" + ("" if n == a.samples else f"_{n}")
            if lean:
                e = ratio_entry(
                    f"LOS lean run, {n} samples, 1 thread, per-sample outputs and their quantiles only: NumPy over Poise",
                    poise=figure(poise_cpu, "CPU-s", "poise run --threads 1 with [output] samples_csv, grid_values, "
                                 "maps and plots false, no sweeps or contribution reruns, user + system CPU"),
                    baseline=figure(numpy_cpu, "CPU-s", "los_numpy.py --lean, user + system CPU"), target_min=5.0)
            else:
                e = ratio_entry(
                    f"LOS whole run, {n} samples, 1 thread, results written: NumPy over Poise",
                    poise=figure(poise_cpu, "CPU-s", "poise run --threads 1 --no-plots of studies/los_seeker_wang2011.toml "
                                 "without sweeps and contribution reruns, user + system CPU"),
                    baseline=figure(numpy_cpu, "CPU-s", "los_numpy.py with samples.csv and summary written, user + system CPU"),
                    target_min=5.0)
            e["samples"] = n
            e["pairs"] = [{"ratio": r, "poise_cpu_s": pc, "numpy_cpu_s": nc} for r, pc, nc in pairs]
            e["value"] = finite(ratio)  # the median pair's own ratio
            doc["ratios"][key] = e
    # Flat cost per sample: Poise's CPU per sample at the smallest scale over that at each larger
    # one (1 = flat, below 1 = dearer at scale); target within 20 %.
    for mode in ("whole", "lean"):
        for n in scales[1:]:
            small, big = per_sample[(mode, scales[0])], per_sample[(mode, n)]
            e = ratio_entry(
                f"Poise's {mode}-run CPU per sample at {scales[0]} samples over at {n} (1 = flat)",
                poise=figure(big * 1e6, "us/sample", f"poise run, {n} samples, 1 thread ({mode})"),
                baseline=figure(small * 1e6, "us/sample", f"poise run, {scales[0]} samples, 1 thread ({mode})"),
                target_min=round(1 / 1.2, 3))
            doc["ratios"][f"los_{mode}_cost_flatness_{n}"] = e
            print(f"LOS {mode} run cost per sample: {small * 1e6:.1f} us at {scales[0]}, {big * 1e6:.1f} us at {n} "
                  f"-> flatness {small / big:.2f} (target >= 0.83: within 20 %)")

    # Gimbal measurement.
    g = gbench(os.path.join(a.build, "bench", "poise_gimbal_bench"), "BM_Measurement36By", "0.5" if not a.quick else "0.1")
    rtols = ["1e-4", "3e-4", "1e-3"] if a.quick else ["1e-4", "3e-4", "1e-3", "2e-3", "3e-3"]
    out = run([sys.executable, os.path.join(HERE, "gimbal_scipy.py"), "--sweep", "--rtol", *rtols])
    # Each side judged by the same rule: the worst torque error over the bench's accuracy sweep
    # (4 rotors x 3 noise seeds), not one case.
    lsoda = []  # (rtol, worst error, cpu s)
    for m in sorted(re.finditer(r"rtol ([\d.e+-]+): MT_s [\d.]+ mN\*m, \|dMT_s\|/load ([\d.e+-]+), cpu ([\d.]+) s per "
                                r"measurement, steps (\d+), rhs_evals (\d+)(?:, worst of \d+ cases ([\d.e+-]+))?", out),
                    key=lambda m: float(m.group(1))):
        rt, one, cpu, steps, rhs_evals = float(m.group(1)), float(m.group(2)), float(m.group(3)), int(m.group(4)), \
            int(m.group(5))
        err = float(m.group(6)) if m.group(6) else float("nan")
        print(f"gimbal LSODA rtol {rt:g}: {cpu * 1e3:.0f} ms CPU per measurement, |dMT_s|/load {err:.1e} (worst of "
              f"12 cases; this rotor {one:.1e}), {steps} steps, {rhs_evals} RHS evaluations")
        doc["gimbal_lsoda"].append({"rtol": rt, "cpu_ms": finite(cpu * 1e3), "torque_error_rel": finite(err),
                                    "torque_error_rel_this_rotor": finite(one), "steps": steps,
                                    "rhs_evals": rhs_evals})
        lsoda.append((rt, err, cpu))
    rows = []  # (formulation, loose, max_order, ms, err)
    for name, bm in g.items():
        m = re.search(r"quasi_static:(\d)/loose:(\d+)/max_order:(\d)", name)
        # The worst over the bench's accuracy sweep (4 rotors x 3 noise seeds), not one lucky case.
        rows.append((int(m.group(1)), int(m.group(2)), int(m.group(3)), cpu_seconds(bm) * 1e3,
                     bm.get("worst_torque_rel", float("nan"))))
        print(f"gimbal {name}: {rows[-1][3]:.1f} ms CPU, |dMT_s|/load {rows[-1][4]:.1e} (worst of 12 cases; "
              f"this rotor {bm.get('tol_torque_rel', float('nan')):.1e}), {bm.get('steps', 0):.0f} steps, "
              f"{bm.get('rhs_evals', 0):.0f} RHS evaluations")
        doc["gimbal_poise"].append({"name": name, "quasi_static": bool(rows[-1][0]), "loose": rows[-1][1],
                                    "max_order": rows[-1][2], "cpu_ms": finite(rows[-1][3]),
                                    "torque_error_rel": finite(rows[-1][4]), "steps": bm.get("steps"),
                                    "rhs_evals": bm.get("rhs_evals")})

    # "At the same accuracy": the loosest setting that, with every tighter one scanned, keeps the
    # torque within 1e-4 of the load of its tight value (the error is not monotone in the
    # tolerance; a lucky loose setting alone does not count).
    def safest(settings):  # [(tolerance, err, cost)] sorted by tolerance
        best = None
        for tol, err, cost in settings:
            if not err <= 1e-4:
                break
            best = (tol, err, cost)
        return best

    ref = safest(lsoda)
    for quasi, label in ((0, "dynamic supports"), (1, "quasi-static supports")):
        mine = safest(sorted((r[1], r[4], r[3]) for r in rows if r[0] == quasi and r[2] == 0))
        key = "gimbal_quasi_static" if quasi else "gimbal_dynamic"
        if ref and mine:
            print(f"gimbal {label}: {mine[2]:.1f} ms CPU at {mine[0]}x the model's tolerances (|dMT_s|/load "
                  f"{mine[1]:.1e}) vs LSODA {ref[2] * 1e3:.0f} ms at rtol {ref[0]:g} ({ref[1]:.1e}) -> "
                  f"{ref[2] * 1e3 / mine[2]:.1f}x per core (target >= 50x)")
            e = ratio_entry(
                f"gimbal 36-point measurement, {label}, at the same accuracy (torque within 1e-4 of the load): "
                "LSODA over Poise",
                poise=figure(mine[2], "ms", f"poise_gimbal_bench BM_Measurement36By, {mine[0]}x the model's "
                             "tolerances, CPU time"),
                baseline=figure(ref[2] * 1e3, "ms", f"gimbal_scipy.py LSODA rtol {ref[0]:g}, CPU time"), target_min=50.0)
            e["poise"]["loose"] = mine[0]
            e["poise"]["torque_error_rel"] = finite(mine[1])
            e["baseline"]["rtol"] = ref[0]
            e["baseline"]["torque_error_rel"] = finite(ref[1])
        else:  # no setting kept the torque within 1e-4: no ratio at the same accuracy
            e = {"description": f"gimbal 36-point measurement, {label}, at the same accuracy", "value": None,
                 "unit": "x", "better": "higher", "target": {"min": 50.0},
                 "reason": ("no LSODA tolerance" if not ref else "no Poise setting") +
                           " kept the torque within 1e-4 of the load"}
        doc["ratios"][key] = e
    # Stack-up (issue 54): the formula kind at 10^6 samples against a vectorised NumPy script.
    pairs = stackup_pairs(a.build, 1000000, 1 if a.quick else 3)
    ratio, p_cpu, n_cpu = pairs[len(pairs) // 2]
    print(f"Stack-up (Drake, 10^6 samples): poise {p_cpu:.2f} CPU-s, numpy {n_cpu:.2f} CPU-s -> {ratio:.2f}x "
          f"(range {pairs[0][0]:.2f}-{pairs[-1][0]:.2f}; target >= 1x)")
    doc["ratios"]["stackup"] = ratio_entry(
        "stack-up, Drake's motor assembly at 10^6 samples with its statistics: NumPy over Poise's formula kind",
        poise=figure(p_cpu, "s", "poise run, formula kind, --threads 1, no samples.csv or plots, user + sys CPU"),
        baseline=figure(n_cpu, "s", "stackup_numpy.py, 10^6 samples, user + sys CPU"), target_min=1.0)
    if a.json:
        doc["finished_utc"] = utc_now()
        doc["load_avg_end"] = [round(x, 2) for x in os.getloadavg()]
        write_json_atomic(a.json, doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
