"""The registration pipeline's stages as the binary lists them for the tools (`tigris register
--list-stages`, registration/pipeline.hpp's stage_list), so no tool carries a copy of the list:

  [{"key": "normals", "title": "normal estimation"}, ...,
   {"key": "icp", "title": "ICP", "parts": [{"title": "RPCE", "time": "kdtree_search"},
                                           {"title": "transformation estimation", "time": "rest"}]}]

`key` is registration.json's `stages.<key>` (and odometry metrics.json's), `title` the paper's
name, `parts` the paper's split of a stage: each part is the stage's KD-tree search seconds
("kdtree_search") or the rest of its seconds ("rest").

  pipeline_stages(tigris)   the binary's list, asked once per binary path; Refused naming the
                            binary when it cannot be run, fails or prints no valid list
  parse_stages(text, what)  the same check of a list's JSON text (`what` names its source)
  paper_stages(stages)      the paper's rows [(title, key, time)]: time "seconds" for a whole
                            stage, "kdtree_search" or "rest" for a part
"""
import json, os, re, subprocess

from .base import Refused
from .children import capture

__all__ = ["PART_TIMES", "pipeline_stages", "parse_stages", "paper_stages"]

PART_TIMES = ("kdtree_search", "rest")   # which of its stage's seconds a part is
_KEY = re.compile(r"[A-Za-z0-9_]+")      # a key is one component of a dotted column name


def parse_stages(text, what):
    """The stages of a `--list-stages` JSON text as fresh dicts {"key", "title", "parts":
    [{"title", "time"}]} (parts empty when the stage is whole); Refused naming `what` when the
    text is not such a list (keys and titles, parts' titles included, distinct)."""
    def bad(msg):
        return Refused(f"{what}: {msg}")
    try:
        raw = json.loads(text)
    except ValueError as e:
        raise bad(f"did not print JSON ({e})")
    if not isinstance(raw, list) or not raw:
        raise bad("the stages are not a non-empty JSON list of {key, title[, parts]}")
    out, keys, titles = [], set(), set()
    for i, s in enumerate(raw):
        at = f"stage {i}"
        if not isinstance(s, dict):
            raise bad(f"{at} is not an object {{key, title[, parts]}}")
        key, title, parts = s.get("key"), s.get("title"), s.get("parts", [])
        if not isinstance(key, str) or not _KEY.fullmatch(key):
            raise bad(f"{at}: \"key\" {json.dumps(key)[:60]} is not a stage key (letters, digits, _)")
        if not isinstance(title, str) or not title.strip():
            raise bad(f"{at} ({key}): \"title\" is not a non-empty text")
        if key in keys:
            raise bad(f"{at}: key '{key}' is listed twice")
        keys.add(key)
        if not isinstance(parts, list):
            raise bad(f"{at} ({key}): \"parts\" is not a list of {{title, time}}")
        stage = {"key": key, "title": title, "parts": []}
        times = set()
        for j, p in enumerate(parts):
            pat = f"{at} ({key}) part {j}"
            if not isinstance(p, dict) or not isinstance(p.get("title"), str) or not p["title"].strip():
                raise bad(f"{pat}: not an object with a non-empty \"title\"")
            if p.get("time") not in PART_TIMES:
                raise bad(f"{pat} ({p['title']}): \"time\" {json.dumps(p.get('time'))[:60]} is not one of "
                          f"{', '.join(PART_TIMES)}")
            if p["time"] in times:
                raise bad(f"{pat} ({p['title']}): a second part of time \"{p['time']}\"")
            times.add(p["time"])
            stage["parts"].append({"title": p["title"], "time": p["time"]})
        for t in [stage["title"]] + [p["title"] for p in stage["parts"]]:
            if t in titles:
                raise bad(f"{at} ({key}): title '{t}' is used twice")
            titles.add(t)
        out.append(stage)
    return out


def pipeline_stages(tigris, _seen={}):
    """`tigris register --list-stages` of the binary at `tigris`, parsed (parse_stages); the
    binary is asked once per path in a process. Refused naming the binary when it is missing,
    fails or prints no valid list. A fresh copy each call: the caller may change it."""
    path = os.path.abspath(tigris)
    if path not in _seen:
        what = f"{path} register --list-stages"
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            raise Refused(f"tigris binary not found or not executable: {path} (the pipeline's stages come "
                          "from `tigris register --list-stages`)")
        try:
            p = capture([path, "register", "--list-stages"], timeout=60)
        except (OSError, subprocess.TimeoutExpired) as e:
            raise Refused(f"cannot run {what}: {e}")
        if p.returncode != 0:
            err = p.stderr.strip().splitlines()
            raise Refused(f"{what} failed (exit {p.returncode}){': ' + err[0] if err else ''} (the pipeline's "
                          "stages come from it: is the binary of this source tree, rebuilt?)")
        _seen[path] = parse_stages(p.stdout, what)
    return [dict(s, parts=[dict(p) for p in s["parts"]]) for s in _seen[path]]


def paper_stages(stages):
    """The paper's rows of a stage list (pipeline_stages, or parse_stages): [(title, key, time)]
    in the pipeline's order, a stage the paper splits giving one row per part. time: "seconds"
    (the whole stage), "kdtree_search" (its KD-tree search seconds) or "rest" (the others)."""
    rows = []
    for s in stages:
        parts = s.get("parts") or []
        rows += [(p["title"], s["key"], p["time"]) for p in parts] if parts else [(s["title"], s["key"], "seconds")]
    return rows
