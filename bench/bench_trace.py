#!/usr/bin/python3
"""Whole registrations on the accelerator: for each workload and preset, runs
`tigris register --compare` (FLANN, golden model, accelerator in the loop exact and approximate),
records the
registration's trace with the golden model (exact and approximate) and times the same
registration with PCL's FLANN (the CPU baseline), replays each trace with --jobs 1 and --jobs 2,
and prints per stage: jobs, queries, recorded CPU KD-tree seconds, modeled seconds; and the
end-to-end reduction against the CPU with FLANN, exact against approximate, trace size and
replay wall times.

  bench/bench_trace.py [--tigris PATH] [--kitti DIR] [--presets dp4,dp7] [--out DIR]

The KITTI pair (frame 1 into frame 0) is used when DIR (default ../shared/data/kitti-00) exists.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0,):
        sys.exit(f"bench_trace: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr[-2000:]}")
    return time.time() - t0, p.stdout


def spread(sp, fmt):
    """median [min-max] of a comparison.json *_spread, the median alone for one sample."""
    if len(sp["samples"]) < 2:
        return fmt % sp["median"]
    return f"{fmt % sp['median']} [{fmt % sp['min']}-{fmt % sp['max']}]"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tigris", default=os.path.join(HERE, "..", "build", "testbench", "tigris"))
    ap.add_argument("--kitti", default=os.path.join(HERE, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--presets", default="dp4,dp7")
    ap.add_argument("--out", default="bench-trace-out")
    a = ap.parse_args()
    workloads = [("synthetic", [])]
    if os.path.isdir(a.kitti):
        workloads.append(("kitti", ["--source", os.path.join(a.kitti, "000001.bin"),
                                    "--target", os.path.join(a.kitti, "000000.bin")]))
    rows, compares = [], []
    for name, pair in workloads:
        for preset in a.presets.split(","):
            tag = f"{name}_{preset}"
            base = os.path.join(a.out, tag)
            # The four back-ends side by side (the accelerator in the loop included).
            wall_cmp, _ = run([a.tigris, "register", "--preset", preset, "--compare", "--out", base + "_compare"] + pair)
            compare = json.load(open(os.path.join(base + "_compare", "comparison.json")))
            loop_walls = {srch: json.load(open(os.path.join(base + "_compare", srch, "registration.json")))["accelerator"]["wall_seconds"]
                          for srch in ("accel", "accel-approx")}
            compares.append((name, preset, compare, wall_cmp, loop_walls))
            flann_row = compare["rows"][0]  # FLANN's median over --repeat runs (cpu_baseline.hpp)
            wall_flann, _ = run([a.tigris, "register", "--preset", preset, "--search", "flann", "--out", base + "_flann"] + pair)
            flann = json.load(open(os.path.join(base + "_flann", "registration.json")))
            for search in ("exact", "approx"):
                trace = base + f"_{search}.trace"
                wall_rec, _ = run([a.tigris, "register", "--preset", preset, "--search", search,
                                   "--record-trace", trace, "--out", base + f"_{search}"] + pair)
                reg = json.load(open(os.path.join(base + f"_{search}", "registration.json")))
                walls = {}
                for jobs in (1, 2):
                    walls[jobs], _ = run([a.tigris, "run", "--trace", trace, "--jobs", str(jobs),
                                          "--out", base + f"_{search}_replay{jobs}"])
                s = json.load(open(os.path.join(base + f"_{search}_replay1", "stats.json")))
                rows.append({"workload": name, "preset": preset, "search": search, "stats": s, "reg": reg,
                             "flann": flann, "trace_mb": os.path.getsize(trace) / 1e6, "record_wall": wall_rec,
                             "replay_wall": walls, "flann_wall": wall_flann, "flann_row": flann_row})
    for r in rows:
        s, e = r["stats"], r["stats"]["end_to_end"]
        print(f"\n## {r['workload']} {r['preset']} search {r['search']}: verdict {s['verdict']}, "
              f"trace {r['trace_mb']:.1f} MB, {s['trace']['jobs']} jobs")
        print("| stage | jobs | queries | CPU KD-tree s (golden) | modeled s (search + host) | KD-tree speed-up |")
        print("|---|---:|---:|---:|---:|---:|")
        for st in r["reg"]["stages"]:
            if st not in s["stages"]:
                continue
            x = s["stages"][st]
            m = x["modeled_search_seconds"] + x["modeled_host_seconds"]
            print(f"| {st} | {x['jobs']:.0f} | {x['queries']:.0f} | {x['cpu_search_seconds']:.3f} | {m:.4f} | "
                  f"{x['cpu_search_seconds'] / max(m, 1e-12):.0f}x |")
        fr = r["flann_row"]
        fl_kd, fl_s = fr["kdtree_seconds"], fr["end_to_end_seconds"]
        accel_e2e = fl_s - fl_kd + e["accelerator_kdtree_seconds"]
        print(f"- end to end, golden CPU: {e['cpu_seconds']:.3f} s -> accelerated {e['accelerated_seconds']:.3f} s "
              f"({e['reduction_percent']:.1f}% less)")
        sp = fr["end_to_end_seconds_spread"]
        print(f"- against the CPU with FLANN (median of {fr['runs']} runs of register --compare, "
              f"{sp['min']:.3f}-{sp['max']:.3f} s): {fl_s:.3f} s (KD-tree search {fl_kd:.3f} s) -> "
              f"{accel_e2e:.3f} s ({100 * (1 - accel_e2e / fl_s):.1f}% less)")
        print(f"- wall: record {r['record_wall']:.1f} s, FLANN registration {r['flann_wall']:.1f} s, replay "
              f"--jobs 1 {r['replay_wall'][1]:.1f} s, --jobs 2 {r['replay_wall'][2]:.1f} s "
              f"({r['replay_wall'][2] / r['flann_wall']:.1f}x the FLANN registration's wall time)")
    for name, preset, c, wall, loop_walls in compares:
        print(f"\n## {name} {preset}: tigris register --compare ({wall:.0f} s wall; in the loop: accel "
              f"{loop_walls['accel']:.0f} s, accel-approx {loop_walls['accel-approx']:.0f} s)")
        m = c["machine"]
        print(f"(CPU rows: median [min-max] of {c['repeat']} runs on {m['cpu_model']}, {m['cores']} cores, 1-minute load "
              f"{m['load_average_before']['1min']} before, {m['load_average_after']['1min']} after, commit {m['commit']}"
              + "".join(f"; WARNING: {w}" for w in c["warnings"]) + ")")
        print("| back-end | KD-tree s | KD-tree speed-up vs FLANN | end to end s | vs FLANN | KD-tree energy | error m | error deg |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        rows_by = {row["back_end"]: row for row in c["rows"]}
        print(f"(accelerator exact's transform equals the golden model's bit for bit: "
              f"{'yes' if rows_by['accel']['transform'] == rows_by['exact']['transform'] else 'NO'}; "
              f"error: only where a ground truth scores it, never on KITTI 00's first frames)")
        for row in c["rows"]:
            en = f"{row['kdtree_energy_pj'] * 1e-6:.1f} uJ" if row["kdtree_energy_pj"] is not None else "n/a (CPU)"
            err = row["error"] or {}
            kd, ee = row["kdtree_seconds_spread"], row["end_to_end_seconds_spread"]
            x, red = row["kdtree_speedup_vs_flann_range"], row["end_to_end_reduction_vs_flann_percent_range"]
            print(f"| {row['label']} | {spread(kd, '%.4f')} | {x['median']:.1f}x [{x['min']:.1f}-{x['max']:.1f}] | "
                  f"{spread(ee, '%.3f')} | {-red['median']:+.1f}% [{-red['max']:+.1f}, {-red['min']:+.1f}] | {en} | "
                  f"{err.get('translation_m', float('nan')):.4f} | {err.get('rotation_deg', float('nan')):.4f} |")
    by = {(r["workload"], r["preset"], r["search"]): r for r in rows}
    for (w, p, srch), r in by.items():
        if srch == "approx" and (w, p, "exact") in by:
            ex = by[(w, p, "exact")]["stats"]["end_to_end"]
            ap_ = r["stats"]["end_to_end"]
            print(f"\n{w} {p}: approximate vs exact on the accelerator: KD-tree {ex['accelerator_kdtree_seconds']:.4f} s -> "
                  f"{ap_['accelerator_kdtree_seconds']:.4f} s ({ex['accelerator_kdtree_seconds'] / max(ap_['accelerator_kdtree_seconds'], 1e-12):.2f}x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
