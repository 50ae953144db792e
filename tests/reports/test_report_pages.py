"""Every report kind as a person sees it (issue 33): a run of each study kind, a sensitivity
run, a budget, a diagnosis and an optimization, each made at a few samples through the poise
binary, then checked by report_check: structure (unique ids, the answer first, figures with
titles or labels in words and no "[1]" unit, no number with more than 7 significant digits
outside figures) and rendering in headless Chromium (no script or resource error, every
figure drawn with a size). Chromium is Debian's `chromium`, installed by the test command's
set-up (scripts/install_deps.sh --tests).

Run by ctest (report_pages) with POISE_EXE and POISE_SOURCE_DIR set."""
import os
import re
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_check  # noqa: E402


EXE = os.environ.get("POISE_EXE", "build/poise")
SRC = os.environ.get("POISE_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, os.path.join(SRC, "scripts", "docs"))
import gallery  # noqa: E402  (the optimize report's file)


def poise(*args, ok=(0,)):
    r = subprocess.run([EXE, *args], capture_output=True, text=True, timeout=600)
    assert r.returncode in ok, f"poise {' '.join(args)} exited {r.returncode}: {r.stderr[-2000:]}"
    return r


def study(name):
    return os.path.join(SRC, "studies", name)


def seeker_study(tmp):
    text = open(study("los_seeker_wang2011.toml"), encoding="utf-8").read()
    text = text.replace('model = "../models/', 'model = "' + os.path.join(SRC, "models") + "/", 1)
    text = re.sub(r"samples = 4096", "samples = 16", text)
    text += "\n[output]\ncontribution_samples = 16\n"
    path = os.path.join(tmp, "seeker.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def optimization_file(tmp):
    """The gallery's small test-plan question (scripts/docs/gallery.py), at fewer samples."""
    return gallery.optimization_file(SRC, tmp, samples=4, evaluations=4, verification=8)


RUNS = {
    "seeker_los": lambda tmp: ["run", seeker_study(tmp), "--samples", "256"],
    "gimbal": lambda tmp: ["run", study("gimbal_unbalance_mc.toml"), "--samples", "8"],
    "balancing": lambda tmp: ["run", study("wang2014_balancing_mc.toml"), "--samples", "8"],
    "platform": lambda tmp: ["run", study("platform_balancing_sequence.toml"), "--samples", "8"],
    "geometry_mass_properties": lambda tmp: ["run", study("geometry_mass_properties.toml"), "--samples", "8"],
    "los_obstruction": lambda tmp: ["run", study("los_obstruction.toml"), "--samples", "8"],
    "shaft_sag": lambda tmp: ["run", study("shaft_sag_example.toml"), "--samples", "8"],
    "sensitivity": lambda tmp: ["sensitivity", study("shaft_sag_example.toml"), "--base", "32"],
}


def make_report(kind, tmp):
    out = os.path.join(tmp, "out")
    if kind in RUNS:
        poise(*RUNS[kind](tmp), "-q", "--threads", "2", "--out", out)
    elif kind == "budget":
        poise("budget", study("wang2011_budget.toml"), "--out", out)
    elif kind == "diagnose":
        poise("diagnose", os.path.join(SRC, "data", "yang2015", "table1_loading_test_36pt.csv"), "--out", out,
              "--load-torque", "12.91 mN*m", "--load-angle", "45.5 deg")
    elif kind == "diagnose_record":  # a real quasi-static cogging map (tests/data/real)
        poise("diagnose-record", os.path.join(SRC, "tests", "data", "real", "odrive_gchenfc_coggingmap", "map.csv"),
              "--column", "angle=count", "--unit", "angle=1/8192 rev", "--column", "current=Iq_A", "--kt", "1 N*m/A",
              "--out", out)
    elif kind == "optimize":
        poise("optimize", optimization_file(tmp), "-q", "--threads", "2", "--out", out)
    elif kind == "balance":  # a campaign whose truth is known (examples/balance_campaign)
        poise("balance", os.path.join(SRC, "examples", "balance_campaign", "campaign.toml"), "--out", out)
    return os.path.join(out, "report.html")


KINDS = list(RUNS) + ["budget", "diagnose", "diagnose_record", "optimize", "balance"]


@pytest.mark.parametrize("kind", KINDS)
def test_report_reads_right(kind, tmp_path):
    report = make_report(kind, str(tmp_path))
    with open(report, encoding="utf-8") as f:
        problems = report_check.structure_problems(f.read())
    assert not problems, f"{kind}: " + "\n".join(problems[:20])
    if kind not in ("shaft_sag", "sensitivity"):  # pages of three sections or more have contents
        with open(report, encoding="utf-8") as f:
            assert "<nav class='toc'>" in f.read(), f"{kind}: no table of contents"
    if kind == "seeker_los":  # values on hover, and the main output against its drivers
        with open(report, encoding="utf-8") as f:
            page = f.read()
        assert "strongest drivers" in page, f"{kind}: no scatter of the main output against its drivers"
        assert re.search(r"<title>\d+ samples: mean ", page), f"{kind}: the convergence figure has no values on hover"
    exe = report_check.chromium()
    assert exe, "chromium is not installed: scripts/install_deps.sh --tests installs it"
    problems = report_check.render_problems(report, exe)
    assert not problems, f"{kind} in Chromium: " + "\n".join(problems[:20])


def test_checker_finds_what_it_checks():
    """The checks fail on a page that breaks each rule (a check that cannot fail is no check)."""
    bad = ("<html><body><h1>t</h1><h2 id='a'>x</h2><p class='answer'>late</p><p id='a'>0.123456789 m</p>"
           "<a href='#nowhere'>x</a>"
           "<figure><svg><text>0</text><text>1</text></svg></figure>"
           "<figure><svg><text>ratio [1]</text></svg></figure>"
           "<figure><svg><g onmousemove=\"gnuplot_svg.showHypertext(evt,'1, 2')\"><text>x [mm]</text></g></svg></figure>"
           "</body></html>")
    problems = "\n".join(report_check.structure_problems(bad))
    for expected in ("used more than once", "after the first section heading", "significant digits",
                     "no title or axis label", "gives 1 as a unit", "which no element is", "gnuplot's JavaScript"):
        assert expected in problems, expected
    good = ("<html><body><h1>t</h1><p class='answer'>yes</p><h2 id='a'>x</h2><p>0.1235 m, seed 20111101</p>"
            "<figure><svg><text>length [mm]</text></svg></figure></body></html>")
    assert report_check.structure_problems(good) == []
