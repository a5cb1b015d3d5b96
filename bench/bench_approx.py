#!/usr/bin/env python3
"""Exact vs approximate search on the accelerator (issue 7 benchmark).

Runs `tigris run` on the KITTI pair (frame 1 searched in frame 0, top height 10, the default
machine) or, without it, the built-in synthetic pair: NN (thd 1.2 m) and radius 0.30 / 0.75
(thd 0.4 r), exact and approximate. Prints visits per query, cycles, energy, power, accuracy,
leader decisions, the energy split beside the paper's DP4 split, and the area beside the
paper's. Every run must MATCH its golden check (the script stops otherwise).
Usage: bench/bench_approx.py [--tigris build/testbench/tigris] [--kitti DIR] [--height 10]
"""
import argparse, json, os, subprocess, sys, tempfile

PAPER_SPLIT = {"pe": 53.7, "sram_read": 34.8, "sram_write": 8.0, "leakage": 3.3, "dram": 0.2}

def run(tigris, args, out):
    cmd = [tigris, "run", "--out", out] + args
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stdout + p.stderr)
    with open(os.path.join(out, "stats.json")) as f:
        return json.load(f)

def nodes(s):
    v = s["visits"]
    return v["top"] + v["leaf_points"] + v["follower_points"] + v["leader_checks"]

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--tigris", default=os.path.join(here, "..", "build", "testbench", "tigris"))
    ap.add_argument("--kitti", default=os.path.join(here, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--height", default="10")
    a = ap.parse_args()
    k0, k1 = os.path.join(a.kitti, "000000.bin"), os.path.join(a.kitti, "000001.bin")
    workload = ["--cloud", k0, "--queries", k1] if os.path.exists(k0) and os.path.exists(k1) else []
    print("## Workload: " + ("KITTI 00, frame 1 in frame 0" if workload else "synthetic pair (KITTI not found)") +
          f", top height {a.height}, default machine\n")
    searches = [("NN", ["--mode", "nn"], "1.2"), ("radius 0.30", ["--mode", "radius", "--radius", "0.30"], "0.12"),
                ("radius 0.75", ["--mode", "radius", "--radius", "0.75"], "0.30")]
    tmp = tempfile.mkdtemp(prefix="bench_approx_")
    rows = []
    for name, args, thd in searches:
        ex = run(a.tigris, workload + ["--height", a.height] + args, tmp)
        ap_ = run(a.tigris, workload + ["--height", a.height, "--approx-thd", thd] + args, tmp)
        rows.append((name, thd, ex, ap_))
    print("| search | variant | nodes/query | cycles | speedup | energy uJ | power W | accuracy | leaders / followers / buffer-full | verdict |")
    print("|---|---|---:|---:|---:|---:|---:|---|---|---|")
    for name, thd, ex, ap_ in rows:
        for label, s in (("exact", ex), (f"approx thd {thd}", ap_)):
            q = s["queries"]
            e = s["energy_pj"]["total"] / 1e6
            pw = s.get("power_w", float("nan"))
            acc = ""
            if "accuracy" in s:
                c = s["accuracy"]
                acc = (f"recall {c['recall']:.4f}, precision {c['precision']:.4f}" if "recall" in c else
                       f"{100*c['exact_match_fraction']:.1f}% exact, +{c['mean_extra_distance_m']:.3f} m mean, +{c['max_extra_distance_m']:.2f} m max")
            l = s.get("leaders")
            lead = f"{l['leaders']:,} / {l['followers']:,} / {l['leader_buffer_full']:,}" if l else ""
            print(f"| {name} | {label} | {nodes(s)/q:.1f} | {s['cycles']:,} | {ex['cycles']/s['cycles']:.2f}x | {e:,.1f} | {pw:.2f} | {acc} | {lead} | {s['verdict']} |")
        print(f"| | visited nodes | {100*(nodes(ap_)/nodes(ex)-1):+.1f}% | | | | | | | |")
    print("\n### Energy split (% of total)\n")
    comps = [c for c in ("pe", "ru", "sram_read", "sram_write", "node_cache", "leader_buffer", "dram", "leakage")
             if c in rows[0][2]["energy_pj"]]
    print("| run | " + " | ".join(comps) + " |")
    print("|---|" + "---:|" * len(comps))
    print("| paper DP4 | " + " | ".join(f"{PAPER_SPLIT[c]:.1f}" if c in PAPER_SPLIT else "" for c in comps) + " |")
    for name, thd, ex, ap_ in rows:
        for label, s in (("exact", ex), ("approx", ap_)):
            tot = s["energy_pj"]["total"]
            print(f"| {name} {label} | " + " | ".join(f"{100*s['energy_pj'][c]/tot:.1f}" for c in comps) + " |")
    area = rows[0][2].get("area_mm2")
    if area:
        print("\n### Area (mm2, 16 nm)\n")
        print(f"| | SRAM | logic | total |\n|---|---:|---:|---:|\n| paper | 8.38 | 7.19 | 15.57 |")
        print(f"| model | {area['sram']:.2f} | {area['logic']:.2f} | {area['total']:.2f} |")
        print("\n| block | mm2 |\n|---|---:|")
        for kind, blocks in area.get("by_block", {}).items():
            for block, mm2 in blocks.items():
                print(f"| {kind}: {block} | {mm2:.3f} |")

if __name__ == "__main__":
    main()
