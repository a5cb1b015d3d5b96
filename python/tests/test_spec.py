#!/usr/bin/python3
"""Sweep driver: bad specs and arguments exit 2 with a message naming the key or path in the
spec, before any point runs and without making the sweep folder."""
import os
from common import main, Workdir, options, small_workload, sweep, write_spec

a = options()

# (spec, words the error must contain); the spec folder holds cloud.bin and queries.bin
BAD = [
    ({"bse": {}}, ["bse", "unknown top-level key"]),
    ([1, 2], ["must be a JSON object"]),
    ({"grid": {"fe.recursion_units": []}}, ['grid["fe.recursion_units"]', "empty list"]),
    ({"grid": {"fe.recursion_units": 16}}, ['grid["fe.recursion_units"]', "list"]),
    ({"grid": {"fe.recursion_unit": [16]}}, ["fe.recursion_unit", "unknown configuration key",
                                            "did you mean 'fe.recursion_units'"]),
    ({"grid": {"hieght": [8]}}, ['grid["hieght"]', "unknown run flag", "height"]),
    ({"base": {"set": {"fe.bypasing": False}}}, ['base.set["fe.bypasing"]', "fe.bypassing"]),
    ({"base": {"set": {"height": 8}}}, ['base.set["height"]', "run flag"]),
    ({"base": {"out": "x"}}, ['base["out"]', "cannot be set"]),
    ({"base": {"set": []}}, ["base.set", "must be an object"]),
    ({"base": []}, ["base", "must be an object"]),
    ({"points": {"height": 8}}, ["points", "list"]),
    ({"points": [{"fe.forwarding": [True]}]}, ['points[0]["fe.forwarding"]', "got a list"]),
    ({"points": [{"height": None}]}, ['points[0]["height"]', "null"]),
    ({"grid": {"height": [8, {"a": 1}]}}, ['grid["height"][1]', "object"]),
    ({"base": {"mode": True}}, ['base["mode"]', "boolean"]),
    ({"base": {"cloud": "missing.bin"}}, ['base["cloud"]', "no such file", "missing.bin"]),
    ({"grid": {"queries": ["queries.bin", "nope.bin"]}}, ['grid["queries"][1]', "nope.bin"]),
    ({"points": []}, ["points", "nothing to run"]),
    # Values only tigris knows are bad: found by the dry check, before any point runs.
    ({"grid": {"fe.recursion_units": [16, 0]}}, ["fe.recursion_units=0", "out of range",
                                                'grid["fe.recursion_units"]']),
    ({"base": {"set": {"be.issue_policy": "mqxx"}}, "grid": {"height": [6, 8]}},
     ["be.issue_policy", "mqxx", 'base.set["be.issue_policy"]']),
    ({"base": {"k": 5}, "grid": {"mode": ["nn", "knn"]}}, ["--k applies to --mode knn", 'base["k"]']),
    ({"points": [{"approx-thd": "abc"}]}, ["approx-thd", "abc", 'points[0]["approx-thd"]']),
    ({"grid": {"split_axis": ["widest", "diagonal"]}}, ["split-axis", "diagonal", "not in", 'grid["split_axis"]']),
]


def test_bad_specs():
    with Workdir(a, "spec") as d:
        small_workload(d, 200, 50)
        for i, (spec, words) in enumerate(BAD):
            path = write_spec(d, spec, f"bad{i}.json")
            out = os.path.join(d, f"out{i}")
            p = sweep(a, path, "--out", out, "--tigris", a.tigris, "--jobs", "2")
            msg = p.stderr
            assert p.returncode == 2, f"spec {spec}: exit {p.returncode}, expected 2\n{msg}"
            for w in words:
                assert w in msg, f"spec {spec}: the error does not name {w!r}:\n{msg}"
            assert "[1/" not in msg, f"spec {spec}: a point ran:\n{msg}"
            assert not os.path.exists(out), f"spec {spec}: {out} was made"


def test_bad_json():
    with Workdir(a, "spec") as d:
        bad = os.path.join(d, "bad.json")
        with open(bad, "w") as f:
            f.write('{"grid": {"height": [8, 10],}}\n')
        p = sweep(a, bad, "--out", os.path.join(d, "o"), "--tigris", a.tigris)
        assert p.returncode == 2 and "bad.json:1:" in p.stderr and "not valid JSON" in p.stderr, p.stderr
        with open(bad, "w") as f:
            f.write('{"grid": {"height": [8]}, "grid": {"height": [10]}}\n')
        p = sweep(a, bad, "--out", os.path.join(d, "o"), "--tigris", a.tigris)
        assert p.returncode == 2 and 'duplicate key "grid"' in p.stderr, p.stderr
        p = sweep(a, os.path.join(d, "none.json"), "--out", os.path.join(d, "o"), "--tigris", a.tigris)
        assert p.returncode == 2 and "none.json" in p.stderr, p.stderr


def test_bad_arguments():
    with Workdir(a, "spec") as d:
        spec = write_spec(d, {"grid": {"height": [8]}})
        o = os.path.join(d, "o")
        for args, words in ((["--chunk", "2"], ["--chunk", "--slurm"]),
                            (["--no-wait"], ["--no-wait", "--slurm"]),
                            (["--jobs", "0"], ["--jobs"]),
                            (["--slurm", "--chunk", "0"], ["--chunk"])):
            p = sweep(a, spec, "--out", o, "--tigris", a.tigris, *args)
            assert p.returncode == 2 and all(w in p.stderr for w in words), (args, p.stderr)
        p = sweep(a, spec, "--out", o, "--tigris", os.path.join(d, "no-tigris"))
        assert p.returncode == 2 and "no-tigris" in p.stderr, p.stderr
        p = sweep(a, "collect", d)
        assert p.returncode == 2 and "plan.json" in p.stderr, p.stderr
        assert not os.path.exists(o)


if __name__ == "__main__":
    main(__file__)
