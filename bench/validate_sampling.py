#!/usr/bin/python3
"""Sampled simulation against full simulation (docs/sampling.md): every case run twice, with
sim.sampling=off and with a sampling setting (default auto), on the built-in pair and, when given,
a KITTI pair; the modes, policies, unit counts and heights of the issue's list, and every job of a
DP4 and a DP7 registration (recorded as traces, replayed). Two machines: the paper's, and one
holding fewer queries in flight (a smaller Query Stack), where jobs are long enough to sample.
Prints one Markdown table per machine and the summary: jobs sampled, the largest error, how often
the full value lies inside the 95% interval, simulation time full against sampled.

    bench/validate_sampling.py [--build build] [--kitti DIR] [--sampling auto] [--json OUT]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MACHINES = {
    "paper": [],
    # 40 KiB of Query Stack: 512 queries in flight at top height 10 instead of 15,728.
    "small-stack": ["--set", "sram.query_stack.bytes=40960"],
}
CASES = [
    ("NN", ["--mode", "nn"]),
    ("kNN k=8", ["--mode", "knn", "--k", "8"]),
    ("kNN k=51", ["--mode", "knn", "--k", "51"]),
    ("radius 0.3", ["--mode", "radius", "--radius", "0.3"]),
    ("radius 0.6", ["--mode", "radius", "--radius", "0.6"]),
    ("approx NN", ["--mode", "nn", "--approx-thd", "default"]),
    ("NN, MQMN", ["--mode", "nn", "--set", "be.issue_policy=mqmn"]),
    ("NN, 16 RU x 8 SU", ["--mode", "nn", "--set", "fe.recursion_units=16", "--set", "be.search_units=8"]),
    ("NN, height 6", ["--mode", "nn", "--height", "6"]),
    ("NN, height 14", ["--mode", "nn", "--height", "14"]),
]


def run(tig, args, out):
    p = subprocess.run([tig, "run", "--out", out] + args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"validate_sampling: {' '.join(args)} failed:\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    with open(os.path.join(out, "stats.json")) as f:
        return json.load(f)


def row(name, full, samp, full_wall, samp_wall):
    """One job's comparison: full figures against the sampled run's estimate."""
    sm = samp["sampling"]
    fc, ec = full["cycles"], samp["cycles"]
    lo, hi = samp["cycles_ci95"]
    total = lambda e: e["total"] if isinstance(e, dict) else e  # a run's split, or a trace job's total
    fe, ee = total(full["energy_pj"]), total(samp["energy_pj"])
    return {"case": name, "queries": sm["queries"], "in_flight": sm.get("in_flight"), "sampled": sm["sampled"],
            "why": sm.get("why", ""), "simulated": sm["simulated"], "full_cycles": fc, "cycles": ec,
            "error": (ec - fc) / fc if fc else 0.0, "half": (hi - lo) / 2 / ec if ec else 0.0,
            "inside": lo <= fc <= hi, "energy_error": (ee - fe) / fe if fe else 0.0,
            "full_wall": full_wall, "sampled_wall": samp_wall}


def pair_cases(tig, tmp, machine, workload, sampling):
    rows = []
    for name, args in CASES:
        base = workload + MACHINES[machine] + args
        full = run(tig, base + ["--set", "sim.sampling=off"], os.path.join(tmp, "full"))
        samp = run(tig, base + ["--set", "sim.sampling=" + sampling], os.path.join(tmp, "samp"))
        rows.append(row(name, full, samp, full["wall_seconds"]["simulation"], samp["wall_seconds"]["simulation"]))
        r = rows[-1]
        print(f"  {machine} {name}: {'sampled' if r['sampled'] else 'full'} error {100 * r['error']:+.2f}%",
              file=sys.stderr)
    return rows


def trace_jobs(tig, tmp, machine, trace, label, sampling):
    """Every job of a recorded registration, replayed with sampling off and on."""
    rows = []
    out = {}
    for mode in ("off", sampling):
        o = os.path.join(tmp, "trace-" + mode)
        run(tig, ["--trace", trace] + MACHINES[machine] + ["--set", "sim.sampling=" + mode], o)
        with open(os.path.join(o, "stats.json")) as f:
            out[mode] = json.load(f)["jobs"]
    for full, samp in zip(out["off"], out[sampling]):
        name = f"{label} job {full['job']} ({full['stage']}, {full['mode']})"
        f = {"cycles": full["cycles"], "energy_pj": full["energy_pj"]}
        s = {"cycles": samp["cycles"], "energy_pj": samp["energy_pj"], "cycles_ci95": samp["cycles_ci95"],
             "sampling": samp["sampling"]}
        rows.append(row(name, f, s, full["phase_seconds"]["simulate"], samp["phase_seconds"]["simulate"]))
    return rows


def table(rows):
    lines = ["| job | queries | in flight | simulated | cycles (full) | error | 95% interval | inside | energy error |"
             " simulation s (full / sampled) |",
             "|---|--:|--:|--:|--:|--:|--:|:-:|--:|--:|"]
    for r in rows:
        if r["sampled"]:
            lines.append(f"| {r['case']} | {r['queries']} | {r['in_flight']} | "
                         f"{100 * r['simulated'] / r['queries']:.0f}% | {r['full_cycles']} | {100 * r['error']:+.2f}% | "
                         f"+-{100 * r['half']:.2f}% | {'yes' if r['inside'] else 'NO'} | "
                         f"{100 * r['energy_error']:+.2f}% | {r['full_wall']:.2f} / {r['sampled_wall']:.2f} |")
        else:
            lines.append(f"| {r['case']} | {r['queries']} | {r['in_flight'] or ''} | full | {r['full_cycles']} | "
                         f"{100 * r['error']:+.2f}% | exact | {'yes' if r['inside'] else 'NO'} | "
                         f"{100 * r['energy_error']:+.2f}% | {r['full_wall']:.2f} / {r['sampled_wall']:.2f} |")
    return "\n".join(lines)


def summary(rows):
    s = [r for r in rows if r["sampled"]]
    if not s:
        return f"{len(rows)} jobs, none sampled (every one simulated in full: too short for its queries in flight)"
    worst = max(s, key=lambda r: abs(r["error"]))
    inside = sum(r["inside"] for r in s)
    full_t = sum(r["full_wall"] for r in s)
    samp_t = sum(r["sampled_wall"] for r in s)
    return (f"{len(rows)} jobs, {len(s)} sampled: largest error {100 * worst['error']:+.2f}% ({worst['case']}), "
            f"{sum(abs(r['error']) <= 0.02 for r in s)} of {len(s)} within 2%, the full value inside the 95% interval "
            f"for {inside} of {len(s)} ({100 * inside / len(s):.0f}%); simulation {full_t:.1f} s full, {samp_t:.1f} s "
            f"sampled ({full_t / samp_t:.1f}x)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--kitti", default=os.path.join(ROOT, "..", "shared", "data", "kitti-00"),
                    help="a KITTI sequence folder with 000000.bin and 000001.bin (skipped when missing)")
    ap.add_argument("--sampling", default="auto", help="the sim.sampling value compared with off")
    ap.add_argument("--machines", default="paper,small-stack")
    ap.add_argument("--no-traces", action="store_true", help="skip the DP4 and DP7 registrations' jobs")
    ap.add_argument("--json", help="write every row here")
    a = ap.parse_args()
    tig = os.path.join(a.build, "bin", "tigris")
    tmp = tempfile.mkdtemp(prefix="validate-sampling-")
    workloads = [("built-in pair", [])]
    kitti = [os.path.join(a.kitti, f) for f in ("000000.bin", "000001.bin")]
    if all(os.path.exists(f) for f in kitti):
        workloads.append(("KITTI 00 1->0", ["--cloud", kitti[0], "--queries", kitti[1]]))
    traces = []
    if not a.no_traces and len(workloads) > 1:
        for preset in ("dp4", "dp7"):
            t = os.path.join(tmp, preset + ".trace")
            subprocess.run([tig, "register", "--source", kitti[1], "--target", kitti[0], "--preset", preset,
                            "--search", "exact", "--out", os.path.join(tmp, "reg-" + preset), "--record-trace", t],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            traces.append((preset.upper(), t))
    every = {}
    for machine in a.machines.split(","):
        rows = []
        for label, args in workloads:
            for r in pair_cases(tig, tmp, machine, args, a.sampling):
                r["case"] = f"{label}: {r['case']}"
                rows.append(r)
        for label, t in traces:
            rows += trace_jobs(tig, tmp, machine, t, "KITTI " + label, a.sampling)
        every[machine] = rows
        print(f"\n### Machine: {machine} {' '.join(MACHINES[machine])}\n")
        print(table(rows))
        print("\n" + summary(rows))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(every, f, indent=1)


if __name__ == "__main__":
    main()
