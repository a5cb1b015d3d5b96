#!/usr/bin/python3
"""Sweep driver, Slurm back-end, on a real one-node cluster (scripts/local_slurm.sh): the same
sweep as one job array (chunks of points) gives the same CSV as the local back-end, wall times
aside; --no-wait returns at once and `collect` gathers the finished array; sbatch's errors are
shown. Skips (exit 77) with the reason when the cluster cannot start (not root and no sudo, no
packages), unless TIGRIS_REQUIRE_SLURM=1. The cluster is stopped by PID whatever happens."""
import os, re, subprocess, time
from common import main, options, read_csv, small_workload, sweep, tool_command, write_spec

a = options()
SPEC = {"base": {"cloud": "cloud.bin", "queries": "queries.bin", "set": {"be.issue_policy": "mqmn"}},
        "grid": {"fe.recursion_units": [16, 64], "height": [6, 8]},
        "points": [{"mode": "radius", "radius": 0.8}, {"height": 14}]}    # height 14: an error row


def same_csv(x, y):
    cx, rx = read_csv(x)
    cy, ry = read_csv(y)
    assert cx == cy, f"columns differ: {set(cx) ^ set(cy)}"
    assert len(rx) == len(ry) == 6
    for r, s in zip(rx, ry):
        diff = [c for c in cx if r[c] != s[c] and not c.startswith("wall_seconds")
                and c != "command_line"]  # each back-end's own --out
        assert not diff, f"{r['point']}: {[(c, r[c], s[c]) for c in diff]}"


def slurm_vs_local(env, d):
    small_workload(d)
    spec = write_spec(d, SPEC)
    local, array, nowait = (os.path.join(d, n) for n in ("local", "array", "nowait"))
    sweep(a, spec, "--out", local, "--jobs", "2", "--tigris", a.tigris, check=1)

    p = sweep(a, spec, "--out", array, "--slurm", "--chunk", "4", "--time", "5", "--mem", "300M",
              "--sbatch-arg", "--comment=tigris-sweep-test", "--tigris", a.tigris, check=1, env=env)
    assert "2 task(s) for 6 point(s)" in p.stderr and "[6/6]" in p.stderr, p.stderr
    same_csv(os.path.join(local, "sweep.csv"), os.path.join(array, "sweep.csv"))
    job = re.search(r"submitted Slurm job array (\S+):", p.stderr).group(1)
    logs = sorted(f for f in os.listdir(os.path.join(array, "slurm")) if f.endswith(".out"))
    assert logs == [f"{job}_0.out", f"{job}_1.out"], logs
    pj = open(os.path.join(array, "points", "fe.recursion_units=16,height=6", "point.json")).read()
    assert f'"array_job_id": "{job}"' in pj, pj        # really run by an array task
    ctl = subprocess.run(["scontrol", "show", "job", job], capture_output=True, text=True, env=env).stdout
    assert "Comment=tigris-sweep-test" in ctl, ctl       # the raw sbatch argument went through

    # rerun: nothing to submit
    p = sweep(a, spec, "--out", array, "--slurm", "--tigris", a.tigris, check=1, env=env)
    assert "5 finished earlier (skipped), 1 to run" in p.stderr, p.stderr     # the error row retries

    # --no-wait: returns the job id and the collect command; collect after the array ends
    p = sweep(a, spec, "--out", nowait, "--slurm", "--no-wait", "--tigris", a.tigris, check=0, env=env)
    assert p.stdout.startswith("job ") and " collect " in p.stdout, p.stdout
    job = p.stdout.split()[1]
    t0 = time.monotonic()
    while subprocess.run(["squeue", "-h", "-j", job, "-o", "%i"], capture_output=True, text=True,
                         env=env).stdout.strip():
        assert time.monotonic() - t0 < 120, "the --no-wait array did not finish"
        time.sleep(0.5)
    sweep(a, "collect", nowait, check=1, env=env)
    same_csv(os.path.join(local, "sweep.csv"), os.path.join(nowait, "sweep.csv"))

    # sbatch's own error is shown, exit 3
    p = sweep(a, spec, "--out", os.path.join(d, "bad"), "--slurm", "--partition", "no-such-partition",
              "--tigris", a.tigris, env=env)
    assert p.returncode == 3 and "sbatch failed" in p.stderr and "partition" in p.stderr, p.stderr


def dse_slurm_vs_local(env, d):
    """tigris pipeline-dse on Slurm: every point's errors, statuses and knobs equal the local run's
    (times are measurements, so the frontiers may differ by noise and are not compared)."""
    space = write_spec(d, {"base": {"preset": "dp4"}, "anchors": [],
                           "knobs": [{"key": "icp.max_iterations", "values": [2, 10]},
                                     {"key": "icp.error", "values": ["point_to_point", "point_to_plane"]}]},
                       "space.json")
    rows = {}
    for where, extra in (("local", ["--jobs", "2"]), ("array", ["--slurm", "--time", "10"])):
        out = os.path.join(d, f"dse-{where}")
        cmd, cenv = tool_command("pipeline-dse", "--space", space, "--samples", "3", "--pairs", "1",
                                 "--tigris", a.tigris, "--out", out, *extra, env=env)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=cenv)
        assert p.returncode == 0, p.stderr[-3000:]
        rows[where] = read_csv(os.path.join(out, "points.csv"))[1]
    assert "submitted Slurm job array" in p.stderr, p.stderr[-2000:]
    same = ("point", "status", "rpe_translation_m", "rpe_rotation_deg", "icp.max_iterations", "icp.error", "pairs")
    for r, s in zip(rows["local"], rows["array"]):
        assert {c: r[c] for c in same} == {c: s[c] for c in same}, (r, s)
    assert len(rows["local"]) == len(rows["array"]) == 3


def test_slurm_vs_local(slurm_cluster):
    slurm_vs_local(*slurm_cluster)


def test_pipeline_dse_slurm_vs_local(slurm_cluster):
    dse_slurm_vs_local(*slurm_cluster)


if __name__ == "__main__":
    main(__file__)
