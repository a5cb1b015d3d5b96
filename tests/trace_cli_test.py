#!/usr/bin/env python3
"""Record and replay through the command line: `tigris register --record-trace` on a
small scene (exact and approximate search), `tigris run --trace` replaying it bit-exact with
--jobs 1 and --jobs 2 (the same figures), per-stage sums equal to the totals, the end-to-end
formula, and clear errors for a damaged trace, a bad --trace-stages and flags that do not go
with --trace; `tigris register --search accel` (the accelerator in the loop) giving the exact
transform bit for bit, its modeled end-to-end formula and its configuration errors; and
`tigris register --compare`, the four back-ends side by side.

Run: python3 -m pytest tests/trace_cli_test.py --tigris PATH (or python3 tests/trace_cli_test.py
--tigris PATH). Each test reports every check that failed, not only the first.
"""
import json
import os
import shutil
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_inputs import make_register_files  # noqa: E402  (the room scene)
from support import Checks  # noqa: E402

FIGURES = ("cycles", "energy_pj", "neighbors", "verdict", "modeled_seconds", "host_bytes", "visits", "vs_recorded")


CHECKS = Checks()            # the binary is the `scene` fixture's
run, check = CHECKS.run, CHECKS.check


def record_and_replay(d, pair):
    """Record exact and approximate registrations; replay each with --jobs 1 and 2: the same
    figures, per-stage sums equal to the totals, the end-to-end formula."""
    for backend in ("exact", "approx"):
        tr = os.path.join(d, f"{backend}.trace")
        run(["register"] + pair + ["--search", backend, "--record-trace", tr, "--out", os.path.join(d, "reg_" + backend)])
        reg = json.load(open(os.path.join(d, "reg_" + backend, "registration.json")))
        check(reg["trace"]["jobs"] > 0, f"{backend}: no jobs recorded")
        stats = {}
        for jobs in (1, 2):
            out = os.path.join(d, f"rep_{backend}_{jobs}")
            text = run(["run", "--trace", tr, "--jobs", str(jobs), "--out", out], 0, "MATCH")
            check("end to end" in text, f"{backend}: no end-to-end line")
            stats[jobs] = json.load(open(os.path.join(out, "stats.json")))
        s1, s2 = stats[1], stats[2]
        check(s1["verdict"] == "match", f"{backend}: verdict {s1['verdict']}")
        check(len(s1["jobs"]) == reg["trace"]["jobs"], f"{backend}: {len(s1['jobs'])} jobs replayed")
        for j1, j2 in zip(s1["jobs"], s2["jobs"]):
            for k in FIGURES:
                check(j1.get(k) == j2.get(k), f"{backend}: job {j1['job']} {k} differs between --jobs 1 and 2")
        # Per-stage sums equal the totals; the end to end follows its formula.
        for key in ("jobs", "queries", "cycles", "energy_pj", "cpu_search_seconds", "modeled_search_seconds",
                    "modeled_host_seconds"):
            total = sum(s[key] for s in s1["stages"].values())
            check(abs(total - s1["total"][key]) <= 1e-9 * max(1.0, abs(total)), f"{backend}: stages' {key} != total")
            per_job = sum(j["cycles"] if key == "cycles" else 0 for j in s1["jobs"])
            if key == "cycles":
                check(per_job == s1["total"]["cycles"], f"{backend}: jobs' cycles != total")
        e = s1["end_to_end"]
        want = e["cpu_seconds"] - e["cpu_kdtree_search_seconds"] + e["accelerator_kdtree_seconds"]
        check(abs(e["accelerated_seconds"] - want) < 1e-9, f"{backend}: end to end {e['accelerated_seconds']} != {want}")
        if backend == "exact":
            check(s1["total"].get("queries_differing_from_recorded", 0) == 0,
                  "exact: the accelerator's results differ from the recorded golden results")


def replay_errors(d, f, pair):
    """--trace-stages, flags that do not go with --trace, damaged and missing traces."""
    tr = os.path.join(d, "exact.trace")
    if not os.path.isfile(tr):                   # record_and_replay did not run first (-k)
        run(["register"] + pair + ["--record-trace", tr, "--out", os.path.join(d, "reg_errors")])
    run(["run", "--trace", tr, "--trace-stages", "normals,icp", "--out", os.path.join(d, "some")], 0, "MATCH")
    some = json.load(open(os.path.join(d, "some", "stats.json")))
    check(sorted(some["stages"]) == ["icp", "normals"], f"--trace-stages: stages {sorted(some['stages'])}")
    run(["run", "--trace", tr, "--trace-stages", "normal", "--out", os.path.join(d, "x")], 2, "'normal' is no stage")
    run(["run", "--trace", tr, "--cloud", f["room.ply"], "--out", os.path.join(d, "x")], 2, "--cloud does not go with --trace")
    run(["run", "--jobs", "2", "--out", os.path.join(d, "x")], 2, "--jobs goes with --trace")
    data = open(tr, "rb").read()
    for name, bad, needle in (("cut", data[: len(data) // 2], "truncated"),
                              ("foreign", b"GARBAGE!" + data[8:], "byte 0: not a Tigris workload trace"),
                              ("newer", data[:8] + bytes([9]) + data[9:], "version 9 is newer"),
                              ("flipped", data[:-10] + bytes([data[-10] ^ 0xFF]) + data[-9:], "corrupt")):
        p = os.path.join(d, name + ".trace")
        open(p, "wb").write(bad)
        run(["run", "--trace", p, "--out", os.path.join(d, "x")], 2, needle)
    run(["run", "--trace", os.path.join(d, "missing.trace"), "--out", os.path.join(d, "x")], 2, "missing.trace")


def in_the_loop(d, f, pair):
    """In the loop: exact on the accelerator gives the CPU's transform bit for bit; the modeled
    end to end follows its formula; configuration errors are clear."""
    regs = {}
    for search in ("exact", "accel", "accel-approx"):
        out = os.path.join(d, "loop_" + search)
        text = run(["register"] + pair + ["--search", search, "--out", out])
        regs[search] = json.load(open(os.path.join(out, "registration.json")))
        if search != "exact":
            check("on the accelerator" in text and "end to end" in text, f"{search}: no accelerator table")
    check(regs["accel"]["transform"] == regs["exact"]["transform"],
          "--search accel: the transform differs from --search exact")
    for search in ("accel", "accel-approx"):
        reg = regs[search]
        acc = reg["accelerator"]
        check(reg["search"] == search, f"{search}: search {reg['search']}")
        check(acc["jobs"] == len(acc["job_list"]) and acc["jobs"] > 0, f"{search}: {acc['jobs']} jobs")
        check(all(j["verdict"] == "match" for j in acc["job_list"]), f"{search}: a job did not match")
        staged = [s for s in reg["stages"].values() if "accelerator" in s]
        check(sum(s["accelerator"]["jobs"] for s in staged) == acc["jobs"], f"{search}: stage jobs != total")
        for name in ("normals", "icp"):
            st = reg["stages"][name]["accelerator"]
            check(st["fallback_searches"] == 0 and st["queries"] == reg["stages"][name]["queries"],
                  f"{search}: {name} searches not all batched: {st}")
        want = reg["seconds"] + sum(s["accelerator"]["modeled_kdtree_seconds"] - s["search_seconds"] for s in staged)
        check(abs(acc["modeled_end_to_end_seconds"] - want) < 1e-9,
              f"{search}: modeled end to end {acc['modeled_end_to_end_seconds']} != {want}")
        check(acc["modeled_kdtree_seconds"] < sum(s["search_seconds"] for s in staged),
              f"{search}: the modeled KD-tree time is not below the simulation's wall time")
    check(regs["accel-approx"]["stages"]["icp"]["accelerator"]["jobs"] > 0, "accel-approx: no ICP jobs")


def side_by_side(d, pair):
    """--compare: four runs, one table; flags that do not go with it; loop configuration errors."""
    cmp_out = os.path.join(d, "compare")
    gt = os.path.join(d, "room_gt.txt")  # room_b is the room moved by (-0.2, -0.1, 0)
    open(gt, "w").write("1 0 0 0.2\n0 1 0 0.1\n0 0 1 0\n0 0 0 1\n")
    # (--accel-set goes to the accelerator runs only; a folder tigris did not write, here with a
    # stale registration.json, is refused before any back-end runs)
    os.makedirs(os.path.join(cmp_out, "accel"))
    open(os.path.join(cmp_out, "accel", "registration.json"), "w").write('{"stale": true}')
    run(["register"] + pair + ["--compare", "--out", cmp_out], 2, "did not write (accel)")
    shutil.rmtree(cmp_out)
    text = run(["register"] + pair + ["--compare", "--ground-truth", gt, "--accel-set", "clock_mhz=1000",
                                      "--repeat", "2", "--out", cmp_out])
    c = json.load(open(os.path.join(cmp_out, "comparison.json")))
    check([r["back_end"] for r in c["rows"]] == ["flann", "exact", "accel", "accel-approx"],
          f"--compare: rows {[r['back_end'] for r in c['rows']]}")
    rows = {r["back_end"]: r for r in c["rows"]}
    acc_reg = json.load(open(os.path.join(cmp_out, "accel", "registration.json")))
    check(acc_reg.get("accelerator", {}).get("config", {}).get("clock_mhz") == 1000,
          "--compare: --accel-set did not reach the accelerator run")
    check(rows["accel"]["transform"] == rows["exact"]["transform"], "--compare: accel and exact transforms differ")
    check(rows["flann"]["kdtree_energy_pj"] is None and rows["accel"]["kdtree_energy_pj"] > 0,
          "--compare: energy only for the accelerator rows")
    check(abs(rows["flann"]["kdtree_speedup_vs_flann"] - 1.0) < 1e-12, "--compare: FLANN is not the baseline")
    # --repeat 2: the CPU rows are timed twice (medians, min, max), the modeled rows once.
    check(c["repeat"] == 2 and [r["runs"] for r in c["rows"]] == [2, 2, 1, 1],
          f"--compare --repeat 2: runs {[r['runs'] for r in c['rows']]}")
    check(c["runs"]["flann"] == [os.path.join(cmp_out, "flann", "registration.json"),
                                 os.path.join(cmp_out, "flann-repeat-2", "registration.json")],
          f"--compare: the flann runs are {c['runs']['flann']}")
    for r in c["rows"]:
        sp = r["kdtree_seconds_spread"]
        check(len(sp["samples"]) == r["runs"] and sp["min"] <= sp["median"] <= sp["max"]
              and sp["median"] == r["kdtree_seconds"] and abs(sp["median"] - sum(sp["samples"]) / len(sp["samples"])) < 1e-9,
              f"--compare: {r['back_end']}'s spread {sp}")
    fl, ac = rows["flann"]["kdtree_seconds_spread"], rows["accel"]["kdtree_seconds_spread"]
    rng = rows["accel"]["kdtree_speedup_vs_flann_range"]
    check(abs(rng["min"] - fl["min"] / ac["max"]) < 1e-9 * rng["min"] and abs(rng["max"] - fl["max"] / ac["min"]) < 1e-9 * rng["max"],
          f"--compare: the accelerator's speed-up range {rng} is not FLANN's min and max over its time {ac}")
    check(set(c["machine"]) >= {"cpu_model", "cores", "commit", "load_average_before", "load_average_after"},
          f"--compare: the machine record is {c['machine']}")
    check("machine:" in text and "of 2 runs" in text, "--compare: the table does not name the machine and runs")
    check(all(r["error"] is not None for r in c["rows"]), "--compare: an error column is missing")
    check("accelerator, approximate" in text and "comparison.json" in text, "--compare: no table printed")
    x = os.path.join(d, "x")
    run(["register"] + pair + ["--compare", "--search", "exact", "--out", x], 2, "--search does not go with --compare")
    run(["register"] + pair + ["--repeat", "3", "--out", x], 2, "--repeat goes with --compare")
    run(["register"] + pair + ["--compare", "--repeat", "0", "--out", x], 2, "--repeat")
    run(["register"] + pair + ["--search", "accel", "--accel-set", "sram.points.bytes=1024", "--out", x], 2,
        "does not fit the accelerator")
    run(["register"] + pair + ["--search", "accel", "--accel-set", "bogus.key=1", "--out", x], 2, "bogus.key")
    run(["register"] + pair + ["--accel-set", "sram.points.bytes=1024", "--out", x], 2, "needs --search accel")
    run(["register"] + pair + ["--search", "accel", "--record-trace", os.path.join(d, "y.trace"), "--out", x], 2,
        "--record-trace records the CPU's searches")


@pytest.fixture(scope="module")
def scene(tigris, tmp_path_factory):
    """(folder, the room scene's files, register's --source/--target flags)."""
    CHECKS.tigris = tigris
    d = str(tmp_path_factory.mktemp("trace"))
    f = {}
    make_register_files(d, f)
    return d, f, ["--source", f["room_b.ply"], "--target", f["room.ply"]]


def holds(part, *args):
    """Runs a part of checks; fails naming every check that did not hold."""
    part(*args)
    CHECKS.verify()


def test_record_and_replay(scene):
    holds(record_and_replay, scene[0], scene[2])


def test_replay_errors(scene):
    holds(replay_errors, *scene)


def test_in_the_loop(scene):
    holds(in_the_loop, *scene)


def test_side_by_side(scene):
    holds(side_by_side, scene[0], scene[2])


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
