#!/usr/bin/python3
"""A design-space exploration in a Python loop: Recursion Units x Search Units x PEs per SU
(16..128 each, 64 points, the grid of python/tigris/tools/examples/units.json) on the built-in pair, each
point one accelerator job checked against the golden model; then search time against power,
one point per configuration (the paper's Figure 13), into dse_loop.png.

    PYTHONPATH=PREFIX/lib/python3/dist-packages python3 dse_loop.py [--jobs 2] [--quick]
    (from the build tree: PYTHONPATH=build/python)

--quick: 8 points (16 and 64 of each). The jobs run `--jobs` at a time (each is a process of its
own); the table and the figure say what ran.
"""
import argparse
import itertools
import time
from concurrent.futures import ThreadPoolExecutor

import tigris


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jobs", type=int, default=2, help="accelerator jobs at once (default 2)")
    ap.add_argument("--quick", action="store_true", help="8 points instead of 64")
    ap.add_argument("--out", default="dse_loop.png", help="the figure (default dse_loop.png)")
    a = ap.parse_args()
    sizes = [16, 64] if a.quick else [16, 32, 64, 128]
    cloud, queries = tigris.synthetic_pair()
    grid = list(itertools.product(sizes, sizes, sizes))

    def one(point):
        ru, su, pe = point
        job = tigris.run(cloud, queries, mode="nn",
                         config={"fe.recursion_units": ru, "be.search_units": su, "be.pes_per_su": pe})
        return point, job

    t0 = time.monotonic()
    rows = []
    with ThreadPoolExecutor(a.jobs) as pool:
        for (ru, su, pe), job in pool.map(one, grid):
            rows.append((ru, su, pe, job.cycles, job.seconds, job.stats["power_w"], job.bound))
            print(f"RU {ru:3d}  SU {su:3d}  PE {pe:3d}  {job.cycles:9,d} cycles  {job.stats['power_w']:6.2f} W  "
                  f"{job.bound}  {job.verdict}", flush=True)
    wall = time.monotonic() - t0
    print(f"{len(rows)} points in {wall:.1f} s ({a.jobs} at a time)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for ru in sizes:
        pts = [r for r in rows if r[0] == ru]
        ax.scatter([r[5] for r in pts], [r[4] * 1e3 for r in pts], label=f"{ru} RUs", s=22)
    ax.set_xlabel("power (W)")
    ax.set_ylabel("search time (ms)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.set_title(f"NN on the built-in pair ({len(queries):,} queries, {len(cloud):,} points):\n"
                 f"RU x SU x PE in {sizes}, {len(rows)} accelerator jobs", fontsize=10)
    ax.legend(title="front end")
    fig.text(0.01, 0.01, "made by examples/python/dse_loop.py (tigris.run per point)", fontsize=7, color="gray")
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"figure: {a.out}")


if __name__ == "__main__":
    main()
