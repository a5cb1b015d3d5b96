#!/usr/bin/python3
"""Writes the field tables of docs/stats.md from the stats schema (`tigris run --stats-schema`).

    scripts/stats_doc.py [--tigris build/bin/tigris] [--check]

Each section of the schema owns the first table under its heading (`## <title>`); the prose
around the tables is left as it is. After adding or changing a counter (hw/), a derived
formula (testbench/stat_formulas.cpp), a configuration key (hw/config.hpp) or another field
(testbench/stats_schema.cpp), run this to update the docs. --check changes nothing: it prints
the difference and exits 1 when the docs are out of date (the ctest `newcomer` runs it).
"""
import argparse
import difflib
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "stats.md")


def cell(s):
    return s.replace("|", "\\|")


def table(fields):
    lines = ["| PATH | UNIT | meaning |", "|---|---|---|"]
    for f in fields:
        meaning = f["meaning"] + (f" = `{f['formula']}`" if f.get("formula") else "")
        lines.append(f"| `{f['path']}` | {cell(f['unit'])} | {cell(meaning)} |")
    return lines


def render(doc_lines, schema):
    out, i = [], 0
    titles = {f"## {s['title']}": s["id"] for s in schema["sections"]}
    done = set()
    while i < len(doc_lines):
        line = doc_lines[i]
        out.append(line)
        i += 1
        sid = titles.get(line.rstrip("\n"))
        if sid is None:
            continue
        while i < len(doc_lines) and not doc_lines[i].startswith("|") and not doc_lines[i].startswith("## "):
            out.append(doc_lines[i])
            i += 1
        if i >= len(doc_lines) or not doc_lines[i].startswith("|"):
            sys.exit(f"stats_doc: docs/stats.md: section '{line.strip()}' has no table")
        while i < len(doc_lines) and doc_lines[i].startswith("|"):
            i += 1
        out.extend(l + "\n" for l in table([f for f in schema["fields"] if f["section"] == sid]))
        done.add(sid)
    missing = [s["title"] for s in schema["sections"] if s["id"] not in done]
    if missing:
        sys.exit(f"stats_doc: docs/stats.md has no heading for the schema's sections: {missing}")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tigris", default=os.path.join(ROOT, "build", "bin", "tigris"))
    ap.add_argument("--check", action="store_true", help="only compare; exit 1 when docs/stats.md is out of date")
    a = ap.parse_args()
    p = subprocess.run([a.tigris, "run", "--stats-schema"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"stats_doc: `{a.tigris} run --stats-schema` failed ({p.returncode}): {p.stderr.strip()}")
    schema = json.loads(p.stdout)
    with open(DOC) as f:
        old = f.readlines()
    new = render(old, schema)
    if new == old:
        print("stats_doc: docs/stats.md is up to date with the schema")
        return 0
    if a.check:
        sys.stdout.writelines(difflib.unified_diff(old, new, "docs/stats.md", "from tigris run --stats-schema"))
        print("stats_doc: docs/stats.md is out of date: run scripts/stats_doc.py", file=sys.stderr)
        return 1
    with open(DOC, "w") as f:
        f.writelines(new)
    print("stats_doc: wrote docs/stats.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
