#!/usr/bin/python3
"""Compare runs: `tigris diff A B [C ...] [--json] [--all]`.

Each argument is a stats.json, a run folder holding one (`tigris run --out DIR`), or a sweep
point (SWEEP/points/<id>/): all of `tigris run` or all of trace replays (`tigris run --trace`).
Printed in this order:

  runs           each run's command line and inputs (path and SHA-256, or the built-in workload)
  configuration  every configuration key whose value differs
  headline       cycles (sampled: their 95% interval and the queries simulated), time, energy and
                 its split, power, area, utilizations, the bound, stalls by cause (share of the
                 unit kind's cycles), traffic by buffer, visits, accuracy;
                 side by side, each with its ratio to the first run
  other          every other leaf that differs (the first 40; --all: all of them, per-unit ones too)

Host time (every `wall_seconds` and `phase_seconds` leaf) is never a difference. Exit status as
diff(1): 0 when the runs agree (host time and command lines aside), 1 when they differ, 2 on bad
input (also a file that is not a run's statistics, runs of the two kinds, or a run folder that a
run, or a sweep point that its sweep, is still writing).
"""
import argparse
import json
import math
import os
import shlex
import sys

from .. import core

PROG = "tigris diff"
OTHER_SHOWN = 40
# Leaves that describe the run rather than the model: shown under "runs", never as differences.
RUN_KEYS = ("command_line", "inputs", "wall_seconds", "trace")
# Host time measured while the model ran, anywhere in the tree: never a difference.
HOST_TIME = ("wall_seconds", "phase_seconds")
KINDS = {"run": "the statistics of a `tigris run`", "trace": "the statistics of a trace replay (`tigris run --trace`)"}


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def load(arg):
    path = os.path.join(arg, "stats.json") if os.path.isdir(arg) else arg
    try:                        # a run still writing: no stats.json yet, or the last run's
        core.refuse_if_written(arg, "RUN", enclosing=not os.path.exists(path))
    except core.Refused as e:
        die(str(e))
    if os.path.isdir(arg) and not os.path.exists(path):
        if os.path.isdir(os.path.join(arg, "points")):
            die(f"{arg} is a sweep folder: name one of its points, e.g. {os.path.join(arg, 'points', '<id>')}")
        die(f"{arg} holds no stats.json (a run folder is what `tigris run --out DIR` writes)")
    try:
        doc = core.read_json_input(path, "", core.MAX_SETTINGS_BYTES)
    except core.Refused as e:
        die(str(e))
    kind = stats_kind(doc)
    if kind not in KINDS:
        die(f"{path}: not a run's statistics ({kind}): tigris diff compares the stats.json of `tigris run` "
            "(or of its trace replays)")
    return path, doc, kind


def stats_kind(doc):
    """"run", "trace", or what the document is instead."""
    if not isinstance(doc, dict):
        return "a JSON object is expected"
    cmd = doc.get("command")
    if cmd in ("run", "run --trace") and isinstance(doc.get("trace"), dict) and isinstance(doc.get("total"), dict):
        return "trace"
    if cmd == "run" and "cycles" in doc and isinstance(doc.get("config"), dict):
        return "run"
    if "args" in doc and "exit_code" in doc:
        return "a sweep's point.json: name the point's folder or its stats.json"
    if isinstance(cmd, str) and cmd:
        return f"written by tigris {cmd}" + (", a registration" if cmd == "register" else "")
    return "no command, cycles or configuration" if not doc else "no command, cycles or configuration in it"


def host_time(path):
    return any(part.split("[")[0] in HOST_TIME for part in path.split("."))


def leaves(obj, prefix=""):
    """(dotted path, value) of every scalar leaf; list elements as path[i]."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from leaves(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from leaves(v, f"{prefix}[{i}]")
    else:
        yield prefix, obj


def get(doc, path):
    node = doc
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def same(a, b):
    if is_num(a) and is_num(b) and a != b:
        return isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b)
    return a == b


def trace_rows(docs):
    """The headline of trace replays: the modeled totals, the end-to-end effect, each stage."""
    rows = [("cycles", "cycles", "total.cycles", 1), ("energy", "uJ", "total.energy_pj", 1e-6),
            ("modeled search time", "ms", "total.modeled_search_seconds", 1e3),
            ("modeled host time", "ms", "total.modeled_host_seconds", 1e3),
            ("jobs", "", "total.jobs", 1), ("  sampled", "", "sampled_jobs", 1), ("queries", "", "total.queries", 1),
            ("  differing from recorded", "", "total.queries_differing_from_recorded", 1),
            ("end-to-end speed-up", "x", "end_to_end.speedup", 1),
            ("KD-tree speed-up", "x", "end_to_end.kdtree_speedup", 1),
            ("accelerated seconds", "s", "end_to_end.accelerated_seconds", 1)]
    stages = []
    for d in docs:
        for s in (d.get("stages") or {}):
            if s not in stages:
                stages.append(s)
    for s in stages:
        rows += [(f"{s} cycles", "cycles", f"stages.{s}.cycles", 1), (f"{s} energy", "uJ", f"stages.{s}.energy_pj", 1e-6)]
    return rows + [("verdict", "", "verdict", 1)]


def headline(docs, kind="run"):
    """Rows {name, label, unit, values, ratios, path} of the figures a reader compares first, in
    reading order, for those that any of the runs has. `path`: the stats leaf shown."""
    if kind == "trace":
        return rows_of(docs, trace_rows(docs))
    rows = [("cycles", "cycles", "cycles", 1), ("  95% interval", "", "cycles_ci95", interval),
            ("  simulated", "", "sampling.simulated", simulated), ("time", "ms", "seconds", 1e3),
            ("lower bound", "cycles", "lower_bound_cycles", 1), ("energy", "uJ", "energy_pj.total", 1e-6)]
    for part in ("pe", "ru", "sram_read", "sram_write", "node_cache", "leader_buffer", "dram", "leakage"):
        rows.append((f"  energy {part}", "uJ", f"energy_pj.{part}", 1e-6))
    rows += [("power", "W", "power_w", 1), ("area", "mm2", "area_mm2.total", 1),
             ("RU utilization", "%", "units.recursion_units.utilization", 1),
             ("SU utilization", "%", "units.search_units.utilization", 1),
             ("PE utilization", "%", "units.search_units.pe_utilization", 1),
             ("bound", "", "bottleneck.bound", 1), ("  cause", "", "bottleneck.cause", 1),
             ("  its share", "%", "bottleneck.share", 1),
             ("  cycles / lower bound", "x", "bottleneck.cycles_over_lower_bound", 1)]
    for kind, label in (("recursion_units", "RU"), ("search_units", "SU")):
        causes = sorted({c for d in docs for c in (get(d, f"units.{kind}.stall_cycles") or {})})
        for c in causes:
            rows.append((f"{label} stall {c}", "%", f"units.{kind}.stall_cycles.{c}",
                         lambda d, k=kind, c=c: stall_share(d, k, c)))
    buffers = []
    for d in docs:
        for b in (get(d, "buffers") or {}):
            if b not in buffers:
                buffers.append(b)
    for b in buffers:
        rows.append((f"traffic {b}", "MB", f"buffers.{b}.read_bytes", lambda d, b=b: traffic(d, b)))
    rows += [("visits top", "", "visits.top", 1), ("visits leaf points", "", "visits.leaf_points", 1),
             ("queries exact", "%", "accuracy.exact_match_fraction", 1),
             ("extra distance mean", "m", "accuracy.mean_extra_distance_m", 1), ("recall", "%", "accuracy.recall", 1),
             ("precision", "%", "accuracy.precision", 1), ("verdict", "", "verdict", 1)]
    return rows_of(docs, rows)


def rows_of(docs, rows):
    out = []
    for label, unit, path, how in rows:
        vals = [how(d) if callable(how) else scale(get(d, path), how) if how != 1 else get(d, path) for d in docs]
        stall = path.startswith("units.") and ".stall_cycles." in path
        if any(v is not None for v in vals) and not (stall and not any(vals)):
            out.append({"name": label.strip(), "label": label, "unit": unit, "path": path, "values": vals,
                        "ratios": ratios(vals)})
    return out


def interval(d):
    """A sampled run's cycles interval as text; `exact` when every query was simulated."""
    ci, sm = get(d, "cycles_ci95"), get(d, "sampling")
    if not isinstance(ci, list) or len(ci) != 2 or not isinstance(sm, dict):
        return None  # a run of an older tigris
    if not sm.get("sampled"):
        return "exact"
    lo, hi = ci
    c = get(d, "cycles")
    half = f" (+-{100 * (hi - lo) / 2 / c:.2f}%)" if is_num(c) and c else ""
    return f"[{lo:,.0f}, {hi:,.0f}]{half}"


def simulated(d):
    """How many of the queries were simulated (sampled simulation), as text."""
    sm = get(d, "sampling")
    if not isinstance(sm, dict) or "simulated" not in sm:
        return None
    return f"{sm['simulated']:,} of {sm.get('queries', 0):,}" + (" (sampled)" if sm.get("sampled") else "")


def scale(v, f):
    return v * f if is_num(v) else None


def stall_share(d, kind, cause):
    v, n, c = get(d, f"units.{kind}.stall_cycles.{cause}"), get(d, f"units.{kind}.count"), get(d, "cycles")
    return v / (n * c) if is_num(v) and is_num(n) and is_num(c) and n * c > 0 else None


def traffic(d, b):
    """Read plus write bytes of a buffer, in MB."""
    r, w = get(d, f"buffers.{b}.read_bytes"), get(d, f"buffers.{b}.write_bytes")
    if not is_num(r) and not is_num(w):
        return None
    return ((r or 0) + (w or 0)) * 1e-6


def ratios(vals):
    base = vals[0]
    return [v / base if is_num(v) and is_num(base) and base != 0 else None for v in vals]


def fmt(v, unit=""):
    if v is None:
        return "-"
    if isinstance(v, bool) or not is_num(v):
        text = ("true" if v else "false") if isinstance(v, bool) else str(v)  # as the configuration writes it
        return text if len(text) <= 48 else text[:45] + "..."
    if unit == "%":
        return f"{100 * v:.1f}%"
    if isinstance(v, int) or (abs(v) >= 1000 and float(v).is_integer()) or 1e4 <= abs(v) < 1e15:
        return f"{v:,.0f}"
    return f"{v:.4g}"


def inputs_text(doc):
    ins = doc.get("inputs")
    if not isinstance(ins, list):
        return "inputs not recorded (a stats.json of an older tigris)"
    parts = []
    for i in ins:
        if not isinstance(i, dict):
            continue
        if "builtin" in i:
            parts.append(f"{i.get('role')} {i['builtin']}")
        elif "same_as" in i:
            parts.append(f"{i.get('role')} = {i['same_as']}")
        else:
            parts.append(f"{i.get('role')} {i.get('path')} (sha256 {str(i.get('sha256'))[:12]})")
    return ", ".join(parts)


def input_key(doc):
    ins = doc.get("inputs")
    if not isinstance(ins, list):
        return None
    return json.dumps([{k: v for k, v in i.items() if k != "path"} for i in ins if isinstance(i, dict)
                       and i.get("role") != "config"], sort_keys=True)


def compare(paths, docs, kind="run"):
    config = {}
    for d in docs:
        for p, v in leaves(d.get("config", {})):
            config.setdefault(p, [None] * len(docs))
    for i, d in enumerate(docs):
        for p, v in leaves(d.get("config", {})):
            config[p][i] = v
    config_diff = [{"key": k, "values": v} for k, v in sorted(config.items())
                   if any(not same(x, v[0]) for x in v[1:])]
    heads = headline(docs, kind)
    shown = {h["path"] for h in heads} | {"bottleneck.summary"}
    shown |= {f"buffers.{h['path'].split('.')[1]}.write_bytes" for h in heads if h["path"].startswith("buffers.")}
    other = {}
    for i, d in enumerate(docs):
        for p, v in leaves(d):
            top = p.split(".")[0].split("[")[0]
            if top in RUN_KEYS or top == "config" or p in shown or host_time(p):
                continue
            other.setdefault(p, [None] * len(docs))[i] = v
    other_diff = [{"path": k, "values": v} for k, v in other.items() if any(not same(x, v[0]) for x in v[1:])]
    differ = bool(config_diff or other_diff) or any(
        not same(x, h["values"][0]) for h in heads for x in h["values"][1:])
    keys = {input_key(d) for d in docs}
    return {"runs": [{"path": p, "command": d.get("command"), "command_line": d.get("command_line"),
                      "inputs": d.get("inputs"), "bound": get(d, "bottleneck.summary")}
                     for p, d in zip(paths, docs)],
            "same_inputs": len(keys) == 1 and None not in keys,
            "config": config_diff, "headline": heads, "other": other_diff, "differ": differ}


def table(rows):
    width = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return ["  " + "  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(r, width))).rstrip()
            for r in rows]


def show(res, show_all):
    names = [chr(ord("A") + i) if i < 26 else f"R{i}" for i in range(len(res["runs"]))]
    L = [f"{PROG}: {len(names)} runs"]
    for n, r in zip(names, res["runs"]):
        L.append(f"  {n}  {r['path']}")
        L.append(f"     {r['command_line'] or r['command'] or '(command not recorded)'}")
        L.append(f"     {inputs_text(r)}")
        if r.get("bound"):
            L.append(f"     {r['bound']}")
    if not res["same_inputs"]:
        L.append("  note: the runs read different workloads (or did not record them); their figures are "
                 "not a like-for-like comparison")
    L.append("")
    if res["config"]:
        n = len(res["config"])
        L.append(f"configuration: {n} key{' differs' if n == 1 else 's differ'}")
        L += table([["key"] + names] + [[c["key"]] + [fmt(v) for v in c["values"]] for c in res["config"]])
    else:
        L.append("configuration: the same")
    L.append("")
    L.append("headline" + (f" (ratios to {names[0]})" if len(names) > 1 else ""))
    rows = [["figure", "unit"] + names + [f"{n}/{names[0]}" for n in names[1:]]]
    for h in res["headline"]:
        unit = "" if h["unit"] == "%" else h["unit"]
        vals = [fmt(v, h["unit"]) for v in h["values"]]
        rat = [f"{r:.3f}x" if r is not None else "-" for r in h["ratios"][1:]]
        rows.append([h["label"], unit] + vals + rat)
    L += table(rows)
    L.append("")
    other = res["other"]
    per_unit = [o for o in other if "per_unit[" in o["path"]]
    rest = [o for o in other if "per_unit[" not in o["path"]]
    listed = other if show_all else rest[:OTHER_SHOWN]
    hidden = len(other) - len(listed)
    L.append(f"other differing leaves: {len(other)}" +
             (f" (showing {len(listed)}; --all shows the other {hidden}"
              + (f", {len(per_unit)} of them per unit)" if per_unit else ")") if hidden else ""))
    if listed:
        L += table([["leaf"] + names] + [[o["path"]] + [fmt(v) for v in o["values"]] for o in listed])
    return "\n".join(L)


def compare_main(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n\n".join(__doc__.split("\n\n")[1:]))
    ap.add_argument("runs", nargs="+", metavar="RUN", help="a stats.json, a run folder or a sweep point folder")
    ap.add_argument("--json", action="store_true", help="print the comparison as JSON")
    ap.add_argument("--all", action="store_true", help="list every differing leaf, per-unit ones too")
    ap.add_argument("--list-flags", action="store_true", help="Print this command's flags as JSON (flag, type, "
                    "default, meaning) for tools, and exit")
    core.list_flags(ap, "diff", argv)
    a = ap.parse_args(argv)
    if len(a.runs) < 2:
        points = os.path.join(a.runs[0], "points")
        if os.path.isdir(points):  # a sweep folder: name what can be compared
            names = sorted(n for n in os.listdir(points) if os.path.isdir(os.path.join(points, n)))
            shown = [shlex.quote(os.path.join(points, n)) for n in names[:2]]
            die(f"{a.runs[0]} is a sweep folder: compare two (or more) of its {len(names)} points, e.g.\n"
                f"  {PROG} {' '.join(shown)}\n"
                + "its points:\n" + "\n".join("  " + n for n in names[:12])
                + (f"\n  ... and {len(names) - 12} more" if len(names) > 12 else ""))
        die("give at least two runs to compare")
    loaded = [load(r) for r in a.runs]
    kinds = {k for _, _, k in loaded}
    if len(kinds) > 1:
        first = next(x for x in loaded if x[2] != loaded[0][2])
        die(f"{loaded[0][0]} holds {KINDS[loaded[0][2]]}, {first[0]} {KINDS[first[2]]}: they share no figures "
            "to compare; compare runs with runs, replays with replays")
    res = compare([p for p, _, _ in loaded], [d for _, d, _ in loaded], loaded[0][2])
    if a.json:
        print(json.dumps(res, indent=1))
    else:
        print(show(res, a.all))
    return 1 if res["differ"] else 0


def main(argv):
    """The command: compare_main with a closed pipe (| head) an exit 1, not a traceback."""
    try:
        return compare_main(argv)
    except BrokenPipeError:
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
