#!/usr/bin/python3
"""Wall time of sampled against full simulation, and of the accelerator in the loop against the
CPU registration, measured side by side: each pair of commands run in turn N times (after one
warm-up each); prints each one's median [min-max] seconds and the median of the pairwise ratios.

  run kNN k=51, radius 0.3: `tigris run` with sim.sampling=off and =auto, on a KITTI pair (or the
                built-in pair), on the paper's machine and on one holding 512 queries in flight
                (sram.query_stack.bytes=40960), where jobs are long enough to sample
  register:     `tigris register --search exact` against `--search accel` (sampling auto) on the
                same pair, DP4

    bench/bench_sampling.py [--build build] [--kitti DIR] [--runs 3]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def timed(cmd):
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"bench_sampling: {' '.join(cmd)} failed:\n{p.stderr[-2000:]}")
    return time.monotonic() - t0


def side_by_side(name, a_name, a, b_name, b, runs):
    timed(a), timed(b)  # warm-up: page cache, binary
    ta, tb = [], []
    for _ in range(runs):
        ta.append(timed(a))
        tb.append(timed(b))
    ratio = statistics.median(x / y for x, y in zip(ta, tb))
    fmt = lambda t: f"{statistics.median(t):.2f} s [{min(t):.2f}-{max(t):.2f}]"
    print(f"{name:<44} {a_name} {fmt(ta):<24} {b_name} {fmt(tb):<24} ratio {ratio:.2f}x", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--kitti", default=os.path.join(ROOT, "..", "shared", "data", "kitti-00"))
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    tig = os.path.join(a.build, "bin", "tigris")
    tmp = tempfile.mkdtemp(prefix="bench-sampling-")
    frames = [os.path.join(a.kitti, f) for f in ("000000.bin", "000001.bin")]
    kitti = all(os.path.exists(f) for f in frames)
    pair = ["--cloud", frames[0], "--queries", frames[1]] if kitti else []
    print(f"workload: {'KITTI 00 frame 1 into frame 0' if kitti else 'the built-in pair'}; "
          f"{a.runs} runs each, in turn")
    for machine, sets in (("paper", []), ("512 in flight", ["--set", "sram.query_stack.bytes=40960"])):
        for case, args in (("kNN k=51", ["--mode", "knn", "--k", "51"]),
                           ("radius 0.3", ["--mode", "radius", "--radius", "0.3"])):
            base = [tig, "run", "--out", os.path.join(tmp, "run")] + pair + args + sets
            side_by_side(f"run {case}, {machine}: full / sampled", "full", base + ["--set", "sim.sampling=off"],
                         "auto", base + ["--set", "sim.sampling=auto"], a.runs)
    reg = [tig, "register", "--preset", "dp4", "--out", os.path.join(tmp, "reg")]
    if kitti:
        reg += ["--source", frames[1], "--target", frames[0]]
    side_by_side("register DP4: accel (auto) / exact", "accel", reg + ["--search", "accel"], "exact",
                 reg + ["--search", "exact"], a.runs)


if __name__ == "__main__":
    main()
