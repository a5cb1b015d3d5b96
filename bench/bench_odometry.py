#!/usr/bin/python3
"""Issue 20's benchmark: odometry over a synthetic drive with each preset and back-end.

    bench/bench_odometry.py [--tigris PATH] [--frames 300] [--seed 1] [--jobs 2]
                            [--presets dp4,dp7] [--searches flann,exact,approx,accel]
                            [--table-only] --out DIR

Writes the drive once (DIR/sequence, `tigris synth`), then runs `tigris odometry --sequence
DIR/sequence --preset P --search S --jobs N --out DIR/P_S` for each pair of preset and back-end
that has no metrics.json yet (a rerun resumes), timing each run's wall clock (DIR/P_S/wall.txt).
Then prints one table from the metrics.json files: KITTI errors, ATE, mean RPE, CPU seconds and
KD-tree share, wall time; for the accelerator the modeled KD-tree and end-to-end seconds, the
KD-tree energy, and the reduction against FLANN of the same preset. --table-only prints the table
of what DIR holds (also runs made by hand, e.g. over Slurm, in DIR/P_S).
"""
import argparse
import json
import os
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
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    presets, searches = a.presets.split(","), a.searches.split(",")
    seq = os.path.join(a.out, "sequence")
    if not a.table_only:
        subprocess.run([a.tigris, "synth", "--frames", str(a.frames), "--seed", str(a.seed), "--jobs", str(a.jobs),
                        "--out", seq], check=True)
        for p in presets:
            for s in searches:
                out = os.path.join(a.out, f"{p}_{s}")
                if os.path.exists(os.path.join(out, "metrics.json")):
                    continue
                t0 = time.monotonic()
                r = subprocess.run([a.tigris, "odometry", "--sequence", seq, "--preset", p, "--search", s,
                                    "--jobs", str(a.jobs), "--out", out])
                if r.returncode not in (0, 1):
                    sys.exit(f"bench_odometry: {p} {s} failed (exit {r.returncode})")
                with open(os.path.join(out, "wall.txt"), "w") as f:
                    f.write(f"{time.monotonic() - t0:.1f} s with --jobs {a.jobs}\n")

    print(f"| run | pairs | t_err % | r_err deg/m | ATE m (aligned) | ATE m (unaligned) | mean RPE m / deg | "
          f"CPU s (sum) | KD-tree share | wall |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = {}
    for p in presets:
        for s in searches:
            out = os.path.join(a.out, f"{p}_{s}")
            m = load(os.path.join(out, "metrics.json"))
            if not m:
                continue
            rows[(p, s)] = m
            k, ate, rpe, tot = m.get("kitti") or {}, m.get("ate") or {}, m.get("rpe") or {}, m.get("totals") or {}
            wall = open(os.path.join(out, "wall.txt")).read().strip() if os.path.exists(os.path.join(out, "wall.txt")) else "-"
            print(f"| {p} {s} | {m['pairs']} | {fmt(k.get('t_err_percent'), '%.3f')} | "
                  f"{fmt(k.get('r_err_deg_per_m'), '%.5f')} | {fmt(ate.get('rmse_m'), '%.3f')} | "
                  f"{fmt(ate.get('unaligned_rmse_m'), '%.3f')} | {fmt(rpe.get('mean_translation_m'), '%.4f')} / "
                  f"{fmt(rpe.get('mean_rotation_deg'), '%.4f')} | {fmt(tot.get('seconds'), '%.0f')} | "
                  f"{fmt(100 * tot['kdtree_share'] if 'kdtree_share' in tot else None, '%.1f%%')} | {wall} |")
    print()
    print("| preset | FLANN: KD-tree s / end to end s | accelerator (modeled): KD-tree s / end to end s | "
          "KD-tree speed-up | end-to-end reduction | KD-tree energy |")
    print("|---|---|---|---|---|---|")
    for p in presets:
        f, x = rows.get((p, "flann")), rows.get((p, "accel"))
        if not f or not x:
            continue
        fk, fe = f["totals"]["kdtree_search_seconds"], f["totals"]["seconds"]
        acc = x["accelerator"]
        ak, ae = acc["modeled_kdtree_seconds"], acc["modeled_end_to_end_seconds"]
        print(f"| {p} | {fk:.1f} / {fe:.1f} | {ak:.2f} / {ae:.1f} | {fk / ak:.0f}x | {100 * (1 - ae / fe):.1f}% | "
              f"{acc['kdtree_energy_pj'] * 1e-12:.2f} J |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
