#!/usr/bin/env python3
"""The RTL cross-check (docs/validation.md): every configuration of the matrix run twice,
with the transaction-level Recursion Unit and with the RTL one (`fe.recursion_unit_model=rtl`),
on the built-in pair and, when present, the KITTI pair. Both runs must match the golden model
(`tigris run` exits 1 otherwise); the table compares their cycles and RU figures.

    bench/rtl_crosscheck.py [--build build] [--kitti DIR] [--quick] [--markdown FILE]

The matrix: NN, kNN (k = 8) and radius (0.3 m); 1, 8 and 64 RUs; forwarding and bypassing both
on or both off; top levels replicated 0 and 6. `--quick` runs the built-in pair only. Exit
status 1 when a run fails or a job's cycles differ by more than --tolerance (default 0%); with
--tolerance 0 also when any Recursion Unit statistic or buffer figure differs.
"""

import argparse
import itertools
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(tig, out, pair, mode, rus, opt, top, model):
    cmd = [tig, "run", "--out", out, "--mode", mode] + pair
    if mode == "knn":
        cmd += ["--k", "8"]
    sets = {"fe.recursion_units": rus, "fe.forwarding": opt, "fe.bypassing": opt,
            "fe.top_levels_replicated": top, "fe.recursion_unit_model": model}
    for k, v in sets.items():
        cmd += ["--set", f"{k}={str(v).lower()}"]
    t = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.monotonic() - t
    if p.returncode != 0:
        raise SystemExit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    with open(os.path.join(out, "stats.json")) as f:
        s = json.load(f)
    return s, seconds


def ru_sram_stall(stats):
    return stats["units"]["recursion_units"]["stall_cycles"]["sram"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--kitti", default=os.path.join(ROOT, "..", "shared", "data", "kitti-00"))
    ap.add_argument("--quick", action="store_true", help="the built-in pair only")
    ap.add_argument("--tolerance", type=float, default=0.0,
                    help="largest cycle difference in percent (default 0: the model claims the RU exact)")
    ap.add_argument("--markdown", help="also write the table as Markdown to this file")
    a = ap.parse_args()
    tig = os.path.join(a.build, "bin", "tigris")
    pairs = [("built-in", [])]
    frames = [os.path.join(a.kitti, f) for f in ("000000.bin", "000001.bin")]
    if not a.quick and all(os.path.exists(f) for f in frames):
        pairs.append(("KITTI 00 0/1", ["--cloud", frames[0], "--queries", frames[1]]))
    rows, worst, fails = [], 0.0, 0
    header = ("| pair | mode | RUs | fwd+byp | top | TLM cycles | RTL cycles | diff | RU stall TLM | RU stall RTL "
              "| RU and buffer stats | TLM s | RTL s |")
    print(header)
    print("|" + "---|" * 13)
    with tempfile.TemporaryDirectory() as tmp:
        for (name, pair), mode, rus, opt, top in itertools.product(pairs, ("nn", "knn", "radius"), (1, 8, 64),
                                                                   (True, False), (0, 6)):
            t, ts = run(tig, os.path.join(tmp, "t"), pair, mode, rus, opt, top, "tlm")
            r, rs = run(tig, os.path.join(tmp, "r"), pair, mode, rus, opt, top, "rtl")
            diff = 100.0 * (r["cycles"] - t["cycles"]) / t["cycles"]
            worst = max(worst, abs(diff))
            fails += abs(diff) > a.tolerance
            # Every Recursion Unit statistic and every buffer figure (traffic, conflicts per bank).
            same = t["units"]["recursion_units"] == r["units"]["recursion_units"] and t["buffers"] == r["buffers"]
            fails += not same and a.tolerance == 0
            st, sr = ru_sram_stall(t), ru_sram_stall(r)
            row = (f"| {name} | {mode} | {rus} | {'on' if opt else 'off'} | {top} | {t['cycles']:,} | {r['cycles']:,} "
                   f"| {diff:+.2f}% | {st:,} | {sr:,} | {'equal' if same else 'differ'} | {ts:.1f} | {rs:.1f} |")
            rows.append(row)
            print(row, flush=True)
    print(f"\nlargest difference {worst:.2f}%; {fails} of {len(rows)} configurations beyond {a.tolerance}%")
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(header + "\n|" + "---|" * 13 + "\n" + "\n".join(rows) + "\n")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
