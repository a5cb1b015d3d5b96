#!/usr/bin/python3
"""Sweep driver, local back-end: a 4-point grid with --jobs 2 gives a CSV of 4 rows with the
column contract; a failing point is recorded and the sweep goes on; collect reproduces the CSV."""
import json, os
from common import main, Workdir, options, read_csv, small_workload, sweep, write_spec

a = options()
SPEC = {"base": {"cloud": "cloud.bin", "queries": "queries.bin", "mode": "nn",
                 "set": {"be.issue_policy": "mqsn"}},
        "grid": {"fe.recursion_units": [16, 64], "height": [6, 8]}}


def test_four_points():
    with Workdir(a, "local") as d:
        small_workload(d)
        spec = write_spec(d, SPEC)
        out = os.path.join(d, "out")
        p = sweep(a, spec, "--out", out, "--jobs", "2", "--tigris", a.tigris, check=0)
        assert p.stderr.count(", match") == 4 and "[4/4]" in p.stderr, p.stderr
        cols, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert len(rows) == 4, rows
        # the column contract: point, swept keys, status, the headline figures, error,
        # wall_seconds, then the base settings and the rest
        assert cols[:5] == ["point", "fe.recursion_units", "height", "status", "cycles"], cols[:8]
        head = cols[cols.index("status") + 1:cols.index("error")]
        assert head[:4] == ["cycles", "seconds", "energy_pj.total", "power_w"], head
        assert "bottleneck.bound" in head and cols[cols.index("error") + 1] == "wall_seconds", cols[:30]
        for c in ("cloud", "queries", "mode", "be.issue_policy", "cycles", "seconds", "verdict",
                  "energy_pj.total", "power_w", "area_mm2.total", "visits.top", "visits.leaf_points",
                  "buffers.points.read_bytes", "units.recursion_units.utilization",
                  "wall_seconds.simulation", "stats.queries"):
            assert c in cols, f"no column {c}"
        assert not any(c.startswith("config.") for c in cols), "config leaves must be left out"
        assert not any("per_unit" in c or "mismatches.first" in c for c in cols), "lists must be left out"
        assert len(cols) == len(set(cols))
        want = [("16", "6"), ("16", "8"), ("64", "6"), ("64", "8")]        # grid order, first key outer
        assert [(r["fe.recursion_units"], r["height"]) for r in rows] == want, rows
        assert [r["point"] for r in rows] == [f"fe.recursion_units={u},height={h}" for u, h in want]
        for r in rows:
            assert r["status"] == "ok" and r["error"] == "" and r["verdict"] == "match", r
            assert int(r["cycles"]) > 0 and float(r["energy_pj.total"]) > 0 and float(r["wall_seconds"]) > 0
            assert int(r["stats.queries"]) == 800 and r["queries"] == "queries.bin" and r["cloud"] == "cloud.bin"
            assert r["mode"] == "nn" and r["be.issue_policy"] == "mqsn"
            assert int(r["units.recursion_units.count"]) == int(r["fe.recursion_units"])
            assert int(r["tree.top_height"]) == int(r["height"])
            pj = json.load(open(os.path.join(out, "points", r["point"], "point.json")))
            assert pj["finished"] and pj["exit_code"] == 0 and pj["status"] == "ok", pj
            assert "--out" in pj["command"] and pj["command_line"].startswith(a.tigris), pj
            assert {"stderr_tail", "wall_seconds", "started_at", "ended_at"} <= set(pj)
        # more RUs never make the walk slower here
        by = {(r["fe.recursion_units"], r["height"]): int(r["cycles"]) for r in rows}
        assert by[("64", "8")] <= by[("16", "8")], by
        # sweep.json: the same rows as objects, plus the spec
        sj = json.load(open(os.path.join(out, "sweep.json")))
        assert sj["columns"] == cols and sj["spec"] == SPEC and len(sj["rows"]) == 4
        assert sj["rows"][0]["cycles"] == int(rows[0]["cycles"]) and sj["swept_keys"] == ["fe.recursion_units", "height"]
        before = open(os.path.join(out, "sweep.csv")).read()
        os.remove(os.path.join(out, "sweep.csv"))
        sweep(a, "collect", out, check=0)
        assert open(os.path.join(out, "sweep.csv")).read() == before, "collect gives another CSV"


def test_failed_point_recorded():
    """A point tigris refuses at run time (height beyond the cloud's) is an error row; the others run."""
    with Workdir(a, "local") as d:
        small_workload(d, 300, 100)              # full height 9
        spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"},
                              "grid": {"height": [4, 12]}, "points": [{"fe.forwarding": False}]})
        out = os.path.join(d, "out")
        p = sweep(a, spec, "--out", out, "--jobs", "2", "--tigris", a.tigris, check=1)
        assert "ERROR" in p.stderr and "exceeds the full height" in p.stderr, p.stderr
        cols, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["point"] for r in rows] == ["height=4", "height=12", "fe.forwarding=false"]
        assert cols[:5] == ["point", "height", "fe.forwarding", "status", "cycles"], cols
        assert cols[cols.index("error"):cols.index("error") + 3] == ["error", "wall_seconds", "cloud"], cols
        ok, bad, fwd = rows
        assert ok["status"] == "ok" and fwd["status"] == "ok" and bad["status"] == "error"
        assert "exceeds the full height" in bad["error"] and bad["cycles"] == "" and int(ok["cycles"]) > 0
        assert fwd["fe.forwarding"] == "false" and ok["fe.forwarding"] == "true"   # effective config
        assert fwd["height"] == "9"                                # default 10 clamped to the cloud's 9
        pj = json.load(open(os.path.join(out, "points", "height=12", "point.json")))
        assert pj["exit_code"] == 2 and not pj["finished"] and "exceeds" in pj["stderr_tail"]
        # a rerun retries only the failed point
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=1)
        assert "2 finished earlier" in p.stderr and "[1/1] height=12" in p.stderr, p.stderr


FAKE = """#!/bin/sh
# The real tigris, except: a run with --seed 7 then reports a golden mismatch (exit 1, verdict
# mismatch), one with --seed 8 is killed by SIGKILL.
"{real}" "$@"; rc=$?
out=; prev=
for x in "$@"; do [ "$prev" = --out ] && out=$x; prev=$x; done
[ "$rc" = 0 ] || exit $rc                 # the dry check and real errors pass through
case " $* " in
  *" --seed 7 "*) sed -i 's/"verdict": "match"/"verdict": "mismatch"/' "$out/stats.json"
                  echo "tigris run: 3 queries with other results, 0 with other visit counts; first:" >&2
                  exit 1 ;;
  *" --seed 8 "*) kill -KILL $$ ;;
esac
exit $rc
"""


def test_mismatch_and_signal():
    """A mismatching point (exit 1, verdict mismatch) is `mismatch` and finished; a killed one is
    `error`; the others are ok and the sweep exits 1."""
    with Workdir(a, "local") as d:
        small_workload(d, 300, 100)
        fake = os.path.join(d, "fake-tigris")
        with open(fake, "w") as f:
            f.write(FAKE.format(real=a.tigris))
        os.chmod(fake, 0o755)
        spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"}, "grid": {"seed": [6, 7, 8]}})
        out = os.path.join(d, "out")
        p = sweep(a, spec, "--out", out, "--tigris", fake, check=1)
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        st = {r["point"]: (r["status"], r["error"], r["verdict"]) for r in rows}
        assert st["seed=6"] == ("ok", "", "match"), st
        assert st["seed=7"] == ("mismatch", "tigris run: 3 queries with other results, 0 with other visit "
                                "counts; first:", "mismatch"), st
        assert st["seed=8"][0] == "error" and "SIGKILL" in st["seed=8"][1], st
        assert "MISMATCH" in p.stderr and "ERROR: killed by signal SIGKILL" in p.stderr, p.stderr
        # a mismatch is a result (finished), a killed point is not: only seed 8 runs again
        p = sweep(a, spec, "--out", out, "--tigris", fake, check=1)
        assert "2 finished earlier" in p.stderr and "[1/1] seed=8" in p.stderr, p.stderr


def test_ref_points_and_switches():
    """`"command": "ref"` sweeps the golden model; a switch flag (`redundancy`) is true or false
    and only true passes it."""
    with Workdir(a, "local") as d:
        small_workload(d, 2000, 300)
        spec = write_spec(d, {"command": "ref", "base": {"cloud": "cloud.bin", "queries": "queries.bin", "height": 5},
                              "grid": {"mode": ["nn", "radius"], "redundancy": [True, False]}})
        out = os.path.join(d, "out")
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        assert p.stderr.count(", done") == 4, p.stderr
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["status"] for r in rows] == ["ok"] * 4, rows
        for r in rows:
            has = r.get("redundancy.authors.ratio", "") != ""
            assert has == (r["redundancy"] == "true"), r
            assert ("--redundancy" in r["command_line"]) == has, r["command_line"]
        bad = write_spec(d, {"command": "ref", "base": {"cloud": "cloud.bin", "redundancy": "yes"}})
        p = sweep(a, bad, "--out", os.path.join(d, "bad"), "--tigris", a.tigris, check=2)
        assert "is a switch: true or false" in p.stderr, p.stderr


if __name__ == "__main__":
    main(__file__)
