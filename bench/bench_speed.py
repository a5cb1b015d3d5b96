#!/usr/bin/env python3
"""Simulator speed against the golden model, side by side in one run (docs/performance.md).

For NN, kNN k=51 and radius 0.3 on the built-in pair and, when present, the KITTI pair (frame 1
searched in frame 0): the simulation's wall time (`tigris run`, stats.json
wall_seconds.simulation) over the golden model's search time on the same input and mode
(`tigris ref`, wall_seconds.search). And the accelerator in the loop against the golden model
on the CPU: `tigris register --search accel` over `--search exact`, whole commands (DP4, the
same pair). Each figure is the median [min-max] of --runs paired ratios; runs interleave every
binary and command, so a slow minute of a shared machine touches all alike.

Give --tigris more than once (NAME=PATH, or a path) to compare builds, e.g. before and after:

    bench/bench_speed.py --tigris before=/tmp/tigris-old --tigris after=build/bin/tigris --runs 5
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SEARCHES = [("NN", ["--mode", "nn"]), ("kNN k=51", ["--mode", "knn", "--k", "51"]),
            ("radius 0.3", ["--mode", "radius", "--radius", "0.3"])]


def run(cmd, out):
    t0 = time.monotonic()
    p = subprocess.run(cmd + ["--out", out], capture_output=True, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stdout[-1500:] + p.stderr[-1500:])
    path = os.path.join(out, "stats.json")
    stats = json.load(open(path)) if os.path.exists(path) else {}
    return stats, wall


def spread(xs):
    return f"{statistics.median(xs):.2f} [{min(xs):.2f}-{max(xs):.2f}]"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tigris", action="append", help="NAME=PATH or PATH (repeatable; default build/bin/tigris)")
    ap.add_argument("--kitti", default=os.path.join(HERE, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--no-register", action="store_true", help="skip the accelerator-in-the-loop rows")
    a = ap.parse_args()
    bins = []
    for t in a.tigris or [os.path.join(HERE, "..", "build", "bin", "tigris")]:
        name, _, path = t.rpartition("=")
        bins.append((name or os.path.basename(os.path.dirname(os.path.dirname(os.path.abspath(path)))), path))
    workloads = [("built-in", [], None)]
    k0, k1 = os.path.join(a.kitti, "000000.bin"), os.path.join(a.kitti, "000001.bin")
    if os.path.exists(k0) and os.path.exists(k1):
        workloads.append(("KITTI 00 1 in 0", ["--cloud", k0, "--queries", k1], ["--source", k1, "--target", k0]))
    else:
        print(f"(no KITTI pair in {a.kitti}: the built-in pair only)")
    tmp = tempfile.mkdtemp(prefix="bench_speed_")
    rows = {}  # (workload, what, binary) -> [ratio], plus seconds
    secs = {}
    for r in range(a.runs):
        print(f"run {r + 1}/{a.runs}", file=sys.stderr, flush=True)
        for wname, wargs, regargs in workloads:
            for sname, sargs in SEARCHES:
                for bname, path in bins:
                    ref, _ = run([path, "ref", *wargs, *sargs], os.path.join(tmp, "ref"))
                    sim, _ = run([path, "run", *wargs, *sargs], os.path.join(tmp, "run"))
                    g, s = ref["wall_seconds"]["search"], sim["wall_seconds"]["simulation"]
                    rows.setdefault((wname, sname, bname), []).append(s / g)
                    secs.setdefault((wname, sname, bname), []).append((s, g))
            if regargs is None or a.no_register:
                continue
            for bname, path in bins:
                _, ex = run([path, "register", *regargs, "--search", "exact"], os.path.join(tmp, "reg"))
                _, ac = run([path, "register", *regargs, "--search", "accel"], os.path.join(tmp, "reg"))
                rows.setdefault((wname, "DP4 registration", bname), []).append(ac / ex)
                secs.setdefault((wname, "DP4 registration", bname), []).append((ac, ex))
    print(f"\nmedian [min-max] of {a.runs} runs, interleaved; "
          f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f} at the end\n")
    print("| pair | search | build | simulation s | golden model s | simulation / golden |")
    print("|---|---|---|---:|---:|---:|")
    for (wname, sname, bname), ratios in rows.items():
        s = [x for x, _ in secs[(wname, sname, bname)]]
        g = [y for _, y in secs[(wname, sname, bname)]]
        if sname == "DP4 registration":
            sname = "DP4: `register --search accel` / `--search exact` (whole command)"
        print(f"| {wname} | {sname} | {bname} | {spread(s)} | {spread(g)} | **{spread(ratios)}x** |")


if __name__ == "__main__":
    main()
