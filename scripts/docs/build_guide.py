#!/usr/bin/env python3
"""Builds the guide (scripts/docs.sh calls it): the pages of docs/, the pages generated from the
program (reference/: commands, keys, exit codes, Python API, summary.json fields; gallery), the
READMEs the repository keeps beside its files (results/, bench/NIGHTLY.md), then
`mkdocs build --strict` (Debian's mkdocs) into BUILD/docs/site.

    scripts/docs/build_guide.py [--build build]

The sources are assembled in BUILD/docs/src (docs/ is never written to); a warning of MkDocs
(a broken link, a page outside the navigation) fails the build."""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gallery  # noqa: E402
import reference_pages  # noqa: E402

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Files the repository keeps beside what they describe, shown in the guide as they are.
KEPT = {
    "results/README.md": "reference/result-folder.md",
    "bench/NIGHTLY.md": "reference/nightly-internals.md",
    "bench/baselines/README.md": "reference/baselines.md",
    "data/yang2015/README.md": "reference/yang2015-data.md",
}


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def real_records_page(poise):
    """Poise beside the oracle on each real record (tests/real_records/compare.py)."""
    sys.path.insert(0, os.path.join(SOURCE, "tests", "real_records"))
    import compare  # noqa: E402
    return ("# Real records\n\nPoise's `diagnose-record` on the real records of `tests/data/real/` beside "
            "each record's oracle (an ordinary least-squares fit that knows the orders; `SOURCE` and "
            "`oracle.py` in each folder), made when this guide was built by "
            "`tests/real_records/compare.py`. Amplitudes in A (the records hold currents; Poise runs "
            "with K_T = 1 N*m/A). How to read your own: [Your own records](../metrologist.md#your-own-records).\n\n"
            + compare.table(poise) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(SOURCE, "build"), help="the build folder (default: build)")
    args = parser.parse_args()
    build = os.path.abspath(args.build)
    poise = os.path.join(build, "poise")
    if not os.access(poise, os.X_OK):
        raise SystemExit(f"build_guide: {poise} is not built (./scripts/build.sh builds it)")
    out = os.path.join(build, "docs")
    src = os.path.join(out, "src")
    shutil.rmtree(src, ignore_errors=True)
    shutil.copytree(os.path.join(SOURCE, "docs"), src)
    for kept, page in KEPT.items():
        os.makedirs(os.path.dirname(os.path.join(src, page)), exist_ok=True)
        shutil.copyfile(os.path.join(SOURCE, kept), os.path.join(src, page))

    commands, _ = reference_pages.commands_page(poise)
    write(os.path.join(src, "reference", "commands.md"), commands)
    keys, _ = reference_pages.keys_page(poise)
    write(os.path.join(src, "reference", "keys.md"), keys)
    write(os.path.join(src, "reference", "exit-codes.md"), reference_pages.exit_codes_page(poise))
    write(os.path.join(src, "reference", "python.md"), reference_pages.python_page(os.path.join(build, "python")))
    write(os.path.join(src, "reference", "real-records.md"), real_records_page(poise))
    with tempfile.TemporaryDirectory() as work:
        made, summaries = gallery.make(poise, SOURCE, src, work)
    write(os.path.join(src, "gallery.md"), gallery.page(made))
    write(os.path.join(src, "reference", "summary-json.md"), reference_pages.summary_page(summaries))

    with open(os.path.join(SOURCE, "mkdocs.yml"), encoding="utf-8") as f:
        config = yaml.safe_load(f)
    config["docs_dir"] = src
    config["site_dir"] = os.path.join(out, "site")
    config_path = os.path.join(out, "mkdocs.yml")
    write(config_path, yaml.safe_dump(config, sort_keys=False))
    r = subprocess.run(["mkdocs", "build", "--strict", "--quiet", "-f", config_path])
    if r.returncode != 0:
        raise SystemExit(f"build_guide: mkdocs build --strict failed (exit {r.returncode})")
    print(f"build_guide: the guide is in {os.path.join(out, 'site', 'index.html')}")


if __name__ == "__main__":
    main()
