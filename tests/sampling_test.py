#!/usr/bin/python3
"""Sampled simulation from the command line (docs/sampling.md): a sampled run against the full
run of the same job, what auto declines and why, what refuses sampling, and what reports say.

    python3 -m pytest tests/sampling_test.py --tigris build/bin/tigris
"""
import json
import os
import subprocess
import sys

import pytest

# 315 kNN k=51 slots in flight: the built-in job (115,110 queries) is long enough to sample.
SMALL = ["--mode", "knn", "--k", "51", "--set", "sram.results.bytes=262144"]


def check(ok, what):
    assert ok, what


def run(tig, out, *args, code=0):
    p = subprocess.run([tig, "run", "--out", out, *args], capture_output=True, text=True)
    assert p.returncode == code, f"tigris run {' '.join(args)}: exit {p.returncode}, wanted {code}\n{p.stderr[-800:]}"
    stats = None
    if code == 0 and os.path.exists(os.path.join(out, "stats.json")):
        with open(os.path.join(out, "stats.json")) as f:
            stats = json.load(f)
    return p, stats


@pytest.fixture(scope="module")
def d(tmp_path_factory):
    return str(tmp_path_factory.mktemp("sampling"))


def test_sampled_against_full(tigris, d):
    """A sampled run against the full run."""
    tig = tigris
    _, full = run(tig, os.path.join(d, "full"), *SMALL, "--dump-results", os.path.join(d, "full.csv"))
    p, samp = run(tig, os.path.join(d, "samp"), *SMALL, "--set", "sim.sampling=auto",
                  "--dump-results", os.path.join(d, "samp.csv"))
    sm = samp["sampling"]
    check(full["sampling"] == {"requested": "off", "sampled": False, "why": "sim.sampling is off",
                               "queries": full["queries"], "in_flight": 315, "simulated": full["queries"],
                               "checked": full["queries"],
                               "cycles_ci95": [full["cycles"]] * 2, "relative_half_width": 0.0},
          "a full run's sampling record: " + json.dumps(full["sampling"]))
    check(full["cycles_ci95"] == [full["cycles"]] * 2, "a full run's interval is its cycles")
    check(sm["sampled"] and sm["requested"] == "auto", "auto sampled the job: " + str(sm.get("why")))
    check(sm["in_flight"] == 315 and sm["warm_per_window"] == 315 and sm["measured_per_window"] == 315,
          f"auto's windows and warming are one in-flight generation: {sm}")
    check(sm["checked"] == sm["simulated"] < 0.3 * sm["queries"], f"simulated and checked {sm['simulated']}")
    check(samp["verdict"] == "match", "the sampled run matches the golden model")
    lo, hi = samp["cycles_ci95"]
    check(lo <= full["cycles"] <= hi, f"the full cycles {full['cycles']} lie in the interval [{lo}, {hi}]")
    check(abs(samp["cycles"] - full["cycles"]) <= 0.05 * full["cycles"],
          f"the estimate {samp['cycles']} is within 5% of {full['cycles']}")
    elo, ehi = sm["energy_pj_ci95"]
    check(elo <= full["energy_pj"]["total"] <= ehi, "the full energy lies in its interval")
    check(samp["visits"] == full["visits"], "the visits are the job's, every query counted")
    with open(os.path.join(d, "full.csv")) as a, open(os.path.join(d, "samp.csv")) as b:
        check(a.read() == b.read(), "every query's results are the full run's (simulated ones checked, the rest golden)")
    check("  sampled " in p.stdout and "estimates" in p.stdout and "cycles  ~" in p.stdout,
          "the summary says the figures are estimates:\n" + p.stdout)


def test_auto_simulates_in_full(tigris, d):
    """What auto simulates in full, and why."""
    tig = tigris
    _, paper = run(tig, os.path.join(d, "paper"), "--mode", "nn", "--set", "sim.sampling=auto")
    check(not paper["sampling"]["sampled"] and "too short to sample" in paper["sampling"]["why"],
          "the paper's machine holds 15,728 queries in flight: too short: " + paper["sampling"]["why"])
    p, approx = run(tig, os.path.join(d, "approx"), "--mode", "nn", "--approx-thd", "default",
                    "--set", "sram.query_stack.bytes=40960", "--set", "sim.sampling=auto")
    check(not approx["sampling"]["sampled"] and "approximate search" in approx["sampling"]["why"],
          "approximate search is simulated in full: " + approx["sampling"]["why"])
    check("sampled no: approximate search" in p.stdout, "the summary says why:\n" + p.stdout)


def test_refusals_and_bad_values(tigris, d):
    """What refuses sampling, and bad values."""
    tig = tigris
    p, _ = run(tig, os.path.join(d, "vcd"), *SMALL, "--set", "sim.sampling=auto", "--vcd",
               os.path.join(d, "w.vcd"), code=2)
    check("sim.sampling=off" in p.stderr, "waveforms need every query: " + p.stderr)
    p, _ = run(tig, os.path.join(d, "tl"), *SMALL, "--set", "sim.sampling=0.2", "--timeline",
               os.path.join(d, "t.json"), code=2)
    check("sim.sampling=off" in p.stderr, "a timeline needs every query: " + p.stderr)
    p, _ = run(tig, os.path.join(d, "sch"), *SMALL, "--set", "sim.sampling=0.2", "--dump-schedule",
               os.path.join(d, "s.csv"), code=2)
    check("sim.sampling=off" in p.stderr and not os.path.exists(os.path.join(d, "s.csv")),
          "a schedule needs every query (issue 54: it was written with a fifth of the rows): " + p.stderr)
    for bad in ("sim.sampling=2", "sim.sampling=maybe", "sim.windows=1"):
        p, _ = run(tig, os.path.join(d, "bad"), "--set", bad, code=2)
        check(bad.split("=")[0] in p.stderr, f"--set {bad} names the key: {p.stderr}")


def test_a_share(tigris, d):
    """A share."""
    tig = tigris
    _, share = run(tig, os.path.join(d, "share"), *SMALL, "--set", "sim.sampling=0.2")
    check(share["sampling"]["sampled"] and abs(share["sampling"]["simulated"] - 0.2 * share["queries"]) < 50,
          f"sim.sampling=0.2 simulates a fifth: {share['sampling']['simulated']} of {share['queries']}")


def test_without_warming(tigris, d):
    """Without warming: a window's end is the next one's start."""
    tig = tigris
    _, cold = run(tig, os.path.join(d, "cold"), *SMALL, "--set", "sim.sampling=auto", "--set", "sim.warm_queries=0")
    check(cold["sampling"]["sampled"] and cold["sampling"]["warm_per_window"] == 0 and cold["verdict"] == "match",
          f"sim.warm_queries=0 samples: {cold['sampling']}")


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
