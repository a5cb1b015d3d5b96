#!/usr/bin/python3
"""Sweep driver and reproduce.py against hostile input: empty paths, a setting given two ways,
specs too deep, too big or not UTF-8, unwritable or full folders, a damaged plan.json, collect
during a sweep, SIGHUP and SIGTERM, reproduce on a tiny cloud, with every point failing and with
a changed workload. Each case: the exit code and a message naming the key, file or flag; never
a traceback. Last, 2,000 seeded mutations of a valid spec through the validator (exit 0 or a
clean exit 2, bounded time)."""
import contextlib, importlib.util, io, json, os, random, re, resource, signal, subprocess, sys, time
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import Workdir, options, read_csv, run_tests, small_workload, sweep, write_cloud, write_spec

a = options()
REPRODUCE = os.path.join(os.path.dirname(a.sweep), "reproduce.py")
if not os.path.isfile(REPRODUCE):                # an installed driver: the repository's reproduce.py
    REPRODUCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reproduce.py")


def clean(p, code, *words):
    """p exited `code` with every word in stderr and no traceback."""
    msg = p.stderr
    assert p.returncode == code, f"exit {p.returncode}, expected {code}:\n{msg}"
    assert "Traceback" not in msg, msg
    for w in words:
        assert w in msg, f"the message does not name {w!r}:\n{msg}"


def reproduce(*args, cwd=None, timeout=300):
    return subprocess.run([sys.executable, REPRODUCE] + list(args), capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:                                         # a zombie has ended
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


# A tigris whose real runs with --seed 9 first sleep (recording the shell's and sleep's PIDs),
# so a sweep is caught mid-run; --help, --list-flags, --list-config and the dry check pass straight through.
SLOW = """#!/bin/sh
case " $* " in
  *" --seed 9 "*".dry-check-no-such-folder"*) ;;
  *" --seed 9 "*) echo $$ > "{d}/slow.sh.pid"; sleep 60 & echo $! > "{d}/slow.sleep.pid"; wait $! ;;
esac
exec "{real}" "$@"
"""
# A tigris whose real runs all fail.
FAILING = """#!/bin/sh
case " $* " in
  *--help*|*--list-flags*|*--list-config*|*".dry-check-no-such-folder"*) exec "{real}" "$@" ;;
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
        p = subprocess.run([sys.executable, a.sweep, spec, "--out", "", "--tigris", a.tigris],
                           capture_output=True, text=True, cwd=cwd)
        clean(p, 2, "--out is empty")
        p = subprocess.run([sys.executable, a.sweep, "collect", ""], capture_output=True, text=True, cwd=cwd)
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
            drv = subprocess.Popen([sys.executable, a.sweep, spec, "--out", out, "--jobs", "2", "--tigris", fake],
                                   stderr=subprocess.PIPE, text=True,   # even under nohup
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
            clean(p, 2, f"{name}", "tigris_sweep: error:", *words[name])
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
        p = subprocess.run([sys.executable, a.sweep, spec, "--out", out, "--tigris", a.tigris],
                           capture_output=True, text=True, preexec_fn=full_disk())
        clean(p, 2, "manifest.json", "too large")
        assert not os.path.exists(out), os.listdir(out)
        # the same into a finished sweep folder grown by a point: the old plan.json stays whole
        sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        plan = open(os.path.join(out, "plan.json")).read()
        grown = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"},
                               "grid": {"height": [4, 5, 6]}}, "grown.json")
        p = subprocess.run([sys.executable, a.sweep, grown, "--out", out, "--tigris", a.tigris],
                           capture_output=True, text=True, preexec_fn=full_disk())
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
    check left out): each ends in exit 0 or exit 2 with one `tigris_sweep: error:` message, never
    another exception, each within 5 s; every 200th also through the real command line."""
    spec_mod = importlib.util.spec_from_file_location("tigris_sweep_under_test", a.sweep)
    ts = importlib.util.module_from_spec(spec_mod)
    spec_mod.loader.exec_module(ts)
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
                assert msg.startswith("tigris_sweep: error: ") and msg.count("tigris_sweep: error:") == 1, \
                    f"input {i}: {msg!r}"
                kind = msg.strip()[len("tigris_sweep: error: "):].replace(d + os.sep, "")
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
                p = subprocess.run([sys.executable, a.sweep, path, "--check", "--jobs", "2", "--tigris", a.tigris],
                                   capture_output=True, text=True, timeout=60)
                assert "Traceback" not in p.stderr, p.stderr
                if code == 2:
                    assert p.returncode == 2 and p.stderr.splitlines()[0] == msg.splitlines()[0], (p.stderr, msg)
                else:
                    assert p.returncode in (0, 2), p.stderr
                    assert p.returncode == 0 or p.stderr.startswith("tigris_sweep: error: "), p.stderr
    total = time.monotonic() - t_all
    print(f"  2000 inputs in {total:.1f} s (slowest {slowest[0]:.2f} s, input {slowest[1]}); "
          f"{sum(n for (c, _), n in classes.items() if c == 0)} exit 0, "
          f"{sum(n for (c, _), n in classes.items() if c == 2)} exit 2 in {len(classes) - 1} kinds:")
    for (c, kind), n in sorted(classes.items(), key=lambda kv: -kv[1]):
        print(f"    {n:5d}  exit {c}  {kind}")


if __name__ == "__main__":
    run_tests([test_empty_paths, test_one_setting_two_ways, test_hostile_spec_files, test_unwritable_folders,
               test_damaged_plan, test_cloud_alone_and_queries_alone, test_dry_check_progress,
               test_collect_and_signals_mid_sweep, test_reproduce_every_point_failed,
               test_reproduce_keeps_its_workload, test_reproduce_tiny_cloud, test_spec_fuzz])
