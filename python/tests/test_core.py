#!/usr/bin/python3
"""tigris/core/ on its own: the input opener (links, kinds, bounds, JSON depth and duplicates),
atomic writes, output folders (claim, foreign entries, lock, resume or fresh, the parent's files,
the manifest), child processes (process groups, the death signal, stop on a signal), the
Slurm and --list-flags helpers, provenance (what a figure's footer says) and the pipeline's
stages as a binary lists them (fake binaries; test_pipeline_dse asks the real one). No tigris
binary needed; about 10 s.

    python3 python/tests/test_core.py [--keep]"""
import argparse, hashlib, json, os, signal, subprocess, sys, tempfile, textwrap, time
import pytest
from common import main, alive, LIST_STAGES, LIST_STAGES_OUTPUT, PAPER_STAGES, package_env
from tigris import core

KEEP = os.environ.get("TIGRIS_TEST_KEEP") == "1"
D = tempfile.mkdtemp(prefix="tigris-core-")


@pytest.fixture(scope="module", autouse=True)
def _folder():
    """D for every test here, removed at the end unless --keep."""
    yield
    if KEEP:
        print(f"(files kept in {D})")
    else:
        subprocess.run(["rm", "-rf", D])


def path(*p):
    return os.path.join(D, *p)


def refused(fn, *words):
    """fn() raises core.Refused whose message holds every word; returns the message."""
    try:
        fn()
    except core.Refused as e:
        msg = str(e)
        for w in words:
            assert w in msg, f"{w!r} not in: {msg}"
        return msg
    raise AssertionError(f"not refused (expected {words})")


def write(p, data):
    os.makedirs(os.path.dirname(p), exist_ok=True)
    with open(p, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    return p


# ----------------------------------------------------------------------------------------------
# Inputs

def test_input_kinds():
    f = write(path("in", "a.txt"), "hello\n")
    assert core.read_input(f) == b"hello\n"
    assert core.read_text_input(f, "x") == "hello\n"
    refused(lambda: core.read_input(path("in", "none")), "none", "no such file")
    refused(lambda: core.read_input(""), "empty path")
    os.symlink(path("in", "gone"), path("in", "broken"))
    refused(lambda: core.read_input(path("in", "broken"), "--config"), "broken", "--config",
            "broken symbolic link", "gone")
    os.symlink(path("in", "loop2"), path("in", "loop1"))
    os.symlink(path("in", "loop1"), path("in", "loop2"))
    refused(lambda: core.read_input(path("in", "loop1")), "loop1", "loop of symbolic links")
    os.symlink(f, path("in", "good"))
    assert core.read_input(path("in", "good")) == b"hello\n"
    refused(lambda: core.read_input(path("in")), "a folder", "not a regular file")
    fifo = path("in", "fifo")
    os.mkfifo(fifo)
    t0 = time.monotonic()
    refused(lambda: core.read_json_input(fifo, "--space"), "fifo", "FIFO", "--space")
    assert time.monotonic() - t0 < 2
    refused(lambda: core.read_input("/dev/zero", "stats"), "/dev/zero", "character device")
    big = write(path("in", "big"), b"x" * 2000)
    refused(lambda: core.read_input(big, "a spec", 1000), "2000 bytes", "more than the 1000 bytes",
            "is it the right file")
    refused(lambda: core.read_input(big, "a spec", 1000, "split the sweep"), "split the sweep")
    bad = write(path("in", "latin1.txt"), b"one\ntwo\ncaf\xe9\n")
    refused(lambda: core.read_text_input(bad), "latin1.txt:3", "not UTF-8")


def test_json_inputs():
    ok = write(path("j", "ok.json"), '{"a": [1, {"b": "x[[[[{"}]}')
    assert core.read_json_input(ok) == {"a": [1, {"b": "x[[[[{"}]}
    refused(lambda: core.read_json_input(write(path("j", "bad.json"), '{\n "a": 1,\n}')), "bad.json:3:", "not valid JSON")
    refused(lambda: core.read_json_input(write(path("j", "dup.json"), '{"a": 1,\n "b": 2,\n "a": 3}')),
            "dup.json:3", 'duplicate key "a"')
    refused(lambda: core.read_json_input(write(path("j", "nan.json"), '{"a": NaN}')), "nan.json", "NaN")
    at = write(path("j", "512.json"), "[" * 512 + "]" * 512)
    core.read_json_input(at)
    refused(lambda: core.read_json_input(write(path("j", "513.json"), "[" * 513 + "]" * 513)),
            "513.json:1", "nested too deeply")
    t0 = time.monotonic()
    refused(lambda: core.read_json_input(write(path("j", "deep.json"), "[" * 100000 + "]" * 100000)),
            "deep.json", "nested too deeply")
    assert time.monotonic() - t0 < 2
    refused(lambda: core.read_json_input(write(path("j", "digits.json"), "[" + "7" * 5000 + "]")),
            "digits.json", "too many digits")


def test_identity_and_atomic_write():
    f = write(path("id", "x.bin"), b"abc" * 1000)
    ident = core.input_identity("cloud", f)
    assert ident == {"role": "cloud", "path": os.path.realpath(f), "bytes": 3000,
                     "sha256": hashlib.sha256(b"abc" * 1000).hexdigest()}, ident
    out = path("id", "out.json")
    core.write_json(out, {"a": 1})
    core.atomic_write(out, "replaced")
    assert open(out).read() == "replaced" and os.listdir(path("id")) == ["out.json", "x.bin"] or \
        sorted(os.listdir(path("id"))) == ["out.json", "x.bin"]
    refused(lambda: core.atomic_write(path("id", "no", "such", "f"), "x"), "cannot write")
    assert sorted(os.listdir(path("id"))) == ["out.json", "x.bin"]


# ----------------------------------------------------------------------------------------------
# Output folders

def manifest(d):
    return json.load(open(os.path.join(d, core.MANIFEST)))


class commit_env:
    """TIGRIS_COMMIT set to a value (None: unset) inside a with block."""
    def __init__(self, value):
        self.value = value

    def __enter__(self):
        self.old = os.environ.pop(core.COMMIT_ENV, None)
        if self.value is not None:
            os.environ[core.COMMIT_ENV] = self.value

    def __exit__(self, *exc):
        os.environ.pop(core.COMMIT_ENV, None)
        if self.old is not None:
            os.environ[core.COMMIT_ENV] = self.old


def test_claim_and_manifest():
    d = path("f1")
    f = core.OutFolder(d, "tool", ["result.json", "jobs/"], argv=["--out", d])
    spec = write(path("f1-spec.json"), "{}")
    with commit_env("0123456789ab-dirty"):
        f.claim(settings={"n": 3}, inputs=[core.input_identity("spec", spec)], input_paths=[("SPEC", spec)])
    m = manifest(d)
    assert list(m) == ["tigris_manifest", "command", "argv", "cwd", "commit", "settings", "inputs", "outputs",
                       "status", "pid", "started", "finished"], list(m)
    assert m["commit"] == "0123456789ab-dirty", m["commit"]
    assert m["status"] == "running" and m["pid"] == os.getpid() and m["finished"] is None
    assert m["inputs"][0]["role"] == "spec" and m["argv"][1:] == ["tool", "--out", d]
    assert m["started"].endswith("Z")
    f.write_json("result.json", {"ok": 1})
    os.makedirs(os.path.join(d, "jobs"))
    f.finish(0)
    assert manifest(d)["status"] == "done" and manifest(d)["finished"]
    # an interrupted or failed end is recorded as such
    g = core.OutFolder(d, "tool", ["result.json", "jobs/"])
    with commit_env(None):
        g.claim(settings={"n": 3}, inputs=[core.input_identity("spec", spec)])
    assert manifest(d)["commit"] == "unknown"      # run without the tigris binary
    g.finish(143)
    assert manifest(d)["status"] == "interrupted"
    g.claim(settings={"n": 3}, inputs=[core.input_identity("spec", spec)])
    g.finish(2)
    assert manifest(d)["status"] == "failed"
    # a folder this run made and left empty is removed on failure
    e = core.OutFolder(path("f1-empty"), "tool", ["r"])
    e.claim()
    e.finish(2)
    assert not os.path.exists(path("f1-empty"))


def test_foreign_and_other_command():
    d = path("f2")
    for n in ("calib.txt", "poses.txt", "a", "b"):
        write(os.path.join(d, n), "mine")
    f = core.OutFolder(d, "tool", ["poses.txt"])
    refused(f.claim, "did not write", "(a, b, calib.txt, poses.txt)")
    assert open(os.path.join(d, "poses.txt")).read() == "mine"
    refused(lambda: core.OutFolder(write(path("f2-file"), "x"), "tool", []).claim(), "exists and is not a folder")
    other = path("f2-other")
    o = core.OutFolder(other, "odometry", ["poses.txt"])
    o.claim()
    o.finish(0)
    refused(core.OutFolder(other, "tool", ["poses.txt"]).claim, "tigris odometry", "not of tigris tool")
    write(os.path.join(path("f2-bad"), core.MANIFEST), "{")
    refused(core.OutFolder(path("f2-bad"), "tool", []).claim, "manifest.json:1:")


def test_inputs_are_not_outputs():
    d = path("f3")
    spec = write(os.path.join(d, "sweep.json"), "{}")
    f = core.OutFolder(d, "sweep", ["sweep.json", "points/"])
    refused(lambda: f.claim(input_paths=[("the spec", spec)]), "the spec", "sweep.json", "would be overwritten")
    deep = write(os.path.join(d, "points", "x", "cloud.bin"), b"1")
    refused(lambda: f.claim(input_paths=[("--cloud", deep)]), "--cloud", "points/")
    assert open(spec).read() == "{}"


def test_lock():
    d = path("f4")
    a = core.OutFolder(d, "tool", ["r"])
    a.claim()
    b = core.OutFolder(d, "tool", ["r"])
    refused(b.claim, "locked", f"pid {os.getpid()}", "tigris tool")
    refused(b.attach, "locked")
    a.finish(0)
    b.claim()                                    # the lock went with the first run
    b.finish(0)
    # a killed holder leaves no lock behind
    p = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import time; from tigris import core
        core.OutFolder({d!r}, "tool", ["r"]).claim(); print("held", flush=True); time.sleep(60)""")],
                         stdout=subprocess.PIPE, text=True, env=package_env())
    assert p.stdout.readline().strip() == "held"
    refused(core.OutFolder(d, "tool", ["r"]).claim, f"pid {p.pid}")
    p.kill()
    p.wait()
    c = core.OutFolder(d, "tool", ["r"])
    c.claim()
    c.finish(0)


def test_resume_or_fresh():
    d = path("f5")
    inp = write(path("f5-in.bin"), b"1234")
    f = core.OutFolder(d, "tool", ["r.json", "jobs/"])
    f.claim(settings={"frames": [0, 3], "k": 1}, inputs=[core.input_identity("scan 000002", inp)])
    f.write("r.json", "{}")
    write(os.path.join(d, "jobs", "job_1.json"), "{}")
    write(os.path.join(d, core.TMP_PREFIX + "r.json-99"), "half")
    f.finish(0)
    same = core.OutFolder(d, "tool", ["r.json", "jobs/"])
    same.claim(settings={"frames": [0, 3], "k": 1}, inputs=[core.input_identity("scan 000002", inp)])
    assert os.path.exists(os.path.join(d, "jobs", "job_1.json"))          # resumed: kept
    assert not os.path.exists(os.path.join(d, core.TMP_PREFIX + "r.json-99"))
    same.finish(0)
    msg = refused(lambda: core.OutFolder(d, "tool", ["r.json", "jobs/"]).claim(
        settings={"frames": [0, 5], "k": 1}, inputs=[core.input_identity("scan 000002", inp)]),
        "settings.frames: [0, 3] -> [0, 5]")
    assert "k:" not in msg, msg
    write(inp, b"12345")
    refused(lambda: core.OutFolder(d, "tool", ["r.json", "jobs/"]).claim(
        settings={"frames": [0, 3], "k": 1}, inputs=[core.input_identity("scan 000002", inp)]),
        "input scan 000002", inp, "content changed (4 -> 5 bytes)")
    # a new input: refused when every input must match, accepted otherwise (a grown sweep)
    extra = core.input_identity("extra", inp)
    refused(lambda: core.OutFolder(d, "tool", ["r.json"]).claim(settings={"frames": [0, 3], "k": 1},
                                                                 inputs=[extra]), "input extra", "new")
    # a fresh run removes the earlier run's outputs, never the parent's files
    write(os.path.join(d, "point.json"), "parent's")
    os.environ[core.PARENT_ENV] = "point.json stdout.txt"
    try:
        g = core.OutFolder(d, "tool", ["r.json", "jobs/"])
        refused(lambda: core.OutFolder(d, "tool", ["point.json"]).claim(resume=False), "point.json",
                "writes itself")
        g.claim(resume=False)
        assert sorted(os.listdir(d)) == ["manifest.json", "point.json"], os.listdir(d)
        refused(lambda: g.write("point.json", "x"), "the parent's")
        g.finish(0)
    finally:
        del os.environ[core.PARENT_ENV]
    refused(core.OutFolder(d, "tool", ["r.json"]).claim, "point.json")   # without the variable: foreign


# ----------------------------------------------------------------------------------------------
# Children

def wait_gone(pids, limit=3.0):
    t0 = time.monotonic()
    while any(alive(p) for p in pids) and time.monotonic() - t0 < limit:
        time.sleep(0.02)
    return not any(alive(p) for p in pids)


def test_children_groups_and_death_signal():
    p = core.spawn(["sleep", "30"])
    assert os.getpgid(p.pid) == p.pid and os.getsid(p.pid) == p.pid
    core.stop_groups([p])
    assert p.returncode == -signal.SIGTERM and p not in core.children._live
    # SIGKILL after the grace for a child that ignores SIGTERM
    p = core.spawn(["sh", "-c", "trap '' TERM; sleep 30 & wait"])
    time.sleep(0.2)
    t0 = time.monotonic()
    core.stop_groups([p], grace=0.5)
    assert p.returncode == -signal.SIGKILL and time.monotonic() - t0 < 3
    # the death signal: a middle process killed with SIGKILL (no clean-up) takes its child along
    mid = subprocess.Popen([sys.executable, "-c", textwrap.dedent("""
        import time; from tigris import core
        p = core.spawn(["sleep", "30"]); print(p.pid, flush=True); time.sleep(60)""")],
                           stdout=subprocess.PIPE, text=True, env=package_env())
    child = int(mid.stdout.readline())
    assert alive(child)
    mid.kill()
    mid.wait()
    assert wait_gone([child]), "the child outlived its SIGKILLed parent"
    # TIGRIS_PARENT_OUTPUTS reaches only the child it is given to
    os.environ[core.PARENT_ENV] = "leaked"
    try:
        r = core.capture(["sh", "-c", "echo \"[$TIGRIS_PARENT_OUTPUTS]\""])
        assert r.stdout.strip() == "[]", r.stdout
        p = core.spawn(["sh", "-c", "echo \"[$TIGRIS_PARENT_OUTPUTS]\""], parent_files=["point.json", "stdout.txt"],
                       stdout=subprocess.PIPE, text=True)
        assert p.communicate()[0].strip() == "[point.json stdout.txt]"
        core.wait(p)
    finally:
        del os.environ[core.PARENT_ENV]


POOL = """
import os, sys, time; from tigris import core
core.handle_stop_signals()
pids = open({pids!r}, "w")
def launch(t):
    p = core.spawn(["sh", "-c", "sleep 30 & echo $! >> {pids}.grand; wait"])
    pids.write(f"{{p.pid}}\\n"); pids.flush()
    return p
try:
    core.pool(range(6), 3, launch, lambda t, p, rc: None)
except KeyboardInterrupt as e:
    sys.exit(core.exit_status(e))
"""


def test_pool_stops_on_signal():
    for sig in (signal.SIGTERM, signal.SIGHUP, signal.SIGINT):
        pids = path(f"pool-{sig}.pids")
        # default dispositions even when started in the background (a shell ignores SIGINT there)
        drv = subprocess.Popen([sys.executable, "-c", POOL.format(pids=pids)], env=package_env(),
                               preexec_fn=lambda: [signal.signal(s, signal.SIG_DFL) for s in core.STOP_SIGNALS])
        t0 = time.monotonic()
        while not (os.path.exists(pids + ".grand") and len(open(pids + ".grand").read().split()) == 3):
            assert time.monotonic() - t0 < 10 and drv.poll() is None
            time.sleep(0.02)
        kids = [int(x) for x in open(pids).read().split() + open(pids + ".grand").read().split()]
        drv.send_signal(sig)
        assert drv.wait(timeout=30) == 128 + sig
        assert wait_gone(kids), f"{signal.Signals(sig).name}: children left"


# ----------------------------------------------------------------------------------------------
# Provenance: what a figure's footer says (matplotlib's part: python/tests/test_plots.py)

def test_shortening():
    assert core.shorten("abcdef", 6) == "abcdef"
    s = core.shorten("/a/very/long/folder/of/runs/kitti00-dp4", 20)
    assert len(s) == 20 and s.count(core.ELLIPSIS) == 1 and s.endswith("kitti00-dp4") and s.startswith("/a/v"), s
    line = ("made by tigris odometry --sequence /data/kitti/dataset/sequences/00 --frames 0:400 --preset dp4 "
            "--out /scratch/user/runs/kitti00-dp4-accel")
    assert core.fit_line(line, 200) == line
    for n in (130, 120, 100, 80, 60, 30, 12, 1):
        out = core.fit_line(line, n)
        assert len(out) <= n, (n, out)
    # Paths give way first, in their middles, the longest first; the rest of the line stays whole.
    out = core.fit_line(line, len(line) - 3)     # the --out path (36 characters) alone gives way
    assert "--sequence /data/kitti/dataset/sequences/00 --frames 0:400 --preset dp4" in out, out
    assert out.count(core.ELLIPSIS) == 1 and out.endswith("kitti00-dp4-accel") and len(out) == len(line) - 3, out
    out = core.fit_line(line, len(line) - 10)    # then both, to the same length
    assert "--frames 0:400 --preset dp4" in out and out.count(core.ELLIPSIS) == 2, out
    # Then whole words from the middle, one ellipsis for them: never two in one path.
    out = core.fit_line(line, 100)
    assert f" {core.ELLIPSIS} " in out and out.startswith("made by tigris") and out.endswith("dp4-accel"), out
    assert all(w.count(core.ELLIPSIS) <= 1 for w in out.split()), out
    assert len(core.fit_line("x" * 300, 40)) == 40
    # The footer's parts flow into two lines: each on the line so far when it fits, the rest last.
    S = core.SEP
    lines = ["made by tigris x --out o", S.join(["commit c0ffee", "a" * 10, "b" * 30, "c" * 10])]
    assert core.flow(lines, 200) == [S.join(["made by tigris x --out o", "commit c0ffee", "a" * 10, "b" * 30,
                                             "c" * 10])]
    assert core.flow(lines, 60) == [S.join(["made by tigris x --out o", "commit c0ffee", "a" * 10]),
                                    S.join(["b" * 30, "c" * 10])]
    two = core.flow(lines, 30)
    assert len(two) == 2 and two[0] == "made by tigris x --out o" and all(len(x) <= 30 for x in two), two
    assert two[1].startswith("commit c0ffee") and two[1].endswith("c" * 10), two


def test_provenance():
    d = path("prov")
    os.makedirs(d)
    # No manifest: said so, the command line given instead, the commit from the environment.
    with commit_env("feedc0ffee12"):
        p = core.provenance(d, argv=["/x/build/bin/tigris", "plot", "sw dir"])
    assert p["note"] == f"no manifest.json in {d}" and p["command_line"] == "tigris plot 'sw dir'", p
    assert p["commit"] == "feedc0ffee12" and p["inputs"] == [] and p["config_sha256"] is None
    with commit_env(None):
        p = core.provenance(d)
        assert p["commit"] == "unknown" and p["command_line"] is None
        lines = core.footer_lines(p)
    assert lines[0] == f"made by an unrecorded command (no manifest.json in {d})", lines
    assert lines[1] == "commit unknown", lines
    # A manifest: its argv, inputs, settings digest and commit (before the environment's).
    spec = write(path("prov-spec.json"), '{"grid": {}}')
    ident = core.input_identity("spec", spec)
    settings = {"b": [1, 2], "a": "x"}
    with commit_env("aaaaaaaaaaaa"):
        f = core.OutFolder(d, "sweep", ["sweep.csv"], argv=[spec, "--out", d])
        f.claim(settings=settings, inputs=[ident])
        f.finish(0)
    m = manifest(d)
    with commit_env("bbbbbbbbbbbb"):
        p = core.provenance(d, argv=["ignored"])
    assert p["argv"] == m["argv"] and p["command_line"] == f"tigris sweep {spec} --out {d}", p
    assert p["commit"] == "aaaaaaaaaaaa" and p["note"] is None
    assert p["config_sha256"] == hashlib.sha256(b'{"a":"x","b":[1,2]}').hexdigest() == core.digest(settings)
    lines = core.footer_lines(p, details=["seed 4"])
    assert lines == [f"made by tigris sweep {spec} --out {d}",
                     f"commit aaaaaaaaaaaa{core.SEP}seed 4{core.SEP}spec {ident['path']} (sha256 {ident['sha256'][:12]})"
                     f"{core.SEP}settings sha256 {p['config_sha256'][:12]}"], lines
    # A manifest without a commit (written before it was recorded): the environment's.
    m.pop("commit")
    write(os.path.join(d, core.MANIFEST), json.dumps(m))
    with commit_env("cccccccccccc"):
        assert core.provenance(d)["commit"] == "cccccccccccc"
    with commit_env(None):
        assert core.provenance(d)["commit"] == "unknown"
    # Another command's manifest is not taken for the one asked for; a broken one is said so.
    assert core.provenance(d, command="odometry")["note"].endswith("is of tigris sweep, not of tigris odometry")
    write(path("prov-bad", core.MANIFEST), "{not json")
    assert "not a readable manifest" in core.provenance(path("prov-bad"))["note"]
    # Data files by SHA-256; a drawing tool's footer names its data's maker.
    with commit_env("dddddddddddd"):
        data = core.provenance(d, command="sweep", files=[spec])
        lines = core.footer_lines([data], drawn=core.provenance(argv=["tigris", "plot", d]))
    assert data["files"] == [{"path": ident["path"], "sha256": ident["sha256"]}]
    assert lines[0] == f"drawn by tigris plot {d}{core.SEP}commit dddddddddddd", lines
    assert lines[1].startswith(f"from {ident['path']} (sha256 {ident['sha256'][:12]}), made by tigris sweep {spec}"), lines
    assert "(commit dddddddddddd; spec " in lines[1], lines
    # Many inputs: their number, folder and one digest of their digests; built-in ones by name.
    many = [{"role": f"scan {i}", "path": f"/seq/velodyne/{i:06d}.bin", "sha256": f"{i:064x}"} for i in range(5)]
    text = core.inputs_text(many + [{"role": "cloud", "builtin": "synthetic"}])
    joint = hashlib.sha256("".join(f"{i['sha256']}\n" for i in many).encode()).hexdigest()[:12]
    assert text == ["cloud synthetic, built in", f"5 inputs in /seq/velodyne, sha256 of their sha256s {joint}"], text


# ----------------------------------------------------------------------------------------------
# Slurm and --list-flags

def test_sbatch_failure_and_flags():
    fake = write(path("bin", "sbatch"), "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n")
    os.chmod(fake, 0o755)
    try:
        core.sbatch([fake, "--parsable", "x.sh"])
        raise AssertionError("sbatch failure not raised")
    except core.SlurmFailed as e:
        assert "invalid partition" in str(e) and "exit 1" in str(e), e
    try:
        core.sbatch([path("bin", "no-sbatch"), "x.sh"])
        raise AssertionError("missing sbatch not raised")
    except core.SlurmFailed as e:
        assert "not found" in str(e)
    ap = argparse.ArgumentParser()
    ap.add_argument("spec")
    ap.add_argument("--jobs", type=int, default=4, help="at once (default %(default)s)")
    ap.add_argument("--check", action="store_true", help="dry")
    j = core.flags_json(ap, "sweep")
    assert j["command"] == "sweep"
    by = {f["flag"]: f for f in j["flags"]}
    assert set(by) == {"help", "jobs", "check"}
    assert by["jobs"] == {"flag": "jobs", "takes_value": True, "type": "INT", "default": "4", "doc": "at once (default 4)"}
    assert by["check"]["takes_value"] is False and by["check"]["type"] == ""


# ----------------------------------------------------------------------------------------------
# The pipeline's stages (`tigris register --list-stages`)

def fake_tigris(name, script):
    """An executable that answers like tigris would: a shell script."""
    p = write(path("stages", name), "#!/bin/sh\n" + script)
    os.chmod(p, 0o755)
    return p


def test_pipeline_stages():
    calls = path("stages", "calls")
    out = write(path("stages", "list.json"), LIST_STAGES_OUTPUT)
    good = fake_tigris("good", f'echo "$@" >> {calls}\n[ "$*" = "register --list-stages" ] || exit 9\ncat {out}\n')
    got = core.pipeline_stages(good)
    assert got == LIST_STAGES, got
    assert core.paper_stages(got) == PAPER_STAGES
    assert [t for t, _, _ in PAPER_STAGES[-2:]] == ["RPCE", "transformation estimation"]
    assert {k for _, k, _ in PAPER_STAGES[-2:]} == {"icp"} and PAPER_STAGES[-1][2] == "rest"
    got[0]["key"] = "changed"                            # the caller's copy; the cache keeps its own
    assert core.pipeline_stages(good) == LIST_STAGES
    assert core.pipeline_stages(os.path.relpath(good)) == LIST_STAGES   # one binary, another spelling
    assert open(calls).read() == "register --list-stages\n", "asked once per binary"
    # A stage without parts is one row; the paper's rows of the raw JSON are the same.
    assert core.paper_stages(json.loads(LIST_STAGES_OUTPUT)) == PAPER_STAGES
    assert core.paper_stages([{"key": "a", "title": "A"}]) == [("A", "a", "seconds")]
    # Refused, naming the binary: missing, failing, no JSON, the wrong JSON.
    refused(lambda: core.pipeline_stages(path("stages", "none")), path("stages", "none"), "not found")
    old = fake_tigris("old", "echo 'tigris: error: tigris register takes no --list-stages' >&2\nexit 2\n")
    refused(lambda: core.pipeline_stages(old), old, "register --list-stages failed (exit 2)", "takes no --list-stages")
    refused(lambda: core.pipeline_stages(fake_tigris("text", "echo stages\n")), "text register --list-stages",
            "did not print JSON")
    bad = [({"key": "a"}, "not a non-empty JSON list"), ([], "not a non-empty JSON list"),
           ([["a"]], "stage 0 is not an object"), ([{"title": "A"}], "\"key\" null"),
           ([{"key": "a.b", "title": "A"}], "not a stage key"), ([{"key": "a", "title": ""}], "\"title\""),
           ([{"key": "a", "title": "A"}, {"key": "a", "title": "B"}], "key 'a' is listed twice"),
           ([{"key": "a", "title": "A"}, {"key": "b", "title": "A"}], "title 'A' is used twice"),
           ([{"key": "a", "title": "A", "parts": {}}], "\"parts\" is not a list"),
           ([{"key": "a", "title": "A", "parts": [{"time": "rest"}]}], "part 0: not an object"),
           ([{"key": "a", "title": "A", "parts": [{"title": "P", "time": "search"}]}], "\"time\" \"search\""),
           ([{"key": "a", "title": "A", "parts": [{"title": "P", "time": "rest"}, {"title": "Q", "time": "rest"}]}],
            "a second part"),
           ([{"key": "a", "title": "A", "parts": [{"title": "A", "time": "rest"}]}], "title 'A' is used twice")]
    for k, (value, want) in enumerate(bad):
        f = write(path("stages", f"bad{k}.json"), json.dumps(value))
        b = fake_tigris(f"bad{k}", f"cat {f}\n")
        refused(lambda: core.pipeline_stages(b), b, want)
        refused(lambda: core.parse_stages(json.dumps(value), "the list"), "the list: ", want)


if __name__ == "__main__":
    main(__file__)
