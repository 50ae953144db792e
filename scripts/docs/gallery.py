"""The guide's gallery: a real report of each study kind and of each command that writes one,
made by build/poise at small sample counts when the guide is built, its first screen taken by
headless Chromium (Debian's `chromium`), the report itself kept beside the picture.

Used by scripts/docs/build_guide.py."""
import json
import os
import shutil
import subprocess
import tempfile


def optimization_file(source, folder, samples=8, evaluations=6, verification=16):
    """A small test-plan question on the gimbal study: 8 or 12 positions, the period searched,
    test time second (also tests/reports' optimize report, at fewer samples)."""
    path = os.path.join(folder, "plan.toml")
    study = os.path.join(source, "studies", "gimbal_unbalance_mc.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f'''[optimization]
name = "plan"
study = "{study}"
samples = {samples}
seed = 5
algorithm = "cobyla"
max_evaluations = {evaluations}
[[variable]]
parameter = "oscillation.period"
lower = "1 s"
upper = "6 s"
start = "4 s"
[[choice]]
parameter = "group.positions"
values = ["8", "12"]
[overrides]
"oscillation.periods" = "1"
[objective]
output = "g_rmse_torque_mNm"
statistic = "p95"
[pareto]
output = "g_test_time_min"
statistic = "max"
points = 1
[verification]
samples = {verification}
seed = 9
''')
    return path


# (anchor, title, the guide page that produces it, the command's arguments after `poise`)
def entries(source, folder):
    study = lambda name: os.path.join("studies", name)  # noqa: E731  (run from the source folder)
    return [
        ("seeker_los", "Seeker LOS error (study kind seeker_los)", "papers.md",
         ["run", study("los_seeker_wang2011.toml"), "--samples", "1024"]),
        ("shaft_sag", "Your own closed-form mechanism (study kind shaft_sag)", "own-mechanism.md",
         ["run", study("shaft_sag_example.toml"), "--samples", "4096"]),
        ("formula", "Your own mechanism as formulas, no C++ (study kind formula)", "own-mechanism.md",
         ["run", study("bearing_stack_formula.toml"), "--samples", "20000"]),
        ("external", "Your own mechanism as a program of its own (study kind external)", "own-mechanism.md",
         ["run", study("bearing_stack_external.toml"), "--samples", "4096", "--allow-programs"]),
        ("python", "Your own mechanism as a Python function (study kind python)", "own-mechanism.md",
         ["python", study("bearing_stack_python.toml"), os.path.join("models", "bearing_stack_python.py")]),
        ("gimbal_static_unbalance", "Static-unbalance test of a gimbal axis (gimbal_static_unbalance)", "designer.md",
         ["run", study("gimbal_unbalance_mc.toml"), "--samples", "16"]),
        ("balancing_machine", "Spring-plate balancing machine (balancing_machine)", "balancing.md",
         ["run", study("wang2014_balancing_mc.toml"), "--samples", "32"]),
        ("platform_balancing", "Three-gimbal platform balanced axis by axis (platform_balancing)", "papers.md",
         ["run", study("platform_balancing_sequence.toml"), "--samples", "8"]),
        ("geometry_mass_properties", "A part as built (geometry_mass_properties)", "cad-parts.md",
         ["run", study("geometry_mass_properties.toml"), "--samples", "16"]),
        ("los_obstruction", "The beam through the seeker's frames (los_obstruction)", "papers.md",
         ["run", study("los_obstruction.toml"), "--samples", "16"]),
        ("sensitivity", "Which tolerance drives what (poise sensitivity)", "running-studies.md",
         ["sensitivity", study("shaft_sag_example.toml"), "--base", "256"]),
        ("budget", "A reviewer's error budget (poise budget)", "reviewer.md",
         ["budget", study("wang2011_budget.toml")]),
        ("diagnose", "Measured turntable data diagnosed (poise diagnose)", "metrologist.md",
         ["diagnose", os.path.join("data", "yang2015", "table1_loading_test_36pt.csv"),
          "--load-torque", "12.91 mN*m", "--load-angle", "45.5 deg"]),
        ("diagnose_record", "A real record's cogging map (poise diagnose-record)", "metrologist.md",
         ["diagnose-record", os.path.join("tests", "data", "real", "odrive_gchenfc_coggingmap", "map.csv"),
          "--column", "angle=count", "--unit", "angle=1/8192 rev", "--column", "current=Iq_A", "--kt", "1 N*m/A"]),
        ("optimize", "A test plan optimized (poise optimize)", "test-planner.md",
         ["optimize", optimization_file(source, folder)]),
    ]


def chromium():
    for exe in ("chromium", "chromium-browser"):
        found = shutil.which(exe)
        if found:
            return found
    raise SystemExit("build_guide: chromium is not installed (scripts/install_deps.sh --tests installs it)")


def screenshot(exe, page, png):
    with tempfile.TemporaryDirectory() as profile:
        r = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                            "--user-data-dir=" + profile, "--window-size=1200,900", "--virtual-time-budget=3000",
                            "--screenshot=" + png, "file://" + os.path.abspath(page)],
                           capture_output=True, text=True, timeout=600)
    if r.returncode != 0 or not os.path.isfile(png):
        raise SystemExit(f"build_guide: Chromium could not take a picture of {page}: {r.stderr[-1000:]}")


def answer_of(out):
    for name in ("summary.json", "budget.json", "diagnosis.json", "record.json"):
        path = os.path.join(out, name)
        if os.path.isfile(path):
            with open(path, encoding="utf-8") as f:
                answer = json.load(f).get("answer")
            if isinstance(answer, str):
                return answer
    return ""


# A Python function's study run from Python: study, the function's file (its `model`), folder.
PYTHON_RUN = """import runpy, sys
import poise
study, function, out = sys.argv[1:]
poise.run(study, model=runpy.run_path(function)["model"], threads=2, out=out, plots=True)
"""


def make(poise, source, site_src, work):
    """Writes gallery/<anchor>.html and .png under site_src; returns [(anchor, title, page, answer,
    command)] and [(anchor, summary dict)] of the study runs."""
    gallery = os.path.join(site_src, "gallery")
    os.makedirs(gallery, exist_ok=True)
    exe = chromium()
    made, summaries = [], []
    for anchor, title, page, args in entries(source, work):
        out = os.path.join(work, anchor)
        env = None
        if args[0] == "python":  # a Python function's study: poise.run(study, model=f) from Python
            command = ["/usr/bin/python3", "-c", PYTHON_RUN, args[1], args[2], out]
            env = dict(os.environ, PYTHONPATH=os.path.join(os.path.dirname(poise), "python"))
        else:
            command = [poise, *args, "--out", out] + (["-q", "--threads", "2"] if args[0] in ("run", "sensitivity", "optimize") else [])
        r = subprocess.run(command, cwd=source, capture_output=True, text=True, timeout=1800, env=env)
        if r.returncode not in (0, 3):  # 3: a requirement not met, or a design not verified: still a report
            raise SystemExit(f"build_guide: {' '.join(command)} exited {r.returncode}:\n{r.stderr[-2000:]}")
        report = os.path.join(out, "report.html")
        shutil.copyfile(report, os.path.join(gallery, anchor + ".html"))
        screenshot(exe, report, os.path.join(gallery, anchor + ".png"))
        shown = ["build/poise"] + [os.path.basename(a) if a.startswith(work + os.sep) else a for a in args]
        if args[0] == "python":
            shown = [f'poise.run("{args[1]}",', f'model=runpy.run_path("{args[2]}")["model"])']
        made.append((anchor, title, page, answer_of(out), shown))
        summary = os.path.join(out, "summary.json")
        if args[0] == "run" and os.path.isfile(summary):
            with open(summary, encoding="utf-8") as f:
                summaries.append((anchor, json.load(f)))
    return made, summaries


def quoted(arg):
    return f'"{arg}"' if (" " in arg or "*" in arg) else arg


def page(made):
    parts = ["# Gallery\n",
             "The first screen of a real report of each study kind and of each command that writes "
             "one, made when this guide was built (small sample counts: the figures are real, the "
             "statistics of few samples). Click a picture to open the report itself.\n"]
    for anchor, title, producer, answer, shown in made:
        parts.append(f"## {title} {{#{anchor}}}\n")
        parts.append(f"Made by `{' '.join(quoted(a) for a in shown)}` ([how]({producer})).\n")
        if answer:
            parts.append(f"> {answer}\n")
        parts.append(f"[![The first screen of the report]({'gallery/' + anchor + '.png'})]({'gallery/' + anchor + '.html'})\n")
    return "\n".join(parts)
