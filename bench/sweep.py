#!/usr/bin/env python3
"""Design-space sweeps of the accelerator model (DESIGN.md section 9): RU x SU x PE counts and
the top-tree height, each point a `tigris run` (exact search, golden-checked). Prints Markdown
tables of simulated cycles. Usage:
  bench/sweep.py [--tigris PATH] [--mode nn] [--units 16,32,64,128] [--heights 6,8,10,12,14]
                 [--] extra tigris run arguments (e.g. --cloud A.bin --queries B.bin)
"""
import argparse, json, os, subprocess, sys, tempfile

def cycles(tigris, args, out):
    p = subprocess.run([tigris, "run", "--out", out] + args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: tigris run " + " ".join(args) + "\n" + p.stdout + p.stderr)
    with open(os.path.join(out, "stats.json")) as f:
        s = json.load(f)
    return s["cycles"], s["energy_pj"]["total"]

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--tigris", default=os.path.join(here, "..", "build", "testbench", "tigris"))
    ap.add_argument("--mode", default="nn")
    ap.add_argument("--units", default="16,32,64,128")
    ap.add_argument("--heights", default="6,8,10,12,14")
    ap.add_argument("extra", nargs="*")
    a = ap.parse_args()
    units = [int(u) for u in a.units.split(",")]
    base = ["--mode", a.mode] + a.extra
    out = tempfile.mkdtemp(prefix="sweep_")
    print(f"## RU x SU x PE sweep ({a.mode}, top height 10): simulated cycles\n")
    print("| RU \\ SU x PE | " + " | ".join(f"{s}x{p}" for s in units for p in units) + " |")
    print("|---|" + "---:|" * (len(units) ** 2))
    for ru in units:
        row = []
        for su in units:
            for pe in units:
                c, _ = cycles(a.tigris, base + ["--set", f"fe.recursion_units={ru}", "--set",
                              f"be.search_units={su}", "--set", f"be.pes_per_su={pe}"], out)
                row.append(f"{c:,}")
            print(f"{ru} RU ...", file=sys.stderr)
        print(f"| {ru} | " + " | ".join(row) + " |")
    print(f"\n## Top-tree height sweep ({a.mode}, default units)\n")
    print("| top height | cycles | energy (uJ) |")
    print("|---:|---:|---:|")
    for h in a.heights.split(","):
        c, e = cycles(a.tigris, base + ["--height", h], out)
        print(f"| {h} | {c:,} | {e / 1e6:.1f} |")

if __name__ == "__main__":
    main()
