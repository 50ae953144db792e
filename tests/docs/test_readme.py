"""The README is one screen that leads into the guide (issue 55): about 120 lines at most, nothing
of the former README lost (each of its section titles, tests/docs/readme_sections_before.txt,
is a heading of a guide page), every link of it resolves, and a new user reaches how to run
their own study, their own records and their own formula within two clicks."""
import glob
import os
import re

SRC = os.environ.get("POISE_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
LINK = re.compile(r"\]\(([^)\s]+)\)")


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def headings(text):
    found, fence = [], False
    for line in text.split("\n"):
        if line.startswith("```"):
            fence = not fence
        elif not fence and re.match(r"#+ ", line):
            found.append(re.sub(r"\s*\{#[^}]*\}$", "", line.lstrip("#").strip()))
    return found


def links(path):
    """The files a Markdown page links to (relative links, anchors dropped)."""
    folder = os.path.dirname(path)
    out = []
    for target in LINK.findall(read(path)):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        out.append(os.path.normpath(os.path.join(folder, target.split("#", 1)[0])))
    return out


def test_readme_is_one_screen():
    lines = read(os.path.join(SRC, "README.md")).count("\n")
    assert lines <= 120, f"README.md has {lines} lines"


def test_nothing_of_the_former_readme_is_lost():
    before = [t for t in read(os.path.join(SRC, "tests", "docs", "readme_sections_before.txt")).split("\n") if t]
    guide = set()
    for page in glob.glob(os.path.join(SRC, "docs", "*.md")):
        guide.update(headings(read(page)))
    guide.update(headings(read(os.path.join(SRC, "README.md"))))
    missing = [t for t in before if t not in guide]
    assert len(before) >= 15
    assert not missing, "sections of the former README found in no guide page: " + "; ".join(missing)


def test_every_link_of_the_readme_and_the_guide_sources_resolves():
    """Links between docs/*.md as GitHub shows them (the built site is checked by test_site;
    reference pages exist only there)."""
    broken = []
    for page in [os.path.join(SRC, "README.md")] + glob.glob(os.path.join(SRC, "docs", "*.md")):
        for target in links(page):
            generated = os.path.relpath(target, os.path.join(SRC, "docs"))
            if generated.startswith("reference" + os.sep) or generated in ("gallery.md",) or generated.startswith("gallery" + os.sep):
                continue  # made by scripts/docs.sh
            if not os.path.exists(target):
                broken.append(f"{os.path.relpath(page, SRC)}: {os.path.relpath(target, SRC)}")
    assert not broken, "\n".join(broken)


def within_two_clicks(start):
    reached = {start}
    frontier = [start]
    for _ in range(2):
        frontier = [t for page in frontier if page.endswith(".md") and os.path.isfile(page) for t in links(page)]
        reached.update(frontier)
    return reached


def test_a_new_user_finds_their_own_study_records_and_formula_within_two_clicks():
    reached = within_two_clicks(os.path.join(SRC, "README.md"))
    wanted = {
        "their own study": ("designer.md", "Your own study"),
        "their own records": ("metrologist.md", "Your own records"),
        "their own formula": ("own-mechanism.md", "Your own formula"),
    }
    for what, (page, says) in wanted.items():
        path = os.path.join(SRC, "docs", page)
        assert path in reached, f"how to run {what} (docs/{page}) is not within two clicks of the README"
        assert says in headings(read(path)), f"docs/{page} has no section '{says}'"
