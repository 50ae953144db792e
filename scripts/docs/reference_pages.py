"""The guide's reference pages, generated from the program itself so that they cannot drift:
every command's --help, every study and model key of every kind (`poise keys KIND`), the exit
codes (the "Exit status" part of `poise --help`), the Python API (the module's docstrings and
signatures) and the fields of summary.json with their units (read off the gallery's runs).

Used by scripts/docs/build_guide.py; each function returns a page's Markdown."""
import inspect
import json
import os
import re
import subprocess


def run_text(args, env=None):
    r = subprocess.run(args, capture_output=True, text=True, env=env, timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"build_guide: {' '.join(args)} exited {r.returncode}:\n{r.stderr[-2000:]}")
    return r.stdout


def fenced(text):
    """A text block shown as it is printed (no Markdown inside)."""
    return "```text\n" + text.rstrip("\n") + "\n```\n"


def subcommands(main_help):
    """The subcommand names listed under "Subcommands:" in `poise --help`."""
    names, inside = [], False
    for line in main_help.splitlines():
        if line.startswith("Subcommands:"):
            inside = True
        elif inside and not line.strip():
            break
        elif inside:
            m = re.match(r"\s{2}(\S+)\s", line)
            if m:
                names.append(m.group(1))
    return names


def study_kinds(keys_text):
    """The kind names `poise keys` lists (two-space indent, one word)."""
    return [m.group(1) for m in re.finditer(r"^  ([a-z0-9_]+)$", keys_text, re.M)]


def commands_page(poise):
    main_help = run_text([poise, "--help"])
    names = subcommands(main_help)
    parts = ["# Commands\n",
             "Every command's `--help`, as `build/poise` prints it (generated when the guide is built). "
             "Exit codes: [Exit codes](exit-codes.md).\n",
             "## poise\n", fenced(main_help)]
    for name in names:
        parts += [f"## poise {name}\n", fenced(run_text([poise, name, "--help"]))]
    return "\n".join(parts), names


def keys_page(poise):
    overview = run_text([poise, "keys"])
    kinds = study_kinds(overview)
    parts = ["# Study and model keys\n",
             "Every key of every study kind's study file and model file, with its type, unit and "
             "default, as `build/poise keys KIND` prints it from the program's own reading of the "
             "files (generated when the guide is built). A misspelled key is refused with "
             "\"did you mean ...\".\n",
             "## The study kinds\n", fenced(overview)]
    for kind in kinds:
        parts += [f"## {kind}\n", fenced(run_text([poise, "keys", kind]))]
    return "\n".join(parts), kinds


def exit_codes(main_help):
    """[(code, meaning)] from the "Exit status" part of `poise --help`."""
    at = main_help.find("Exit status")
    if at < 0:
        raise SystemExit("build_guide: `poise --help` has no \"Exit status\" part")
    rows = []
    for line in main_help[at:].splitlines()[1:]:
        m = re.match(r"\s{2}(\d[\d +N]*?)\s{2,}(.*)", line)
        if m:
            rows.append([m.group(1).strip(), m.group(2).strip()])
        elif line.startswith("    ") and rows:
            rows[-1][1] += " " + line.strip()
        elif line.strip() and not line.startswith(" "):
            break
    if not rows:
        raise SystemExit("build_guide: no exit codes read from `poise --help`")
    return rows


def exit_codes_page(poise):
    rows = exit_codes(run_text([poise, "--help"]))
    text = ["# Exit codes\n",
            "The same for every command (from `poise --help`, generated when the guide is built):\n",
            "| exit status | meaning |", "| --- | --- |"]
    text += [f"| {code} | {meaning.replace('|', '/')} |" for code, meaning in rows]
    return "\n".join(text) + "\n"


def python_page(python_dir):
    """The module's public names (`poise.__all__`), each with its signature and docstring."""
    script = r'''
import inspect, json, poise
out = {"doc": inspect.getdoc(poise), "names": []}
for name in poise.__all__:
    obj = getattr(poise, name)
    entry = {"name": name, "doc": inspect.getdoc(obj) or "", "members": []}
    if inspect.isclass(obj):
        entry["kind"] = "class"
        try:
            entry["signature"] = str(inspect.signature(obj))
        except (TypeError, ValueError):
            entry["signature"] = ""
        for member, value in vars(obj).items():
            if member.startswith("_"):
                continue
            doc = inspect.getdoc(value) or ""
            if isinstance(value, property):
                entry["members"].append({"name": member, "signature": " (property)", "doc": doc})
            elif callable(value):
                entry["members"].append({"name": member, "signature": str(inspect.signature(value)), "doc": doc})
    elif callable(obj):
        entry["kind"] = "function"
        entry["signature"] = str(inspect.signature(obj))
    else:
        entry["kind"] = "value"
        entry["signature"] = " = " + repr(obj)
    out["names"].append(entry)
print(json.dumps(out))
'''
    env = dict(os.environ, PYTHONPATH=python_dir)
    api = json.loads(run_text(["/usr/bin/python3", "-c", script], env=env))
    parts = ["# Python API\n",
             "The module `poise` (`PYTHONPATH=build/python`), from its own docstrings and signatures "
             "(generated when the guide is built). How to use it: [From Python](../python.md).\n",
             fenced(api["doc"])]
    for entry in api["names"]:
        parts.append(f"## {entry['name']}\n")
        parts.append(f"`{entry['kind']} poise.{entry['name']}{entry['signature']}`\n")
        if entry["doc"]:
            parts.append(fenced(entry["doc"]))
        for member in entry["members"]:
            parts.append(f"### {entry['name']}.{member['name']}\n")
            parts.append(f"`{member['name']}{member['signature']}`\n")
            if member["doc"]:
                parts.append(fenced(member["doc"]))
    return "\n".join(parts)


def json_fields(value, path="", depth=0, rows=None, max_depth=3):
    """(path, type, example) of each field, outputs' own names collapsed to <output>."""
    rows = [] if rows is None else rows
    if isinstance(value, dict):
        for key, sub in value.items():
            here = f"{path}.{key}" if path else key
            rows.append((here, type(sub).__name__, sub))
            if depth + 1 < max_depth:
                json_fields(sub, here, depth + 1, rows, max_depth)
    elif isinstance(value, list) and value and isinstance(value[0], dict):
        json_fields(value[0], path + "[]", depth, rows, max_depth)
    return rows


def example_of(value):
    if isinstance(value, (dict, list)):
        return ""
    text = json.dumps(value)
    return "`" + (text if len(text) <= 60 else text[:57] + "...") + "`"


JSON_TYPES = {"dict": "object", "list": "array", "str": "string", "int": "integer", "float": "number",
              "bool": "boolean", "NoneType": "null"}


def summary_page(summaries):
    """summaries: [(kind, summary dict)] of the gallery's runs."""
    parts = ["# summary.json\n",
             "Read off a run of each study kind when the guide is built (the gallery's runs), so "
             "the fields below are those the program writes. What each field means: "
             "[The result folder](result-folder.md). Every output's `unit` is the unit of its "
             "statistics (`mean`, `std`, `p50`, `p95`, `p99_73`, `max`, each `{value, ci95}`).\n"]
    common = None
    for _, summary in summaries:
        keys = set(summary)
        common = keys if common is None else common & keys
    parts.append("## Fields of every run\n")
    parts.append("| field | type | example |\n| --- | --- | --- |")
    first = summaries[0][1]
    collapsed = {}
    for name in sorted(common):
        for path, kind, value in json_fields({name: first[name]}):
            if name == "outputs" or name == "sample_convergence":
                path = re.sub(r"^(outputs|sample_convergence\.figures)\.[^.]+", r"\1.<output>", path)
            if path in collapsed:
                continue
            collapsed[path] = True
            parts.append(f"| `{path}` | {JSON_TYPES.get(kind, kind)} | {example_of(value)} |")
    parts.append("")
    for kind, summary in summaries:
        parts.append(f"## {kind}\n")
        outputs = summary.get("outputs", {})
        parts.append("| output | unit | what it is |\n| --- | --- | --- |")
        for name, out in outputs.items():
            unit = out.get("unit", "") if isinstance(out, dict) else ""
            parts.append(f"| `{name}` | {unit or '(none)'} | {out.get('description', '') if isinstance(out, dict) else ''} |")
        extra = sorted(set(summary) - common)
        if extra:
            parts.append("\nFields of this kind beside those of every run: " + ", ".join(f"`{k}`" for k in extra) + ".")
        parts.append("")
    return "\n".join(parts)
