"""Every example of the guide is run (issue 55): each ```console block's commands, with what the
page shows they print compared with what they print; each ```pycon block as a doctest; each
```sh block's `poise` subcommands and repository paths checked to exist. A page whose example
fails, or whose shown answer changed, fails here. Conventions: tests/docs/guide_blocks.py.

Run by ctest (guide_examples) with POISE_EXE and POISE_SOURCE_DIR set."""
import doctest
import glob
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import guide_blocks  # noqa: E402

SRC = os.environ.get("POISE_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
EXE = os.environ.get("POISE_EXE", os.path.join(SRC, "build", "poise"))
BUILD = os.path.dirname(os.path.abspath(EXE))
PAGES = sorted(glob.glob(os.path.join(SRC, "docs", "*.md")))


def page_id(path):
    return os.path.basename(path)


def workspace(tmp):
    """A folder where the guide's relative paths mean what they mean in the repository, and
    where a run's results stay out of it."""
    for name in ("studies", "models", "data", "examples", "tests"):
        os.symlink(os.path.join(SRC, name), os.path.join(tmp, name))
    os.symlink(BUILD, os.path.join(tmp, "build"))
    return tmp


def environment():
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"), LC_ALL="C.UTF-8")
    env.pop("POISE_INJECT_HOLD_AT_SAMPLE", None)
    return env


def runnable(path, language):
    with open(path, encoding="utf-8") as f:
        return [b for b in guide_blocks.blocks(f.read()) if b[0] == language]


@pytest.mark.parametrize("page", [p for p in PAGES if runnable(p, "console")], ids=page_id)
def test_console_examples_print_what_the_page_shows(page, tmp_path):
    folder = workspace(str(tmp_path))
    failures = []
    for _, line, lines in runnable(page, "console"):
        for command, shown, status in guide_blocks.transcript(lines):
            r = subprocess.run(["bash", "-c", command], cwd=folder, env=environment(), capture_output=True,
                               text=True, timeout=1800)
            where = f"{os.path.relpath(page, SRC)}:{line}: $ {command}"
            if r.returncode != status:
                failures.append(f"{where}\n  exited {r.returncode}, the page shows {status}:\n{r.stderr[-1500:]}")
                continue
            missing = guide_blocks.missing_lines(shown, r.stdout, r.stderr)
            if missing:
                failures.append(f"{where}\n  the page shows lines it did not print:\n    " + "\n    ".join(missing)
                                + "\n  it printed:\n" + r.stdout[-3000:])
    assert not failures, "\n\n".join(failures)


@pytest.mark.parametrize("page", [p for p in PAGES if runnable(p, "pycon")], ids=page_id)
def test_python_examples_print_what_the_page_shows(page, tmp_path, monkeypatch):
    folder = workspace(str(tmp_path))
    monkeypatch.chdir(folder)
    monkeypatch.syspath_prepend(os.path.join(BUILD, "python"))
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    session = {}
    report = []
    for _, line, lines in runnable(page, "pycon"):
        test = parser.get_doctest("\n".join(lines) + "\n", session, os.path.relpath(page, SRC), page, line - 1)
        runner.run(test, out=report.append, clear_globs=False)
    assert runner.failures == 0, "".join(report)
    assert runner.tries > 0


def test_every_page_with_a_command_runs_one():
    """The pages that show a user's path from a file to the answer run it (not only show it)."""
    for name in ("designer.md", "reviewer.md", "metrologist.md", "cad-parts.md", "balancing.md"):
        assert runnable(os.path.join(SRC, "docs", name), "console"), f"docs/{name} runs no example"
    assert runnable(os.path.join(SRC, "docs", "python.md"), "pycon"), "docs/python.md runs no example"


def test_shown_commands_name_what_exists():
    subcommands = set(subprocess.run([EXE, "--help"], capture_output=True, text=True).stdout.split())
    failures = []
    for page in PAGES + [os.path.join(SRC, "README.md")]:
        with open(page, encoding="utf-8") as f:
            for language, line, lines in guide_blocks.blocks(f.read()):
                if language not in ("sh", "console"):
                    continue
                for k, text in enumerate(lines):
                    where = f"{os.path.relpath(page, SRC)}:{line + k}"
                    for sub in guide_blocks.poise_subcommands(text):
                        if sub not in subcommands:
                            failures.append(f"{where}: poise has no subcommand '{sub}'")
                    for path in guide_blocks.repository_paths(text):
                        if not os.path.exists(os.path.join(SRC, path)):
                            failures.append(f"{where}: {path} does not exist")
    assert not failures, "\n".join(failures)


def test_the_comparison_fails_where_it_should():
    """A changed answer, a missing line, lines out of order and a wrong status are caught (a
    check that cannot fail is no check)."""
    printed = "first line\nThe requirement is met: p95 is 1.2 mm.\nreport: out/report.html\n"
    assert guide_blocks.missing_lines(["The requirement is met: p95 is 1.2 mm."], printed, "") == []
    assert guide_blocks.missing_lines(["The requirement is met: p95 is 1.3 mm."], printed, "") != []
    assert guide_blocks.missing_lines(["report: out/report.html", "first line"], printed, "") == ["first line"]
    assert guide_blocks.missing_lines(["The requirement is met: ...", "...", "report: ..."], printed, "") == []
    assert guide_blocks.missing_lines(["poise: warning: x"], printed, "poise: warning: x\n") == []
    steps = guide_blocks.transcript(["$ build/poise validate a.toml \\", "  --x", "out", "[exit 2]"])
    assert steps == [("build/poise validate a.toml  --x", ["out"], 2)]
    assert guide_blocks.repository_paths("build/poise run studies/x.toml --out DIR  # models/y.toml") == ["studies/x.toml"]
    assert guide_blocks.repository_paths("poise run --resume results/<run id> studies/STUDY.toml") == []
    assert guide_blocks.poise_subcommands("build/poise run a; poise keys") == ["run", "keys"]
