#!/usr/bin/python3
"""The odometry benchmark: odometry over a synthetic drive with each preset and back-end.

    bench/bench_odometry.py [--tigris PATH] [--frames 300] [--seed 1] [--jobs 2]
                            [--presets dp4,dp7] [--searches flann,exact,approx,accel]
                            [--repeat 3] [--table-only] --out DIR

Writes the drive once (DIR/sequence, `tigris synth`), then runs `tigris odometry --sequence
DIR/sequence --preset P --search S --jobs N --out DIR/P_S` for each pair of preset and back-end
that has no metrics.json yet (a rerun resumes), timing each run's wall clock (DIR/P_S/wall.txt).
The CPU back-ends (flann, exact, approx) run --repeat times, interleaved (DIR/P_S-repeat-K), and
their times are printed as median [min-max]; the accelerator's modeled times run once.
Then prints one table from the metrics.json files: KITTI errors, ATE, mean RPE, CPU seconds and
KD-tree share, wall time; for the accelerator the modeled KD-tree and end-to-end seconds, the
KD-tree energy, and the reduction against FLANN of the same preset. --table-only prints the table
of what DIR holds (also runs made by hand, e.g. over Slurm, in DIR/P_S).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def default_tigris():
    for p in (os.path.join(HERE, "..", "build", "testbench", "tigris"),):
        if os.path.exists(p):
            return os.path.abspath(p)
    return "tigris"


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def spread(xs, f):
    """median [min-max] of repeated timings; the value alone for one."""
    if len(xs) < 2:
        return f % xs[0] if xs else "-"
    return f"{f % statistics.median(xs)} [{f % min(xs)}-{f % max(xs)}]"


def machine():
    """The CPU, cores and load average the timings were taken on."""
    model = "unknown"
    try:
        model = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{model}, {os.cpu_count()} cores, 1-minute load now {load:.2f}"


def fmt(x, f):
    return "-" if x is None else f % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tigris", default=default_tigris())
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--presets", default="dp4,dp7")
    ap.add_argument("--searches", default="flann,exact,approx,accel")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each CPU back-end (median [min-max])")
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    presets, searches = a.presets.split(","), a.searches.split(",")
    if a.repeat < 1:
        sys.exit("bench_odometry: --repeat must be at least 1")

    def folders(p, s):
        n = 1 if s.startswith("accel") else a.repeat
        return [os.path.join(a.out, f"{p}_{s}" + ("" if k == 1 else f"-repeat-{k}")) for k in range(1, n + 1)]
    seq = os.path.join(a.out, "sequence")
    if not a.table_only:
        subprocess.run([a.tigris, "synth", "--frames", str(a.frames), "--seed", str(a.seed), "--jobs", str(a.jobs),
                        "--out", seq], check=True)
        todo = [(k, p, s, out) for p in presets for s in searches for k, out in enumerate(folders(p, s))]
        for k, p, s, out in sorted(todo):  # repeat 1 of every run first: interleaved
            if os.path.exists(os.path.join(out, "metrics.json")):
                continue
            t0 = time.monotonic()
            r = subprocess.run([a.tigris, "odometry", "--sequence", seq, "--preset", p, "--search", s,
                                "--jobs", str(a.jobs), "--out", out])
            if r.returncode not in (0, 1):
                sys.exit(f"bench_odometry: {p} {s} failed (exit {r.returncode})")
            with open(os.path.join(out, "wall.txt"), "w") as f:
                f.write(f"{time.monotonic() - t0:.1f} s with --jobs {a.jobs}\n")

    print("| run | pairs | t_err % | r_err deg/m | ATE m (aligned) | ATE m (unaligned) | mean RPE m / deg | "
          "CPU s (sum; median [min-max] of the runs) | KD-tree share | wall |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = {}
    for p in presets:
        for s in searches:
            out = os.path.join(a.out, f"{p}_{s}")
            m = load(os.path.join(out, "metrics.json"))
            if not m:
                continue
            rows[(p, s)] = m
            reps = [x for x in (load(os.path.join(f, "metrics.json")) for f in folders(p, s)) if x]
            m["_kd"] = [x["totals"]["kdtree_search_seconds"] for x in reps]
            m["_e2e"] = [x["totals"]["seconds"] for x in reps]
            k, ate, rpe, tot = m.get("kitti") or {}, m.get("ate") or {}, m.get("rpe") or {}, m.get("totals") or {}
            wall = open(os.path.join(out, "wall.txt")).read().strip() if os.path.exists(os.path.join(out, "wall.txt")) else "-"
            print(f"| {p} {s} | {m['pairs']} | {fmt(k.get('t_err_percent'), '%.3f')} | "
                  f"{fmt(k.get('r_err_deg_per_m'), '%.5f')} | {fmt(ate.get('rmse_m'), '%.3f')} | "
                  f"{fmt(ate.get('unaligned_rmse_m'), '%.3f')} | {fmt(rpe.get('mean_translation_m'), '%.4f')} / "
                  f"{fmt(rpe.get('mean_rotation_deg'), '%.4f')} | {spread(m['_e2e'], '%.0f')} | "
                  f"{fmt(100 * tot['kdtree_share'] if 'kdtree_share' in tot else None, '%.1f%%')} | {wall} |")
    print()
    print("| preset | FLANN: KD-tree s / end to end s | accelerator (modeled): KD-tree s / end to end s | "
          "KD-tree speed-up | end-to-end reduction | KD-tree energy |")
    print("|---|---|---|---|---|---|")
    for p in presets:
        f, x = rows.get((p, "flann")), rows.get((p, "accel"))
        if not f or not x:
            continue
        fk, fe = f["_kd"], f["_e2e"]
        acc = x["accelerator"]
        ak, ae = acc["modeled_kdtree_seconds"], acc["modeled_end_to_end_seconds"]
        print(f"| {p} | {spread(fk, '%.1f')} / {spread(fe, '%.1f')} | {ak:.2f} / {ae:.1f} | "
              f"{statistics.median(fk) / ak:.0f}x [{min(fk) / ak:.0f}-{max(fk) / ak:.0f}] | "
              f"{100 * (1 - ae / statistics.median(fe)):.1f}% [{100 * (1 - ae / min(fe)):.1f}, {100 * (1 - ae / max(fe)):.1f}] | "
              f"{acc['kdtree_energy_pj'] * 1e-12:.2f} J |")
    print(f"\n(FLANN: median [min-max] of its runs; machine: {machine()})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
