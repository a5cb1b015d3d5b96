#!/usr/bin/env python3
"""Figures of the accelerator model (issue: simulator speed, cycles vs lower bound, stall causes,
Acc-KD vs Acc-2SKD, forwarding/bypassing, MQSN vs MQMN, Node Cache, peak memory).

Runs `tigris run` on the built-in synthetic pair and, when present, the KITTI pair
(frame 1 searched in frame 0). Wall times are medians of --runs runs measured in this one
invocation. Usage: bench/bench_accel.py [--tigris build/bin/tigris] [--kitti DIR] [--runs 3]

--instructions also counts instructions with valgrind's callgrind (one run per search, about a
minute each, with --sim-threads 1): the simulation (tigris::simulate) against the golden model's search (its call of
tigris::search, without the scoreboard's replay). Unlike wall times they do not move with the machine's load.
"""
import argparse, json, os, re, shutil, statistics, subprocess, sys, tempfile

def run(tigris, args, out):
    cmd = ["/usr/bin/time", "-f", "%M", tigris, "run", "--out", out] + args
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stdout + p.stderr)
    peak_kb = int(p.stderr.strip().splitlines()[-1])
    with open(os.path.join(out, "stats.json")) as f:
        return json.load(f), peak_kb

def instructions(tigris, args, tmp):
    """Inclusive instruction counts of the simulation and of the golden model's search loop."""
    out = os.path.join(tmp, "callgrind.out")
    # One simulation thread: tigris::simulate then holds all of the simulation's instructions
    # (with two, the scans on the second thread would be counted apart).
    cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, tigris, "run", "--sim-threads", "1",
           "--out", tmp] + args
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stderr[-2000:])
    report = subprocess.run(["callgrind_annotate", "--inclusive=yes", out], capture_output=True, text=True).stdout
    def count(pattern):
        for line in report.splitlines():
            m = re.match(r"\s*([\d,]+)\s.*" + pattern, line)
            if m:
                return int(m.group(1).replace(",", ""))
        sys.exit(f"callgrind_annotate has no line for {pattern!r}")
    # tigris::search runs twice: the golden model, then the scoreboard's replay of the
    # simulation's schedule (run_replay); the golden model is the difference.
    return count(r"tigris::simulate\("), count(r"tigris::search\(") - count(r"run_replay<")

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--tigris", default=os.path.join(here, "..", "build", "testbench", "tigris"))
    ap.add_argument("--kitti", default=os.path.join(here, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--instructions", action="store_true",
                    help="also count instructions with valgrind --tool=callgrind (slow, but stable)")
    a = ap.parse_args()
    if a.instructions and not (shutil.which("valgrind") and shutil.which("callgrind_annotate")):
        sys.exit("--instructions needs valgrind (Debian package valgrind)")
    workloads = [("synthetic", [])]
    k0, k1 = os.path.join(a.kitti, "000000.bin"), os.path.join(a.kitti, "000001.bin")
    if os.path.exists(k0) and os.path.exists(k1):
        workloads.append(("KITTI 00 (1 in 0)", ["--cloud", k0, "--queries", k1]))
    else:
        print(f"(KITTI pair not found in {a.kitti}: synthetic only)\n")
    variants = [
        ("Acc-2SKD h=10 (default)", []),
        ("Acc-KD (canonical tree)", ["--height", "full"]),
        ("no bypassing", ["--set", "fe.bypassing=false"]),
        ("no forwarding", ["--set", "fe.forwarding=false"]),
        ("neither (No-Opt)", ["--set", "fe.bypassing=false", "--set", "fe.forwarding=false"]),
        ("MQMN", ["--set", "be.issue_policy=mqmn"]),
        ("no Node Cache", ["--set", "node_cache.bytes=0"]),
    ]
    tmp = tempfile.mkdtemp(prefix="bench_accel_")
    for wname, wargs in workloads:
        print(f"## {wname}\n")
        print("### Simulator speed (median of %d runs)\n" % a.runs)
        print("| search | simulated cycles | time at 500 MHz | simulator wall s | sw_ref wall s | ratio | peak memory MiB | verdict |")
        print("|---|---:|---:|---:|---:|---:|---:|---|")
        for sname, sargs in [("NN", ["--mode", "nn"]), ("radius 0.30", ["--mode", "radius", "--radius", "0.30"])]:
            sims, golds, peaks = [], [], []
            for _ in range(a.runs):
                s, peak = run(a.tigris, wargs + sargs, tmp)
                sims.append(s["wall_seconds"]["simulation"]); golds.append(s["wall_seconds"]["golden"]); peaks.append(peak)
            ms, mg = statistics.median(sims), statistics.median(golds)
            print(f"| {sname} | {s['cycles']:,} | {s['seconds']*1e3:.3f} ms | {ms:.3f} | {mg:.3f} | {ms/mg:.1f}x | {max(peaks)/1024:.0f} | {s['verdict']} |")
        if a.instructions:
            print("\n### Instructions (valgrind --tool=callgrind, one run each)\n")
            print("| search | simulation (tigris::simulate) | golden model (tigris::search) | ratio |")
            print("|---|---:|---:|---:|")
            for sname, sargs in [("NN", ["--mode", "nn"]), ("radius 0.30", ["--mode", "radius", "--radius", "0.30"])]:
                sim, gold = instructions(a.tigris, wargs + sargs, tmp)
                print(f"| {sname} | {sim/1e9:.2f} G | {gold/1e9:.2f} G | {sim/gold:.1f}x |")
        print("\n### Configurations, exact NN (cycles vs lower bound, stall causes)\n")
        print("| variant | cycles | lower bound | cycles / bound | RU util | SU util | PE util | queries/batch | RU sram stall | RU bqb-full stall | SU issue search | SU sram stall | Point Buffer reads (words) | verdict |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        base = None
        for vname, vargs in variants:
            s, _ = run(a.tigris, wargs + ["--mode", "nn"] + vargs, tmp)
            u = s["units"]; ru = u["recursion_units"]; su = u["search_units"]
            base = base or s["cycles"]
            print(f"| {vname} | {s['cycles']:,} ({s['cycles']/base:.2f}x) | {s['lower_bound_cycles']:,.0f} | {s['cycles']/max(s['lower_bound_cycles'],1):.1f} | "
                  f"{ru['utilization']*100:.1f}% | {su['utilization']*100:.1f}% | {su['pe_utilization']*100:.1f}% | {su['queries_per_batch']:.2f} | "
                  f"{ru['stall_cycles']['sram']:,} | {ru['stall_cycles']['bqb_full']:,} | {su['stall_cycles']['issue_search']:,} | {su['stall_cycles']['sram']:,} | "
                  f"{s['buffers']['points']['reads']:,} | {s['verdict']} |")
        print("\n(RU/SU stall cycles are summed over all units of the kind.)\n")

if __name__ == "__main__":
    main()
