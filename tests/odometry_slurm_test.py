#!/usr/bin/env python3
"""`tigris odometry --slurm` on a real one-node cluster (scripts/local_slurm.sh): the
pairs of a 5-frame synthetic drive as one job array (chunks of 2) chain the same poses and give
the same metrics as local processes; --no-wait returns the job id and a rerun collects; sbatch's
own error is shown, exit 2. Skips (ctest: exit 77) with the reason when the cluster cannot start (not
root and no sudo, no packages), unless TIGRIS_REQUIRE_SLURM=1. The cluster is stopped by PID
whatever happens.

Usage: python3 -m pytest tests/odometry_slurm_test.py --tigris PATH
"""
import json
import os
import subprocess
import sys
import time

import pytest


def check(cond, what):
    assert cond, what


def test_odometry_on_slurm(tigris, slurm_cluster):
    env, d = slurm_cluster

    def run(args, code=0, needle=None):
        p = subprocess.run([tigris] + args, capture_output=True, text=True, timeout=900, env=env)
        out = p.stdout + p.stderr
        assert p.returncode == code and (not needle or needle in out), (
            f"tigris {' '.join(args)}: exit {p.returncode} (want {code})" + (f", no {needle!r}" if needle else "")
            + "\n    " + out.strip()[-1500:].replace("\n", "\n    "))
        return out

    local, array, nowait = (os.path.join(d, n) for n in ("local", "array", "nowait"))
    base = ["odometry", "--synthetic", "5"]
    run(base + ["--jobs", "2", "--out", local])
    text = run(base + ["--slurm", "--chunk", "2", "--time", "10", "--out", array], 0, "2 task(s) for 4 command(s)")
    check("Slurm job" in text and "4/4 pairs" in text, f"no progress from the array:\n{text}")
    logs = [f for f in os.listdir(os.path.join(array, "slurm")) if f.endswith(".out")]
    check(len(logs) == 2, f"task logs {logs}")

    def same(x, y):
        px, py = (open(os.path.join(f, "poses.txt")).read() for f in (x, y))
        check(px == py, f"{y}/poses.txt differs from the local run's")
        mx, my = (json.load(open(os.path.join(f, "metrics.json"))) for f in (x, y))
        for key in ("ate", "rpe", "kitti"):
            check(mx[key] == my[key], f"{y}: metrics {key} {my[key]} != local {mx[key]}")

    same(local, array)
    run(base + ["--slurm", "--out", array], 0, "4 already in")  # a rerun submits nothing

    out = run(base + ["--slurm", "--no-wait", "--out", nowait], 0, "rerun the same command")
    job = out.split()[1] if out.startswith("job ") else ""
    check(job.isdigit(), f"--no-wait printed no job id: {out}")
    t0 = time.monotonic()
    while subprocess.run(["squeue", "-h", "-j", job, "-o", "%i"], capture_output=True, text=True,
                         env=env).stdout.strip():
        check(time.monotonic() - t0 < 600, "the --no-wait array did not finish in 10 min")
        time.sleep(1.0)
    run(base + ["--slurm", "--no-wait", "--out", nowait], 0, "4 already in")
    same(local, nowait)

    run(base + ["--slurm", "--partition", "no-such-partition", "--out", os.path.join(d, "bad")], 3, "sbatch failed")
    run(base + ["--chunk", "2", "--out", os.path.join(d, "bad2")], 2, "--slurm")


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
