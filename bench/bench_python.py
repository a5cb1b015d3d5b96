#!/usr/bin/python3
"""The Python module's cost against the command line: the same 64-point design-space exploration
(RU x SU x PE 16..128, exact NN on the built-in pair, python/tigris/tools/examples/units.json's grid) as a
Python loop (examples/python/dse_loop.py: tigris.run per point, arrays written per job) and as
`tigris sweep`, both two jobs at a time, run in turn N times; prints each one's median
[min-max] wall seconds and the median of the pairwise ratios.

    bench/bench_python.py [--build build] [--runs 3] [--jobs 2]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def timed(cmd, env):
    t0 = time.monotonic()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    tig = os.path.join(a.build, "bin", "tigris")
    env = dict(os.environ, PYTHONPATH=os.path.join(a.build, "python"))
    tmp = tempfile.mkdtemp(prefix="bench-python-")
    loop = ["/usr/bin/python3", os.path.join(ROOT, "examples", "python", "dse_loop.py"), "--jobs", str(a.jobs),
            "--out", os.path.join(tmp, "dse.png")]
    sweep_out = os.path.join(tmp, "sw")
    sweep = [tig, "sweep", os.path.join(ROOT, "python", "tigris", "tools", "examples", "units.json"), "--out", sweep_out,
             "--jobs", str(a.jobs)]
    py, sw = [], []
    try:
        for i in range(a.runs + 1):                 # the first pair warms the caches, not counted
            shutil.rmtree(sweep_out, ignore_errors=True)
            t_py, t_sw = timed(loop, env), timed(sweep, env)
            if i:
                py.append(t_py), sw.append(t_sw)
                print(f"run {i}: python loop {t_py:.1f} s, tigris sweep {t_sw:.1f} s", file=sys.stderr)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    ratios = [p / s for p, s in zip(py, sw)]
    print(f"64 points, {a.jobs} at a time, {a.runs} runs each in turn:")
    print(f"  python loop (tigris.run)  {statistics.median(py):6.1f} s  [{min(py):.1f}-{max(py):.1f}]")
    print(f"  tigris sweep              {statistics.median(sw):6.1f} s  [{min(sw):.1f}-{max(sw):.1f}]")
    print(f"  python / sweep            {statistics.median(ratios):6.3f}x")


if __name__ == "__main__":
    main()
