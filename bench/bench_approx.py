#!/usr/bin/env python3
"""Exact vs approximate search on the accelerator (a benchmark).

Runs `tigris run` on the KITTI pair (frame 1 searched in frame 0, top height 10, the default
machine) or, without it, the built-in synthetic pair: NN (thd 1.2 m) and radius 0.30 / 0.75
(thd 0.4 r), exact and approximate. Prints visits per query, cycles, energy, power, accuracy,
leader decisions, the energy split beside the paper's DP4 split, and the area beside the
paper's. Every run must MATCH its golden check (the script stops otherwise).

`--sweep` instead runs the approximate-search thresholds on the synthetic pair and (when found) the KITTI
pair: NN at thd 0.3-2.0 m and radius 0.30 m at 0.2-0.6 r, under the three readings of approximate
search (first_leaf wait, the default; first_leaf finished_only; every_leaf), each against exact:
followers, nodes per query, cycles, energy, the bound and the accuracy.
Usage: bench/bench_approx.py [--tigris build/bin/tigris] [--kitti DIR] [--height 10] [--sweep]
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

READINGS = [("first_leaf wait", []), ("first_leaf finished_only", ["--leader-in-flight", "finished_only"]),
            ("every_leaf", ["--leader-scope", "every_leaf"])]


def accuracy(s):
    c = s.get("accuracy", {})
    if "recall" in c:
        return f"recall {c['recall']:.4f}, precision {c['precision']:.4f}"
    return f"{100*c['exact_match_fraction']:.1f}% exact, +{c['mean_extra_distance_m']:.3f} m mean"


def short_bound(s):
    b = s.get("bottleneck", {})
    return f"{b.get('bound', '?')} ({b.get('cause', '?')} {100*b.get('share', 0):.0f}%)"


def sweep(a, workloads):
    """The threshold tables: one per workload and search, every reading against exact."""
    tmp = tempfile.mkdtemp(prefix="bench_approx_")
    nn = [0.3, 0.6, 1.2, 2.0]
    r = 0.30
    for wname, wargs in workloads:
        for sname, sargs, thds in (("NN", ["--mode", "nn"], nn),
                                    (f"radius {r:.2f} m", ["--mode", "radius", "--radius", str(r)],
                                     [round(f * r, 4) for f in (0.2, 0.3, 0.4, 0.6)])):
            base = wargs + ["--height", a.height] + sargs
            ex = run(a.tigris, base, tmp)
            q = ex["queries"]
            print(f"\n### {wname}, {sname}: exact {ex['cycles']:,} cycles, {nodes(ex)/q:.1f} nodes/query, "
                  f"{ex['energy_pj']['total']/1e6:,.1f} uJ, {short_bound(ex)}\n")
            print("| thd m | reading | followers | nodes/query | cycles | speed-up | energy | bound | accuracy | verdict |")
            print("|---:|---|---:|---:|---:|---:|---:|---|---|---|")
            for thd in thds:
                for rname, rargs in READINGS:
                    s = run(a.tigris, base + ["--approx-thd", str(thd)] + rargs, tmp)
                    l = s["leaders"]
                    print(f"| {thd:g} | {rname} | {100*l['followers']/q:.1f}% | {nodes(s)/q:.1f} ({100*(nodes(s)/nodes(ex)-1):+.0f}%) "
                          f"| {s['cycles']:,} | {ex['cycles']/s['cycles']:.2f}x | {s['energy_pj']['total']/ex['energy_pj']['total']:.2f}x "
                          f"| {short_bound(s)} | {accuracy(s)} | {s['verdict']} |")
                    sys.stdout.flush()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--tigris", default=os.path.join(here, "..", "build", "testbench", "tigris"))
    ap.add_argument("--kitti", default=os.path.join(here, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--height", default="10")
    ap.add_argument("--sweep", action="store_true", help="the threshold tables of every reading")
    a = ap.parse_args()
    k0, k1 = os.path.join(a.kitti, "000000.bin"), os.path.join(a.kitti, "000001.bin")
    workload = ["--cloud", k0, "--queries", k1] if os.path.exists(k0) and os.path.exists(k1) else []
    if a.sweep:
        sweep(a, [("synthetic pair", [])] + ([("KITTI 00 frame 1 in frame 0", workload)] if workload else []))
        return
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
        print("| | SRAM | logic | total |\n|---|---:|---:|---:|\n| paper | 8.38 | 7.19 | 15.57 |")
        print(f"| model | {area['sram']:.2f} | {area['logic']:.2f} | {area['total']:.2f} |")
        print("\n| block | mm2 |\n|---|---:|")
        for kind, blocks in area.get("by_block", {}).items():
            for block, mm2 in blocks.items():
                print(f"| {kind}: {block} | {mm2:.3f} |")

if __name__ == "__main__":
    main()
