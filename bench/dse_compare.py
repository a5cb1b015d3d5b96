#!/usr/bin/env python3
"""Compares two `tigris pipeline-dse` runs of the same space (e.g. local and Slurm) point by point.

    bench/dse_compare.py A/points.csv B/points.csv [--names local,slurm]

Errors and search counts are properties of the configuration and must be equal; times are host
seconds and differ. Prints, in markdown: points in both, knob or status mismatches, the largest
error differences, the time ratio B/A (median and spread), and both Pareto sets with their DPs.
Exit 0 when every common point has the same status and errors equal to 1e-9 (relative), 1 when
not (the first differing point is named), 2 on bad input.
"""
import argparse, csv, statistics, sys

ERRORS = ("rpe_translation_m", "rpe_rotation_deg")
KEEP = {"point", "dp", "status", "seconds_per_pair", "kdtree_share", "on_translation_frontier",
        "on_rotation_frontier", "pairs", "not_converged_pairs", "error", "sweep_id"}


def fail(msg):
    print(f"dse_compare: {msg}", file=sys.stderr)
    sys.exit(2)


def read(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    if not rows or "point" not in rows[0] or any(k not in rows[0] for k in ERRORS):
        fail(f"{path}: not a pipeline-dse points.csv (no point/error columns)")
    return {r["point"]: r for r in rows}


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def rel(a, b):
    if a is None or b is None:
        return 0.0 if a is b else float("inf")
    return abs(a - b) / max(abs(a), abs(b), 1e-300)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--names", default="A,B", help="the two runs' names in the output (default A,B)")
    args = ap.parse_args(argv)
    na, nb = args.names.split(",", 1) if "," in args.names else ("A", "B")
    a, b = read(args.a), read(args.b)
    common = [p for p in a if p in b]
    print(f"{len(a)} points in {na}, {len(b)} in {nb}, {len(common)} in both")
    bad = []
    for p in common:
        knobs = [k for k in a[p] if k not in KEEP and k not in ERRORS and not k.endswith(" s")]
        if any(a[p].get(k) != b[p].get(k) for k in knobs):
            bad.append((p, "different knobs: not the same space or seed"))
        elif a[p]["status"] != b[p]["status"]:
            bad.append((p, f"status {a[p]['status']} in {na}, {b[p]['status']} in {nb}"))
        else:
            d = max(rel(num(a[p][e]), num(b[p][e])) for e in ERRORS)
            if d > 1e-9:
                bad.append((p, f"errors differ by {d:.3g} (relative): "
                               + ", ".join(f"{e} {a[p][e]} vs {b[p][e]}" for e in ERRORS)))
    statuses = {}
    for p in common:
        statuses[a[p]["status"]] = statuses.get(a[p]["status"], 0) + 1
    print(f"statuses (both): {', '.join(f'{n} {s}' for s, n in sorted(statuses.items()))}")
    ratios = sorted(num(b[p]["seconds_per_pair"]) / num(a[p]["seconds_per_pair"]) for p in common
                    if num(a[p]["seconds_per_pair"]) and num(b[p]["seconds_per_pair"]))
    if ratios:
        q = statistics.quantiles(ratios, n=10) if len(ratios) > 1 else ratios * 9
        print(f"seconds per pair {nb}/{na}: median {statistics.median(ratios):.3f}, 10-90% {q[0]:.3f}-{q[-1]:.3f}, "
              f"min {ratios[0]:.3f}, max {ratios[-1]:.3f} ({len(ratios)} points)")
    for name, run in ((na, a), (nb, b)):
        dps = sorted((r for r in run.values() if r["dp"]), key=lambda r: int(r["dp"][2:]))
        print(f"\n{name}: {len(dps)} Pareto points\n\n| DP | point | s/pair | RPE m | RPE deg | KD-tree | frontier |\n"
              "|---|---|---:|---:|---:|---:|---|")
        for r in dps:
            on = "+".join(w for w, k in (("translation", "on_translation_frontier"), ("rotation", "on_rotation_frontier"))
                          if r[k] == "true")
            kd = num(r["kdtree_share"])
            print(f"| {r['dp']} | {r['point']} | {num(r['seconds_per_pair']):.2f} | {num(r['rpe_translation_m']):.5f} | "
                  f"{num(r['rpe_rotation_deg']):.5f} | {'-' if kd is None else f'{100 * kd:.0f}%'} | {on} |")
    sa = {p for p, r in a.items() if r["dp"]}
    sb = {p for p, r in b.items() if r["dp"]}
    print(f"\nPareto points in both: {len(sa & sb)}; only in {na}: {', '.join(sorted(sa - sb)) or 'none'}; "
          f"only in {nb}: {', '.join(sorted(sb - sa)) or 'none'}")
    if bad:
        print(f"\n{len(bad)} points differ; the first: {bad[0][0]}: {bad[0][1]}")
        for p, why in bad[1:10]:
            print(f"  {p}: {why}")
        return 1
    print("\nevery common point: same status, errors equal")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
