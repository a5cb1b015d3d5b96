"""The Python module against the command line: the same neighbours, cycles and transforms from
NumPy arrays as from `tigris ref`, `tigris run` and `tigris register` on the same points, and
clear errors on bad arrays. Run by ctest (python_module) with pytest:
    PYTHONPATH=build/python python3 -m pytest python/tests -q
"""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import tigris

TIG = tigris.binary()


def cli(*args, ok=(0,)):
    p = subprocess.run([TIG, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.returncode in ok, p.stderr
    return p


def write_bin(path, a):
    out = np.zeros((len(a), 4), dtype="<f4")
    out[:, :3] = a
    out.tofile(path)


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    """Two overlapping clouds, 'a street' of 6,000 points and the same shifted and jittered."""
    d = tmp_path_factory.mktemp("pair")
    rng = np.random.default_rng(7)
    cloud = (rng.random((6000, 3)) * [40, 12, 3]).astype(np.float32)
    queries = (cloud[::2] + rng.normal(0, 0.05, (3000, 3)) + [0.4, 0, 0]).astype(np.float32)
    write_bin(d / "cloud.bin", cloud)
    write_bin(d / "queries.bin", queries)
    return d, cloud, queries


def read_dump(path):
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return rows[:, 0].astype(int), rows[:, 2].astype(np.uint32), rows[:, 3].astype(np.float32)


@pytest.mark.parametrize("mode,extra,kw", [
    ("nn", [], {}),
    ("knn", ["--k", "8"], {"k": 8}),
    ("radius", ["--radius", "0.6"], {"radius": 0.6}),
    ("nn", ["--approx-thd", "default"], {"approx_thd": "default"}),
    ("knn", ["--k", "5", "--height", "full"], {"k": 5, "height": "full"}),
])
def test_search_is_tigris_ref(pair, mode, extra, kw):
    d, cloud, queries = pair
    dump, out = d / f"ref-{mode}-{len(extra)}.csv", d / f"ref-{mode}-{len(extra)}"
    cli("ref", "--cloud", str(d / "cloud.bin"), "--queries", str(d / "queries.bin"), "--mode", mode, *extra,
        "--dump-results", str(dump), "--out", str(out))
    q, idx, dist2 = read_dump(dump)
    r = tigris.search(tigris.load_cloud(d / "cloud.bin"), tigris.load_cloud(d / "queries.bin"), mode=mode, **kw)
    assert np.array_equal(r.indices.reshape(-1), idx)
    assert np.array_equal(r.dist2.reshape(-1), dist2)          # bit for bit
    assert np.array_equal(np.repeat(np.arange(len(queries)), np.diff(r.offsets).astype(int)), q)
    if mode == "nn":
        assert r.indices.shape == (len(queries),)
    if mode == "knn":
        assert r.indices.shape == (len(queries), kw["k"])
    stats = json.load(open(out / "stats.json"))
    for key in ("top", "pruned", "leaf_points"):
        assert r.visits[key] == stats["visits"]["totals"][key] if "totals" in stats["visits"] \
            else r.visits[key] == stats["visits"][key]
    assert int(r.visits_top.sum()) == r.visits["top"]


def test_load_cloud_is_the_file(pair):
    d, cloud, _ = pair
    a = tigris.load_cloud(str(d / "cloud.bin"))
    assert a.dtype == np.float32 and a.shape == cloud.shape and np.array_equal(a, cloud)
    assert a.flags["C_CONTIGUOUS"] and not a.flags["OWNDATA"]    # the reader's vector, no copy


def without_run_facts(stats):
    """stats.json less what names the run rather than the job: its command line, input paths,
    wall-clock times and commit."""
    s = json.loads(json.dumps(stats))
    for k in ("command_line", "inputs", "wall_seconds", "commit", "workload"):
        s.pop(k, None)
    return s


def test_run_is_tigris_run(pair):
    d, cloud, queries = pair
    out = d / "run-cli"
    cli("run", "--cloud", str(d / "cloud.bin"), "--queries", str(d / "queries.bin"), "--mode", "knn", "--k", "8",
        "--config", "top-6", "--set", "fe.recursion_units=16", "--dump-results", str(d / "run.csv"),
        "--out", str(out))
    want = json.load(open(out / "stats.json"))
    job = tigris.run(cloud, queries, mode="knn", k=8, preset="top-6", set={"fe.recursion_units": 16})
    assert job.verdict == "match" and job.cycles == want["cycles"] > 0
    assert without_run_facts(job.stats) == without_run_facts(want)
    assert job.bound == want["bottleneck"]["bound"]
    _, idx, dist2 = read_dump(d / "run.csv")
    assert np.array_equal(job.indices.reshape(-1), idx) and np.array_equal(job.dist2.reshape(-1), dist2)
    # A preset's keys and a dict over them: the dict's value wins, the preset's others stay.
    both = tigris.run(cloud, queries, mode="knn", k=8, preset="top-6", config={"fe": {"recursion_units": 16}})
    assert both.cycles == job.cycles
    assert both.stats["config"]["fe"]["top_levels_replicated"] == 6
    # A key of the dict that the preset sets too: the dict's, in either form.
    for over in ({"fe": {"top_levels_replicated": 2}}, {"fe.top_levels_replicated": 2}):
        mine = tigris.run(cloud, queries, mode="knn", k=8, preset="top-6", config=over)
        assert mine.stats["config"]["fe"]["top_levels_replicated"] == 2


def test_run_paper_accounting(pair):
    # The paper's accounting is a preset like any: the same results, no DRAM energy for them.
    _, cloud, queries = pair
    phys = tigris.run(cloud, queries, mode="radius", radius=0.3)
    paper = tigris.run(cloud, queries, mode="radius", radius=0.3, preset="paper-accounting")
    assert paper.verdict == "match" and np.array_equal(paper.indices, phys.indices)
    assert paper.stats["config"]["dram"]["writeback"] == "off_critical_path"
    assert paper.stats["energy_pj"]["dram"] == 0 < phys.stats["energy_pj"]["dram"]
    assert paper.stats["buffers"]["dram"]["write_bytes"] == phys.stats["buffers"]["dram"]["write_bytes"] > 0
    assert paper.cycles <= phys.cycles


def test_run_sampled():
    # The built-in pair with 315 kNN slots in flight: long enough to sample (docs/sampling.md).
    small = {"sram.results.bytes": 262144}
    full = tigris.run(mode="knn", k=51, set=small)
    assert not full.sampled and full.cycles_ci95 == [full.cycles, full.cycles]
    job = tigris.run(mode="knn", k=51, set=small, sampling="auto")
    assert job.verdict == "match" and job.sampled
    assert job.sampling["simulated"] < 0.3 * job.sampling["queries"]
    lo, hi = job.cycles_ci95
    assert lo <= job.cycles <= hi and lo <= full.cycles <= hi
    # Every query's results, simulated or not, are the golden model's: the same as the full run's.
    assert np.array_equal(job.indices, full.indices) and np.array_equal(job.dist2, full.dist2)


def test_register_is_tigris_register(tmp_path):
    cli("register", "--preset", "dp4", "--search", "exact", "--out", str(tmp_path / "cli"))
    want = json.load(open(tmp_path / "cli" / "registration.json"))
    reg = tigris.register(preset="dp4", search="exact")
    assert reg.status == want["status"]
    assert np.array_equal(reg.transform, np.array(want["transform"]))
    assert set(reg.stages) == set(want["stages"])


def test_synthetic_pair_is_the_built_in_workload():
    cloud, queries = tigris.synthetic_pair()
    assert cloud.dtype == np.float32 and cloud.shape[1] == 3 and len(queries) > 100000
    a, b = tigris.run(cloud, queries, sim_threads=1), tigris.run(sim_threads=1)
    assert a.cycles == b.cycles and without_run_facts(a.stats) == without_run_facts(b.stats)
    assert np.array_equal(a.indices, tigris.search(cloud, queries).indices)


def test_config_keys_and_presets():
    keys = {k["key"]: k for k in tigris.config_keys()}
    assert keys["fe.recursion_units"]["default"] == 64 and keys["fe.recursion_units"]["type"] == "integer"
    ps = tigris.presets()
    assert ps["paper"]["changes"] == {}
    assert ps["dram-2x"]["changes"] == {"dram.bytes_per_cycle": [51.2, 102.4]}
    assert all(os.path.isfile(p["file"]) for p in ps.values())


@pytest.mark.parametrize("bad,message", [
    (np.zeros((5, 2), np.float32), "shape (N, 3)"),
    (np.zeros((5, 3), np.float64), "must be float32"),
    (np.zeros((0, 3), np.float32), "is empty"),
    (np.array([[0, 0, 0], [1, np.nan, 0]], np.float32), "row 1 is not a finite"),
    (np.array([[0, 0, 0], [1, 0, np.inf]], np.float32), "row 1 is not a finite"),
    ([[0.0, 0.0, 0.0]], "NumPy array"),
])
def test_bad_arrays(bad, message):
    good = np.zeros((4, 3), np.float32)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        tigris.search(bad)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        tigris.search(good, bad)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        tigris.run(bad)


def test_errors_carry_the_cli_messages(tmp_path):
    with pytest.raises(ValueError, match="nope.bin"):
        tigris.load_cloud(str(tmp_path / "nope.bin"))
    (tmp_path / "short.bin").write_bytes(b"\0" * 10)
    with pytest.raises(ValueError, match="short.bin"):
        tigris.load_cloud(str(tmp_path / "short.bin"))
    with pytest.raises(tigris.TigrisError, match="fe.recursion_unit.*did you mean"):
        tigris.run(config={"fe.recursion_unit": 3})
    with pytest.raises(tigris.TigrisError, match="no preset named 'dram2x'"):
        tigris.run(preset="dram2x")
    with pytest.raises(ValueError, match="height"):
        tigris.search(np.zeros((4, 3), np.float32), height=31)
    with pytest.raises(ValueError, match="mode"):
        tigris.search(np.zeros((4, 3), np.float32), mode="knm")
    with pytest.raises(tigris.TigrisError, match="preset"):
        tigris.register(preset="dp99")


# ---------------------------------------------------------------------------------- keep=DIR

def snapshot(folder):
    """Every file under `folder` with its bytes (and every folder), to compare before and after."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for d in dirs:
            out[os.path.relpath(os.path.join(root, d), folder) + "/"] = None
        for f in files:
            with open(os.path.join(root, f), "rb") as fh:
                out[os.path.relpath(os.path.join(root, f), folder)] = fh.read()
    return out


def users_folder(path, names):
    """A folder of the user's own files under the names keep= writes: a KITTI scan with its
    reflectance, a results table, a configuration."""
    path.mkdir()
    rng = np.random.default_rng(5)
    for name in names:
        if name.endswith(".bin"):
            rng.random((300, 4)).astype("<f4").tofile(path / name)     # reflectance in column 4
        else:
            (path / name).write_text(f"the user's own {name}\n")
    return snapshot(path)


@pytest.mark.parametrize("function,names", [
    ("run", ["cloud.bin", "queries.bin", "results.csv", "config.json"]),
    ("run", ["cloud.bin"]),
    ("run", ["results.csv"]),
    ("register", ["source.bin", "target.bin", "pipeline.json"]),
    ("register", ["source.bin"]),
])
def test_keep_refuses_a_folder_of_the_users_files(tmp_path, function, names):
    # Issue 54, reproduction 3: keep= overwrote these (a scan's reflectance zeroed, source.bin
    # truncated); now the rule of --out: a TigrisError naming the folder and the files, and not
    # a byte changed (nor a file added).
    d = tmp_path / "mine"
    before = users_folder(d, names)
    cloud = (np.random.default_rng(1).random((200, 3)) * 10).astype(np.float32)
    call = (lambda: tigris.run(cloud, cloud, mode="knn", k=4, config={"fe.recursion_units": 16}, keep=str(d))) \
        if function == "run" else (lambda: tigris.register(cloud, cloud, config={}, keep=d))
    with pytest.raises(tigris.TigrisError) as e:
        call()
    msg = str(e.value)
    assert f"keep={d}" in msg and f"tigris.{function} did not write" in msg and "nothing was written" in msg
    for name in names:
        assert name in msg
    assert snapshot(d) == before


def test_keep_a_file_is_refused(tmp_path):
    f = tmp_path / "notes.txt"
    f.write_text("mine\n")
    cloud = np.zeros((4, 3), np.float32)
    for call in (lambda: tigris.run(cloud, keep=f), lambda: tigris.register(cloud, cloud, keep=str(f))):
        with pytest.raises(tigris.TigrisError, match=f"keep={f}: {f} exists and is not a folder"):
            call()
    assert f.read_text() == "mine\n" and sorted(os.listdir(tmp_path)) == ["notes.txt"]
    with pytest.raises(ValueError, match="keep must name a folder"):
        tigris.run(cloud, keep="")


def test_keep_folder_reused_and_its_record(pair, tmp_path):
    # The job's files in DIR itself (the command's --out): stats.json, results.csv, manifest.json
    # beside the module's inputs and their record; a second call into it replaces them.
    _, cloud, queries = pair
    d = tmp_path / "job"
    first = tigris.run(cloud, queries, mode="knn", k=8, config={"fe.recursion_units": 16}, keep=d)
    assert sorted(os.listdir(d)) == ["cloud.bin", "config.json", "keep.json", "manifest.json", "queries.bin",
                                      "results.csv", "stats.json"]
    assert json.load(open(d / "stats.json")) == first.stats
    manifest = json.load(open(d / "manifest.json"))
    assert manifest["command"] == "run" and manifest["status"] == "done"
    assert np.array_equal(tigris.load_cloud(d / "queries.bin"), queries)
    # Again with other settings and no queries: queries.bin and config.json (this module's,
    # unchanged) go; the job is the same as one without keep=.
    again = tigris.run(cloud, mode="knn", k=4, keep=str(d))
    assert sorted(os.listdir(d)) == ["cloud.bin", "keep.json", "manifest.json", "results.csv", "stats.json"]
    assert again.cycles == tigris.run(cloud, mode="knn", k=4).cycles
    assert np.array_equal(again.indices, tigris.search(cloud, mode="knn", k=4).indices)
    # A run the command refuses: its message, not the earlier run's stats.json; the folder stays
    # the module's (the next call into it runs).
    with pytest.raises(tigris.TigrisError, match="fe.recursion_unit.*did you mean"):
        tigris.run(cloud, mode="knn", k=4, config={"fe.recursion_unit": 3}, keep=d)
    assert tigris.run(cloud, mode="knn", k=4, keep=d).cycles == again.cycles
    # The user changes the module's cloud.bin (or adds a file): refused, nothing written.
    with open(d / "cloud.bin", "r+b") as f:
        f.seek(12)
        f.write(np.float32(0.75).tobytes())                   # a reflectance of their own
    (d / "notes.txt").write_text("mine\n")
    before = snapshot(d)
    with pytest.raises(tigris.TigrisError, match=r"did not write \(notes.txt\) and a file tigris.run wrote "
                                                 r"that has changed since \(cloud.bin\)"):
        tigris.run(cloud, keep=d)
    assert snapshot(d) == before


def test_keep_after_a_refused_first_call(tmp_path):
    # The command refused the first call before writing its record: the folder holds only the
    # module's files (and keep.json), and the next call into it runs.
    d = tmp_path / "job"
    cloud = (np.random.default_rng(1).random((300, 3)) * 10).astype(np.float32)
    with pytest.raises(tigris.TigrisError, match="fe.recursion_unit.*did you mean"):
        tigris.run(cloud, config={"fe.recursion_unit": 3}, keep=d)
    assert sorted(os.listdir(d)) == ["cloud.bin", "config.json", "keep.json"]
    assert tigris.run(cloud, keep=d).verdict == "match"
    assert sorted(os.listdir(d)) == ["cloud.bin", "keep.json", "manifest.json", "results.csv", "stats.json"]


def test_keep_folder_of_the_command_line_and_of_another_function(pair, tmp_path):
    d, cloud, queries = pair
    out = tmp_path / "cli"
    cli("run", "--cloud", str(d / "cloud.bin"), "--out", str(out))
    job = tigris.run(cloud, keep=out)                          # `tigris run --out` wrote it: the rule of --out
    assert job.verdict == "match" and "cloud.bin" in os.listdir(out)
    before = snapshot(out)
    with pytest.raises(tigris.TigrisError, match="holds the output of tigris run, not of tigris register"):
        tigris.register(cloud, cloud, keep=out)
    assert snapshot(out) == before


def test_keep_folder_in_use_is_refused(tmp_path):
    import fcntl
    d = tmp_path / "busy"
    d.mkdir()
    fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)        # as a running tigris holds it
        with pytest.raises(tigris.TigrisError, match="another run is writing into this folder"):
            tigris.run(np.zeros((4, 3), np.float32), keep=d)
    finally:
        os.close(fd)
    assert os.listdir(d) == []


def test_register_keep(tmp_path):
    d = tmp_path / "reg"
    reg = tigris.register(keep=d, config={})
    assert sorted(os.listdir(d)) == ["keep.json", "manifest.json", "pipeline.json", "registration.json"]
    assert json.load(open(d / "registration.json"))["status"] == reg.status
    again = tigris.register(keep=d)
    assert np.array_equal(again.transform, reg.transform)
    assert sorted(os.listdir(d)) == ["keep.json", "manifest.json", "registration.json"]


# -------------------------------------------------------------- whole numbers, indices, flags

@pytest.mark.parametrize("kw,message", [
    ({"mode": "knn", "k": 2.5}, "k must be a whole number from 1 to 2147483647, got 2.5"),
    ({"mode": "knn", "k": 2.0}, "k must be a whole number from 1 to 2147483647, got 2.0"),
    ({"mode": "knn", "k": 2**31}, "k must be a whole number from 1 to 2147483647, got 2147483648"),
    ({"mode": "knn", "k": 0}, "k must be a whole number from 1 to 2147483647, got 0"),
    ({"mode": "knn", "k": True}, "k must be a whole number"),
    ({"mode": "radius", "max_nn": -1}, "max_nn must be a whole number from 0 to 4294967295, got -1"),
    ({"mode": "radius", "max_nn": 2**32}, "max_nn must be a whole number from 0 to 4294967295"),
    ({"mode": "radius", "max_nn": 2.5}, "max_nn must be a whole number from 0 to 4294967295, got 2.5"),
    ({"approx_thd": 1, "leader_capacity": 2**40}, "leader_capacity must be a whole number from 0 to 2147483647"),
    ({"approx_thd": 1, "leader_capacity": 1.5}, "leader_capacity must be a whole number"),
    ({"approx_thd": 1, "leader_width": -1}, "leader_width must be a whole number from 0 to 2147483647"),
    ({"height": 2.5}, "height must be 'full' or a whole number from 0 to 30, got 2.5"),
])
def test_whole_number_arguments(kw, message):
    # Issue 54, reproduction 11 and the unclear errors: k=2.5 searched with k=2, k=2**31,
    # max_nn=-1 and leader_capacity=2**40 were pybind11's TypeError dumps.
    cloud = (np.random.default_rng(1).random((50, 3)) * 10).astype(np.float32)
    escaped = message.replace("(", r"\(").replace(")", r"\)")
    with pytest.raises(ValueError, match=escaped):
        tigris.search(cloud, **kw)
    with pytest.raises(ValueError, match=escaped):        # run checks them before the binary
        tigris.run(cloud, **kw)
    assert tigris.search(cloud, mode="knn", k=np.int64(3)).indices.shape == (50, 3)   # NumPy ints are whole


def test_whole_number_flags_and_seed():
    cloud = np.zeros((4, 3), np.float32)
    with pytest.raises(ValueError, match="leader_capacity must be a whole number from 0 to 2147483647, got 8.5"):
        tigris.run(cloud, approx_thd=1, leader_capacity=8.5)
    with pytest.raises(ValueError, match="jobs must be a whole number"):
        tigris.register(jobs=1.5)
    with pytest.raises(ValueError, match="seed must be a whole number from 0 to 18446744073709551615, got 1.5"):
        tigris.synthetic_pair(1.5)


def test_neighbors_index_range():
    # Issue 54, reproduction 11: neighbors(-1) was empty and neighbors(-2) the last query's.
    cloud = (np.random.default_rng(2).random((30, 3)) * 10).astype(np.float32)
    for mode in ("knn", "radius"):
        r = tigris.search(cloud, mode=mode, k=3, radius=3.0)
        idx, d2 = r.neighbors(29)
        a, b = int(r.offsets[29]), int(r.offsets[30])
        assert np.array_equal(idx, r.indices.reshape(-1)[a:b]) and np.array_equal(d2, r.dist2.reshape(-1)[a:b])
        for q in (-1, -2, 30, 10**12):
            with pytest.raises(IndexError, match=rf"query {q} is out of range: the result holds 30 queries, 0 \.\. 29"):
                r.neighbors(q)
        with pytest.raises(TypeError, match="whole number"):
            r.neighbors(1.5)


@pytest.mark.parametrize("function,flag,message", [
    ("run", "list_config", r"list_config is not an option of tigris.run: .*tigris.config_keys\(\)"),
    ("run", "stats_schema", "stats_schema is not an option of tigris.run"),
    ("run", "out", "keep=DIR"),
    ("run", "dump_results", "dump_results is not an option of tigris.run"),
    ("register", "list_config", "list_config is not an option of tigris.register"),
    ("register", "compare", "compare is not an option of tigris.register"),
])
def test_flags_that_run_nothing(function, flag, message):
    # Issue 54: run(list_config=True) was TigrisError "no message".
    with pytest.raises(ValueError, match=message):
        getattr(tigris, function)(**{flag: True if flag not in ("out", "dump_results") else "x"})


def test_search_work_bound_and_ctrl_c():
    """Issue 54, 13: a job the command line refuses by its work bound is refused here too, before
    it starts (it ran 30 s and more, deaf to Ctrl-C); max_results=0 lifts the bound."""
    import time
    # A radius around the whole cloud: 15,000 hits per query, 2.25e8 in all (the bound is 2e8);
    # the estimate's 128 sampled queries are cheap, also under the sanitizers.
    pts = np.random.default_rng(3).uniform(-10, 10, (15000, 3)).astype(np.float32)
    t0 = time.monotonic()
    with pytest.raises(ValueError, match="max-results"):
        tigris.search(pts, pts, mode="radius", radius=100.0, height=0)
    assert time.monotonic() - t0 < 10
    small = pts[:300]
    res = tigris.search(small, small[:5], mode="knn", k=300, height=0, max_results=0, max_work=0)
    assert res.indices.shape == (5, 300)


def test_search_stops_on_ctrl_c():
    """Issue 54, 13: Ctrl-C stops a long search inside the extension (KeyboardInterrupt)."""
    import signal
    import time
    code = ("import numpy as np, tigris, sys\n"
            "p = np.random.default_rng(3).uniform(-10, 10, (30000, 3)).astype(np.float32)\n"
            "print('started', flush=True)\n"
            "try:\n"
            "    tigris.search(p, p, mode='knn', k=3000, height=0, max_work=0, max_results=0)\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True); sys.exit(3)\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.5)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 3 and "interrupted" in out, (p.returncode, out)
    assert time.monotonic() - t0 < 20
