#!/usr/bin/python3
"""Sweep driver and reproduce.py against hostile input: empty paths, a setting given two ways,
specs too deep, too big or not UTF-8, unwritable or full folders, a damaged plan.json, collect
during a sweep, SIGHUP and SIGTERM, reproduce on a tiny cloud, with every point failing and with
a changed workload. Each case: the exit code and a message naming the key, file or flag; never
a traceback. Last, 2,000 seeded mutations of a valid spec through the validator (exit 0 or a
clean exit 2, bounded time)."""
import contextlib, io, json, os, random, re, resource, shutil, signal, subprocess, sys, time
from common import (PACKAGE, main, Workdir, alive, descendants, digest, options, package_env, read_csv, small_workload, sweep, tool_command,
                    write_cloud, write_spec)

a = options()


def clean(p, code, *words):
    """p exited `code` with every word in stderr and no traceback."""
    msg = p.stderr
    assert p.returncode == code, f"exit {p.returncode}, expected {code}:\n{msg}"
    assert "Traceback" not in msg, msg
    for w in words:
        assert w in msg, f"the message does not name {w!r}:\n{msg}"


def reproduce(*args, cwd=None, timeout=300):
    cmd, env = tool_command("reproduce", *args)
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=timeout, env=env)


# A tigris whose real runs with --seed 9 first sleep (recording the shell's and sleep's PIDs),
# so a sweep is caught mid-run; --help, --list-flags, --list-config and the dry check pass straight through.
SLOW = """#!/bin/sh
case " $* " in
  *" --seed 9 "*".dry-check-no-such-folder"*) ;;
  *" --seed 9 "*) echo $$ > "{d}/slow.sh.pid"; sleep 60 & echo $! > "{d}/slow.sleep.pid"; wait $! ;;
esac
exec "{real}" "$@"
"""
# A tigris whose real runs all fail (what it lists for tools, --list-stages too, it lists).
FAILING = """#!/bin/sh
case " $* " in
  *--help*|*--list-flags*|*--list-config*|*--list-stages*|*".dry-check-no-such-folder"*|" presets --json ") exec "{real}" "$@" ;;
esac
echo "tigris run: error: injected failure" >&2
exit 2
"""
# A tigris whose dry checks take 0.25 s each.
SLOW_CHECK = """#!/bin/sh
case " $* " in *".dry-check-no-such-folder"*) sleep 0.25 ;; esac
exec "{real}" "$@"
"""


def wrapper(d, name, text):
    path = os.path.join(d, name)
    with open(path, "w") as f:
        f.write(text.format(d=d, real=a.tigris))
    os.chmod(path, 0o755)
    return path


# ---------------------------------------------------------------------------------- finding 1

def test_empty_paths():
    """--out '' (and collect '', reproduce --out '') would be the current folder; an empty path
    in a spec is no file: all exit 2 naming the flag or key, nothing written."""
    with Workdir(a, "hostile") as d:
        small_workload(d, 200, 50)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4]}})
        cwd = os.path.join(d, "cwd")
        os.mkdir(cwd)
        clean(sweep(a, spec, "--out", "", "--tigris", a.tigris, cwd=cwd), 2, "--out is empty")
        p = sweep(a, "collect", "", cwd=cwd)
        clean(p, 2, "collect DIR")
        clean(reproduce("--out", "", "--specs-only", cwd=cwd), 2, "--out is empty")
        clean(reproduce("--out", "o", "--cloud", "", "--specs-only", cwd=cwd), 2, "--cloud", "no such file")
        assert os.listdir(cwd) == [], os.listdir(cwd)
        for i, (spec, where) in enumerate([({"base": {"cloud": ""}}, 'base["cloud"]'),
                                           ({"base": {"cloud": "cloud.bin", "queries": " "}}, 'base["queries"]'),
                                           ({"points": [{"config": ""}]}, 'points[0]["config"]'),
                                           ({"grid": {"cloud": ["cloud.bin", ""]}}, 'grid["cloud"][1]')]):
            out = os.path.join(d, f"o{i}")
            p = sweep(a, write_spec(d, spec, f"e{i}.json"), "--out", out, "--tigris", a.tigris)
            clean(p, 2, where, "needs a file name")
            assert not os.path.exists(out)


# ---------------------------------------------------------------------------------- finding 2

def test_one_setting_two_ways():
    """A run flag that overrides a configuration key, and that key, in one spec (anywhere):
    refused naming both spellings, since the CSV would show values that did not run."""
    with Workdir(a, "hostile") as d:
        small_workload(d, 200, 50)
        w = {"cloud": "cloud.bin", "queries": "queries.bin"}
        cases = [
            ({"base": dict(w, height=8), "grid": {"tree.top_height": [4, 6, 10]}}, ["'height'", "'tree.top_height'"]),
            ({"base": dict(w, **{"split-axis": "widest"}), "points": [{"tree.split_axis": "round-robin"}]},
             ["'split-axis'", "'tree.split_axis'", "points[0]"]),
            ({"base": dict(w, set={"leader.capacity_per_leaf": 16}), "grid": {"leader-capacity": [8]}},
             ["'leader-capacity'", "'leader.capacity_per_leaf'", 'base.set["leader.capacity_per_leaf"]']),
            ({"base": w, "points": [{"height": 6, "set": {"tree.top_height": 8}}]},
             ["'height'", "'tree.top_height'", 'points[0].set["tree.top_height"]']),
            ({"base": dict(w, split_axis="widest"), "grid": {"tree.split_axis": ["widest"]}}, ["'split_axis'"]),
        ]
        for i, (spec, words) in enumerate(cases):
            out = os.path.join(d, f"o{i}")
            p = sweep(a, write_spec(d, spec, f"s{i}.json"), "--out", out, "--tigris", a.tigris)
            clean(p, 2, "set one thing two ways", *words)
            assert not os.path.exists(out)
        # one spelling is fine
        p = sweep(a, write_spec(d, {"base": w, "grid": {"tree.top_height": [4, 6]}}), "--check", "--tigris", a.tigris)
        clean(p, 0, "2 points, valid")


# ---------------------------------------------------------------------------------- finding 3

def test_reproduce_keeps_its_workload():
    """OUT/workload.json: --report-only or a rerun without --cloud reuses the recorded workload
    (the specs keep naming it); another workload is refused; --queries alone is refused."""
    with Workdir(a, "hostile") as d:
        write_cloud(os.path.join(d, "a.bin"), 2000, 1)
        write_cloud(os.path.join(d, "b.bin"), 2000, 2)
        out = os.path.join(d, "repro")
        common = ["--out", out, "--only", "optimizations", "--jobs", "2", "--tigris", a.tigris]
        clean(reproduce("--cloud", os.path.join(d, "a.bin"), *common), 0)
        spec_file = os.path.join(out, "specs", "optimizations.json")
        rec = json.load(open(os.path.join(out, "workload.json")))
        assert rec == {"cloud": os.path.join(d, "a.bin"), "queries": None}, rec
        p = reproduce("--report-only", *common)
        clean(p, 0, "reusing that workload", "a.bin")
        assert json.load(open(spec_file))["base"]["cloud"] == os.path.join(d, "a.bin")
        p = reproduce(*common)                   # a plain rerun: nothing to run again
        clean(p, 0, "reusing that workload", "4 finished earlier")
        before = open(spec_file).read()
        p = reproduce("--cloud", os.path.join(d, "b.bin"), *common)
        clean(p, 2, "workload.json", "a.bin", "b.bin", "would mix")
        assert open(spec_file).read() == before
        with open(os.path.join(out, "workload.json"), "w") as f:
            f.write('{"cloud": 5}')
        clean(reproduce("--report-only", *common), 2, "workload.json", "unreadable")
        assert open(spec_file).read() == before
        clean(reproduce("--queries", os.path.join(d, "b.bin"), "--out", os.path.join(d, "r2"), "--specs-only"),
              2, "--queries needs --cloud")
        clean(reproduce("--cloud", os.path.join(d, "b.bin"), "--out", os.path.join(d, "r3"), "--specs-only"), 0)
        base = json.load(open(os.path.join(d, "r3", "specs", "optimizations.json")))["base"]
        assert base["cloud"] == os.path.join(d, "b.bin") and "queries" not in base, base


# ---------------------------------------------------------------------------------- finding 4

def test_reproduce_every_point_failed():
    with Workdir(a, "hostile") as d:
        fake = wrapper(d, "failing-tigris", FAILING)
        out = os.path.join(d, "repro")
        p = reproduce("--out", out, "--only", "optimizations", "--jobs", "2", "--tigris", fake)
        clean(p, 1, "every point failed", "REPORT.md")
        text = open(os.path.join(out, "REPORT.md")).read()
        assert "injected failure" in text and "## Rows not ok" in text


# ---------------------------------------------------------------------------------- findings 5, 6

def test_collect_and_signals_mid_sweep():
    """While a sweep runs, collect is refused (the lock); SIGHUP and SIGTERM stop the driver like
    Ctrl-C: exit 129 / 143, its tigris runs killed with their process groups, finished points
    kept, the lock file gone."""
    for sig in (signal.SIGHUP, signal.SIGTERM):
        with Workdir(a, "hostile") as d:
            small_workload(d, 300, 100)
            fake = wrapper(d, "slow-tigris", SLOW)
            spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"}, "grid": {"seed": [1, 9]}})
            out = os.path.join(d, "out")
            cmd, env = tool_command("sweep", spec, "--out", out, "--jobs", "2", "--tigris", fake)
            drv = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, env=env,   # even under nohup
                                   preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_DFL))
            t0 = time.monotonic()
            while not (os.path.exists(os.path.join(out, "points", "seed=1", "point.json"))
                       and os.path.exists(os.path.join(d, "slow.sleep.pid"))):
                assert drv.poll() is None and time.monotonic() - t0 < 60, "the sweep did not get going"
                time.sleep(0.02)
            time.sleep(0.1)
            pids = [int(open(os.path.join(d, f"slow.{n}.pid")).read()) for n in ("sh", "sleep")]
            assert all(alive(p) for p in pids)
            if sig == signal.SIGHUP:
                p = sweep(a, "collect", out)
                clean(p, 2, "is locked by a run still writing into it", f"pid {drv.pid}")
                assert not os.path.exists(os.path.join(out, "sweep.csv"))
            drv.send_signal(sig)
            err = drv.communicate(timeout=60)[1]
            assert drv.returncode == 128 + sig, f"exit {drv.returncode}\n{err}"
            assert "interrupted" in err and "Traceback" not in err, err
            t0 = time.monotonic()
            while any(alive(p) for p in pids) and time.monotonic() - t0 < 5:
                time.sleep(0.05)
            assert not any(alive(p) for p in pids), "a tigris run outlived the driver"
            assert json.load(open(os.path.join(out, "points", "seed=1", "point.json")))["status"] == "ok"
            assert json.load(open(os.path.join(out, "manifest.json")))["status"] == "interrupted"
            p = sweep(a, "collect", out)         # now it may: seed 9 did not run
            clean(p, 1, "1 ok")


# ---------------------------------------------------------------------------------- finding 7

def test_reproduce_tiny_cloud():
    """A cloud of 600 points: heights beyond its full height fail, the default height is the
    canonical tree; REPORT.md is still written, the claims without rows say why (n/a)."""
    with Workdir(a, "hostile") as d:
        write_cloud(os.path.join(d, "tiny.bin"), 600, 3)
        out = os.path.join(d, "repro")
        p = reproduce("--quick", "--only", "units-su", "heights-nn", "--cloud", os.path.join(d, "tiny.bin"),
                      "--out", out, "--jobs", "2", "--tigris", a.tigris)
        clean(p, 0, "claims measured", "sweeps with failed points: heights-nn")
        text = open(os.path.join(out, "REPORT.md")).read()
        assert "| not measured |" in text and "n/a: " in text and "runs failed" in text, text
        assert "exceeds the full height" in text, text


# ---------------------------------------------------------------------------------- finding 8

def test_hostile_spec_files():
    """Too deep, a 5,000-digit number, not UTF-8, a 1.5e10-point grid: exit 2 naming the spec
    (and the count), fast, no traceback, no folder."""
    with Workdir(a, "hostile") as d:
        small_workload(d, 200, 50)
        files = {"deep.json": ('{"comment": "x", "base": ' + "[" * 100000 + "]" * 100000 + "}").encode(),
                 "digits.json": ('{"grid": {"seed": [' + "7" * 5000 + "]}}").encode(),
                 "latin1.json": '{"comment": "caf\u00e9"}'.encode("latin-1"),
                 "huge.json": json.dumps({"grid": {"fe.recursion_units": list(range(1, 101)),
                                                   "be.search_units": list(range(1, 101)),
                                                   "be.pes_per_su": list(range(1, 101)),
                                                   "seed": list(range(100)),
                                                   "k": list(range(1, 151))}}).encode()}
        words = {"deep.json": ["nested too deeply"], "digits.json": ["too many digits"],
                 "latin1.json": ["not UTF-8"], "huge.json": ["15,000,000,000 points", "100,000"]}
        for name, data in files.items():
            path = os.path.join(d, name)
            with open(path, "wb") as f:
                f.write(data)
            out = os.path.join(d, "out-" + name)
            t0 = time.monotonic()
            p = sweep(a, path, "--out", out, "--tigris", a.tigris, timeout=60)
            clean(p, 2, f"{name}", "tigris sweep: error:", *words[name])
            assert time.monotonic() - t0 < 10, f"{name}: {time.monotonic() - t0:.1f} s"
            assert not os.path.exists(out)


@contextlib.contextmanager
def read_only(path):
    """path made unwritable, even for root (chattr +i); None when that cannot be done."""
    if os.geteuid() != 0:
        os.chmod(path, 0o555)
        try:
            yield path
        finally:
            os.chmod(path, 0o755)
        return
    if subprocess.run(["chattr", "+i", path], capture_output=True).returncode != 0:
        yield None
        return
    try:
        yield path
    finally:
        subprocess.run(["chattr", "-i", path], capture_output=True)


def full_disk():
    """A child whose files cannot grow beyond 512 bytes (EFBIG), the way a full disk fails."""
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (512, 512))
    return limit


def leftovers(out):
    return [f for f in os.listdir(out) if "tmp" in f or f == ".lock"] if os.path.isdir(out) else []


def test_unwritable_folders():
    with Workdir(a, "hostile") as d:
        small_workload(d, 300, 100)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"}, "grid": {"height": [4, 5]}})
        afile = os.path.join(d, "afile")
        open(afile, "w").close()
        clean(sweep(a, spec, "--out", afile, "--tigris", a.tigris), 2, afile, "not a folder")
        clean(sweep(a, spec, "--out", os.path.join(afile, "sub"), "--tigris", a.tigris), 2, afile, "not a folder")
        clean(reproduce("--out", afile, "--specs-only"), 2, afile, "not a folder")
        ro = os.path.join(d, "ro")
        os.mkdir(ro)
        with read_only(ro) as r:
            if r is None:
                print("  (read-only folder: chattr +i not possible here, skipped)")
            else:
                p = sweep(a, spec, "--out", os.path.join(ro, "out"), "--tigris", a.tigris)
                clean(p, 2, ro)
                clean(reproduce("--out", os.path.join(ro, "repro"), "--specs-only"), 2, "not writable", ro)
                assert os.listdir(ro) == []
        # a full disk: the manifest (the first file) cannot be written; no temporary file, no new folder left
        out = os.path.join(d, "full")
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, preexec_fn=full_disk())
        clean(p, 2, "manifest.json", "too large")
        assert not os.path.exists(out), os.listdir(out)
        # the same into a finished sweep folder grown by a point: the old plan.json stays whole
        sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        plan = open(os.path.join(out, "plan.json")).read()
        grown = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"},
                               "grid": {"height": [4, 5, 6]}}, "grown.json")
        p = sweep(a, grown, "--out", out, "--tigris", a.tigris, preexec_fn=full_disk())
        clean(p, 2, "manifest.json", "too large")
        assert open(os.path.join(out, "plan.json")).read() == plan and leftovers(out) == [], leftovers(out)
        assert json.load(open(os.path.join(out, "manifest.json")))["status"] == "done"   # the old one, whole


def test_damaged_plan():
    """collect on a plan.json that is no JSON, the wrong JSON or too deep: exit 2 naming it."""
    with Workdir(a, "hostile") as d:
        out = os.path.join(d, "out")
        os.makedirs(os.path.join(out, "points"))
        ok = {"names": {}, "swept": [], "base_columns": [], "config_keys": [], "defaults": {}, "points": []}
        for text in ("{", "[]", "[" * 100000, '{"points": 5}', json.dumps(dict(ok, swept=["height"])),
                     json.dumps(dict(ok, points=[{"id": "../x", "args": [], "params": {}, "own": {}}])),
                     json.dumps(dict(ok, points=[{"id": "a", "args": [1], "params": {}, "own": {}}])),
                     b"\xff\xfe{}"):
            with open(os.path.join(out, "plan.json"), "wb") as f:
                f.write(text if isinstance(text, bytes) else text.encode())
            clean(sweep(a, "collect", out), 2, os.path.join(out, "plan.json"))
            assert leftovers(out) == [] and not os.path.exists(os.path.join(out, "sweep.csv"))


# ---------------------------------------------------------------------------------- finding 9

def test_dry_check_progress():
    with Workdir(a, "hostile") as d:
        small_workload(d, 200, 50)
        fake = wrapper(d, "slow-check", SLOW_CHECK)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"seed": list(range(40))}})
        p = sweep(a, spec, "--check", "--jobs", "2", "--tigris", fake)
        clean(p, 0, "40 points, valid")
        assert re.search(r"dry check: checked \d+ of 40 points", p.stderr), p.stderr


# ---------------------------------------------------------------------------------- finding 10

def test_cloud_alone_and_queries_alone():
    with Workdir(a, "hostile") as d:
        small_workload(d, 300, 100)
        out = os.path.join(d, "out")
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4]}})
        sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert rows[0]["cloud"] == rows[0]["queries"] == "cloud.bin" and rows[0]["stats.queries"] == "300", rows
        for i, s in enumerate([{"base": {"queries": "queries.bin"}},
                               {"grid": {"queries": ["queries.bin"]}},
                               {"grid": {"cloud": ["cloud.bin"]}, "points": [{"queries": "queries.bin"}]}]):
            o = os.path.join(d, f"q{i}")
            clean(sweep(a, write_spec(d, s, f"q{i}.json"), "--out", o, "--tigris", a.tigris), 2,
                  "'queries'", "without 'cloud'")
            assert not os.path.exists(o)


# ---------------------------------------------------------------------------------- the fuzz

VALID = {"base": {"cloud": "cloud.bin", "queries": "queries.bin", "mode": "nn", "set": {"be.issue_policy": "mqsn"}},
         "grid": {"fe.recursion_units": [16, 64], "height": [6, 8]},
         "points": [{"fe.forwarding": False}, {"k": 4, "mode": "knn"}], "comment": "fuzz"}
KEYS = ["base", "grid", "points", "set", "comment", "cloud", "queries", "config", "height", "tree.top_height",
        "split-axis", "split_axis", "tree.split_axis", "leader-capacity", "leader.capacity_per_leaf", "out",
        "mode", "k", "seed", "approx-thd", "fe.recursion_units", "be.search_units", "clock_mhz", "fe.forwarding",
        "", "x" * 300, "\u00e9", "fe.", "..", "dump-results"]
VALUES = [None, True, False, 0, -1, 1.5, -0.0, 1e308, 2 ** 63, 10 ** 4000, "", " ", "\0", "\ud800", "x" * 5000,
          "../../etc/passwd", "cloud.bin", "/dev/zero", ".", [], {}, [[]], {"a": {"b": 1}}, float("nan"),
          float("inf"), list(range(200000)), list(range(5000)), ["cloud.bin"] * 3, "nn", "full", "widest", 16]


class Dup(dict):
    """A dict serialised with one of its keys twice."""


def dump(o):
    if isinstance(o, Dup):
        items = list(o.items())
        items.append(items[0] if items else ("k", 1))
        return "{" + ", ".join(f"{json.dumps(k)}: {dump(v)}" for k, v in items) + "}"
    if isinstance(o, dict):
        return "{" + ", ".join(f"{json.dumps(k)}: {dump(v)}" for k, v in o.items()) + "}"
    if isinstance(o, list) and any(isinstance(v, (dict, list)) for v in o):
        return "[" + ", ".join(dump(v) for v in o) + "]"
    return json.dumps(o)


def nodes(o, path=()):
    yield path, o
    if isinstance(o, dict):
        for k, v in o.items():
            yield from nodes(v, path + (k,))
    elif isinstance(o, list):
        for i, v in enumerate(o[:8]):
            yield from nodes(v, path + (i,))


def mutate(r):
    """One hostile spec (bytes) from VALID: 1-3 structural mutations, then maybe byte edits."""
    o = json.loads(json.dumps(VALID))
    for _ in range(r.randint(1, 3)):
        containers = [(p, n) for p, n in nodes(o) if isinstance(n, (dict, list)) and n]
        path, node = r.choice(containers)
        key = r.choice(list(node)) if isinstance(node, dict) else r.randrange(len(node))
        op = r.randrange(7)
        if op == 0:                              # delete
            del node[key]
        elif op == 1:                            # a wrong or extreme value
            node[key] = r.choice(VALUES)
        elif op == 2 and isinstance(node, dict):  # rename, or another key beside
            v = node.pop(key)
            node[r.choice(KEYS) if r.random() < 0.7 else key[:-1] + "x"] = v
        elif op == 3 and isinstance(node, dict):
            node[r.choice(KEYS)] = r.choice(VALUES + [["cloud.bin"], [4, 6], {"tree.top_height": 6}])
        elif op == 4:                            # wrapped in a list or an object
            node[key] = [node[key]] if r.random() < 0.5 else {"v": node[key]}
        elif op == 5 and isinstance(node, dict) and path:  # a key twice
            parent = o
            for p in path[:-1]:
                parent = parent[p]
            parent[path[-1]] = Dup(node)
        else:                                    # a grid too big to build
            o["grid"] = {k: list(range(1, 1 + r.choice([10, 1000]))) for k in
                         ("fe.recursion_units", "be.search_units", "be.pes_per_su", "seed")[:r.randint(2, 4)]}
    data = dump(o).encode("utf-8", "surrogatepass")
    roll = r.random()
    if roll < 0.15:                              # random bytes
        b = bytearray(data)
        for _ in range(r.randint(1, 6)):
            i = r.randrange(len(b) + 1)
            b[i:i + r.randint(0, 3)] = bytes(r.randrange(256) for _ in range(r.randint(0, 3)))
        data = bytes(b)
    elif roll < 0.20:
        data = data[:r.randrange(len(data) + 1)]
    elif roll < 0.23:
        data = ("[" * r.choice([1000, 100000]) + "]" * r.choice([0, 1000, 100000])).encode()
    elif roll < 0.26:
        data = data.replace(b"16", b"9" * r.choice([4000, 5000]), 1)
    return data


def test_spec_fuzz():
    """2,000 seeded mutations of a valid spec through the driver's own main() (--check, the dry
    check left out): each ends in exit 0 or exit 2 with one `tigris sweep: error:` message, never
    another exception, each within 5 s; every 200th also through the real command line."""
    from tigris.tools import sweep as ts
    ts.dry_check = lambda *args, **kw: None      # tigris per point: the CLI samples below have it
    r = random.Random(20240601)
    classes, slowest, t_all = {}, (0.0, None), time.monotonic()
    with Workdir(a, "fuzz") as d:
        small_workload(d, 200, 50)
        path = os.path.join(d, "fuzz.json")
        for i in range(2000):
            data = mutate(r)
            with open(path, "wb") as f:
                f.write(data)
            err, t0 = io.StringIO(), time.monotonic()
            try:
                with contextlib.redirect_stderr(err):
                    code = ts.main([path, "--check", "--tigris", a.tigris])
            except SystemExit as e:
                code = e.code
            except BaseException as e:          # the folder is kept: the test fails
                bad = os.path.join(d, f"crash{i}.json")
                os.replace(path, bad)
                raise AssertionError(f"input {i} ({bad}) raised instead of exit 2") from e
            dt = time.monotonic() - t0
            slowest = max(slowest, (dt, i))
            msg = err.getvalue()
            assert code in (0, 2), f"input {i}: exit {code}\n{msg}\n{data[:300]!r}"
            if code == 2:
                assert msg.startswith("tigris sweep: error: ") and msg.count("tigris sweep: error:") == 1, \
                    f"input {i}: {msg!r}"
                kind = msg.strip()[len("tigris sweep: error: "):].replace(d + os.sep, "")
                kind = re.sub(r"^fuzz\.json(:\d+:\d+)?: ((base|grid|points|comment)[^ ]*: )?", "", kind)
                kind = re.sub(r"'[^']*'|\"[^\"]*\"", "'...'", re.sub(r" \([^()]*\)", "", kind).split(": /")[0])
                kind = re.sub(r"\d[\d,]*", "N", re.sub(r"^.*: unknown", "unknown", kind))[:60]
            else:
                kind = "valid"
            classes[(code, kind)] = classes.get((code, kind), 0) + 1
            # A hang detector, not a speed target (a loaded CI machine is 10x slower): the
            # 1.5e10-point grid used to take minutes and gigabytes before the size check.
            assert dt < 60, f"input {i} took {dt:.1f} s"
            m = re.search(r"(\d+) points, valid", msg)
            if i % 200 == 0 and (code == 2 or m and int(m.group(1)) <= 16):
                p = sweep(a, path, "--check", "--jobs", "2", "--tigris", a.tigris, timeout=60)
                assert "Traceback" not in p.stderr, p.stderr
                if code == 2:
                    assert p.returncode == 2 and p.stderr.splitlines()[0] == msg.splitlines()[0], (p.stderr, msg)
                else:
                    assert p.returncode in (0, 2), p.stderr
                    assert p.returncode == 0 or p.stderr.startswith("tigris sweep: error: "), p.stderr
    total = time.monotonic() - t_all
    print(f"  2000 inputs in {total:.1f} s (slowest {slowest[0]:.2f} s, input {slowest[1]}); "
          f"{sum(n for (c, _), n in classes.items() if c == 0)} exit 0, "
          f"{sum(n for (c, _), n in classes.items() if c == 2)} exit 2 in {len(classes) - 1} kinds:")
    for (c, kind), n in sorted(classes.items(), key=lambda kv: -kv[1]):
        print(f"    {n:5d}  exit {c}  {kind}")


# ---------------------------------------------------------------------------------- the shared core
# Each reproduction of the shared core's Python cases: exit code and message, never a traceback, and what
# must not have been written. T = the tigris binary; the tools run as `python3 -m tigris TOOL`.

PY = "/usr/bin/python3" if os.access("/usr/bin/python3", os.X_OK) else sys.executable   # with matplotlib


def tool_cmd(name, *args):
    """(argv, env) of a tool by its tigris sub-command name, on PY, with TIGRIS set."""
    return tool_command(name, *args, env=dict(os.environ, TIGRIS=a.tigris), python=PY)


def tool(name, *args, cwd=None, timeout=60, env=None):
    t0 = time.monotonic()
    cmd, cenv = tool_cmd(name, *args)
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=timeout, env=dict(cenv, **(env or {})))
    p.seconds = time.monotonic() - t0
    return p


# A tigris whose real runs (not the dry check, the lists or synth) sleep: a run to stop mid-way.
SLEEPY = """#!/bin/sh
case " $* " in
  *--help*|*--list-flags*|*--list-config*|*--list-stages*|*".dry-check-no-such-folder"*|*" synth "*|" presets --json ") exec "{real}" "$@" ;;
esac
sleep {secs} & wait $!
exec "{real}" "$@"
"""


def sleepy(d, secs):
    path = os.path.join(d, f"sleepy-{secs}")
    with open(path, "w") as f:
        f.write(SLEEPY.format(real=a.tigris, secs=secs))
    os.chmod(path, 0o755)
    return path


def tiny_sequence(d, frames=3):
    """A KITTI-layout folder of `frames` small random clouds with identity-ish poses."""
    seq = os.path.join(d, "seq")
    os.makedirs(os.path.join(seq, "velodyne"), exist_ok=True)
    for i in range(frames):
        write_cloud(os.path.join(seq, "velodyne", f"{i:06d}.bin"), 60, i + 1)
    with open(os.path.join(seq, "poses.txt"), "w") as f:
        f.writelines(f"1 0 0 0 0 1 0 0 0 0 1 {i}\n" for i in range(frames))
    return seq


SPACE = {"anchors": [], "knobs": [{"key": "icp.max_iterations", "values": [2, 10]}]}


def test_sweep_spec_inside_out():
    """#2: `cd exp && tigris sweep sweep.json --out .` replaced the spec with its results."""
    with Workdir(a, "core") as d:
        exp = os.path.join(d, "exp")
        os.mkdir(exp)
        small_workload(exp, 200, 50)
        spec = write_spec(exp, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4]}}, "sweep.json")
        before = digest(spec)
        clean(tool("sweep", "sweep.json", "--out", ".", cwd=exp), 2, "the spec", "sweep.json", "would be overwritten")
        assert digest(spec) == before and sorted(os.listdir(exp)) == ["cloud.bin", "queries.bin", "sweep.json"]
        # under another name it is still a folder of the user's files: refused, naming them
        os.rename(spec, os.path.join(exp, "mine.json"))
        clean(tool("sweep", "mine.json", "--out", ".", cwd=exp), 2, "did not write", "cloud.bin", "mine.json")
        clean(tool("sweep", "mine.json", "--out", ".", "--check", cwd=exp), 2, "did not write")   # --check says so too
        assert sorted(os.listdir(exp)) == ["cloud.bin", "mine.json", "queries.bin"]


def test_concurrent_sweeps():
    """Two sweeps into one folder started together: exactly one succeeds, the other exits 2 naming
    the lock and its holder; the winner's results are whole."""
    with Workdir(a, "core") as d:
        small_workload(d, 200, 50)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4, 5]}})
        slow, out = sleepy(d, 2), os.path.join(d, "out")
        cmd, env = tool_command("sweep", spec, "--out", out, "--jobs", "2", "--tigris", slow, python=PY)
        procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
                 for _ in range(2)]
        res = [(p.pid,) + (p.wait(timeout=120),) + p.communicate() for p in procs]
        codes = sorted(r[1] for r in res)
        assert codes == [0, 2], [(r[1], r[3]) for r in res]
        winner = next(r for r in res if r[1] == 0)
        loser = next(r for r in res if r[1] == 2)
        assert "locked" in loser[3] and f"pid {winner[0]}" in loser[3] and "Traceback" not in loser[3], loser[3]
        m = json.load(open(os.path.join(out, "manifest.json")))
        assert m["status"] == "done" and m["pid"] == winner[0], m
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["status"] for r in rows] == ["ok", "ok"], rows


def test_changed_input_resume():
    """A rerun after an input's content changed stops with exit 2 saying what changed: the sweep
    (a cloud its finished points read), pipeline-dse (the sequence's poses.txt, the space file)."""
    with Workdir(a, "core") as d:
        small_workload(d, 200, 50)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4]}})
        out = os.path.join(d, "out")
        clean(tool("sweep", spec, "--out", out), 0)
        clean(tool("sweep", spec, "--out", out), 0, "1 finished earlier")
        write_cloud(os.path.join(d, "cloud.bin"), 200, 7)
        clean(tool("sweep", spec, "--out", out), 2, "input cloud cloud.bin", "content changed")
        assert json.load(open(os.path.join(out, "manifest.json")))["status"] == "done"   # the old run's record
        # pipeline-dse, with a tigris whose runs all fail at once (no point converges: exit 1)
        fake = wrapper(d, "failing-tigris", FAILING)
        seq = tiny_sequence(d, 3)
        space = write_spec(d, SPACE, "space.json")
        dse_out = os.path.join(d, "dse")
        args = ["--space", space, "--samples", "2", "--sequence", seq, "--tigris", fake, "--out", dse_out]
        clean(tool("pipeline-dse", *args, timeout=120), 1, "no point converged")
        with open(os.path.join(seq, "poses.txt"), "a") as f:
            f.write("1 0 0 0 0 1 0 0 0 0 1 9\n")
        spec_before = digest(os.path.join(dse_out, "spec.json"))
        clean(tool("pipeline-dse", *args), 2, "input sequence/poses.txt", "content changed")
        write_spec(d, dict(SPACE, comment="changed"), "space.json")
        p = tool("pipeline-dse", *args)
        clean(p, 2, "input space", "content changed", "input sequence/poses.txt")
        assert digest(os.path.join(dse_out, "spec.json")) == spec_before


def test_pipeline_dse_space_and_frames():
    """#3: --space D/spec.json (or D/dse.json) --out D overwrote the space; a refused rerun with
    other --frames still rewrote OUT/spec.json. #22: --samples 100000 and --frames 3:1 are refused
    before anything is written or run."""
    with Workdir(a, "core") as d:
        fake = wrapper(d, "failing-tigris", FAILING)
        seq = tiny_sequence(d, 3)
        D = os.path.join(d, "D")
        os.mkdir(D)
        for name in ("spec.json", "dse.json"):
            space = write_spec(D, SPACE, name)
            before = digest(space)
            clean(tool("pipeline-dse", "--space", space, "--pairs", "1", "--samples", "1", "--tigris", fake,
                       "--out", D), 2, "--space", name, "would be overwritten")
            assert digest(space) == before and os.listdir(D) == [name], os.listdir(D)
            os.remove(space)
        space = write_spec(d, SPACE, "space.json")
        out = os.path.join(d, "out")
        base = ["--space", space, "--samples", "2", "--sequence", seq, "--tigris", fake, "--out", out]
        clean(tool("pipeline-dse", *base, "--frames", "0:1", timeout=120), 1, "no point converged")
        spec_before = digest(os.path.join(out, "spec.json"))
        clean(tool("pipeline-dse", *base, "--frames", "0:2"), 2, "settings.frames", "0:1", "0:2")
        assert digest(os.path.join(out, "spec.json")) == spec_before
        for extra, words in ((["--samples", "100000"], ["--samples 100000", "10,000"]),
                             (["--frames", "3:1"], ["--frames must be A:B", "3:1"]),
                             (["--frames", "0:7"], ["--frames 0:7", "frames 0..2"])):
            fresh = os.path.join(d, "fresh")
            p = tool("pipeline-dse", "--space", space, "--sequence", seq, "--tigris", fake, "--out", fresh, *extra)
            clean(p, 2, *words)
            assert not os.path.exists(fresh) and p.seconds < 10, (p.seconds, extra)


def make_trace_runs(d):
    """A registration of two small clouds recorded as a trace, and two replays of it (A, B)."""
    import struct
    r = random.Random(1)
    pts = [(r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-0.5, 0.5)) for _ in range(4000)]
    for name, dx in (("s.bin", 0.1), ("t.bin", 0.0)):
        with open(os.path.join(d, name), "wb") as f:
            for x, y, z in pts:
                f.write(struct.pack("<4f", x + dx, y, z, 0.0))
    tr = os.path.join(d, "t.trace.json")
    subprocess.run([a.tigris, "register", "--source", os.path.join(d, "s.bin"), "--target", os.path.join(d, "t.bin"),
                    "--record-trace", tr, "--out", os.path.join(d, "reg")], check=True, capture_output=True)
    for x in ("A", "B"):
        subprocess.run([a.tigris, "run", "--trace", tr, "--trace-stages", "icp", "--out", os.path.join(d, x)],
                       check=True, capture_output=True)


def test_diff_hostile():
    """#8: two replays of one trace differ only in host time: exit 0, the headline shows cycles and
    energy. #13: a file that is not a run's statistics, or a run against a replay: exit 2. #15: 100k
    nested brackets: exit 2 naming the file. #18: /dev/zero and a FIFO: exit 2 at once."""
    with Workdir(a, "core") as d:
        make_trace_runs(d)
        A, B = os.path.join(d, "A"), os.path.join(d, "B")
        p = tool("diff", A, B)
        clean(p, 0)
        head = p.stdout.split("headline")[1]
        assert "cycles" in head and "energy" in head and "other differing leaves: 0" in p.stdout, p.stdout
        # a host-time difference alone is no difference; a modeled one is
        doc = json.load(open(os.path.join(B, "stats.json")))
        doc["jobs"][0]["wall_seconds"] = 1e6
        doc["jobs"][0]["phase_seconds"] = {"simulate": 1e6}
        with open(os.path.join(d, "host.json"), "w") as f:
            json.dump(doc, f)
        clean(tool("diff", A, os.path.join(d, "host.json")), 0)
        doc["total"]["cycles"] += 1
        with open(os.path.join(d, "cycles.json"), "w") as f:
            json.dump(doc, f)
        p = tool("diff", A, os.path.join(d, "cycles.json"))
        assert p.returncode == 1 and "Traceback" not in p.stderr, p.stderr
        # files that are not a run's statistics
        run_dir = os.path.join(d, "run")
        subprocess.run([a.tigris, "run", "--out", run_dir, "--set", "tree.top_height=4"], check=True, capture_output=True)
        small_workload(d, 200, 50)
        sw = os.path.join(d, "sw")
        sweep(a, write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4]}}), "--out", sw, "--tigris",
              a.tigris, check=0)
        with open(os.path.join(d, "empty.json"), "w") as f:
            f.write("{}")
        with open(os.path.join(d, "deep.json"), "w") as f:
            f.write("[" * 100000 + "]" * 100000)
        fifo = os.path.join(d, "fifo")
        os.mkfifo(fifo)
        for other, words in ((os.path.join(d, "empty.json"), ["empty.json", "not a run's statistics"]),
                             (os.path.join(d, "reg", "registration.json"), ["registration.json", "tigris register"]),
                             (os.path.join(sw, "points", "height=4", "point.json"), ["point.json", "sweep's point.json"]),
                             (A, ["trace replay", "compare runs with runs"]),
                             (os.path.join(d, "deep.json"), ["deep.json", "nested too deeply"]),
                             ("/dev/zero", ["/dev/zero", "character device"]),
                             (fifo, ["fifo", "FIFO"])):
            p = tool("diff", run_dir, other, timeout=20)
            clean(p, 2, *words)
            assert p.seconds < 10, (other, p.seconds)
        clean(tool("diff", run_dir, os.path.join(sw, "points", "height=4")), 1)    # a sweep point's stats: fine


def test_plot_hostile():
    """#10: a text column (--y bottleneck.bound) or a non-numeric `cycles` drew empty panels at exit 0:
    exit 2 naming the column; the subtitle of a CSV whose rows are all skipped named the built-in
    workload. #16: --out an existing file: a traceback. #18: a FIFO as the CSV: no hang."""
    with Workdir(a, "core") as d:
        small_workload(d, 200, 50)
        sw = os.path.join(d, "sw")
        sweep(a, write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"}, "grid": {"height": [4, 5]}}),
              "--out", sw, "--jobs", "2", "--tigris", a.tigris, check=0)
        clean(tool("plot", sw, "--y", "bottleneck.bound"), 2, "column bottleneck.bound", "no number")
        assert not os.path.exists(os.path.join(sw, "plots"))
        lines = open(os.path.join(sw, "sweep.csv")).read().splitlines()
        cols = lines[0].split(",")
        at = cols.index("cycles")
        bad = [lines[0]] + [",".join(c if i != at else "n/a" for i, c in enumerate(l.split(","))) for l in lines[1:]]
        lone = os.path.join(d, "lone")
        os.mkdir(lone)
        with open(os.path.join(lone, "bad.csv"), "w") as f:
            f.write("\n".join(bad) + "\n")
        clean(tool("plot", os.path.join(lone, "bad.csv")), 2, "column cycles", "'n/a'")
        afile = os.path.join(d, "afile")
        open(afile, "w").close()
        clean(tool("plot", sw, "--out", afile), 2, "--out", "exists and is not a folder")
        fifo = os.path.join(d, "fifo.csv")
        os.mkfifo(fifo)
        p = tool("plot", fifo, "--out", os.path.join(d, "p"), timeout=20)
        clean(p, 2, "fifo.csv", "FIFO")
        # every row skipped (its height is text): the subtitle still names the CSV's workload
        at = cols.index("height")
        with open(os.path.join(lone, "h.csv"), "w") as f:
            f.write("\n".join([lines[0]] + [",".join(c if i != at else "abc" for i, c in enumerate(l.split(",")))
                                            for l in lines[1:]]) + "\n")
        code = ("import sys; from tigris.data import evaldata as ed; "
                "print(ed.workload_text(ed.Sweep([sys.argv[1]])))")
        p = subprocess.run([PY, "-c", code, os.path.join(lone, "h.csv")], capture_output=True, text=True,
                           env=package_env(dict(os.environ, TIGRIS=a.tigris)))
        assert p.stdout.startswith("cloud cloud.bin, queries queries.bin"), (p.stdout, p.stderr)
        # a plot into the sweep's own folder (its default, plots/) keeps the sweep resumable
        clean(tool("plot", sw, "--which", "sweep"), 0)
        assert sorted(os.listdir(os.path.join(sw, "plots"))) == ["manifest.json", "sweep_height.png", "sweep_height.svg"]
        clean(sweep(a, os.path.join(d, "spec.json"), "--out", sw, "--tigris", a.tigris), 0, "2 finished earlier")


def test_inputs_that_are_devices():
    """#18: a FIFO or character device as any Python tool's input: a clear error, never a hang."""
    with Workdir(a, "core") as d:
        fifo = os.path.join(d, "fifo")
        os.mkfifo(fifo)
        cases = [("sweep", [fifo, "--out", os.path.join(d, "o1")], ["fifo", "FIFO"]),
                 ("sweep", ["/dev/zero", "--check"], ["/dev/zero", "character device"]),
                 ("pipeline-dse", ["--space", fifo, "--out", os.path.join(d, "o2")], ["--space", "FIFO"]),
                 ("reproduce", ["--cloud", fifo, "--out", os.path.join(d, "o3"), "--specs-only"], ["--cloud", "FIFO"]),
                 ("reproduce", ["--variants-file", "/dev/zero", "--out", os.path.join(d, "o4"), "--specs-only"],
                  ["/dev/zero", "character device"])]
        for name, args, words in cases:
            p = tool(name, *args, timeout=20)
            clean(p, 2, *words)
            assert p.seconds < 10 and not any(os.path.exists(os.path.join(d, f"o{i}")) for i in range(1, 5)), (name, args)


ROLES = {"sweep": {"out": "out_folder", "tigris": "input"},
         "reproduce": {"out": "out_folder", "cloud": "input", "queries": "input", "tigris": "input",
                       "driver": "input", "dse": "input", "variants-file": "input"},
         "diff": {}, "plot": {"out": "out_folder"},
         "pipeline-dse": {"out": "out_folder", "space": "input", "sequence": "input", "tigris": "input"}}


def test_list_flags():
    """#23: --list-flags on sweep, reproduce, diff, plot and pipeline-dse prints the command's flags
    as JSON in the format of the C++ commands' (`tigris run --list-flags`). #54: a path flag has a
    "role" (output, out_folder, input), other flags none."""
    ref = json.loads(subprocess.run([a.tigris, "run", "--list-flags"], capture_output=True, text=True).stdout)
    keys = set(ref["flags"][0]) - {"role"}
    for name, some in (("sweep", "jobs"), ("reproduce", "quick"), ("diff", "all"), ("plot", "which"),
                       ("pipeline-dse", "samples")):
        p = tool(name, "--list-flags")
        clean(p, 0)
        j = json.loads(p.stdout)
        assert j["command"] == name and all(set(f) - {"role"} == keys for f in j["flags"]), j
        by = {f["flag"]: f for f in j["flags"]}
        assert some in by and by[some]["doc"] and "list-flags" in by and "help" in by, sorted(by)
        roles = {f["flag"]: f["role"] for f in j["flags"] if "role" in f}
        assert roles == ROLES[name], (name, roles)
    via = subprocess.run([a.tigris, "sweep", "--list-flags"], capture_output=True, text=True)
    assert via.returncode == 0 and json.loads(via.stdout)["command"] == "sweep", via.stderr


def stop_parent_only(name, args, cwd, want_kids):
    """Starts tool `name` with args, waits until it has want_kids descendants, SIGTERMs the parent
    alone: exit 143, and within a few seconds none of its descendants is left (/proc)."""
    cmd, env = tool_cmd(name, *args)
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    kids, t0 = set(), time.monotonic()
    while len(kids) < want_kids:
        assert p.poll() is None and time.monotonic() - t0 < 60, f"{name}: exit {p.poll()} before its children ran"
        kids = {k for k in descendants(p.pid) if alive(k)}
        time.sleep(0.05)
    kids |= descendants(p.pid)
    os.kill(p.pid, signal.SIGTERM)
    err = p.communicate(timeout=60)[1]
    t0 = time.monotonic()
    while any(alive(k) for k in kids) and time.monotonic() - t0 < 8:
        time.sleep(0.05)
    left = [k for k in kids if alive(k)]
    for k in left:
        os.kill(k, signal.SIGKILL)
    assert p.returncode == 143 and not left and "Traceback" not in err, (name, p.returncode, left, err[-2000:])
    return err


def test_parent_only_sigterm():
    """SIGTERM to the parent alone (not its group): sweep, reproduce and pipeline-dse stop every
    child and grandchild (the driver, tigris, the sleeping wrapper) and exit 143."""
    with Workdir(a, "core") as d:
        small_workload(d, 200, 50)
        slow = sleepy(d, 60)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin"}, "grid": {"height": [4, 5]}})
        err = stop_parent_only("sweep", [spec, "--out", os.path.join(d, "s"), "--jobs", "2", "--tigris", slow],
                               d, 4)                                    # 2 x (sh, sleep)
        assert json.load(open(os.path.join(d, "s", "manifest.json")))["status"] == "interrupted", err
        stop_parent_only("reproduce", ["--out", os.path.join(d, "r"), "--only", "optimizations", "--jobs", "2",
                                       "--tigris", slow], d, 5)         # driver + 2 x (sh, sleep)
        assert json.load(open(os.path.join(d, "r", "manifest.json")))["status"] == "interrupted"
        space = write_spec(d, SPACE, "space.json")
        stop_parent_only("pipeline-dse", ["--space", space, "--samples", "2", "--pairs", "1", "--jobs", "2",
                                          "--tigris", slow, "--out", os.path.join(d, "p")], d, 5)
        assert json.load(open(os.path.join(d, "p", "manifest.json")))["status"] == "interrupted"


# ---------------------------------------------------------------------------------- issue 54

def tree(folder):
    """{relative path: bytes} of every file under folder: what a command must leave as it was."""
    out = {}
    for root, _, files in os.walk(folder):
        for f in files:
            out[os.path.relpath(os.path.join(root, f), folder)] = digest(os.path.join(root, f))
    return out


def two_height_sweeps(d):
    """Two sweeps of one key (height) into d/sw/s1 and d/sw/s2."""
    small_workload(d, 200, 50)
    w = {"cloud": "cloud.bin", "queries": "queries.bin"}
    for name, hs in (("s1", [4, 5]), ("s2", [6, 7])):
        sweep(a, write_spec(d, {"base": w, "grid": {"height": hs}}, f"{name}.json"), "--out",
              os.path.join(d, "sw", name), "--tigris", a.tigris, check=0)
    return os.path.join(d, "sw", "s1"), os.path.join(d, "sw", "s2")


def test_plot_two_sources_one_key():
    """#54.4: `plot sw/s1 sw/s2 --out P`, both sweeping height, wrote P/sweep_height.png twice (the
    second survived): each sweep's figure carries its name; one CSV given twice is refused."""
    with Workdir(a, "core") as d:
        s1, s2 = two_height_sweeps(d)
        before = tree(os.path.join(d, "sw"))
        P = os.path.join(d, "P")
        p = tool("plot", s1, s2, "--out", P, "--which", "sweep", timeout=300)
        clean(p, 0, "sweep_height-s1.png", "sweep_height-s2.png")
        assert p.stderr.count("wrote ") == 2, p.stderr
        assert sorted(os.listdir(P)) == ["manifest.json", "sweep_height-s1.png", "sweep_height-s1.svg",
                                         "sweep_height-s2.png", "sweep_height-s2.svg"], os.listdir(P)
        assert digest(os.path.join(P, "sweep_height-s1.svg")) != digest(os.path.join(P, "sweep_height-s2.svg"))
        # two sweeps of one name: numbered by their place
        os.makedirs(os.path.join(d, "x"))
        os.symlink(s2, os.path.join(d, "x", "s1"))
        Q = os.path.join(d, "Q")
        p = tool("plot", s1, os.path.join(d, "x", "s1"), "--out", Q, "--which", "sweep", timeout=300)
        clean(p, 0, "sweep_height-s1-1.png", "sweep_height-s1-2.png")
        was = tree(P)
        clean(tool("plot", s1, os.path.join(s1, "sweep.csv"), "--out", P), 2, "give it once", "s1")
        assert tree(P) == was and tree(os.path.join(d, "sw")) == before


def test_plot_default_folder_per_input():
    """#54.5: `plot two/a.csv` then `plot two/b.csv` both wrote two/plots/, the second deleting
    a.csv's figures: each CSV has its own default (two/a-plots, two/b-plots); a default folder
    holding another plot's figures is kept, the plot refused."""
    with Workdir(a, "core") as d:
        s1, s2 = two_height_sweeps(d)
        two = os.path.join(d, "two")
        os.mkdir(two)
        for name, src in (("a.csv", s1), ("b.csv", s2)):
            shutil.copyfile(os.path.join(src, "sweep.csv"), os.path.join(two, name))
        clean(tool("plot", os.path.join(two, "a.csv"), "--which", "sweep", timeout=300), 0, "a-plots")
        first = tree(os.path.join(two, "a-plots"))
        assert "sweep_height.png" in first, first
        csvs = {n: digest(os.path.join(two, n)) for n in ("a.csv", "b.csv")}
        clean(tool("plot", os.path.join(two, "b.csv"), "--which", "sweep", timeout=300), 0, "b-plots")
        assert tree(os.path.join(two, "a-plots")) == first
        assert sorted(os.listdir(two)) == ["a-plots", "a.csv", "b-plots", "b.csv"], os.listdir(two)
        # a sweep folder: SWEEP/plots; several sweeps write the first's, which another plot then keeps
        clean(tool("plot", s1, s2, "--which", "sweep", timeout=300), 0, "sweep_height-s2.png")
        both = tree(os.path.join(s1, "plots"))
        p = tool("plot", s1, "--which", "sweep", timeout=300)
        clean(p, 2, "holds the output of another run of tigris plot", "give --out",
              "is the default --out of SWEEP " + s1)
        assert tree(os.path.join(s1, "plots")) == both
        clean(tool("plot", s1, s2, "--which", "sweep", timeout=300), 0)        # the same sweeps: replaced
        assert {n: digest(os.path.join(two, n)) for n in csvs} == csvs


def test_read_while_written():
    """#54.10: `plot` of a sweep folder that `tigris sweep` is extending plotted the stale
    sweep.csv (exit 0), and `diff` of its point not yet run said "holds no stats.json": both are
    refused (exit 2) naming the folder, the sweep's pid and command line; nothing is written."""
    with Workdir(a, "hostile") as d:
        small_workload(d, 300, 100)
        w = {"cloud": "cloud.bin", "queries": "queries.bin"}
        out = os.path.join(d, "out")
        sweep(a, write_spec(d, {"base": w, "grid": {"seed": [1, 2]}}), "--out", out, "--tigris", a.tigris, check=0)
        fake = wrapper(d, "slow-tigris", SLOW)
        spec = write_spec(d, {"base": w, "grid": {"seed": [1, 2, 9]}})
        cmd, env = tool_command("sweep", spec, "--out", out, "--tigris", fake)
        drv = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, env=env)
        try:
            t0 = time.monotonic()
            while not os.path.exists(os.path.join(d, "slow.sleep.pid")):
                assert drv.poll() is None and time.monotonic() - t0 < 60, "the sweep did not get going"
                time.sleep(0.02)
            before = tree(out)
            for args in ([out], [os.path.join(out, "sweep.csv")]):
                clean(tool("plot", *args), 2, args[0], "still being written", f"pid {drv.pid}",
                      f"tigris sweep {spec}")
            p = tool("diff", os.path.join(out, "points", "seed=1"), os.path.join(out, "points", "seed=9"))
            clean(p, 2, "seed=9", out, "still being written", f"pid {drv.pid}", "tigris sweep")
            assert "holds no stats.json" not in p.stderr
            p = tool("diff", os.path.join(out, "points", "seed=1"), os.path.join(out, "points", "seed=2"))
            assert p.returncode in (0, 1) and not p.stderr, p.stderr       # finished points: compared
            assert tree(out) == before and not os.path.exists(os.path.join(out, "plots"))
        finally:
            drv.send_signal(signal.SIGTERM)
            drv.communicate(timeout=60)
        clean(tool("plot", out, "--which", "sweep", timeout=300), 0)           # it has stopped: plotted


def test_sweep_dir_without_core():
    """#54: TIGRIS_PYTHONPATH at a copy of the package tigris without its layers (core/ and the
    rest) gave a traceback: one line naming the variable and the folder, exit 2."""
    with Workdir(a, "core") as d:
        pkg = os.path.join(d, "tigris")
        os.mkdir(pkg)
        for f in os.listdir(PACKAGE):
            if f.endswith(".py"):
                shutil.copyfile(os.path.join(PACKAGE, f), os.path.join(pkg, f))
        for args in (["plot", "--help"], ["diff", "a", "b"], ["sweep", "--list-flags"]):
            p = subprocess.run([a.tigris] + args, capture_output=True, text=True, timeout=60,
                               env=dict(os.environ, TIGRIS_PYTHONPATH=d))
            clean(p, 2, f"TIGRIS_PYTHONPATH={d}", "has no core/")
            assert len(p.stderr.strip().splitlines()) == 1 and not p.stdout, p.stderr


def test_preset_and_file_of_one_name():
    """#54: `config: ["NAME", "./NAME"]` (a preset, a local file) named the file's point config=NAME
    and the preset's config=NAME.json with its path in the CSV: the preset is named as written, the
    file by its path as written (config=._NAME), and each ran what it names."""
    with Workdir(a, "core") as d:
        small_workload(d, 200, 50)
        presets = json.loads(subprocess.run([a.tigris, "presets", "--json"], capture_output=True, text=True,
                                            check=True).stdout)["presets"]
        name, file = presets[0]["name"], presets[0]["file"]
        shutil.copyfile(file, os.path.join(d, name))
        spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"},
                              "grid": {"config": [name, "./" + name]}})
        kept = {p: digest(p) for p in (spec, os.path.join(d, name), file)}
        out = os.path.join(d, "sw")
        clean(sweep(a, spec, "--out", out, "--tigris", a.tigris), 0, f"config={name} ", f"config=./{name} ")
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        got = [(r["point"], r["config"]) for r in rows]
        assert got == [(f"config={name}", name), (f"config=._{name}", "./" + name)], got
        ran = [json.load(open(os.path.join(out, "points", r["point"], "point.json")))["command"] for r in rows]
        assert ran[0][ran[0].index("--config") + 1] == file, ran[0]
        assert ran[1][ran[1].index("--config") + 1] == os.path.join(d, "./" + name), ran[1]
        assert {p: digest(p) for p in kept} == kept


if __name__ == "__main__":
    main(__file__)
