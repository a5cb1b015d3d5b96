#!/usr/bin/env python3
"""`tigris odometry` through the command line: a four-frame KITTI-layout sequence of a
room scene with exact poses (no calib.txt: the axis swap), registered pair by pair; poses.txt,
pairs.csv and metrics.json written, the chained poses near the truth, a short trajectory
reported without KITTI metrics (null, not 0), the plots drawn, --jobs 2 equal to --jobs 1, a
rerun resuming, other settings into the same folder refused, a ground truth of equal steps
flagged, a missing scan and a short poses.txt refused, --compare's four runs and table. Then `tigris synth` (KITTI layout, a rerun
completing a missing scan with the same bytes, another drive into the folder refused) and
`tigris odometry --synthetic 12` registering within the tolerances measured for it.

Run: python3 -m pytest tests/odometry_cli_test.py --tigris PATH [-k sequence|synthetic] (ctest
runs the two tests as odometry_cli and odometry_synthetic). Each test reports every check that
failed, not only the first.
"""
import csv
import json
import math
import os
import random
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_inputs import room_points  # noqa: E402
from support import Checks  # noqa: E402

import pytest  # noqa: E402

AXIS = [[0, -1, 0, 0], [0, 0, -1, 0], [1, 0, 0, 0], [0, 0, 0, 1]]  # p_cam = A p_velo


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def inv(t):  # rigid
    r = [[t[j][i] for j in range(3)] for i in range(3)]
    p = [-sum(r[i][k] * t[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [p[0]], r[1] + [p[1]], r[2] + [p[2]], [0, 0, 0, 1]]


def pose(x, y, yaw_deg):
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return [[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, 0], [0, 0, 0, 1]]


def make_sequence(d, frames=4):
    room = room_points(random.Random(20))
    os.makedirs(os.path.join(d, "velodyne"))
    poses = [pose(0.2 * i, 0.05 * i, 1.0 * i) for i in range(frames)]  # Velodyne i in frame 0
    with open(os.path.join(d, "poses.txt"), "w") as f:
        for p in poses:
            cam = mul(mul(AXIS, p), inv(AXIS))
            f.write(" ".join("%.17g" % cam[r][c] for r in range(3) for c in range(4)) + "\n")
    for i, p in enumerate(poses):
        q = inv(p)
        with open(os.path.join(d, "velodyne", "%06d.bin" % i), "wb") as f:
            for x, y, z in room:
                v = [sum(q[r][k] * w for k, w in enumerate((x, y, z, 1))) for r in range(3)]
                f.write(struct.pack("<4f", v[0], v[1], v[2], 0.0))
    return poses


def synthetic_checks(d, run, check, a_tigris):
    s = os.path.join(d, "drive")
    run(["synth", "--frames", "3", "--out", s], 0, "velodyne/000000.bin .. 000002.bin")
    names = sorted(os.listdir(os.path.join(s, "velodyne")))
    check(names == ["000000.bin", "000001.bin", "000002.bin"], f"velodyne/ holds {names}")
    poses = [l.split() for l in open(os.path.join(s, "poses.txt")) if l.strip()]
    check(len(poses) == 3 and all(len(p) == 12 for p in poses), "synth poses.txt")
    check(float(poses[0][0]) == 1.0 and float(poses[0][11]) == 0.0, f"frame 0 is not the origin: {poses[0]}")
    calib = open(os.path.join(s, "calib.txt")).read()
    check("Tr:" in calib and "P0:" in calib, "calib.txt lacks Tr or P0")
    drive = json.load(open(os.path.join(s, "drive.json")))
    check(drive["settings"]["seed"] == 1 and len(drive["frames"]) == 3, "drive.json")
    scan = os.path.join(s, "velodyne", "000001.bin")
    before = open(scan, "rb").read()
    check(len(before) % 16 == 0 and len(before) > 16 * 80000, f"scan 1 has {len(before)} bytes")
    os.remove(scan)
    run(["synth", "--frames", "3", "--out", s], 0, "(1 scans cast now)")
    check(open(scan, "rb").read() == before, "a completed drive has another scan 1")
    # Interrupted while casting: the rerun completes the drive (the folder was claimed first).
    cut = os.path.join(d, "cut")
    p = subprocess.Popen([a_tigris, "synth", "--frames", "60", "--jobs", "1", "--out", cut],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t0 = time.monotonic()
    while len(os.listdir(os.path.join(cut, "velodyne")) if os.path.isdir(os.path.join(cut, "velodyne")) else []) < 3:
        if time.monotonic() - t0 > 60 or p.poll() is not None:
            break
        time.sleep(0.01)
    p.kill()
    p.wait()
    made = len([f for f in os.listdir(os.path.join(cut, "velodyne")) if f.endswith(".bin")])
    check(0 < made < 60, f"the interrupted synth wrote {made} scans")
    run(["synth", "--frames", "60", "--out", cut], 0, f"({60 - made} scans cast now)")
    check(json.load(open(os.path.join(cut, "drive.json")))["complete"] is True, "the completed drive is not complete")
    check(sorted(os.listdir(os.path.join(cut, "velodyne"))) == ["%06d.bin" % i for i in range(60)],
          "the completed drive's velodyne/ holds other files")
    check(open(os.path.join(cut, "velodyne", "000001.bin"), "rb").read() == before, "scan 1 differs between drives")
    run(["synth", "--frames", "3", "--seed", "2", "--out", s], 2, "settings.seed: 1 -> 2")
    run(["synth", "--frames", "1", "--out", os.path.join(d, "x")], 2, "--frames")
    run(["synth", "--frames", "abc", "--out", os.path.join(d, "x")], 2, "--frames")
    run(["synth", "--frames", "3", "--seed", "-1", "--out", os.path.join(d, "x")], 2, "--seed")
    run(["synth", "--frames", "3", "--seed", "18446744073709551616", "--out", os.path.join(d, "x")], 2, "--seed")
    broken = os.path.join(d, "broken")
    os.makedirs(broken)
    open(os.path.join(broken, "drive.json"), "w").write("{\"settings\": ")
    run(["synth", "--frames", "3", "--out", broken], 2, "tigris synth did not write (drive.json)")
    kitti = os.path.join(d, "kitti")
    os.makedirs(kitti)
    open(os.path.join(kitti, "poses.txt"), "w").write("1 0 0 0 0 1 0 0 0 0 1 0\n")
    run(["synth", "--frames", "3", "--out", kitti], 2, "tigris synth did not write")
    check(open(os.path.join(kitti, "poses.txt")).read().count("\n") == 1, "synth overwrote a KITTI poses.txt")
    x = os.path.join(d, "x")
    run(["odometry", "--synthetic", "3", "--slurm", "--out", x], 3, "sbatch not found",
        env=dict(os.environ, PATH="/nonexistent"))
    run(["odometry", "--synthetic", "3", "--compare", "--search", "exact", "--out", x], 2, "does not go with --compare")
    run(["odometry", "--synthetic", "3", "--chunk", "2", "--out", x], 2, "--slurm")
    run(["odometry", "--sequence", s, "--seed", "2", "--out", x], 2, "--synthetic")
    # 12 frames (11 pairs, 14 m) with DP4 and the exact search. Measured (seed 1): pair RPE at
    # most 0.0145 m and 0.065 deg, mean 0.0052 m and 0.046 deg; ATE unaligned max 0.020 m.
    o = os.path.join(d, "odo")
    text = run(["odometry", "--synthetic", "12", "--jobs", "2", "--out", o], 0, "KITTI metrics: none")
    m = json.load(open(os.path.join(o, "metrics.json")))
    check(m["pairs"] == 11 and m["not_converged_pairs"] == 0, f"pairs {m['pairs']}, {m['not_converged_pairs']} not converged")
    check("exact" in m["ground_truth_source"] and "ground_truth_warning" not in m and "may measure" not in text,
          "a synthetic drive's exact poses are flagged as KITTI's equal steps")
    rows = list(csv.DictReader(open(os.path.join(o, "pairs.csv"))))
    worst_t = max(float(r["rpe_translation_m"]) for r in rows)
    worst_r = max(float(r["rpe_rotation_deg"]) for r in rows)
    check(worst_t < 0.04 and worst_r < 0.15, f"worst pair {worst_t:.4f} m, {worst_r:.4f} deg")
    check(m["rpe"]["mean_translation_m"] < 0.012 and m["rpe"]["mean_rotation_deg"] < 0.1, f"rpe {m['rpe']}")
    check(m["ate"]["unaligned_max_m"] < 0.06, f"ate {m['ate']}")
    run(["odometry", "--synthetic", "12", "--seed", "3", "--out", o], 2, "settings.seed: 1 -> 3")
    run(["odometry", "--synthetic", "12", "--sequence", s, "--out", o], 2, "excludes")
    run(["odometry", "--out", os.path.join(d, "x")], 2, "give --sequence DIR")


def sequence_checks(d, run, check):
    seq = os.path.join(d, "seq")
    make_sequence(seq)
    o1, o2 = os.path.join(d, "o1"), os.path.join(d, "o2")
    text = run(["odometry", "--sequence", seq, "--out", o1], 0, "KITTI metrics: none")
    check("axis swap" in open(os.path.join(o1, "metrics.json")).read(), "the calibration is not named")
    m = json.load(open(os.path.join(o1, "metrics.json")))
    check(m["pairs"] == 3, f"pairs {m['pairs']}")
    icp = m["stages"]["icp"]["per_pair_mean"]
    check(icp["searches"] > 0 and icp["kdtree_search_seconds"] > 0, f"icp stage means {icp}")
    for png in ("trajectory.png", "errors.png"):
        check(os.path.isfile(os.path.join(o1, png)), f"no {png}")
    check(m["kitti"]["too_short"] and m["kitti"]["t_err_percent"] is None, f"kitti {m['kitti']}")
    check(m["rpe"]["mean_translation_m"] < 0.02 and m["rpe"]["mean_rotation_deg"] < 0.2, f"rpe {m['rpe']}")
    check(m["ate"]["unaligned_max_m"] < 0.05, f"ate {m['ate']}")
    lines = open(os.path.join(o1, "poses.txt")).read().split("\n")
    check(len([l for l in lines if l]) == 4 and all(len(l.split()) == 12 for l in lines if l), "poses.txt")
    rows = list(csv.DictReader(open(os.path.join(o1, "pairs.csv"))))
    check([r["target"] for r in rows] == ["0", "1", "2"] and all(r["status"] == "converged" for r in rows),
          f"pairs.csv {rows}")
    # Frame 3's pose from poses.txt against the truth: the camera pose's translation.
    last = [float(v) for v in lines[3].split()]
    truth = mul(mul(AXIS, pose(0.6, 0.15, 3.0)), inv(AXIS))
    err = math.dist((last[3], last[7], last[11]), (truth[0][3], truth[1][3], truth[2][3]))
    check(err < 0.05, f"frame 3 is {err:.3f} m off")
    run(["odometry", "--sequence", seq, "--jobs", "2", "--out", o2])
    check(open(os.path.join(o1, "poses.txt")).read() == open(os.path.join(o2, "poses.txt")).read(),
          "--jobs 2 chained other poses than --jobs 1")
    run(["odometry", "--sequence", seq, "--out", o1], 0, "3 already in")  # resumes
    # --compare: four runs of their own and one table; the accelerator run gets the CPU baseline.
    oc = os.path.join(d, "oc")
    text = run(["odometry", "--sequence", seq, "--compare", "--repeat", "2", "--jobs", "2", "--out", oc], 0,
               "accelerator, exact")
    c = json.load(open(os.path.join(oc, "comparison.json")))
    check([r["back_end"] for r in c["rows"]] == ["flann", "exact", "approx", "accel"], f"rows {c['rows']}")
    acc = c["rows"][3]
    check(acc["kdtree_energy_pj"] and acc["kdtree_speedup_vs_flann"] > 1.0, f"accel row {acc}")
    # --repeat 2: the CPU back-ends twice (OUT/<back-end>-repeat-2/), medians with min and max.
    check([r["runs"] for r in c["rows"]] == [2, 2, 2, 1] and c["repeat"] == 2, f"runs {[r['runs'] for r in c['rows']]}")
    check(os.path.exists(os.path.join(oc, "approx-repeat-2", "metrics.json")), "no approx-repeat-2/metrics.json")
    fl = c["rows"][0]["kdtree_seconds_spread"]
    check(len(fl["samples"]) == 2 and fl["min"] <= fl["median"] <= fl["max"], f"flann's spread {fl}")
    rng = acc["kdtree_speedup_vs_flann_range"]
    check(rng["min"] <= acc["kdtree_speedup_vs_flann"] <= rng["max"], f"the accelerator's speed-up range {rng}")
    check("commit" in c["machine"] and "machine:" in text, f"no machine in the comparison: {c.get('machine')}")
    run(["odometry", "--sequence", seq, "--repeat", "2", "--out", os.path.join(d, "x")], 2, "--repeat goes with --compare")
    # Exact back-ends register the room to ~0; approximate search (first_leaf, thd 1.2 m: a
    # follower takes its leader's neighbour, up to 1.2 m from it, in steps of 0.2 m) measured
    # 0.031 m per pair (every_leaf 0.017 m), so it gets its own bound.
    bound = {"flann": 0.02, "exact": 0.02, "approx": 0.05, "accel": 0.02}
    check(all(r["mean_rpe_translation_m"] < bound[r["back_end"]] for r in c["rows"]),
          f"a back-end registered badly: {[(r['back_end'], r['mean_rpe_translation_m']) for r in c['rows']]}")
    am = json.load(open(os.path.join(oc, "accel", "metrics.json")))
    check(am["compared_with_cpu"]["flann_end_to_end_seconds"] == c["rows"][0]["end_to_end_seconds"],
          "accel/metrics.json lacks the FLANN baseline")
    check(open(os.path.join(oc, "exact", "poses.txt")).read() == open(os.path.join(o1, "poses.txt")).read(),
          "--compare's exact run chained other poses than the plain run")
    run(["odometry", "--sequence", seq, "--frames", "1:3", "--out", o1], 2, "holds a tigris odometry run with other settings or inputs")
    run(["odometry", "--sequence", seq, "--frames", "1:3", "--out", os.path.join(d, "o3")], 0, "frames 1..3")
    run(["odometry", "--sequence", seq, "--frames", "2:9", "--out", os.path.join(d, "x")], 2, "frames 0..3")
    run(["odometry", "--sequence", seq, "--frames", "2", "--out", os.path.join(d, "x")], 2, "--frames must be A:B")
    # Two more poses than scans, all steps equal (KITTI 00's first frames): both are said.
    with open(os.path.join(seq, "poses.txt"), "a") as f:
        for i in (4, 5):
            cam = mul(mul(AXIS, pose(0.2 * i, 0.05 * i, 1.0 * i)), inv(AXIS))
            f.write(" ".join("%.17g" % cam[r][c] for r in range(3) for c in range(4)) + "\n")
    text = run(["odometry", "--sequence", seq, "--out", os.path.join(d, "o4")], 0, "6 poses for 4 scans")
    check("first 5 steps are equal" in text and "may measure the ground truth" in text,
          "no warning for a ground truth of equal steps")
    check("ground_truth_warning" in json.load(open(os.path.join(d, "o4", "metrics.json"))),
          "metrics.json has no ground_truth_warning")
    # register scores a pair of those frames with the same warning.
    rg = os.path.join(d, "rg")
    text = run(["register", "--source", os.path.join(seq, "velodyne", "000001.bin"), "--target",
                os.path.join(seq, "velodyne", "000000.bin"), "--kitti-poses", os.path.join(seq, "poses.txt"),
                "--kitti-frames", "1,0", "--out", rg], 0, "error vs ground truth")
    check("warning: the ground truth's first 5 steps are equal" in text, f"register gave no warning: {text[-400:]}")
    check("equal" in json.load(open(os.path.join(rg, "registration.json")))["ground_truth"].get("warning", ""),
          "registration.json has no ground_truth.warning")
    os.rename(os.path.join(seq, "velodyne", "000002.bin"), os.path.join(d, "moved.bin"))
    run(["odometry", "--sequence", seq, "--out", os.path.join(d, "x")], 2, "000002.bin is missing")
    os.rename(os.path.join(d, "moved.bin"), os.path.join(seq, "velodyne", "000002.bin"))
    scan2 = os.path.join(seq, "velodyne", "000002.bin")
    whole = open(scan2, "rb").read()
    open(scan2, "wb").write(whole[:1000])  # truncated: the pair's register names the file
    run(["odometry", "--sequence", seq, "--out", os.path.join(d, "o5")], 2, "000002.bin: file size 1000 bytes")
    open(scan2, "wb").write(whole)
    with open(os.path.join(seq, "poses.txt")) as f:
        first = f.readline()
    with open(os.path.join(seq, "poses.txt"), "w") as f:
        f.write(first)
    run(["odometry", "--sequence", seq, "--out", os.path.join(d, "x")], 2, "1 poses for 4 scans")
    run(["odometry", "--sequence", seq, "--jobs", "0", "--out", os.path.join(d, "x")], 2, "--jobs")
    gt_before = open(os.path.join(seq, "poses.txt")).read()
    run(["odometry", "--sequence", seq, "--out", seq], 2, "poses.txt")
    check(open(os.path.join(seq, "poses.txt")).read() == gt_before, "--out onto the sequence changed its poses.txt")
    run(["odometry", "--sequence", os.path.join(d, "nothing"), "--out", os.path.join(d, "x")], 2, "no such folder")


def test_sequence(tigris, tmp_path):
    c = Checks(tigris)
    sequence_checks(str(tmp_path), c.run, c.check)
    c.verify()


def test_synthetic(tigris, tmp_path):
    c = Checks(tigris)
    synthetic_checks(str(tmp_path), c.run, c.check, tigris)
    c.verify()


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
