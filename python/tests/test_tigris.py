"""The Python module against the command line: the same neighbours, cycles and transforms from
NumPy arrays as from `tigris ref`, `tigris run` and `tigris register` on the same points, and
clear errors on bad arrays. Run by ctest (python_module) with pytest:
    PYTHONPATH=build/python python3 -m pytest python/tests -q
"""
import json
import os
import subprocess
import tempfile

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
