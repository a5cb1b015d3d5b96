#!/usr/bin/env python3
"""Synthesizes the RTL Recursion Unit (rtl/) with Yosys and reports its cells and flip-flops.

    scripts/rtl_synth.py [--json FILE] [--log FILE]

Yosys (Debian's 0.23) reads the RU with SYNTHESIS defined, so its float32 units are black boxes
(rtl/fp_units.sv), runs its generic `synth` and `stat -tech cmos`. The report: generic gates,
flip-flops (bits of state), the black boxes and Yosys's transistor estimate for the gates.
docs/validation.md compares it with the area model's RU. Exit status 1 when Yosys fails, the
design has no cells, or a module other than the float units is left a black box.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RTL = os.path.join(ROOT, "rtl")
FLOAT_UNITS = {"tigris_fp_dist2", "tigris_fp_plane2"}


def synthesize(log_path=None):
    yosys = shutil.which("yosys")
    if not yosys:
        raise SystemExit("rtl_synth: yosys not found (Debian package yosys)")
    with tempfile.TemporaryDirectory() as tmp:
        stat = os.path.join(tmp, "stat.json")
        script = (f"read_verilog -sv -DSYNTHESIS fp_units.sv tigris_recursion_unit.sv; "
                  f"synth -top tigris_recursion_unit; tee -q -o {stat} stat -json -tech cmos")
        p = subprocess.run([yosys, "-p", script], cwd=RTL, capture_output=True, text=True)
        if log_path:
            with open(log_path, "w") as f:
                f.write(p.stdout + p.stderr)
        if p.returncode != 0:
            raise SystemExit(f"rtl_synth: yosys failed ({p.returncode}):\n{(p.stdout + p.stderr)[-3000:]}")
        with open(stat) as f:
            return json.load(f)


def summary(stat):
    design = stat["design"]
    cells = design["num_cells_by_type"]
    flops = {t: n for t, n in cells.items() if "DFF" in t}
    boxes = {t: n for t, n in cells.items() if not t.startswith("$")}
    gates = {t: n for t, n in cells.items() if t.startswith("$") and t not in flops}
    return {
        "yosys": stat.get("creator", ""),
        "cells": design["num_cells"],
        "gates": sum(gates.values()),
        "flip_flops": sum(flops.values()),
        "black_boxes": boxes,
        "estimated_transistors": str(design.get("estimated_num_transistors", "")),
        "cells_by_type": cells,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", help="write the summary as JSON to this file")
    ap.add_argument("--log", help="write Yosys's whole log to this file")
    a = ap.parse_args()
    s = summary(synthesize(a.log))
    print(f"{s['yosys']}: tigris_recursion_unit (float32 units black boxes)")
    print(f"  cells          {s['cells']:,}")
    print(f"  gates          {s['gates']:,} (generic: AND, OR, XOR, MUX, ...)")
    print(f"  flip-flops     {s['flip_flops']:,}")
    print(f"  black boxes    {', '.join(f'{k} x{v}' for k, v in sorted(s['black_boxes'].items()))}")
    print(f"  transistors    {s['estimated_transistors']} (Yosys's CMOS estimate of the gates)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(s, f, indent=2)
            f.write("\n")
    unexpected = set(s["black_boxes"]) - FLOAT_UNITS
    if s["cells"] == 0 or s["flip_flops"] == 0 or unexpected:
        print(f"rtl_synth: unexpected result: {s['cells']} cells, {s['flip_flops']} flip-flops, "
              f"black boxes {sorted(unexpected)} beyond the float units", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
