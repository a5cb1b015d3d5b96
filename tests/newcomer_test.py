#!/usr/bin/python3
"""What a newcomer relies on, end to end:

  inputs     stats.json records the command line and each input's path, size and SHA-256, and the
             summary prints them and the bound
  schema     every leaf of real runs' stats.json is in the stats schema (tigris run --stats-schema)
             and every schema field in some run; derived fields equal their formulas evaluated
             here; docs/stats.md's tables are the schema's (scripts/stats_doc.py --check)
  diff       `tigris diff` on two known runs: configuration, headline ratios, exit status, --json
  plot       `tigris plot` writes the figures, titled with the workload, a flat axis labelled
  waves      the VCD's machine-wide counts average to the statistics' utilizations and stall shares
  timeline   the whole-machine counters sum to the same, sampled tracks say so, a large request warns
  help       a command's --help lists its own flags with defaults; typos get suggestions
  layers     every folder includes only what the layering allows (docs/architecture.md), and what
             extending relies on (docs/extending.md): fe/ includes nothing of be/, host speed
             (threads, prefetch hints) stays in hw/host/, observers see hardware events only, hw/
             takes from sw_ref/ only arith, tree types and leader policy names; the accelerator's and the pipeline's
             configurations share one mechanism (the same reference table, errors and suggestions)

    python3 -m pytest tests/newcomer_test.py --tigris build/bin/tigris [-k NAME]
(a test per part, in this order, sharing one folder; each names every check that failed)
"""
import csv
import hashlib
import json
import os
import shutil
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIGRIS = None  # the binary under test: the `work` fixture's
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}", flush=True)


def tig(*args, code=None, **kw):
    p = subprocess.run([TIGRIS, *args], capture_output=True, text=True, **kw)
    if code is not None and p.returncode != code:
        raise AssertionError(f"tigris {' '.join(args)}: exit {p.returncode}, expected {code}\n{p.stdout}\n{p.stderr}")
    return p


def write_bin(path, pts):
    import struct
    with open(path, "wb") as f:
        for x, y, z in pts:
            f.write(struct.pack("<4f", x, y, z, 0.0))


def small_cloud(path, n=3000, seed=3):
    import random
    r = random.Random(seed)
    write_bin(path, [(r.uniform(-20, 20), r.uniform(-20, 20), r.uniform(-2, 3)) for _ in range(n)])


def stats(folder):
    with open(os.path.join(folder, "stats.json")) as f:
        return json.load(f)


# ------------------------------------------------------------------------------------------------

def part_inputs(d):
    cloud, queries, cfg = (os.path.join(d, n) for n in ("c.bin", "q.bin", "cfg.json"))
    small_cloud(cloud), small_cloud(queries, 500, 4)
    with open(cfg, "w") as f:
        json.dump({"fe": {"recursion_units": 16}}, f)
    out = os.path.join(d, "in")
    p = tig("run", "--cloud", cloud, "--queries", queries, "--config", cfg, "--height", "6", "--out", out, code=0)
    s = stats(out)
    check(s["command_line"].endswith(f"run --cloud {cloud} --queries {queries} --config {cfg} --height 6 --out {out}"),
          f"command_line records the command: {s['command_line']}")
    roles = {i["role"]: i for i in s["inputs"]}
    for role, path in (("cloud", cloud), ("queries", queries), ("config", cfg)):
        with open(path, "rb") as f:
            data = f.read()
        i = roles.get(role, {})
        check(i.get("path") == path and i.get("bytes") == len(data) and i.get("sha256") == hashlib.sha256(data).hexdigest(),
              f"inputs[{role}] holds path, size and SHA-256: {i}")
        check(path in p.stdout and hashlib.sha256(data).hexdigest()[:12] in p.stdout, f"the summary names the {role} file")
    b = s["bottleneck"]
    check(f"  bound   {b['summary']}" in p.stdout, "the summary prints the bottleneck line")
    check(b["bound"] in ("front-end", "back-end", "result write-back") and 0 < b["share"] <= b["occupancy"],
          f"bottleneck fields: {b}")
    # built-in workload and a cloud alone
    s = stats_of(d, "builtin")
    check([i.get("builtin") for i in s["inputs"]] == ["synthetic:frame0 (seed 1)", "synthetic:frame1 (seed 1)"],
          f"built-in inputs named: {s['inputs']}")
    # README's sample of the default run is what the default run prints (host times and the
    # stats path aside).
    readme = open(os.path.join(ROOT, "README.md")).read()
    sample = readme.split("## The default run", 1)[1].split("```\n", 2)[1].splitlines()
    real = {line.split()[0]: line for line in _printed["builtin"].splitlines() if line.strip()}
    for line in sample:
        key = line.split()[0]
        if key in ("time", "stats"):
            continue
        check(real.get(key) == line, f"README's sample line differs from the default run's:\n  README: {line}\n"
              f"  run:    {real.get(key)}")
    out = os.path.join(d, "alone")
    tig("run", "--cloud", cloud, "--height", "6", "--out", out, code=0)
    check(stats(out)["inputs"][1] == {"role": "queries", "same_as": "cloud"}, "a cloud alone is its own queries")


_runs = {}
_printed = {}  # each run's summary on stdout


def stats_of(d, name, *args):
    if name not in _runs:
        out = os.path.join(d, name)
        _printed[name] = tig("run", *args, "--out", out, code=0).stdout
        _runs[name] = stats(out)
    return _runs[name]


# ------------------------------------------------------------------------------------------------

def leaves(obj, prefix=""):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from leaves(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(obj, list):
        if not obj or not isinstance(obj[0], (dict, list)):
            yield prefix + "[]"
        for v in obj:
            if isinstance(v, (dict, list)):
                yield from leaves(v, prefix + "[]")
    else:
        yield prefix


def formula_value(formula, stats):
    """The formula evaluated independently of the C++ one: paths become look-ups, a division
    by zero is 0 (as documented)."""
    def look(m):
        v = stats
        for k in m.group(0).split("."):
            v = v[k]
        return repr(float(v))
    expr = re.sub(r"[a-z_][a-z0-9_]*(?:\.[a-z0-9_]+)+|\b(?!max\b)[a-z_][a-z0-9_]*\b", look, formula)

    class Z(float):  # x / 0 -> 0
        def __truediv__(self, o):
            return Z(0.0 if float(o) == 0 else float(self) / float(o))
    expr = re.sub(r"(\d[\d.]*(?:e[+-]?\d+)?)", r"Z(\1)", expr)
    return float(eval(expr, {"Z": Z, "max": max, "__builtins__": {}}))


def part_schema(d):
    p = tig("run", "--stats-schema", code=0)
    schema = json.loads(p.stdout)
    fields = schema["fields"]
    check(len(fields) > 200, f"the schema has its fields ({len(fields)})")
    for f in fields:
        check(f["unit"] and f["meaning"], f"schema field {f['path']} has a unit and a meaning: {f}")
    rows = [f["path"] for f in fields]
    check(len(rows) == len(set(rows)), "every schema path is listed once")
    pats = {r: re.compile("^" + re.escape(r).replace(r"\*", r"[^.\[\]]+") + "$") for r in rows}
    cloud = os.path.join(d, "c.bin")
    if not os.path.exists(cloud):
        small_cloud(cloud)
    runs = [stats_of(d, "builtin"), stats_of(d, "knn", "--mode", "knn", "--k", "8"),
            stats_of(d, "radius", "--mode", "radius", "--radius", "0.3"),
            stats_of(d, "approx", "--approx-thd", "default"),
            stats_of(d, "approx_radius", "--mode", "radius", "--approx-thd", "default"),
            stats_of(d, "files", "--cloud", cloud, "--queries", cloud, "--height", "6"),
            stats_of(d, "cloud_alone", "--cloud", cloud, "--height", "6"),
            # Sampled simulation: 315 kNN slots in flight leave the built-in job long enough to sample.
            stats_of(d, "sampled", "--mode", "knn", "--k", "51", "--set", "sram.results.bytes=262144",
                     "--set", "sim.sampling=auto")]
    check(runs[-1]["sampling"]["sampled"], "the sampled run was sampled: " + str(runs[-1]["sampling"].get("why")))
    seen = set()
    for s in runs:
        # Per-bank statistics add up to their buffer's totals, one entry per configured bank.
        for name, b in s["buffers"].items():
            if "banks" not in b:
                continue
            acc, con = b["banks"]["accesses"], b["banks"]["conflict_cycles"]
            # A sampled run's counters are estimates, each rounded on its own: within a count per bank.
            slack = len(acc) if s["sampling"]["sampled"] else 0
            check(len(acc) == len(con) == s["config"]["sram"][name]["banks"],
                  f"buffers.{name}.banks has {len(acc)} entries for {s['config']['sram'][name]['banks']} banks")
            check(abs(sum(acc) - b["reads"] - b["writes"]) <= slack, f"buffers.{name}: banks.accesses sum to {sum(acc)}, "
                  f"reads + writes {b['reads'] + b['writes']} ({s['command_line']})")
            check(abs(sum(con) - b["conflict_cycles"]) <= slack, f"buffers.{name}: banks.conflict_cycles sum to {sum(con)}, "
                  f"conflict_cycles {b['conflict_cycles']} ({s['command_line']})")
        check(all(n in s["buffers"] and "banks" in s["buffers"][n] for n in ("points", "queries", "query_stack", "results")),
              f"every banked buffer has its banks ({s['command_line']})")
        for leaf in leaves(s):
            seen.add(leaf)
            hits = [r for r, p in pats.items() if p.match(leaf)]
            check(hits, f"stats.json field {leaf} ({s['command_line']}) is in the stats schema")
        for f in fields:
            if "formula" in f:
                want = formula_value(f["formula"], s)
                got = s
                for k in f["path"].split("."):
                    got = got[k]
                check(got == want or abs(got - want) <= 1e-12 * abs(want),
                      f"{f['path']} = {got}, its formula {f['formula']} gives {want} ({s['command_line']})")
    for r, p in pats.items():
        check(any(p.match(leaf) for leaf in seen), f"schema field `{r}` matches a field of a real run")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "stats_doc.py"), "--tigris", TIGRIS, "--check"],
                       capture_output=True, text=True)
    check(p.returncode == 0, "docs/stats.md's tables are the schema's (scripts/stats_doc.py):\n" + p.stdout[-3000:]
          + p.stderr)


# ------------------------------------------------------------------------------------------------

def part_diff(d):
    a = os.path.join(d, "builtin")
    stats_of(d, "builtin")
    b = os.path.join(d, "ru32")
    tig("run", "--set", "fe.recursion_units=32", "--out", b, code=0)
    p = tig("diff", a, b, code=1)
    check("configuration: 1 key differs" in p.stdout and re.search(r"fe\.recursion_units\s+64\s+32", p.stdout),
          "diff shows the one configuration difference:\n" + p.stdout[:1500])
    j = json.loads(tig("diff", a, os.path.join(b, "stats.json"), "--json", code=1).stdout)
    check([c["key"] for c in j["config"]] == ["fe.recursion_units"], f"--json config: {j['config']}")
    sa, sb = stats(a), stats(b)
    cyc = next(h for h in j["headline"] if h["name"] == "cycles")
    check(cyc["values"] == [sa["cycles"], sb["cycles"]] and abs(cyc["ratios"][1] - sb["cycles"] / sa["cycles"]) < 1e-12,
          f"headline cycles and ratio: {cyc}")
    check(re.search(r"cycles\s+cycles\s+" + f"{sa['cycles']:,}" + r"\s+" + f"{sb['cycles']:,}" + r"\s+" +
                    re.escape(f"{sb['cycles'] / sa['cycles']:.3f}x"), p.stdout), "the table shows cycles side by side")
    check(j["same_inputs"] is True, "diff sees the same workload")
    check(any(o["path"] == "units.recursion_units.count" for o in j["other"]), "other differing leaves listed")
    tig("diff", a, a, code=0)
    sw = os.path.join(d, "fake_sweep")
    os.makedirs(os.path.join(sw, "points"), exist_ok=True)
    p = tig("diff", a, sw, code=2)
    check("sweep folder" in p.stderr, f"a sweep folder is refused with advice: {p.stderr}")
    for name in ("mode=nn", "mode=knn"):  # the sweep folder alone: its points are named
        shutil.copytree(a, os.path.join(sw, "points", name))
    p = tig("diff", sw, code=2)
    check("compare two (or more) of its 2 points" in p.stderr and "mode=knn" in p.stderr,
          f"diff of one sweep folder names its points: {p.stderr}")
    err = tig("diff", a, os.path.join(ROOT, "README.md"), code=2).stderr
    check("README.md:1:1: not valid JSON" in err, f"a non-JSON file is refused, naming its line: {err}")


# ------------------------------------------------------------------------------------------------

def part_plot(d):
    cloud = os.path.join(d, "c.bin")
    if not os.path.exists(cloud):
        small_cloud(cloud)
    spec = os.path.join(d, "spec.json")
    with open(spec, "w") as f:
        json.dump({"base": {"cloud": cloud, "height": 6}, "grid": {"fe.recursion_units": [8, 16, 32]}}, f)
    sw = os.path.join(d, "sweep")
    p = tig("sweep", spec, "--jobs", "2", "--out", sw, code=0)
    check(re.search(r"point\s+fe\.recursion_units\s+status\s+cycles", p.stderr), "a sweep ends with a summary table")
    with open(os.path.join(sw, "sweep.csv")) as f:
        cols = next(csv.reader(f))
    check(cols[:4] == ["point", "fe.recursion_units", "status", "cycles"], f"sweep.csv starts with the key columns: {cols[:6]}")
    p = tig("plot", sw, "--which", "sweep", code=0)
    svg = os.path.join(sw, "plots", "sweep_fe.recursion_units.svg")
    check(os.path.isfile(svg) and os.path.isfile(svg[:-4] + ".png"), f"plot wrote {svg} and .png: {p.stderr}")
    text = open(svg).read() if os.path.isfile(svg) else ""
    check("c.bin" in text and "height=6" in text, "the figure names its workload and fixed settings")
    # area_mm2.sram does not depend on the RU count: a flat axis, drawn from zero and labelled
    p = tig("plot", sw, "--which", "sweep", "--y", "area_mm2.sram", "cycles", "--out", os.path.join(d, "p2"), code=0)
    text = open(os.path.join(d, "p2", "sweep_fe.recursion_units.svg")).read()
    check("flat: area_mm2.sram" in text and "flat" in p.stderr, "a flat axis says flat")
    check(text.count("flat:") == 1, "only the flat axis is labelled flat")
    p = tig("plot", sw, "--y", "no_such_column", code=2)
    check("no column no_such_column" in p.stderr, f"an unknown column is named: {p.stderr}")
    check(tig("plot", os.path.join(d, "nowhere"), code=2).stderr.startswith("tigris plot: error"), "a missing sweep is an error")


# ------------------------------------------------------------------------------------------------

def vcd_averages(path, names):
    ids, scope, val, last, area, t = {}, [], {}, {}, {}, 0
    with open(path) as f:
        for line in f:
            if line.startswith("$scope"):
                scope.append(line.split()[2])
            elif line.startswith("$upscope"):
                scope.pop()
            elif line.startswith("$var"):
                p = line.split()
                if scope and scope[-1] == "all" and p[4] in names:
                    ids[p[3]] = p[4]
            elif line.startswith("#"):
                t = int(line[1:])
            elif line[:1] in "b01" and line.strip():
                if line[0] == "b":
                    v, code = line[1:].split()
                    v = int(v, 2)
                else:
                    v, code = int(line[0]), line[1:].strip()
                n = ids.get(code)
                if n:
                    area[n] = area.get(n, 0) + val.get(n, 0) * (t - last.get(n, 0))
                    val[n], last[n] = v, t
    for n in names:
        area[n] = area.get(n, 0) + val.get(n, 0) * (t - last.get(n, 0))
    return area, val


def part_waves(d):
    out = os.path.join(d, "waves")
    tig("run", "--vcd", os.path.join(out, "w.vcd"), "--out", out, code=0)
    s = stats(out)
    names = ["rus_busy", "rus_sram_stall", "rus_bqb_full_stall", "rus_writeback_stall", "busy_pes"]
    area, final = vcd_averages(os.path.join(out, "w.vcd"), names)
    ps = 1e6 / s["config"]["clock_mhz"]
    ru, su = s["units"]["recursion_units"], s["units"]["search_units"]
    want = {"rus_busy": ru["busy_cycles"], "rus_sram_stall": ru["stall_cycles"]["sram"],
            "rus_bqb_full_stall": ru["stall_cycles"]["bqb_full"],
            "rus_writeback_stall": ru["stall_cycles"]["result_writeback"], "busy_pes": su["pe_busy_cycles"]}
    for n, cycles in want.items():
        check(abs(area[n] / ps - cycles) <= 1e-9 * max(1, cycles), f"VCD all.{n} integrates to {cycles} cycles: {area[n] / ps}")
        check(final.get(n, 0) == 0, f"all.{n} ends at 0")
    gtkw = open(os.path.join(out, "w.gtkw")).read()
    check("[signals_width]" in gtkw and "rus_sram_stall" in gtkw, "the save file sets a readable width and lists the stalls")
    # What made them: the command line, inputs, configuration digest and commit in the VCD's
    # $comment and the save file; the save file names its dump by an absolute path.
    head = open(os.path.join(out, "w.vcd")).read(4000)
    comment = head.split("$comment", 1)[1].split("$end", 1)[0] if "$comment" in head else ""
    for want in (s["command_line"], "config sha256 " + s["config_sha256"][:12], "commit " + s["commit"],
                 "synthetic:frame0"):
        check(want in comment, f"the VCD's $comment names {want!r}: {comment!r}")
        check("[*] " + want in gtkw or want in gtkw, f"the .gtkw names {want!r}")
    dump = re.search(r'^\[dumpfile\] "(.*)"$', gtkw, re.M)
    check(dump and os.path.isabs(dump.group(1)) and os.path.samefile(dump.group(1), os.path.join(out, "w.vcd")),
          f"the .gtkw finds its dump from any folder: {dump.group(1) if dump else None}")


def part_timeline(d):
    out = os.path.join(d, "tl")
    p = tig("run", "--timeline", os.path.join(out, "t.json"), "--out", out, code=0)
    s = stats(out)
    with open(os.path.join(out, "t.json")) as f:
        t = json.load(f)
    run = t["otherData"].get("run", {})
    check(run.get("command_line") == s["command_line"] and run.get("config_sha256") == s["config_sha256"]
          and run.get("commit") == s["commit"] and run.get("inputs") == s["inputs"],
          f"the timeline's otherData.run says what made it: {run}")
    ev = t["traceEvents"]
    w = t["otherData"]["counter_bin_cycles"]
    sums = {}
    for e in ev:
        if e["ph"] == "C":
            for k, v in e["args"].items():
                key = (e["name"].split(",")[0], k)
                sums[key] = sums.get(key, 0) + v * w
    ru, su = s["units"]["recursion_units"], s["units"]["search_units"]
    for key, cycles in ((("RUs", "busy"), ru["busy_cycles"]), (("RUs", "SRAM stall"), ru["stall_cycles"]["sram"]),
                        (("PEs", "busy"), su["pe_busy_cycles"])):
        # bins are rounded to 1/1000 of a unit: 2000 bins of w cycles, each off by at most 0.0005 x w
        check(abs(sums.get(key, 0) - cycles) <= 0.0005 * w * 2001, f"timeline counter {key} sums to {cycles}: {sums.get(key)}")
    stride = t["otherData"]["sampled_every"]
    names = [e["args"]["name"] for e in ev if e["ph"] == "M" and e["name"] == "thread_name"]
    check(stride > 1 and all(f"sampled 1/{stride}" in n for n in names), "sampled tracks say they are sampled")
    check(f"every {stride}th query" in p.stdout, "the summary says what is sampled")
    # A request for every query of the default pair (~350 MB) warns before it starts.
    pr = subprocess.Popen([TIGRIS, "run", "--timeline", os.path.join(d, "big.json"), "--timeline-queries", "0",
                           "--out", os.path.join(d, "big")], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    line = pr.stderr.readline()
    pr.kill()
    pr.wait()
    check("MB of JSON" in line and "--timeline-queries" in line, f"a large timeline warns first: {line}")


# ------------------------------------------------------------------------------------------------

def part_redundancy(d):
    """tigris ref --redundancy: both conventions, each ratio its own counts' quotient, every
    search checked against the golden model; exact searches only."""
    cloud = os.path.join(d, "red.bin")
    small_cloud(cloud, n=3000)
    for mode in (["--mode", "nn"], ["--mode", "radius", "--radius", "2"]):
        out = os.path.join(d, "red" + mode[1])
        p = tig("ref", "--cloud", cloud, "--height", "6", *mode, "--redundancy", "--out", out, code=0)
        r = stats(out)["redundancy"]
        m, a = r["model"], r["authors"]
        check(abs(m["ratio"] - m["two_stage_per_query"] / m["canonical_per_query"]) < 1e-12, f"model ratio {m}")
        check(abs(a["ratio"] - a["per_query"] / a["leaf_one_per_query"]) < 1e-12, f"authors' ratio {a}")
        check(a["leaf_max"] == -(-3000 // 2 ** 6) and r["queries"] == "the cloud itself", f"redundancy {r}")
        check(a["ratio"] > 1 and m["ratio"] > 1, f"leaf sets cost more than single points: {r}")
        check("authors' convention" in p.stdout and "equal the golden model's" in p.stdout, p.stdout)
    out = os.path.join(d, "red_pair")
    tig("ref", "--redundancy", "--out", out, code=0)
    check(stats(out)["redundancy"]["queries"] == "another frame", "the built-in pair is cross-frame")
    p = tig("ref", "--cloud", cloud, "--approx-thd", "default", "--redundancy", "--out", os.path.join(d, "x"), code=2)
    check("--redundancy counts exact searches" in p.stderr, p.stderr)


def part_help(d):
    run_help = tig("run", "--help", code=0).stdout
    check("--schedule" not in run_help and "--schedule" in tig("ref", "--help", code=0).stdout,
          "run --help leaves out ref's --schedule")
    check(re.search(r"--timeline-queries[^\n]*=2000", run_help), "--timeline-queries shows its default")
    for args, want in ((["rn"], "did you mean 'run'"), (["run", "--mdoe", "nn"], "did you mean --mode"),
                       (["run", "--schedule", "x"], "is a flag of tigris ref"),
                       (["odometry", "--frame", "3"], "did you mean --frames"),
                       (["odometry", "seq"], "did you mean --sequence seq?"),
                       (["register", "--search", "acel"], "did you mean --search accel?"),
                       (["run", "--mode", "nn", "extra"], "takes flags, not the word 'extra'")):
        p = tig(*args, code=2)
        check(want in p.stderr, f"tigris {' '.join(args)} suggests: {p.stderr}")
        check(p.stderr.startswith("tigris: error: ") and not p.stderr.startswith("tigris: error: The following"),
              f"tigris {' '.join(args)}: the project's words come first: {p.stderr}")
    p = tig("run", "--mdoe", "nn", code=2)
    check("the word 'nn'" not in p.stderr, f"a value of an unknown flag is not a stray word: {p.stderr}")
    spec = os.path.join(d, "bad.json")
    with open(spec, "w") as f:
        json.dump({"grid": {"recursion_units": [16, 32]}}, f)
    p = tig("sweep", spec, "--check", code=2)
    check("did you mean 'fe.recursion_units'" in p.stderr, f"a sweep key without its block: {p.stderr}")
    cloud = os.path.join(d, "tiny.bin")
    write_bin(cloud, [(float(i), 0.0, 0.0) for i in range(20)])
    p = tig("run", "--cloud", cloud, "--mode", "knn", "--k", "50", "--height", "1", "--out", os.path.join(d, "k"), code=0)
    check("--k 50 is more than the 20 points" in p.stderr, f"k above the cloud gets a note: {p.stderr}")


def includes(folder):
    """{file: ([quoted includes as root-relative paths], text)} of every C++ source under `folder`."""
    out = {}
    base = os.path.join(ROOT, folder)
    for dirpath, _, files in os.walk(base):
        if "/build" in dirpath or "__pycache__" in dirpath:
            continue
        for name in files:
            if name.endswith((".hpp", ".cpp", ".h")):
                path = os.path.join(dirpath, name)
                with open(path) as f:
                    text = f.read()
                rel = os.path.relpath(path, ROOT)
                found = []
                for inc in re.findall(r'#include "([^"]+)"', text):
                    beside = os.path.normpath(os.path.join(os.path.dirname(rel), inc))
                    found.append(beside if os.path.exists(os.path.join(ROOT, beside)) else inc)
                out[rel] = (found, text)
    return out


# What each folder may include (docs/architecture.md, "Layout and dependency direction"): a
# folder name allows the whole folder, a path one header. The golden model depends on nothing but
# the input error; the hardware takes only the arithmetic, the tree types and the leader policy
# names from it, so the golden check compares two independent implementations of the search.
LAYERS = {
    "core": ["core"],
    "sw_ref": ["sw_ref", "core/input_error.hpp"],
    "config": ["config", "core"],
    "workloads": ["workloads", "sw_ref", "core"],
    "traces": ["traces", "workloads", "sw_ref", "core"],
    "registration": ["registration", "config", "traces", "workloads", "sw_ref", "core"],
    "tlm": ["tlm", "sw_ref/kdtree.hpp", "sw_ref/arith.hpp"],
    "hw": ["hw", "tlm", "config", "traces/vcd_writer.hpp", "sw_ref/arith.hpp", "sw_ref/kdtree.hpp",
           "sw_ref/leader_policy.hpp"],
    "testbench": ["testbench", "hw", "tlm", "config", "traces", "workloads", "sw_ref", "core",
                  "registration/accelerator_port.hpp"],
    # The RTL RU's transactor: the model's headers and Verilator's generated ones.
    "rtl": ["rtl", "hw", "tlm", "config", "sw_ref/arith.hpp", "Vtigris_ru.h", "Vtigris_ru__Dpi.h", "verilated.h"],
    "apps": ["apps", "testbench", "hw", "tlm", "config", "traces", "workloads", "registration", "sw_ref", "core"],
    "python": ["python", "workloads", "sw_ref", "core"],
}


def allowed(inc, rules):
    return any(inc == r or inc.startswith(r + "/") for r in rules)


# What a folder's libraries may link beyond what it includes: the harness links the RTL
# Recursion Unit whole (a plug-in that registers itself) and includes nothing of it.
LINK_EXTRA = {"testbench": ["rtl"]}


def link_graph():
    """{target: (folder, CMakeLists path, [tigris_* targets it links])} of every folder with layering rules."""
    targets, links = {}, {}
    for folder in LAYERS:
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            if "CMakeLists.txt" not in files or "/build" in dirpath:
                continue
            path = os.path.join(dirpath, "CMakeLists.txt")
            text = re.sub(r"#[^\n]*", "", open(path).read())
            for name in re.findall(r"(?:add_library|add_executable|pybind11_add_module)\(\s*(\w+)", text):
                targets[name] = (folder, os.path.relpath(path, ROOT))
            for name, args in re.findall(r"target_link_libraries\(\s*(\w+)([^)]*)\)", text):
                links.setdefault(name, []).extend(re.findall(r"\btigris_\w+", args))
    return {t: (f, p, links.get(t, [])) for t, (f, p) in targets.items()}


def check_layout():
    # The layout is written once, in docs/architecture.md ("Where the code is"): every folder of
    # the tree is there, every file it names exists, and the READMEs point to it.
    doc = open(os.path.join(ROOT, "docs", "architecture.md")).read()
    start = doc.index("## Where the code is")
    block = doc[start:doc.index("\n## ", start + 5)]
    listed = set(re.findall(r"^([\w.-]+)/", block, re.M))
    tracked = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True).stdout.split()
    folders = {f.split("/")[0] for f in tracked if "/" in f and not f.startswith(".")}
    check(folders <= listed, f"docs/architecture.md's layout lacks the folders {sorted(folders - listed)}")
    check(listed <= folders, f"docs/architecture.md's layout names folders the tree lacks: {sorted(listed - folders)}")
    names = {os.path.basename(f) for f in tracked}
    stems = {n.rsplit(".", 1)[0] for n in names}
    for head, alts, ext in re.findall(r"([\w]*)\{([\w,]+)\}([\w]*)\.(?:cpp|hpp)", block):
        for alt in alts.split(","):
            check(head + alt + ext in stems, f"docs/architecture.md's layout names {head}{{{alts}}}{ext}: no {head + alt + ext}.*")
    for name, ext in re.findall(r"(?<![\w{},])([a-z]\w*)\.(\*|cpp|hpp|py|sh|sv)(?!\w)", block):
        check(name in stems if ext == "*" else f"{name}.{ext}" in names,
              f"docs/architecture.md's layout names {name}.{ext}, which the tree does not have")
    for readme in ("README.md", "hw/README.md"):
        check("architecture.md" in open(os.path.join(ROOT, readme)).read(), f"{readme} does not point to the layout")


def check_links():
    # Every library links only libraries of the folders below it, and the graph has no cycle:
    # the link order follows the layers (a plug-in uses the model; the harness links it whole).
    graph = link_graph()
    check({"tigris_hw", "tigris_testbench", "tigris_registration", "tigris"} <= set(graph),
          f"libraries found: {sorted(graph)}")
    for name, (folder, path, linked) in graph.items():
        rules = LAYERS[folder] + LINK_EXTRA.get(folder, [])
        for lib in linked:
            check(lib in graph, f"{path}: {name} links {lib}, which no folder with layering rules builds")
            other = graph.get(lib, (folder,))[0]
            check(other == folder or any(r == other or r.startswith(other + "/") for r in rules),
                  f"{path}: {name} ({folder}/) links {lib} ({other}/): {folder}/ may use only {rules}")
    state = {}

    def visit(name, trail):
        state[name] = "open"
        for lib in graph.get(name, ("", "", []))[2]:
            check(state.get(lib) != "open", f"link cycle: {' -> '.join(trail + [name, lib])}")
            if lib in graph and lib not in state:
                visit(lib, trail + [name])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [])


def part_layers(d):
    # Every folder of sources has its rules, and every file keeps to its folder's.
    folders = {e for e in os.listdir(ROOT) if os.path.isdir(os.path.join(ROOT, e)) and includes(e)}
    check(folders - set(LAYERS) <= {"tests", "bench", "fuzz", "examples"} and "apps" in folders,
          f"folders of C++ sources without layering rules: {sorted(folders - set(LAYERS))}")
    for folder, rules in LAYERS.items():
        files = includes(folder)
        check(files, f"{folder}/ has sources")
        for path, (incs, _) in files.items():
            bad = [i for i in incs if not allowed(i, rules)]
            check(not bad, f"{path} includes {bad}: {folder}/ may include only {rules}")
    check_links()
    check_layout()
    # Command-line parsing (CLI11) lives in apps/ and core/ only (issue 55).
    for folder in set(LAYERS) - {"apps", "core"}:
        for path, (_, text) in includes(folder).items():
            check("CLI/CLI.hpp" not in text and "CLI::" not in text, f"{path} uses CLI11: flags belong to apps/")
    everything = includes("hw")
    check(len(everything) > 40, f"hw/ sources found: {len(everything)}")
    for path, (incs, text) in everything.items():
        if path.startswith("hw/fe/"):
            check(not [i for i in incs if i.startswith("hw/be/")], f"{path} includes be/: {incs}")
        if not path.startswith("hw/host/"):
            check(not re.search(r"std::thread|<thread>|<atomic>|__builtin_prefetch|prefetch_span|LeafBounds", text),
                  f"{path}: host threads, prefetches or leaf boxes outside hw/host/")
            host = [i for i in incs if i.startswith("hw/host/")]
            check(set(host) <= {"hw/host/scan_service.hpp", "hw/host/fifo_ring.hpp"},
                  f"{path} takes more of hw/host/ than the seam (scan_service.hpp) and the FIFO: {host}")
    check("prefetch" not in everything["hw/observer.hpp"][1], "the observer interface has no prefetch hint")
    run_ref = tig("run", "--list-config", code=0).stdout
    reg_ref = tig("register", "--list-config", code=0).stdout
    check(run_ref.startswith("| key | default | unit | allowed | meaning |"), f"run reference: {run_ref[:80]}")
    check(reg_ref.startswith("| key | dp4 | unit | allowed | meaning |"), f"register reference: {reg_ref[:80]}")
    check("| `icp.error` | point_to_plane | - | `point_to_point`, `point_to_plane` |" in reg_ref,
          "register's reference lists an enum key as run's does")
    # run --list-config lists the defaults; its --set is checked before anything runs.
    out = ["--out", os.path.join(d, "layers")]
    for cmd, bad, want in (("run", "fe.recursion_unit=3", "fe.recursion_units"),
                           ("register", "icp.max_iteration=3", "icp.max_iterations")):
        p = tig(cmd, "--set", bad, *out, code=2)
        check(f"--set '{bad}': unknown key '{bad.split('=')[0]}' (did you mean '{want}'?)" in p.stderr,
              f"{cmd} --set {bad}: {p.stderr}")
    for cmd, bad, want in (("run", "be.issue_policy=x", "'be.issue_policy' must be one of `"),
                           ("register", "icp.solver=x", "'icp.solver' must be one of `svd`, `lm`, got \"x\"")):
        p = tig(cmd, "--set", bad, *out, code=2)
        check(want in p.stderr, f"{cmd} --set {bad}: {p.stderr}")


PARTS = {"redundancy": part_redundancy, "inputs": part_inputs, "schema": part_schema, "diff": part_diff, "plot": part_plot,
         "waves": part_waves, "timeline": part_timeline, "help": part_help, "layers": part_layers}



@pytest.fixture(scope="module")
def work(tigris, tmp_path_factory):
    global TIGRIS
    TIGRIS = tigris
    return str(tmp_path_factory.mktemp("newcomer"))


@pytest.mark.parametrize("part", list(PARTS))
def test_part(work, part):
    failures.clear()
    try:
        PARTS[part](work)
    except AssertionError as e:
        check(False, f"{part}: {e}")
    assert not failures, f"{len(failures)} check(s) failed:\n" + "\n".join(failures)


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
