"""The guide's code blocks, read from its Markdown pages (docs/*.md), and how a shown transcript
is compared with what a command printed.

Conventions of the guide (docs/contributing.md, "The guide"):
- ```console blocks are run: each `$ ` line is a command (run by bash from a folder where
  build/, studies/, models/, data/, examples/ and tests/ are the repository's), the lines after it until
  the next `$ ` are what it prints. Each shown line must be printed, in the order shown (stdout;
  a line not on stdout may be on stderr); a shown line ending in `...` stands for a printed
  line that starts with the text before it; a line `...` alone stands for any lines. The
  command must exit 0, or the status a last line `[exit N]` shows.
- ```pycon blocks are run as doctests (ELLIPSIS, NORMALIZE_WHITESPACE), the blocks of one page
  in one session, from the same folder.
- every other fenced block is shown only; in an ```sh block, each `build/poise SUBCOMMAND` must
  name a subcommand poise has and every repository path it names must exist."""
import re

FENCE = re.compile(r"^```(\S*)\s*$")


def blocks(text):
    """[(language, first line number, lines)] of the fenced blocks of a Markdown text."""
    found, language, start, body = [], None, 0, []
    for number, line in enumerate(text.split("\n"), 1):
        m = FENCE.match(line)
        if language is None and m:
            language, start, body = m.group(1) or "", number + 1, []
        elif language is not None and line.startswith("```"):
            found.append((language, start, body))
            language = None
        elif language is not None:
            body.append(line)
    return found


def transcript(lines):
    """[(command, [shown output lines], expected exit status)] of a console block."""
    steps = []
    for line in lines:
        if line.startswith("$ "):
            steps.append([line[2:], [], 0])
        elif steps and steps[-1][0].endswith("\\") and not steps[-1][1]:
            steps[-1][0] = steps[-1][0][:-1] + " " + line.strip()
        elif steps:
            m = re.fullmatch(r"\[exit (\d+)\]", line.strip())
            if m:
                steps[-1][2] = int(m.group(1))
            else:
                steps[-1][1].append(line)
    return [tuple(s) for s in steps]


def _matches(shown, printed):
    shown, printed = shown.strip(), printed.strip()
    if shown.endswith("...") and shown != "...":
        return printed.startswith(shown[:-3].rstrip())
    return shown == printed


def missing_lines(shown, stdout, stderr):
    """The shown lines that the command did not print (in order on stdout, or on stderr)."""
    printed = stdout.split("\n")
    errors = stderr.split("\n")
    at, missing = 0, []
    for line in shown:
        if not line.strip() or line.strip() == "...":
            continue
        k = at
        while k < len(printed) and not _matches(line, printed[k]):
            k += 1
        if k < len(printed):
            at = k + 1
        elif not any(_matches(line, e) for e in errors):
            missing.append(line)
    return missing


REPO_PATH = re.compile(r"(?<![\w/.-])((?:studies|models|data|examples|scripts|tests|bench|python|src|docs)/"
                       r"[A-Za-z0-9_./-]*[A-Za-z0-9_])")


def repository_paths(line):
    """Paths into the repository that a shown command names (placeholders such as <run id>,
    DIR or STUDY are not paths)."""
    line = line.split("#", 1)[0]
    return [p for p in REPO_PATH.findall(line) if "<" not in p and not re.search(r"[A-Z]{3,}", p)]


def poise_subcommands(line):
    """The subcommands that a shown line runs as `build/poise SUB` or `poise SUB`."""
    return re.findall(r"(?:^|[\s;(])(?:build/)?poise\s+([a-z][a-z-]+)", line.split("#", 1)[0])
