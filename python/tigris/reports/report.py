#!/usr/bin/python3
"""REPORT.md from sweep CSVs: the paper's claims (docs/model.md, §9 and §14), measured.

    python3 -m sweep.report CSV... --out DIR [--figures DIR | --no-figures] [--title TEXT]

Writes DIR/REPORT.md: a table of every claim (the paper's value, the measured value, whether the
direction holds, whether the size is within 2x, and an explanation made only of facts the sweep
measured), how each claim is measured, and the figures of plots.py (made into DIR/figures unless
--figures names another folder or --no-figures). Claims whose rows the CSVs lack say which
sweep they need. Nothing here is tuned toward the paper's numbers.
"""
import argparse
import csv
import math
import os
import sys

from . import core
from . import dse_data
from . import evaldata as ed
from . import tigris_sweep as ts
from . import variants as vt
from .evaldata import num

TWO_X = 2.0
KNEE_GAIN = 1.10  # a doubling that speeds up by less than 10% is past the knee
NO_CHANGE = 0.01  # a ratio within 1% of 1 is no change: a direction needs more


def up(ratio):
    """ratio is a change upwards (beyond the no-change band)."""
    return ratio > 1 + NO_CHANGE

# The paper's figures (MICRO 2019, sections 4.1 and 6), as docs/model.md (§9, §14) cites them.
PAPER = {
    "redundancy_nn_32": 35.0, "redundancy_radius_32": 3.0,
    # Acc-2SKD is 77.2x Base-2SKD, which is 1.283x Base-KD; Acc-KD is 18.7x Base-KD.
    "acc2skd_over_acckd": 77.2 * 1.283 / 18.7,
    "bypass_gain": 0.131, "forward_gain": 0.105, "mqmn_speedup": 2.0,
    "pb_share_without_nc": 0.53, "pb_share_with_nc": 0.35,
    "knee": {"ru": 64, "su": 32, "pe": 32},
    "best_height": 10, "approx_visit_cut": 0.728, "approx_speedup": 11.1,
    "split": {"pe": 0.537, "sram_read": 0.348, "sram_write": 0.080, "leakage": 0.033, "dram": 0.002},
    "acckd_energy": 2.5, "mqmn_power": 4.0, "nc_energy_saving": 0.059,
    "area_sram": 8.38, "area_logic": 7.19,
}
SPLIT_NAMES = {"pe": "PE", "sram_read": "SRAM read", "sram_write": "SRAM write",
               "leakage": "leakage", "dram": "DRAM"}
UNIT_NAMES = {"ru": ("RU", "fe.recursion_units"), "su": ("SU", "be.search_units"),
              "pe": ("PE per SU", "be.pes_per_su")}


class Claim:
    def __init__(self, cid, section, text, paper, how):
        self.cid, self.section, self.text, self.paper, self.how = cid, section, text, paper, how
        self.measured = "not measured"
        self.direction = None  # True / False / None (n/a)
        self.within = None
        self.explanation = ""
        self.speed = None        # a speed claim's ratios, slow over fast: cycles, work, leaf, pe, ideal (speed_bound)
        self.work_ratio = False  # the paper's speed-up is a work ratio no machine of this size reaches

    def missing(self, what):
        self.explanation = f"needs {what}"
        return self

    def set(self, measured, direction, within, explanation):
        self.measured, self.direction, self.within, self.explanation = measured, direction, within, explanation
        return self


def within_2x(measured, paper):
    """measured / paper in [1/2, 2]; False when the signs differ; None when either is missing."""
    if measured is None or paper is None:
        return None
    if paper == 0:
        return None
    r = measured / paper
    return r > 0 and 1 / TWO_X <= r <= TWO_X


def within_2x_gain(measured, paper):
    """For a speed-up or ratio claim ("2x"): the gains over 1 within 2x of each other, as for a
    '+x%' claim. On the factors themselves any result from 1.0x to 4x would be within 2x of a 2x
    claim, no change included."""
    return None if measured is None or paper is None else within_2x(measured - 1, paper - 1)


# ------------------------------------------------------------------ the work bound of a speed claim

PE_PARTS = ("visits.leaf_points", "visits.follower_points", "visits.leader_checks")


def run_work(row):
    """(cycles, nodes, leaf points, PE distances, ideal cycles) of a `tigris run` row. Nodes =
    top-tree nodes + PE distances (leaf points + follower points + leader checks); the ideal
    cycles are the model's `lower_bound_cycles`: the configured machine at one node per RU and
    one distance per PE per cycle, no bank conflict, free write-back (docs/model.md)."""
    pe = num(row, "visits.pe_distances")
    if pe is None:  # a row of a tigris before that column: its parts
        pe = sum(num(row, c) or 0 for c in PE_PARTS)
    return (num(row, "cycles"), (num(row, "visits.top") or 0) + pe, num(row, "visits.leaf_points") or 0, pe,
            num(row, "lower_bound_cycles"))


def register_work(row):
    """run_work of a registration with the accelerator in the loop (a registrations CSV row),
    None without its jobs' figures: cycles and visits summed over the stages
    (`stages.<key>.accelerator.*`); the ideal cycles per stage from its visits and the
    accelerator's unit counts (`accelerator.config.*`), summed, a stage's jobs following one
    another."""
    units = [num(row, f"accelerator.config.{k}") for k in ("fe.recursion_units", "be.search_units", "be.pes_per_su")]
    stages = sorted({k[len("stages."):-len(".accelerator.cycles")] for k in row
                     if k.startswith("stages.") and k.endswith(".accelerator.cycles")})
    if not stages or not all(units):
        return None
    total = [0.0] * 5
    for st in stages:
        at = lambda c: num(row, f"stages.{st}.accelerator.{c}") or 0  # noqa: E731
        top, pe = at("visits.top"), sum(at(c) for c in PE_PARTS)
        for i, v in enumerate((at("cycles"), top + pe, at("visits.leaf_points"), pe,
                               max(top / units[0], pe / (units[1] * units[2])))):
            total[i] += v
    return tuple(total)


def ratio(a, b):
    return a / b if a is not None and b else None


def speed_bound(c, slow, fast, paper=None, rule=None):
    """Records on claim c a speed claim's ratios of the slow run over the fast one (run_work
    tuples): cycles, work (nodes) and the ideal machine's; and whether the paper's speed-up
    `paper` (a factor) is a work ratio: within 2x of the work ratio by the claim's own rule
    (default within_2x_gain), yet above the ideal ratio by more than the no-change band, so no
    machine of this size reaches it as a speed-up. Returns the explanation's words for them."""
    r = [ratio(a, b) for a, b in zip(slow, fast)]
    c.speed = dict(zip(("cycles", "work", "leaf", "pe", "ideal"), r))
    c.work_ratio = bool(paper and r[1] and r[4] and (rule or within_2x_gain)(r[1], paper)
                        and paper > r[4] * (1 + NO_CHANGE))
    show = lambda v: xf(v) if v is not None else "n/a"  # noqa: E731
    return (f"work {show(r[1])} in nodes (leaf points {show(r[2])}, PE distances {show(r[3])}), "
            f"ideal machine {show(r[4])}" + (f": the paper's {paper:.3g}x is a work ratio" if c.work_ratio else ""))


def pct(x, digits=1):
    return f"{100 * x:.{digits}f}%"


def xf(x):
    return f"{x:.2f}x"


def searches(rows):
    """The searches (mode, radius, k) present, NN first, each as a `find` keyword dict."""
    seen = {}
    for r in rows:
        e = r["eff"]
        seen.setdefault((e["mode"], e["radius"], e["k"]), {"mode": e["mode"], "radius": e["radius"], "k": e["k"]})
    order = {"nn": 0, "knn": 1, "radius": 2}
    return [seen[k] for k in sorted(seen, key=lambda k: (order.get(k[0], 3), k[1] or 0, k[2] or 0))]


def label(s):
    return ed.search_label(s)


def short_bound(row):
    return ed.bound_facts(row)


# ------------------------------------------------------------------------- section 9 claims

def redundancy_curve(sw, s):
    """[(leaf-set size, redundancy, row)] for one search, from exact runs of one height sweep,
    with the canonical row (redundancy 1 at size 1); None without a canonical row."""
    rows, _ = ed.select(sw.ok, {"height", "mode", "radius", "k"}, where=lambda e: e["approx"] is None)
    canon = ed.find(rows, height=ed.CANONICAL, **s)
    if canon is None:
        return None, None
    base = ed.nodes_per_query(canon)
    pts = []
    for r in rows:
        e = r["eff"]
        if (e["mode"], e["radius"], e["k"]) != (s["mode"], s["radius"], s["k"]) or e["height"] == ed.CANONICAL:
            continue
        ls = num(r, "tree.leaf_set_mean")
        if ls and base:
            pts.append((ls, ed.nodes_per_query(r) / base, r))
    return canon, sorted(pts, key=lambda p: p[0])


def at_size(pts, size):
    """Redundancy at a leaf-set size: log-log interpolation between the two nearest measured
    sizes around it, or the nearest size when the sweep does not reach it."""
    below = [p for p in pts if p[0] <= size]
    above = [p for p in pts if p[0] >= size]
    if below and above:
        (x0, y0, _), (x1, y1, _) = below[-1], above[0]
        if x0 == x1:
            return y0, f"at leaf-set {x0:.0f}"
        t = (math.log(size) - math.log(x0)) / (math.log(x1) - math.log(x0))
        return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0))), \
            f"interpolated between leaf-sets {x0:.0f} and {x1:.0f}"
    near = min(pts, key=lambda p: abs(math.log(p[0] / size)))
    return near[1], f"nearest measured leaf-set {near[0]:.0f} (sweep does not reach {size})"


def grows(pts):
    ys = [p[1] for p in pts]
    if len(ys) < 2:
        return ys[0] > 1 if ys else None
    return ys[-1] > ys[0] and all(b >= a * 0.98 for a, b in zip(ys, ys[1:]))


# The two conventions of the redundancy (docs/model.md, fidelity targets), named in the claims' labels.
MODEL_CONV = "(model's convention: a point in every node)"
AUTHORS_CONV = "(authors' convention: classic tree, leaf size one)"


def claims_redundancy(sw):
    out, at32 = [], {}
    how = ("redundancy = nodes visited per query (top-tree nodes + leaf-set points, "
           "`visits.per_query.nodes.mean`) of the two-stage tree / the canonical tree's "
           "(`height` full), exact search; leaf-set size = `tree.leaf_set_mean`; the value at 32 "
           "is interpolated log-log between the nearest two heights. Direction: redundancy "
           "grows with leaf-set size at every step of the height sweep.")
    for mode, key in (("nn", "redundancy_nn_32"), ("radius", "redundancy_radius_32")):
        c = Claim(f"redundancy-{mode}", "9", f"two-stage redundancy grows with leaf-set size {MODEL_CONV} "
                  f"({'NN' if mode == 'nn' else 'radius'}; value at leaf-set 32)",
                  f"{PAPER[key]:g}x at 32 (KITTI)", how)
        out.append(c)
        ss = [s for s in searches(sw.ok) if s["mode"] == mode]
        if not ss:
            c.missing(f"a height sweep with `height` full and numeric heights, mode {mode}")
            continue
        canon, pts = redundancy_curve(sw, ss[0])
        if canon is None or not pts:
            c.missing(f"a canonical-tree row (`height` full) and numeric heights, {label(ss[0])}")
            continue
        v, where = at_size(pts, 32)
        at32[mode] = v
        base = ed.nodes_per_query(canon)
        near = min(pts, key=lambda p: abs(math.log(p[0] / 32)))
        r = near[2]
        q = num(r, "queries") or 1
        fact = (f"{label(ss[0])}: canonical tree {base:.0f} nodes/query; leaf-set {near[0]:.0f} "
                f"(height {r['eff']['height']}): {ed.nodes_per_query(r):.0f} nodes/query "
                f"({(num(r, 'visits.leaf_points') or 0) / q:.0f} leaf points, "
                f"{(num(r, 'visits.top') or 0) / q:.0f} top nodes); redundancy "
                + ", ".join(f"{p[1]:.2f}x@{p[0]:.0f}" for p in pts) + f"; value {where}")
        c.set(xf(v), grows(pts), within_2x_gain(v, PAPER[key]), fact)
    c = Claim("redundancy-nn-vs-radius", "9", f"redundancy grows faster for NN than for radius {MODEL_CONV} "
              "(NN / radius redundancy at leaf-set 32)",
              f"{PAPER['redundancy_nn_32']:g}x / {PAPER['redundancy_radius_32']:g}x = "
              f"{PAPER['redundancy_nn_32'] / PAPER['redundancy_radius_32']:.1f}", how)
    out.append(c)
    if "nn" in at32 and "radius" in at32:
        ratio = at32["nn"] / at32["radius"]
        paper = PAPER["redundancy_nn_32"] / PAPER["redundancy_radius_32"]
        c.set(f"{at32['nn']:.2f}x / {at32['radius']:.2f}x = {ratio:.2f}", up(ratio),
              within_2x_gain(ratio, paper), "from the two rows above")
    else:
        c.missing("both the NN and the radius height sweeps with a canonical row")
    return out


def claims_redundancy_conventions(path):
    """The redundancy at leaf-set 32 in both conventions, from a `tigris ref --redundancy` sweep
    (reproduce's `redundancy` experiment): frame 1 in frame 0 and the cloud in itself."""
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("status") == "ok" and r.get("redundancy.authors.ratio")]
    how = ("`tigris ref --redundancy` at heights 11 and 12, interpolated log-log to leaf-set 32: the authors' "
           "convention (their code, horizon-research/PointCloud-pipeline kdtree.h) counts distance computations "
           "of a classic tree with points only in leaves and bounding-box pruning, leaves of about the leaf-set "
           "size against leaves of one point; the model's counts nodes visited (top-tree nodes + leaf-set "
           "points) against the canonical tree (docs/model.md, fidelity targets); every search is checked "
           "against the golden model")
    groups = {}
    for r in rows:
        key = (r.get("mode"), r.get("redundancy.queries"))
        groups.setdefault(key, []).append(r)
    out, verdict = [], {}
    for mode, paper in (("nn", PAPER["redundancy_nn_32"]), ("radius", PAPER["redundancy_radius_32"])):
        for queries, where in (("another frame", "frame 1 in frame 0"), ("the cloud itself", "the cloud in itself")):
            g = sorted(groups.get((mode, queries), []), key=lambda r: float(r["tree.leaf_set_mean"]))
            rad = next((r.get("radius") for r in g if r.get("radius")), "")
            label_ = "NN" if mode == "nn" else (f"radius {float(rad):.2f} m" if rad else "radius")
            c = Claim(f"redundancy-authors-{mode}-{'self' if 'itself' in queries else 'cross'}", "9",
                      f"two-stage redundancy at leaf-set 32 {AUTHORS_CONV} ({label_}, {where})",
                      f"{paper:g}x at 32 (KITTI)", how)
            if not g:
                out.append(c.missing("a `tigris ref --redundancy` run of this search "
                                     + ("with a cloud file (the built-in pair has no cloud to search in itself)"
                                        if "itself" in queries else "")))
                continue
            pts = lambda col: [(float(r["tree.leaf_set_mean"]), float(r[col]), r) for r in g]  # noqa: E731
            authors, at = at_size(pts("redundancy.authors.ratio"), 32)
            model, _ = at_size(pts("redundancy.model.ratio"), 32)
            r = min(g, key=lambda x: abs(math.log(float(x["tree.leaf_set_mean"]) / 32)))  # its counts are quoted
            verdict[(mode, queries)] = (abs(math.log(authors / paper)), abs(math.log(model / paper)))
            expl = (f"{at}; authors' convention {authors:.2f}x (at leaf-set {float(r['tree.leaf_set_mean']):.0f}: "
                    f"classic tree, leaves of at most "
                    f"{r['redundancy.authors.leaf_max']} points: {float(r['redundancy.authors.per_query']):.1f} "
                    f"distances/query, leaves of one point {float(r['redundancy.authors.leaf_one_per_query']):.1f}); "
                    f"the model's convention {model:.2f}x ({float(r['redundancy.model.two_stage_per_query']):.1f} "
                    f"nodes/query, canonical tree {float(r['redundancy.model.canonical_per_query']):.1f})")
            if "itself" in queries and mode == "nn":
                expl += ("; degenerate: a leaf-one tree finds a query's own point with about one distance, so "
                         "the ratio is about the leaf size")
            out.append(c.set(f"{authors:.2f}x (model's convention {model:.2f}x)", up(authors), within_2x(authors, paper),
                             expl))
    c = Claim("redundancy-convention", "9", "the paper's redundancy figures (35x NN, 3x radius) are nearer the "
              "authors' convention than the model's (frame 1 in frame 0)", "authors' convention", how)
    cross = [verdict.get((m, "another frame")) for m in ("nn", "radius")]
    if all(cross):
        nearer = [a < m for a, m in cross]
        out.append(c.set(f"authors' nearer for {sum(nearer)} of 2 (NN {math.exp(cross[0][0]):.1f}x vs "
                         f"{math.exp(cross[0][1]):.1f}x off, radius {math.exp(cross[1][0]):.2f}x vs "
                         f"{math.exp(cross[1][1]):.2f}x off)", all(nearer), None,
                         "how far each convention's value at leaf-set 32 is from the paper's (a factor), NN and "
                         "radius, frame 1 in frame 0 (the rows above)"))
    else:
        out.append(c.missing("the NN and radius rows above"))
    return out


def _csv_rows(paths):
    """The ok rows of a CSV, or of several in order (a list: None and missing files skipped)."""
    out = []
    for path in paths if isinstance(paths, (list, tuple)) else [paths]:
        if path and os.path.isfile(path):
            with open(path, newline="") as f:
                out += [r for r in csv.DictReader(f) if r.get("status") == "ok"]
    return out


def _f(row, col):
    try:
        return float(row[col])
    except (KeyError, TypeError, ValueError):
        return None


GPU_HOW = ("needs a GPU: the paper's baselines Base-KD / Base-2SKD run the KD-tree searches on an Nvidia RTX 2080 "
           "Ti (the rest on a Xeon Silver 4110); time the same registrations' searches there (e.g. FLANN's CUDA "
           "KD-tree index) and compare them with the modeled KD-tree seconds of `tigris register --compare`")


def claims_headline(reg_csv, odo_csv):
    """The paper's most quoted claims (section 6): end to end with the accelerator in the loop
    against the CPU-only system, the approximate search's speed-up and accuracy cost, and the
    GPU comparisons (not measurable here). From reproduce's `registrations` sweep (tigris
    register points; several CSVs: a later one's point of a preset and search replaces an
    earlier one's, an accounting's accelerator points the default's) and `odometry-approx`
    sweep (tigris odometry over a synthetic drive)."""
    reg = {(r.get("preset"), r.get("search")): r for r in _csv_rows(reg_csv)}
    how = ("`tigris register` of frame 1 into frame 0 per preset and back-end (reproduce's `registrations` sweep): "
           "end to end = the registration's seconds on the CPU (PCL's FLANN: the CPU-only system) against the "
           "accelerator in the loop (its modeled KD-tree and host time + the run's other CPU time); one timing each, "
           "with the sweep's --jobs points side by side, which slows the CPU parts (`tigris register --compare "
           "--repeat N` gives quotable medians with ranges on an idle machine)")
    out = []

    def e2e(p, s):
        r = reg.get((p, s))
        if not r:
            return None
        return _f(r, "seconds") if s in ("flann", "exact") else _f(r, "accelerator.modeled_end_to_end_seconds")

    def kd(p, s):
        r = reg.get((p, s))
        return None if not r else (_f(r, "kdtree_seconds") if s in ("flann", "exact")
                                   else _f(r, "accelerator.modeled_kdtree_seconds"))

    for p, paper in (("dp7", 0.866), ("dp4", None)):
        c = Claim(f"e2e-cpu-{p}", "9", f"{p.upper()} end to end: the accelerator (exact) against the CPU-only system",
                  "-86.6%" if paper else "n/a (the paper gives DP4 against the GPU only)", how)
        cpu, acc = e2e(p, "flann"), e2e(p, "accel")
        if cpu and acc:
            cut = 1 - acc / cpu
            out.append(c.set(f"-{pct(cut)}", cut > NO_CHANGE, within_2x(cut, paper) if paper else None,
                             f"CPU with FLANN {cpu:.2f} s (KD-tree {kd(p, 'flann'):.2f} s) -> {acc:.2f} s (KD-tree "
                             f"{kd(p, 'accel'):.4f} s modeled); what remains is the CPU's work outside KD-tree search"))
        else:
            out.append(c.missing(f"`tigris register --preset {p}` with --search flann and accel (reproduce's "
                                 "registrations sweep)"))
    c = Claim("approx-kd-dp7", "9", "approximate search speeds up the KD-tree search over Acc-2SKD (DP7, whole "
              "registration; exact / approximate modeled KD-tree seconds)", "11.1x", how)
    ex, ap = kd("dp7", "accel"), kd("dp7", "accel-approx")
    if ex and ap:
        works = [register_work(reg[("dp7", s)]) for s in ("accel", "accel-approx")]
        work = "; accelerator jobs: " + speed_bound(c, *works, PAPER["approx_speedup"]) if all(works) else ""
        fb = [_f(reg[("dp7", s)], "accelerator.fallback_searches") for s in ("accel", "accel-approx")]
        if all(works) and None not in fb:  # the modeled seconds hold both: the jobs' cycles, the CPU's fallbacks
            work += (f"; the jobs' cycles {works[0][0]:,.0f} -> {works[1][0]:,.0f}, searches the accelerator could "
                     f"not batch (timed on the CPU, in the modeled seconds) {fb[0]:,.0f} -> {fb[1]:,.0f}")
        out.append(c.set(xf(ex / ap), up(ex / ap), within_2x_gain(ex / ap, PAPER["approx_speedup"]),
                         f"modeled KD-tree {ex:.4f} s -> {ap:.4f} s (normal estimation's radius searches and ICP's "
                         f"NN searches together; the single-job claims above show each){work}"))
    else:
        out.append(c.missing("`tigris register --preset dp7` with --search accel and accel-approx"))
    c = Claim("approx-e2e-dp7", "9", "approximate search improves the end to end (DP7, accelerator exact / "
              "approximate)", "+7.5%", how)
    ex, ap = e2e("dp7", "accel"), e2e("dp7", "accel-approx")
    if ex and ap:
        g = ex / ap - 1
        out.append(c.set(f"{'+' if g >= 0 else ''}{pct(g)}", g > NO_CHANGE, within_2x(g, 0.075),
                         f"end to end {ex:.2f} s -> {ap:.2f} s"))
    else:
        out.append(c.missing("`tigris register --preset dp7` with --search accel and accel-approx"))

    # Accuracy: per metre of the drive, from the relative pose errors (a short synthetic drive
    # has no 100 m KITTI segment; KITTI's r_err is per metre too).
    # Rows of the authors' convention set the per-stage leaf sizes (reproduce.AUTHORS_ACCURACY).
    odo = {(r.get("preset"), r.get("search"), "authors" if _f(r, "search.rpce_leaf_size") else "model"): r
           for r in _csv_rows(odo_csv)}
    ohow = ("`tigris odometry --synthetic N` per preset, search exact and approximate (reproduce's `odometry-approx` "
            "sweep): translation error = mean RPE translation / mean step, in %; rotation error = mean RPE rotation "
            "/ mean step, in deg/m (the drive is shorter than KITTI's 100 m segments, so its t_err/r_err are empty). "
            "Two conventions: the model's (the preset's top height 10, 16 leaders per leaf) and the authors' "
            "(PointCloud-pipeline's bin/config.txt: leaves of 64 points for normal estimation and 32 for ICP, "
            "`search.normals_leaf_size` / `search.rpce_leaf_size`, and a leader list bounded by nothing, "
            "`search.leader_capacity` 2^20), exact search being the same in both")
    for p, rot in (("dp4", 0.05), ("dp7", 0.0006)):
        for conv, label_ in (("model", ""), ("authors", ", authors' convention: leaves of 64 / 32 points, unbounded "
                                                       "leaders")):
            out += accuracy_claims(p, rot, odo.get((p, "exact", "model")), odo.get((p, "approx", conv)),
                                   "" if conv == "model" else "-authors", label_, ohow)
    for cid, text, paper in (("gpu-kd", "the accelerator's KD-tree search against the GPU (DP7, Acc-2SKD / Base-KD)",
                              "77.2x"),
                             ("gpu-e2e", "end to end against the GPU baseline (DP7)", "-41.7%"),
                             ("gpu-e2e-dp4", "end to end against the GPU two-stage baseline (DP4, Acc-2SKD / "
                              "Base-2SKD)", "-13.6%")):
        c = Claim(cid, "9", text, paper, GPU_HOW)
        c.explanation = GPU_HOW
        out.append(c)
    return out


def _per_metre(r, col):
    """A per-pair error of an odometry row per metre of its drive."""
    v, pairs, length = _f(r, col), _f(r, "pairs"), _f(r, "kitti.trajectory_length_m")
    return v * pairs / length if v is not None and pairs and length else None


def accuracy_claims(p, rot, e, a, suffix, label_, how):
    """The approximate search's accuracy cost for preset p (exact row e, approximate row a):
    translation unchanged, rotation +rot deg/m (the paper's)."""
    c = Claim(f"approx-t-{p}{suffix}", "9", f"approximate search leaves the translation error unchanged "
              f"({p.upper()}{label_})", "unchanged", how)
    c2 = Claim(f"approx-r-{p}{suffix}", "9", f"approximate search adds little rotation error ({p.upper()}, "
               f"deg/m{label_})", f"+{rot:g} deg/m", how)
    want = f"odometry over a synthetic drive with --preset {p}, exact and approximate" + \
        (" (the authors' leaf sizes)" if suffix else "")
    if not (e and a):
        return [c.missing(want), c2.missing(want)]
    te, ta = _per_metre(e, "rpe.mean_translation_m"), _per_metre(a, "rpe.mean_translation_m")
    re_, ra = _per_metre(e, "rpe.mean_rotation_deg"), _per_metre(a, "rpe.mean_rotation_deg")
    if None in (te, ta, re_, ra):
        return [c.missing("the runs' RPE and trajectory length"), c2.missing("the runs' RPE and trajectory length")]
    c.set(f"{100 * te:.3f}% -> {100 * ta:.3f}% of the distance", ta <= te * (1 + NO_CHANGE) + 1e-12, None,
          f"{e.get('pairs')} pairs; mean RPE {_f(e, 'rpe.mean_translation_m') * 1e3:.2f} -> "
          f"{_f(a, 'rpe.mean_translation_m') * 1e3:.2f} mm per pair")
    d = ra - re_
    c2.set(f"{'+' if d >= 0 else ''}{d:.4f} deg/m ({re_:.4f} -> {ra:.4f})", d >= 0,
           within_2x(d, rot) if d > 0 else False,
           f"mean RPE rotation {_f(e, 'rpe.mean_rotation_deg'):.4f} -> {_f(a, 'rpe.mean_rotation_deg'):.4f} deg per pair")
    return [c, c2]


def claims_acc_kd(sw):
    out = []
    how = ("cycles of the canonical tree (`height` full, Acc-KD) / cycles at top height 10 "
           "(Acc-2SKD), exact search, default machine. The paper's figure compares both with "
           "GPU baselines: 77.2x (over Base-2SKD, itself 1.283x Base-KD) vs 18.7x (over Base-KD) "
           "= 5.3x.")
    found = False
    for s in searches(sw.ok):
        kd = ed.find(sw.ok, height=ed.CANONICAL, **s)
        two = ed.find(sw.ok, height=10, **s)
        if kd is None or two is None:
            continue
        found = True
        v = num(kd, "cycles") / num(two, "cycles")
        c = Claim(f"acc2skd-vs-acckd-{s['mode']}", "9", f"Acc-2SKD beats Acc-KD ({label(s)}; "
                  "speed-up of Acc-2SKD over Acc-KD)", f"{PAPER['acc2skd_over_acckd']:.1f}x", how)
        work = speed_bound(c, run_work(kd), run_work(two), PAPER["acc2skd_over_acckd"])
        c.set(xf(v), up(v), within_2x_gain(v, PAPER["acc2skd_over_acckd"]),
              f"Acc-KD {num(kd, 'cycles'):,.0f} cycles, {short_bound(kd)}. "
              f"Acc-2SKD {num(two, 'cycles'):,.0f} cycles, {short_bound(two)}; {work}")
        out.append(c)
    if not found:
        out.append(Claim("acc2skd-vs-acckd", "9", "Acc-2SKD beats Acc-KD (speed-up of Acc-2SKD "
                         "over Acc-KD)", f"{PAPER['acc2skd_over_acckd']:.1f}x", how)
                   .missing("rows at `height` full and 10 (exact, default machine)"))
    return out


def _opt_rows(sw, s):
    f = lambda **kw: ed.find(sw.ok, **dict(s, **kw))  # noqa: E731
    return {"No-Opt": f(bypass=False, forward=False), "Bypass": f(forward=False),
            "+Forward": f(), "MQMN": f(policy="mqmn")}


def claims_optimizations(sw):
    out = []
    spec = [
        ("bypass", "bypassing helps (No-Opt -> Bypass, speed-up)", "No-Opt", "Bypass",
         "bypass_gain", "+13.1%"),
        ("forward", "forwarding helps (Bypass -> +Forward, speed-up)", "Bypass", "+Forward",
         "forward_gain", "+10.5%"),
        ("mqmn-speed", "MQMN ~2x faster than MQSN (+Forward -> MQMN, speed-up)", "+Forward",
         "MQMN", "mqmn_speedup", "2x"),
    ]
    how_gain = ("gain = cycles(before) / cycles(after) - 1, exact search, top height 10, default "
                "machine; No-Opt = fe.bypassing=false, fe.forwarding=false; Bypass = "
                "fe.forwarding=false; +Forward = both on (default); MQMN = be.issue_policy=mqmn "
                "with both on. The size test compares the gains (for MQMN the speed-ups).")
    ss = searches(sw.ok)
    for cid, text, a, b, key, paper in spec:
        done = False
        for s in ss:
            rows = _opt_rows(sw, s)
            ra, rb = rows[a], rows[b]
            if ra is None or rb is None:
                continue
            done = True
            sp = num(ra, "cycles") / num(rb, "cycles")
            c = Claim(f"{cid}-{s['mode']}", "9", f"{text}, {label(s)}", paper, how_gain)
            if cid == "bypass":
                fact = (f"RU prune cycles {num(ra, 'units.recursion_units.prune_cycles') or 0:,.0f} -> "
                        f"{num(rb, 'units.recursion_units.prune_cycles') or 0:,.0f}; No-Opt: {short_bound(ra)}")
            elif cid == "forward":
                fact = (f"RU PI->RS stall cycles "
                        f"{num(ra, 'units.recursion_units.stall_cycles.pi_rs_dependency') or 0:,.0f} -> "
                        f"{num(rb, 'units.recursion_units.stall_cycles.pi_rs_dependency') or 0:,.0f}; "
                        f"Bypass: {short_bound(ra)}")
            else:
                fact = (f"MQSN: {num(ra, 'units.search_units.queries_per_batch') or 0:.2f} queries/batch, "
                        f"{short_bound(ra)}. MQMN: {short_bound(rb)}")
            factor = PAPER[key] if cid == "mqmn-speed" else 1 + PAPER[key]  # a gain's speed-up
            fact += "; " + speed_bound(c, run_work(ra), run_work(rb), factor)
            if cid == "mqmn-speed":
                c.set(xf(sp), up(sp), within_2x_gain(sp, PAPER[key]), fact)
            else:
                c.set(f"{100 * (sp - 1):+.1f}%", up(sp), within_2x(sp - 1, PAPER[key]), fact)
            out.append(c)
        if not done:
            out.append(Claim(cid, "9", text, paper, how_gain).missing(
                f"the {a} and {b} rows (fe.bypassing / fe.forwarding / be.issue_policy)"))
    how = ("Node Set bytes read (Point Buffer `buffers.points.read_bytes` + Node Cache "
           "`buffers.node_cache.read_bytes`: a Node Set streams from one or the other) with MQMN "
           "/ with MQSN (+Forward), exact search, top height 10; the paper gives no number "
           "(direction only). The Point Buffer alone is in the explanation.")
    done = False
    for s in ss:
        rows = _opt_rows(sw, s)
        if rows["+Forward"] is None or rows["MQMN"] is None:
            continue
        done = True
        a, b = rows["+Forward"], rows["MQMN"]
        pa, pb = num(a, "buffers.points.read_bytes") or 0, num(b, "buffers.points.read_bytes") or 0
        na, nb = num(a, "buffers.node_cache.read_bytes") or 0, num(b, "buffers.node_cache.read_bytes") or 0
        v = (pb + nb) / (pa + na) if pa + na else float("nan")
        ta, tb = (sum(ed.buffer_traffic(r, sw.columns).values()) for r in (a, b))
        c = Claim(f"mqmn-traffic-{s['mode']}", "9", f"MQMN has far more Point Buffer (Node Set) "
                  f"traffic than MQSN ({label(s)}; MQMN / MQSN bytes)", "far more (no number)", how)
        c.set(xf(v), up(v), None,
              f"Point Buffer {ed.fmt_bytes(pa)} -> {ed.fmt_bytes(pb)} ({pb / pa if pa else 0:.2f}x); "
              f"Node Cache reads {ed.fmt_bytes(na)} -> {ed.fmt_bytes(nb)}; all on-chip traffic "
              f"{ed.fmt_bytes(ta)} -> {ed.fmt_bytes(tb)}")
        out.append(c)
    if not done:
        out.append(Claim("mqmn-traffic", "9", "MQMN has far more Point Buffer traffic than MQSN",
                         "far more (no number)", how).missing("the +Forward and MQMN rows"))
    return out


def _nc_rows(sw, s):
    return ed.find(sw.ok, **s), ed.find(sw.ok, nc_bytes=0, **s)


def claims_node_cache(sw):
    out = []
    how = ("share of the Point Buffer's bytes (read + write) in all on-chip buffer traffic "
           "(every `buffers.<b>` read + write bytes, the Node Cache's read + fill bytes; DRAM not "
           "counted), top height 10, exact search, `node_cache.bytes` 0 vs the default 128 KiB.")
    done = False
    for s in searches(sw.ok):
        w, wo = _nc_rows(sw, s)
        if w is None or wo is None:
            continue
        done = True
        tw, two = ed.buffer_traffic(w, sw.columns), ed.buffer_traffic(wo, sw.columns)
        sw_, swo = tw.get("points", 0) / sum(tw.values()), two.get("points", 0) / sum(two.values())
        hits, miss = num(w, "buffers.node_cache.hits") or 0, num(w, "buffers.node_cache.misses") or 0
        c1 = Claim(f"pb-share-without-nc-{s['mode']}", "9", f"Point Buffer share of memory traffic "
                   f"without the Node Cache ({label(s)})", "53%", how)
        c1.set(pct(swo, 0), None, within_2x(swo, PAPER["pb_share_without_nc"]),
               f"Point Buffer {ed.fmt_bytes(two.get('points', 0))} of {ed.fmt_bytes(sum(two.values()))}")
        c2 = Claim(f"pb-share-with-nc-{s['mode']}", "9", f"the Node Cache moves Point Buffer "
                   f"traffic down ({label(s)}; share with the Node Cache)", "53% -> 35%", how)
        c2.set(f"{pct(swo, 0)} -> {pct(sw_, 0)}", up(swo / sw_) if sw_ else True, within_2x(sw_, PAPER["pb_share_with_nc"]),
               f"Node Cache hit rate {pct(hits / (hits + miss) if hits + miss else 0, 0)} "
               f"({hits:,.0f} hits, {miss:,.0f} misses), fills {ed.fmt_bytes(num(w, 'buffers.node_cache.fill_bytes') or 0)}, "
               f"reads {ed.fmt_bytes(num(w, 'buffers.node_cache.read_bytes') or 0)}; Point Buffer "
               f"{ed.fmt_bytes(two.get('points', 0))} -> {ed.fmt_bytes(tw.get('points', 0))}")
        out += [c1, c2]
    if not done:
        out.append(Claim("pb-share", "9", "the Node Cache moves Point Buffer traffic from ~53% to "
                         "~35% of the total", "53% -> 35%", how)
                   .missing("rows with `node_cache.bytes` 0 and the default at top height 10"))
    return out


def _speedups(sw, axis, fixed):
    """[(value, cycles, row)] along one unit axis, the other two at their defaults."""
    vals = sorted({r["eff"][axis] for r in sw.ok})
    pts = []
    for v in vals:
        r = ed.find(sw.ok, **dict(fixed, **{axis: v}))
        if r is not None:
            pts.append((v, num(r, "cycles"), r))
    return pts


def claims_units(sw):
    out = []
    how = (f"cycles along one axis of the RU x SU x PE sweep with the other two at the paper's "
           f"64 RU / 32 SU / 32 PE (exact search, top height 10); the knee is the smallest count "
           f"whose doubling speeds up by less than {100 * (KNEE_GAIN - 1):.0f}% (when every doubling "
           f"swept gains more, the knee is at or beyond the largest count: '>= N', within 2x only "
           f"decidable when N > 2x the paper's). Direction: the doubling into the paper's knee "
           f"gains at least {100 * (KNEE_GAIN - 1):.0f}% and more than the doubling out of it. Size: knee within a factor 2 of the paper's.")
    for s in searches(sw.ok)[:1]:
        for axis, (name, col) in UNIT_NAMES.items():
            paper = PAPER["knee"][axis]
            c = Claim(f"knee-{axis}", "9", f"RU/SU/PE sweep: knee in {name} count ({label(s)})",
                      f"{paper}", how)
            out.append(c)
            pts = _speedups(sw, axis, s)
            if len(pts) < 2:
                c.missing(f"a sweep of `{col}` (the other two at the defaults)")
                continue
            by = {v: cyc for v, cyc, _ in pts}
            doublings = [(v, by[v] / by[2 * v]) for v, _, _ in pts if 2 * v in by]
            if not doublings:
                c.missing(f"two `{col}` values a factor 2 apart (the other two at the defaults)")
                continue
            knee = next((v for v, g in doublings if g < KNEE_GAIN), None)
            at = knee if knee is not None else doublings[-1][0]  # the doubling at the knee, or the last
            rows = {v: r for v, _, r in pts}
            work = f"; doubling {at}->{2 * at}: " + speed_bound(c, run_work(rows[at]), run_work(rows[2 * at]))
            direction = None
            if paper // 2 in by and paper in by and 2 * paper in by:
                into, out_of = by[paper // 2] / by[paper], by[paper] / by[2 * paper]
                direction = into >= KNEE_GAIN and out_of < into
            steps = ", ".join(f"{v}->{2 * v} {g:.2f}x" for v, g in doublings)
            if knee is None:
                # Every doubling swept gains >= 10%: the knee lies beyond the last doubling.
                last = doublings[-1][0] * 2
                knee_row = [r for v, _, r in pts if v == last][0]
                c.set(f">= {last} (every doubling swept gains >= {100 * (KNEE_GAIN - 1):.0f}%)",
                      direction, False if last > 2 * paper else None,
                      f"speed-up per doubling: {steps}; at {last} {name}: {short_bound(knee_row)}{work}")
            else:
                knee_row = [r for v, _, r in pts if v == knee][0]
                c.set(f"{knee}", direction, within_2x(knee, paper),
                      f"speed-up per doubling: {steps}; at {knee} {name}: {short_bound(knee_row)}{work}")
        # At few RUs the front-end bounds the run: SU/PE counts help little.
        c = Claim("low-ru-frontend-bound", "9", "at 16-32 RU the front-end bounds the run: more "
                  "SU x PE helps only marginally (back-end scaling gain at the fewest RU / at 64 RU)",
                  "marginal at 16-32 RU; balanced at 64 (no number)",
                  "speed-up from the smallest to the largest SU x PE configuration swept, at the "
                  "fewest RUs swept and at 64 RUs (exact search, top height 10). Direction: the "
                  "gain at the fewest RUs is smaller.")
        out.append(c)
        grid = [r for r in sw.ok if all(r["eff"][k] == v for k, v in s.items())
                and r["eff"]["approx"] is None]
        grid, _ = ed.select(grid, {"ru", "su", "pe"})
        rus = sorted({r["eff"]["ru"] for r in grid})
        common = None
        for ru in rus:
            cf = {(r["eff"]["su"], r["eff"]["pe"]) for r in grid if r["eff"]["ru"] == ru}
            common = cf if common is None else common & cf
        if len(rus) < 2 or 64 not in rus or rus[0] >= 64 or not common or len(common) < 2:
            c.missing("an RU x (SU or PE) grid that includes 64 RU and fewer")
            continue
        lo_cfg = min(common, key=lambda t: (t[0] * t[1], t[0]))
        hi_cfg = max(common, key=lambda t: (t[0] * t[1], t[0]))

        def gain(ru):
            a = ed.find(grid, ru=ru, su=lo_cfg[0], pe=lo_cfg[1], **s)
            b = ed.find(grid, ru=ru, su=hi_cfg[0], pe=hi_cfg[1], **s)
            if a is None or b is None or not num(a, "cycles") or not num(b, "cycles"):
                return None, None
            return num(a, "cycles") / num(b, "cycles"), b
        g_lo, row_lo = gain(rus[0])
        g_64, _ = gain(64)
        if g_lo is None or g_64 is None:         # e.g. a small cloud: no row at top height 10
            c.missing(f"the grid's {lo_cfg[0]}x{lo_cfg[1]} and {hi_cfg[0]}x{hi_cfg[1]} rows at "
                      f"{rus[0]} and 64 RU at the default top height 10")
            continue
        c.set(f"{xf(g_lo)} at {rus[0]} RU vs {xf(g_64)} at 64 RU "
              f"({lo_cfg[0]}x{lo_cfg[1]} -> {hi_cfg[0]}x{hi_cfg[1]})", up(g_64 / g_lo), None,
              f"{rus[0]} RU with {hi_cfg[0]} SU x {hi_cfg[1]} PE: {short_bound(row_lo)}")
    if not out:
        out.append(Claim("knee", "9", "RU/SU/PE sweep 16..128 has its knee near 64/32/32",
                         "64 / 32 / 32", how).missing("an RU x SU x PE sweep"))
    return out


def claims_height(sw):
    out = []
    how = ("cycles over the swept numeric top heights (exact search, default machine); best = "
           "fewest cycles. Direction: cycles fall, then rise (the best is inside the swept "
           "range, not at either end, and both ends take more than 1% more cycles). Size: best height within a factor 2 of 10.")
    for s in searches(sw.ok):
        rows, _ = ed.select(sw.ok, {"height", "mode", "radius", "k"}, where=lambda e: e["approx"] is None)
        rows = sorted((r for r in rows if all(r["eff"][k] == v for k, v in s.items())
                       and r["eff"]["height"] != ed.CANONICAL), key=lambda r: r["eff"]["height"])
        if len(rows) < 3:
            continue
        cyc = [num(r, "cycles") for r in rows]
        i = min(range(len(rows)), key=lambda j: cyc[j])
        best = rows[i]["eff"]["height"]
        spread = max(cyc) / min(cyc)
        c = Claim(f"best-height-{s['mode']}", "9", f"top height ~10 is best ({label(s)})", "10", how)
        c.set(f"{best}", 0 < i < len(rows) - 1 and up(cyc[0] / cyc[i]) and up(cyc[-1] / cyc[i]),
              within_2x(best, PAPER["best_height"]),
              "cycles " + ", ".join(f"h{r['eff']['height']} {v:,.0f}" for r, v in zip(rows, cyc))
              + f" (max/min {spread:.2f}); lowest height: {short_bound(rows[0])}; "
              f"highest: {short_bound(rows[-1])}")
        out.append(c)
    if not out:
        out.append(Claim("best-height", "9", "top height ~10 is best", "10", how)
                   .missing("a sweep of at least three numeric `height` values"))
    return out


def claims_approx(sw):
    out = []
    how = ("1 - nodes visited (top nodes + leaf points + leader checks + follower points per "
           "query) with approximate search at the paper's threshold (1.2 m for NN/kNN, 0.4 r for "
           "radius) / with exact search; top height 10, default machine. The paper's 72.8% is "
           "over DP7's mix of NN and radius searches. Registration error is not part of a "
           "sweep (docs/registration.md: `tigris register --search approx`).")
    for s in searches(sw.ok):
        thd = 0.4 * s["radius"] if s["mode"] == "radius" else 1.2
        ex = ed.find(sw.ok, **s)
        ap = ed.find(sw.ok, approx=thd, **s)
        if ex is None or ap is None:
            continue
        v = 1 - ed.nodes_per_query(ap) / ed.nodes_per_query(ex)
        if s["mode"] == "radius":
            acc = (f"recall {num(ap, 'accuracy.recall') or 0:.4f}, precision "
                   f"{num(ap, 'accuracy.precision') or 0:.4f}")
        else:
            acc = (f"{pct(num(ap, 'accuracy.exact_match_fraction') or 0)} of queries exact, extra "
                   f"distance mean {num(ap, 'accuracy.mean_extra_distance_m') or 0:.3f} m, max "
                   f"{num(ap, 'accuracy.max_extra_distance_m') or 0:.2f} m")
        c = Claim(f"approx-visits-{s['mode']}", "9", f"approximate search cuts visited nodes "
                  f"({label(s)}, thd {thd:.2f} m)", "-72.8% (DP7)", how)
        c.set(f"-{pct(v)}" if v >= 0 else f"+{pct(-v)}", v > NO_CHANGE, within_2x(v, PAPER["approx_visit_cut"]),
              f"nodes/query {ed.nodes_per_query(ex):.0f} -> {ed.nodes_per_query(ap):.0f}; "
              f"{num(ap, 'leaders.leaders') or 0:,.0f} leaders, {num(ap, 'leaders.followers') or 0:,.0f} "
              f"followers; cycles {num(ex, 'cycles'):,.0f} -> {num(ap, 'cycles'):,.0f}; {acc}")
        out.append(c)
        sp = num(ex, "cycles") / num(ap, "cycles")
        c = Claim(f"approx-speedup-{s['mode']}", "9", f"approximate search speeds up the search "
                  f"({label(s)}, thd {thd:.2f} m; exact cycles / approximate cycles)", "11.1x (DP7)",
                  "cycles of exact search / cycles with approximate search at the paper's threshold, "
                  "same machine and tree. The paper's 11.1x is DP7's whole KD-tree search over Acc-2SKD.")
        work = speed_bound(c, run_work(ex), run_work(ap), PAPER["approx_speedup"], rule=within_2x)
        c.set(f"{sp:.2f}x", sp > 1 + NO_CHANGE, within_2x(sp, PAPER["approx_speedup"]),
              f"exact: {short_bound(ex)}; approximate: {short_bound(ap)}; "
              f"{num(ap, 'leaders.followers') or 0:,.0f} followers; {work}")
        out.append(c)
    if not out:
        out.append(Claim("approx-visits", "9", "approximate search cuts visited nodes by ~70%",
                         "-72.8% (DP7)", how)
                   .missing("an exact row and one at `approx-thd` 1.2 (NN) or 0.4 r (radius)"))
    return out


# ------------------------------------------------------------------------- section 14 claims

def claims_energy(sw):
    out = []
    ss = searches(sw.ok)
    how = ("share of `energy_pj.<part>` in `energy_pj.total`, default configuration, exact "
           "search (the first search present, NN preferred); the paper's split is DP4's (NN and "
           "radius 0.30 searches). Direction: the part has the same rank among the five as in "
           "the paper.")
    default = next((ed.find(sw.ok, **s) for s in ss if ed.find(sw.ok, **s) is not None), None)
    if default is not None and num(default, "energy_pj.total"):
        tot = num(default, "energy_pj.total")
        shares = {p: (num(default, f"energy_pj.{p}") or 0) / tot for p in SPLIT_NAMES}
        rank_m = sorted(shares, key=lambda p: -shares[p])
        rank_p = sorted(PAPER["split"], key=lambda p: -PAPER["split"][p])
        others = {p: (num(default, f"energy_pj.{p}") or 0) / tot for p in ("ru", "node_cache", "leader_buffer")}
        s = default["eff"]
        for p, name in SPLIT_NAMES.items():
            if p == "dram":
                wb = num(default, "buffers.dram.write_bytes") or 0
                fact = (f"{ed.fmt_bytes(wb)} of results written to DRAM at "
                        f"{(num(default, 'energy_pj.dram') or 0) / wb if wb else 0:.0f} pJ/byte")
            elif p == "pe":
                q = num(default, "queries") or 1
                fact = (f"{((num(default, 'visits.leaf_points') or 0) + (num(default, 'visits.leader_checks') or 0) + (num(default, 'visits.follower_points') or 0)) / q:.0f} "
                        f"PE distances per query")
            elif p == "leakage":
                fact = (f"{num(default, 'area_mm2.total') or 0:.2f} mm2 over {num(default, 'cycles'):,.0f} cycles")
            else:
                tr = sum(ed.buffer_traffic(default, sw.columns).values())
                fact = f"all on-chip traffic {ed.fmt_bytes(tr)}"
            fact += (f"; rank {rank_m.index(p) + 1} of 5 (paper {rank_p.index(p) + 1}); parts the "
                     f"paper's split does not name: RU {pct(others['ru'])}, Node Cache "
                     f"{pct(others['node_cache'])}, Leader Buffer {pct(others['leader_buffer'])}")
            c = Claim(f"split-{p}", "14", f"energy split: {name} ({label(s)}, default machine)",
                      pct(PAPER["split"][p]), how)
            c.set(pct(shares[p]), rank_m.index(p) == rank_p.index(p),
                  within_2x(shares[p], PAPER["split"][p]), fact)
            out.append(c)
    else:
        out.append(Claim("split", "14", "energy split PE 53.7%, SRAM read 34.8%, write 8.0%, "
                         "leakage 3.3%, DRAM 0.2%", "53.7/34.8/8.0/3.3/0.2%", how)
                   .missing("a default-configuration row"))

    how = "energy_pj.total of Acc-KD (`height` full) / of Acc-2SKD (height 10), exact search."
    done = False
    for s in ss:
        kd, two = ed.find(sw.ok, height=ed.CANONICAL, **s), ed.find(sw.ok, height=10, **s)
        if kd is None or two is None:
            continue
        done = True
        ek, e2 = num(kd, "energy_pj.total"), num(two, "energy_pj.total")
        v = ek / e2
        diffs = sorted(((num(kd, f"energy_pj.{p}") or 0) - (num(two, f"energy_pj.{p}") or 0), p)
                       for p in ("pe", "ru", "sram_read", "sram_write", "node_cache", "dram", "leakage"))
        c = Claim(f"acckd-energy-{s['mode']}", "14", f"Acc-KD uses more energy than Acc-2SKD "
                  f"({label(s)}; energy ratio)", f"{PAPER['acckd_energy']:g}x", how)
        c.set(xf(v), up(v), within_2x_gain(v, PAPER["acckd_energy"]),
              f"{ek / 1e6:,.1f} vs {e2 / 1e6:,.1f} uJ; cycles {num(kd, 'cycles') / num(two, 'cycles'):.2f}x; "
              f"largest changes: " + ", ".join(f"{p} {d / 1e6:+,.1f} uJ" for d, p in
                                                (diffs[0], diffs[-1])) +
              f"; DRAM {pct((num(two, 'energy_pj.dram') or 0) / e2)} of Acc-2SKD's energy")
        out.append(c)
    if not done:
        out.append(Claim("acckd-energy", "14", "Acc-KD uses ~2.5x the energy of Acc-2SKD",
                         "2.5x", how).missing("rows at `height` full and 10"))

    how = "power_w with be.issue_policy=mqmn / with mqsn (+Forward), exact search, top height 10."
    done = False
    for s in ss:
        rows = _opt_rows(sw, s)
        a, b = rows["+Forward"], rows["MQMN"]
        if a is None or b is None:
            continue
        done = True
        v = num(b, "power_w") / num(a, "power_w")
        c = Claim(f"mqmn-power-{s['mode']}", "14", f"MQMN draws more power than MQSN(+Forward) "
                  f"({label(s)}; power ratio)", f"{PAPER['mqmn_power']:g}x", how)
        c.set(xf(v), up(v), within_2x_gain(v, PAPER["mqmn_power"]),
              f"power ratio = energy ratio {num(b, 'energy_pj.total') / num(a, 'energy_pj.total'):.2f}x "
              f"x speed-up {num(a, 'cycles') / num(b, 'cycles'):.2f}x; SRAM read energy "
              f"{(num(a, 'energy_pj.sram_read') or 0) / 1e6:,.1f} -> {(num(b, 'energy_pj.sram_read') or 0) / 1e6:,.1f} uJ; "
              f"DRAM {pct((num(a, 'energy_pj.dram') or 0) / num(a, 'energy_pj.total'))} of MQSN's energy")
        out.append(c)
    if not done:
        out.append(Claim("mqmn-power", "14", "MQMN ~4x the power of MQSN(+Forward)", "4x", how)
                   .missing("the +Forward and MQMN rows"))

    how = "1 - energy_pj.total with the default Node Cache / with node_cache.bytes 0, height 10."
    done = False
    for s in ss:
        w, wo = _nc_rows(sw, s)
        if w is None or wo is None:
            continue
        done = True
        v = 1 - num(w, "energy_pj.total") / num(wo, "energy_pj.total")
        c = Claim(f"nc-energy-{s['mode']}", "14", f"the Node Cache saves energy ({label(s)})",
                  pct(PAPER["nc_energy_saving"]), how)
        c.set(pct(v), v > NO_CHANGE, within_2x(v, PAPER["nc_energy_saving"]),
              f"Point Buffer energy {(num(wo, 'energy_pj.by_unit.points') or 0) / 1e6:,.1f} -> "
              f"{(num(w, 'energy_pj.by_unit.points') or 0) / 1e6:,.1f} uJ, Node Cache "
              f"{(num(w, 'energy_pj.node_cache') or 0) / 1e6:,.1f} uJ, leakage "
              f"{(num(wo, 'energy_pj.leakage') or 0) / 1e6:,.2f} -> {(num(w, 'energy_pj.leakage') or 0) / 1e6:,.2f} uJ; "
              f"DRAM {pct((num(w, 'energy_pj.dram') or 0) / num(w, 'energy_pj.total'))} of the total")
        out.append(c)
    if not done:
        out.append(Claim("nc-energy", "14", "the Node Cache saves 5.9% energy", "5.9%", how)
                   .missing("rows with `node_cache.bytes` 0 and the default at height 10"))

    how = ("`area_mm2.sram` and `.logic` of the default configuration; the area table is "
           "calibrated to these two totals (docs/model.md), so this checks the calibration, not a trend.")
    if default is not None and num(default, "area_mm2.sram") is not None:
        for part, key in (("sram", "area_sram"), ("logic", "area_logic")):
            v = num(default, f"area_mm2.{part}")
            c = Claim(f"area-{part}", "14", f"area: {part.upper() if part == 'sram' else part} (16 nm)",
                      f"{PAPER[key]:.2f} mm2", how)
            c.set(f"{v:.2f} mm2", None, within_2x(v, PAPER[key]),
                  "calibrated default (the table's densities are fitted to the paper's totals)")
            out.append(c)
    else:
        out.append(Claim("area", "14", "area 8.38 mm2 SRAM, 7.19 mm2 logic", "8.38 / 7.19 mm2", how)
                   .missing("a default-configuration row"))
    return out


CLAIM_GROUPS = [claims_redundancy, claims_acc_kd, claims_optimizations, claims_node_cache,
                claims_units, claims_height, claims_approx, claims_energy]


def why_not_measured(sw):
    """What may keep claims from their rows: failed runs (one example error) and a cloud too
    small for the default top height 10 (its rows are then the canonical tree)."""
    why = []
    full = sorted({int(num(r, "tree.full_height")) for r in sw.ok if num(r, "tree.full_height") is not None})
    if full and full[0] <= 10:
        why.append(f"the cloud's full tree height is {full[0]} (`tree.full_height`), so the default top "
                   "height 10 builds the canonical tree: there are no Acc-2SKD rows at height 10")
    if sw.not_ok:
        r = sw.not_ok[0]
        err = (r.get("error") or r.get("status") or "").strip()
        why.append(f"{len(sw.not_ok)} of {len(sw.rows)} runs failed (e.g. `{r.get('point', '')}`: "
                   f"{err[:150] + ('...' if len(err) > 150 else '')})")
    return "n/a: " + "; ".join(why) if why else ""


def all_claims(sw):
    out = []
    for g in CLAIM_GROUPS:
        try:
            out += g(sw)
        except (ArithmeticError, AttributeError, KeyError, TypeError, ValueError) as e:
            # Rows the group did not expect (failed or partial runs) cost its claims, not the
            # report: they are listed as not evaluated, with the reason.
            name = g.__name__[len("claims_"):]
            c = Claim(name, "14" if g is claims_energy else "9", f"the {name} claims", "-", "-")
            c.explanation = f"n/a: could not be evaluated ({type(e).__name__}: {e})"
            out.append(c)
            ed.note(f"report: the {name} claims could not be evaluated: {type(e).__name__}: {e}")
    why = why_not_measured(sw)
    for c in out:
        if c.measured == "not measured" and why:
            c.explanation = f"{c.explanation}; {why}"
    return out


# ----------------------------------------------------------------------------------------------
# The pipeline's design space (the paper's section 3), from a `tigris pipeline-dse` folder

def _shares(dp, order):
    total = sum(v for v in dp["stages"].values() if v) or None
    return {s: (dp["stages"].get(s) or 0) / total for s in order} if total else None


def _own_compute(dp, order):
    """(stage, share of the DP's time, share of the stage) of the stage with the most time
    outside KD-tree search, from the DP's per-stage search seconds (None when absent)."""
    search, total = dp.get("stage_kdtree_seconds"), sum(v for v in dp["stages"].values() if v)
    if not isinstance(search, dict) or not total:
        return None
    rest = {s: (dp["stages"].get(s) or 0) - (search.get(s) or 0) for s in order if dp["stages"].get(s)}
    s = max(rest, key=rest.get)
    return s, rest[s] / total, rest[s] / dp["stages"][s]


def claims_pipeline(dse):
    """The paper's section-3 claims against a pipeline-dse's Pareto points (its dse.json), the
    stages in its order (dse_data.stage_order)."""
    order = dse_data.stage_order(dse)
    dps = [d for d in dse.get("dps", []) if _shares(d, order)]
    how = (f"`tigris pipeline-dse` ({dse.get('sampling')}; {dse.get('points')} points on the {dse.get('sequence')}): "
           "the Pareto points (DP1..DPn) of mean registration seconds per pair against mean relative pose error "
           "(translation, rotation); stage times per pair from `tigris register`, RPCE = ICP's KD-tree searches")
    out = []
    c = Claim("pipe_kd", "3", "KD-tree search takes 50-85% of the time on every Pareto point", "50-85%", how)
    if not dps:
        out.append(c.missing("a pipeline-dse with at least one Pareto point"))
    else:
        kd = [(d["kdtree_share"], d) for d in dps if d.get("kdtree_share") is not None]
        if not kd:
            raise ValueError("no Pareto point has a KD-tree share")
        lo, hi = min(kd, key=lambda t: t[0]), max(kd, key=lambda t: t[0])
        below = [d for v, d in kd if v < 0.5]
        expl = f"{len(dps)} Pareto points; lowest {lo[1]['dp']} ({lo[1]['point']}) {pct(lo[0], 0)}"
        own = _own_compute(lo[1], order)
        if own:
            expl += (f", the rest of its time mostly {own[0]}'s own computation ({pct(own[1], 0)} of the time, "
                     f"{pct(own[2], 0)} of that stage)")
        else:  # a dse.json without per-stage search seconds: the largest stage outside the paper's three
            sh = _shares(lo[1], order)
            top = max((s for s in order if s not in ("normal estimation", "descriptor calculation", "RPCE")),
                      key=lambda s: sh[s])
            expl += f", where {top} takes {pct(sh[top], 0)}"
        expl += f"; highest {hi[1]['dp']} {pct(hi[0], 0)}"
        if below:
            expl += f"; below 50%: {', '.join(d['dp'] for d in below)}"
        out.append(c.set(f"{pct(lo[0], 0)}-{pct(hi[0], 0)}", not below,
                         within_2x(lo[0], 0.5) and within_2x(hi[0], 0.85), expl))
    c = Claim("pipe_big3", "3", "normal estimation, descriptors and RPCE take over 90% of the time", "> 90%", how)
    if dps:
        big = [(sum(_shares(d, order).get(s, 0) for s in ("normal estimation", "descriptor calculation", "RPCE")), d)
               for d in dps]
        v, d = min(big, key=lambda t: t[0])
        sh = _shares(d, order)
        rest = sorted((s for s in order if s not in ("normal estimation", "descriptor calculation", "RPCE")),
                      key=lambda s: -sh[s])[:2]
        out.append(c.set(f"at least {pct(v, 0)} (lowest {d['dp']})", v > 0.9, within_2x(v, 0.9),
                         f"{d['dp']} ({d['point']}), the largest of the rest: " + ", ".join(f"{s} {pct(sh[s], 0)}" for s in rest)
                         + " (outlier removal is a stage this pipeline has and the paper's does not)"))
    else:
        out.append(c.missing("a pipeline-dse with at least one Pareto point"))
    c = Claim("pipe_no_dominant", "3", "no single stage dominates across the Pareto points", "no single stage", how)
    if dps:
        # The paper's sense: no stage is an acceleration target for every DP (normal estimation is
        # about 80% of DP8 and under 30% of DP1-2). Tested as: no stage takes over half the time
        # on every Pareto point; the largest stage per DP is reported beside it.
        tops = {}
        for d in dps:
            sh = _shares(d, order)
            tops.setdefault(max(order, key=lambda s: sh[s]), []).append(d["dp"])
        low = {s: min(_shares(d, order)[s] for d in dps) for s in order}
        high = {s: max(_shares(d, order)[s] for d in dps) for s in order}
        majority = [s for s in order if low[s] > 0.5]
        out.append(c.set("largest stage: " + "; ".join(f"{s} on {len(v)} of {len(dps)}" for s, v in tops.items()),
                         not majority, None,
                         "; ".join(f"{s} takes {pct(low[s], 0)}-{pct(high[s], 0)}" for s in tops)
                         + (f"; {', '.join(majority)} over half the time on every Pareto point" if majority else
                            "; no stage takes over half the time on every Pareto point")
                         + " (paper: normal estimation under 30% in DP1-2, about 80% in DP8)"))
    else:
        out.append(c.missing("a pipeline-dse with at least one Pareto point"))
    c = Claim("pipe_presets", "3", "the paper's DP4 (preset dp4) is performance-oriented, its DP7 (preset dp7) "
              "accuracy-oriented",
              "DP4 faster, DP7 more accurate", how)
    p4, p7 = (dse.get("presets") or {}).get("dp4"), (dse.get("presets") or {}).get("dp7")
    figs = ("seconds_per_pair", "rpe_translation_m", "rpe_rotation_deg")
    if p4 and p7 and all(p.get("status") == "ok" and all(isinstance(p.get(f), (int, float)) for f in figs)
                         for p in (p4, p7)):
        faster = p4["seconds_per_pair"] < p7["seconds_per_pair"]
        better = p7["rpe_translation_m"] < p4["rpe_translation_m"] and p7["rpe_rotation_deg"] < p4["rpe_rotation_deg"]
        where = lambda p: f"Pareto point {p['dp']}" if p.get("dp") else "not on a frontier"  # noqa: E731
        out.append(c.set(f"dp4 {p4['seconds_per_pair']:.2f} s, {p4['rpe_translation_m'] * 1e3:.2f} mm, "
                         f"{p4['rpe_rotation_deg']:.4f} deg; dp7 {p7['seconds_per_pair']:.2f} s, "
                         f"{p7['rpe_translation_m'] * 1e3:.2f} mm, {p7['rpe_rotation_deg']:.4f} deg",
                         faster and better, None,
                         f"dp7 takes {p7['seconds_per_pair'] / p4['seconds_per_pair']:.1f}x dp4's time; "
                         f"dp4: {where(p4)}, dp7: {where(p7)}"))
    else:
        out.append(c.missing("the dp4 and dp7 anchors of a pipeline-dse, both converged"))
    return out


def pipeline_section(dse, dse_dir, fig_rel, standalone=False):
    """The section's lines and claims; `standalone`: the report of the exploration's own folder
    (a title of its own, the folder not named). Pareto points are named F1..Fn (an older
    folder's DP1..DPn read so: dse_data.renamed)."""
    dse = dse_data.renamed(dse)
    claims = claims_pipeline(dse)
    rel = lambda f: os.path.relpath(os.path.join(dse_dir, f), fig_rel) if fig_rel else os.path.join(dse_dir, f)  # noqa: E731
    source = f"`{dse.get('command_line')}`" if standalone else f"`{dse_dir}` (`{dse.get('command_line')}`)"
    L = ["# The pipeline's design space: the paper's section 3 against this pipeline" if standalone else
         "## The pipeline's design space (the paper's section 3)", "",
         f"From {source}: {dse.get('points')} points, {dse.get('ok')} ok, "
         f"{dse.get('not_converged')} with a pair not converged, {dse.get('failed')} failed; "
         f"{len(dse.get('dps', []))} Pareto points (the paper found 8)"
         + (f", named {dse_data.PARETO}1..{dse_data.PARETO}{len(dse['dps'])} by time (not the paper's "
            "DP1..DP8, whose DP4 and DP7 are the presets dp4 and dp7)" if dse.get("dps") else "") + ".", "",
         claim_table(claims).replace("| model.md |", "| paper § |"), "",
         f"![error against time]({rel('fig4.png')})", "", f"![the Pareto points' time]({rel('fig5.png')})", "",
         "| Pareto point | design point | s/pair | RPE mm | RPE deg | KD-tree |", "|---|---|---:|---:|---:|---:|"]
    for d in dse.get("dps", []):
        L.append(f"| {d['dp']} | {d['point']} | {d['seconds_per_pair']:.2f} | {d['rpe_translation_m'] * 1e3:.3f} | "
                 f"{d['rpe_rotation_deg']:.4f} | {pct(d['kdtree_share'] or 0, 0)} |")
    return L + [""], claims


def md_cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


def short_claim(c):
    """A claim's text cut to its statement and the first part of its parenthesis:
    "two-stage redundancy grows with leaf-set size (NN)"."""
    if not c.text.endswith(")") or " (" not in c.text:
        return c.text
    head, _, rest = c.text.rpartition(" (")
    qual = rest[:-1].split(";")[0].strip()
    return f"{head} ({qual})" if qual else head


def _reason(c, limit=110):
    """The measured reason of a failed claim: its explanation's first clause."""
    e = (c.explanation or "").split("; ")[0].strip()
    return e if len(e) <= limit else e[:limit].rsplit(" ", 1)[0] + " ..."


# The summary's groups of verdicts (variants.verdict): size only is a fail there, the direction
# not holding; a work ratio is neither a hold nor a fail.
GROUP = {vt.HOLDS: "hold", vt.DIRECTION_ONLY: "direction", vt.FAILS: "fail", vt.SIZE_ONLY: "fail",
         vt.WORK_RATIO: "work"}


def grouped(cs):
    """{group: [claims]} over hold, direction, fail, work and rest (no verdict)."""
    g = {k: [] for k in ("hold", "direction", "fail", "work", "rest")}
    for c in cs:
        g[GROUP.get(vt.verdict(c), "rest")].append(c)
    return g


def counts(cs):
    g = grouped(cs)
    return (f"{len(g['hold'])} of {len(cs)} hold, {len(g['direction'])} direction only, {len(g['fail'])} fail, "
            f"{len(g['work'])} a work ratio, {len(g['rest'])} without a verdict")


def speed_text(c):
    """A speed claim's ratios as the table and summary show them: "cycles / work / ideal"."""
    show = lambda v: xf(v) if v is not None else "n/a"  # noqa: E731
    return " / ".join(show(c.speed[k]) for k in ("cycles", "work", "ideal"))


def summary_lines(claims, extra=(), paper=None):
    """REPORT.md's opening answer (about ten lines): the counts of each configuration, which
    claims hold, which hold only in direction and by how much they miss, which fail and the
    measured reason, which are work ratios. `extra`: other (title, claims) groups reported in the
    same words (the pipeline's section 3); `paper`: (accounting Variant, {cid: claim}) of the
    same claims under the paper's accounting: its counts, the verdicts it changes and the claims
    that still fail under it with their measured reason."""
    L = ["## Summary: what reproduces", ""]
    pcs = [paper[1].get(c.cid) or Claim(c.cid, c.section, c.text, c.paper, c.how) for c in claims] if paper else []
    if paper:
        L.append(f"- **Default machine: {counts(claims)}; the paper's accounting (`{paper[0].name}`): "
                 f"{counts(pcs)}.**")
    for title, cs in [("", claims)] + [(t, cs) for t, cs in extra]:
        num = {id(c): i for i, c in enumerate(cs, 1)}
        ref = (lambda c: f"{title} #{num[id(c)]}") if title else (lambda c: f"#{num[id(c)]}")  # noqa: E731
        g = grouped(cs)
        where = f" of {title}" if title else ""
        on = " on the default machine" if paper and not title else ""
        L.append(f"- **{len(g['hold'])} of {len(cs)} claims{where} hold**{on} (direction, and size within 2x where "
                 "the paper gives a number): " + ("; ".join(f"{ref(c)} {short_claim(c)}" for c in g["hold"]) or "none") + ".")
        if g["direction"]:
            L.append(f"- **{len(g['direction'])} hold only in direction**, the size off by more than 2x: "
                     + "; ".join(f"{ref(c)} {short_claim(c)}: {c.measured} against {c.paper}" for c in g["direction"]) + ".")
        if g["fail"]:
            L.append(f"- **{len(g['fail'])} fail**: " + "; ".join(
                f"{ref(c)} {short_claim(c)}: {c.measured} against {c.paper} ({_reason(c)})" for c in g["fail"]) + ".")
        if g["work"]:
            L.append(f"- **{len(g['work'])} {'is a work ratio' if len(g['work']) == 1 else 'are work ratios'}**: the "
                     "paper's speed-up is within 2x of the ratio of work but above the ideal machine's ratio (the "
                     "speed-up of a machine of this size running both searches at its bound), so it reads as work "
                     "saved, not time: " + "; ".join(
                         f"{ref(c)} {short_claim(c)}: {c.paper} against cycles / work / ideal {speed_text(c)}"
                         for c in g["work"]) + ".")
        rest = g["rest"]
        if rest:
            gpu = [c for c in rest if c.explanation.startswith("needs a GPU")]
            L.append(f"- {len(rest)} without a verdict (no direction test and no paper number, or not measured): "
                     + ", ".join(ref(c) for c in rest if c not in gpu)
                     + (("; " if len(gpu) < len(rest) else "") + ", ".join(ref(c) for c in gpu)
                        + " need a GPU (the paper's baselines)" if gpu else "") + ".")
        if paper and not title:
            L += accounting_lines(claims, pcs)
    return L + ["", "Each claim's measurement, and the facts behind a miss, are in the tables below.", ""]


def accounting_lines(claims, pcs):
    """The summary's lines of the paper's accounting: the verdicts it changes, the claims that
    still fail under it (with its measured reason)."""
    changed = [(i, c, p) for i, (c, p) in enumerate(zip(claims, pcs), 1)
               if vt.verdict(c) != vt.verdict(p) and vt.verdict(p) != vt.NOT_MEASURED]
    fail = [(i, c, p) for i, (c, p) in enumerate(zip(claims, pcs), 1) if GROUP.get(vt.verdict(p)) == "fail"]
    L = []
    if changed:
        L.append(f"- **The paper's accounting changes {len(changed)} verdict{'s' if len(changed) > 1 else ''}**: "
                 + "; ".join(f"#{i} {short_claim(c)}: {vt.verdict(c)} -> {vt.verdict(p)} ({p.measured})"
                             for i, c, p in changed) + ".")
    L.append(f"- **{len(fail)} still fail under the paper's accounting**" + (": " + "; ".join(
        f"#{i} {short_claim(c)}: {p.measured} against {c.paper} ({_reason(p)})" for i, c, p in fail) if fail else "")
        + ".")
    return L


def claim_table(claims, paper=None):
    """The claim table: each claim's measured value and verdict (variants.verdict); `paper`:
    (accounting Variant, {cid: claim}), the same claims' value and verdict under the paper's
    accounting beside the default's; a column of the speed claims' cycle / work / ideal ratios
    when any claim has them (the paper's accounting's cycles beside the default's where they
    differ: work and the ideal machine do not depend on the accounting)."""
    speed = any(c.speed for c in claims)
    head = ["#", "model.md", "claim", "paper"] + (["default machine", "verdict", "paper's accounting", "verdict"]
                                                  if paper else ["measured", "verdict"])
    head += ["speed-up: cycles / work / ideal"] if speed else []
    lines = ["| " + " | ".join(head + ["explanation (measured facts)"]) + " |",
             "|---:|" + "---|" * len(head)]
    for i, c in enumerate(claims, 1):
        p = paper[1].get(c.cid) if paper else None
        row = [i, f"§{c.section}", c.text, c.paper, c.measured, vt.verdict(c)]
        if paper:
            row += [p.measured if p else "not measured", vt.verdict(p)]
        if speed:
            cell = speed_text(c) if c.speed else ""
            if c.speed and p is not None and p.speed and xf(p.speed["cycles"] or 0) != xf(c.speed["cycles"] or 0):
                cell = cell.replace(" / ", f" (paper's accounting {xf(p.speed['cycles'] or 0)}) / ", 1)
            row.append(cell)
        lines.append("| " + " | ".join(md_cell(x) for x in row + [c.explanation]) + " |")
    return "\n".join(lines)


VERDICTS_TEXT = (
    "Verdicts, one word per configuration: " + "; ".join(f"*{k}*: {vt.MEANING[k]}" for k in vt.VERDICTS) + ". "
    "The direction is the claim's qualitative test (stated per claim below); within 2x is measured / paper "
    "in [0.5, 2] (for a '+x%' or '-x%' claim, the gains or cuts are compared, and for a speed-up or ratio "
    "('2x') its gain over 1: a 1.03x against a 2x claim is +3% against +100%; a gain of the wrong sign is "
    f"not within 2x). A change of less than {100 * NO_CHANGE:.0f}% counts as no change: the direction does "
    "not hold. A claim without a paper number or without a direction has the other test only.")

WORK_BOUND_TEXT = (
    "the column *speed-up: cycles / work / ideal* gives, of the slow run over the fast one, the measured "
    "cycle ratio (the paper's accounting's beside it where it differs), the work ratio in nodes (top-tree "
    "nodes + PE distances, `visits.top` + `visits.pe_distances`; PE distances = leaf points + follower points "
    "+ leader checks; the explanation gives the leaf points' and the PE distances' ratios apart) and the "
    "ideal machine's ratio, `lower_bound_cycles` of the slow run over the fast one: the machine of the "
    "configured size at one node per RU and one distance per PE per cycle, no bank conflict, free "
    "write-back, max(top nodes / #RU, PE distances / (#SU x #PE)) (docs/model.md). Neither the work nor the "
    "ideal machine depends on the accounting. A claim whose paper number is within 2x of the work ratio "
    "(by the claim's own size rule) and above the ideal ratio by more than "
    f"{100 * NO_CHANGE:.0f}% is a *work ratio*: no machine of this size running both searches at its bound "
    "reaches it as a speed-up (a real one exceeds the ideal ratio only by running the slower search further "
    "from its bound; the paper's approximate 11.1x against the nodes visited, say). The knee claims "
    "give the doubling at the measured knee (or the last one swept) and have no paper speed-up; the "
    "registration's approximate speed-up sums its accelerator jobs' cycles and visits over the stages, the "
    "ideal machine per stage (a stage's jobs follow one another); the end-to-end claims have none: the "
    "CPU's own work is in them, and the CPU-only system shares no machine with the accelerator.")


def accounting_text(v):
    return (f"The paper's accounting: every claim experiment also ran under the preset `{v.name}` "
            f"({v.describe()}; docs/model.md, \"Two accountings\": the same machine, charged as the paper's "
            "simulator evidently charged it). The golden model's redundancy and the odometry's accuracy share the "
            "default's rows, and so do the registrations on the CPU; the registrations with the accelerator in "
            "the loop ran with the preset as their --accel-config. A claim whose experiment did not run under it "
            "(--quick leaves out the RU x SU x PE grids) reads *not measured* there.")


def render(sw, claims, figures=None, skipped=None, fig_rel=None, title=None, dse=None, robust=None, command=None,
           paper=None):
    """REPORT.md's text; `paper`: (accounting Variant, {cid: claim}), the claims under the
    paper's accounting (its column, counts and failures in the summary)."""
    measured = [c for c in claims if c.measured != "not measured"]
    dir_n = [c for c in measured if c.direction is not None]
    size_n = [c for c in measured if c.within is not None]
    wl = sorted({(r.get("workload.cloud") or r["eff"]["cloud"] or "synthetic frame 0 (built-in)",
                  r.get("workload.queries") or r["eff"]["queries"] or "synthetic frame 1 (built-in)")
                 for r in sw.ok})
    wtxt = "; ".join(f"cloud `{c}`, queries `{q}`" for c, q in wl) or "none"
    statuses = {}
    for r in sw.rows:
        statuses[r.get("status", "")] = statuses.get(r.get("status", ""), 0) + 1
    L = [f"# {title or 'Tigris TLM: the paper evaluation, reproduced'}", "",
         "Generated by `sweep/report.py` from " + ", ".join(
             f"`{os.path.relpath(p, fig_rel) if fig_rel else p}`" for p in sw.paths) + ".", "",
         f"- Workload: {wtxt}."] + ([f"- Command: `{command}`."] if command else []) + [
         "- Rows: " + ", ".join(f"{n} {s}" for s, n in sorted(statuses.items())) +
         f"; {len(sw.ok)} distinct ok runs used.",
         "- Every number below is measured by the model on this workload; nothing is tuned toward "
         "the paper. A miss is reported as a miss, with the facts the sweep measured beside it.",
         ""]
    if len(wl) > 1:
        L += ["**Warning**: the CSVs hold several workloads; claims compare rows of one workload "
              "only when their other settings match, so mixed workloads may pair badly.", ""]
    extra = [("section 3", pipeline_section(dse[1], dse[0], fig_rel)[1])] if dse is not None else []
    L += summary_lines(claims, extra, paper)
    L += ["## Claims of the fidelity targets (§9) and energy figures (§14) of docs/model.md", "",
          f"{len(measured)} of {len(claims)} claims measured; direction holds for "
          f"{sum(1 for c in dir_n if c.direction)} of {len(dir_n)} with a direction test; size within "
          f"2x for {sum(1 for c in size_n if c.within)} of {len(size_n)} with a paper number.", "",
          claim_table(claims, paper), "",
          VERDICTS_TEXT, ""]
    if paper:
        L += [accounting_text(paper[0]), ""]
    L += robust or []
    L += ["## How each claim is measured", ""]
    seen = set()
    for c in claims:
        if c.how in seen:
            continue
        seen.add(c.how)
        ids = ", ".join(f"#{i}" for i, d in enumerate(claims, 1) if d.how == c.how)
        L.append(f"- {ids}: {c.how}")
    L.append("")
    fast = [f"#{i}" for i, c in enumerate(claims, 1) if c.speed or paper and getattr(paper[1].get(c.cid), "speed", None)]
    if fast:
        L += [f"The work bound of the speed claims ({', '.join(fast)}): {WORK_BOUND_TEXT}", ""]
    L += ["What bounds a run (the explanations): each run's `bottleneck.summary` from its stats.json, "
          "computed by the model from each unit kind's busy and stall cycles by cause "
          "as a share of (units x cycles), summed over its units (`units.*.busy_cycles`, "
          "`units.*.stall_cycles.*`); 'front-end bound' when the RUs are occupied (busy or "
          "stalled) a larger share than the SUs, 'back-end bound' otherwise, 'result write-back "
          "bound' when RUs or SUs wait on the DRAM write-back more than 30% of the time. The lower "
          "bound (`lower_bound_cycles`, 'cycles Nx the lower bound') is the ideal machine's: max(top "
          "visits / #RU, PE distances / (#SU x #PE)).", ""]
    if dse is not None:
        L += pipeline_section(dse[1], dse[0], fig_rel)[0]
    if figures is not None:
        L += ["## Figures", ""]
        from . import plots
        for name, (png, _svg, notes) in figures.items():
            rel = os.path.relpath(png, fig_rel) if fig_rel else png
            L += [f"### {plots.FIGURES[name][1]}", "", f"![{name}]({rel})", ""]
            if notes:
                L += [f"Rows: {'; '.join(notes)}.", ""]
        for name, why in (skipped or {}).items():
            L += [f"- Not drawn: {why}."]
        if skipped:
            L.append("")
    bad = [r for r in sw.rows if r.get("status", "") != "ok"]
    if bad:
        L += ["## Rows not ok", "", "| csv | point | status | error |", "|---|---|---|---|"]
        for r in bad:
            L.append(f"| `{os.path.basename(os.path.dirname(r['_csv'])) or r['_csv']}` | {r.get('point', '')} | "
                     f"{r.get('status', '')} | {md_cell((r.get('error') or '')[:200])} |")
        L.append("")
    return "\n".join(L)


def variant_claims(v, csvs):
    """all_claims of a variant's (or an accounting's) CSVs, its rows read with its keys as the defaults."""
    if not csvs:
        return []
    with ed.DEFAULTS.overridden(vt.overrides(v, ed.SPEC_NAMES)):
        return all_claims(ed.Sweep(csvs, assume=vt.assumed_columns(v)))


def variant_columns(claims, variants):
    """The default's claims and each variant's, as sweep/variants.py's columns. variants:
    [(name, Variant, CSVs)]."""
    return [vt.Column(vt.DEFAULT, None, claims)] + [vt.Column(name, v, variant_claims(v, csvs))
                                                     for name, v, csvs in variants]


def own_claims(redundancy, headline, accel_registrations=None):
    """The claims of reproduce's CSVs that are not `tigris run` sweeps: the redundancy in both
    conventions and the headline claims; `accel_registrations`: an accounting's registrations CSV,
    whose accelerator points replace the default's."""
    out = claims_redundancy_conventions(redundancy) if redundancy else []
    if headline:
        reg, odo = headline
        out += claims_headline([reg, accel_registrations] if accel_registrations else reg, odo)
    return out


def variants_section(cols, figures_dir, out, draw, log=ed.note):
    """REPORT.md's robustness section and, when drawing, figures_dir/variants.png."""
    tig = ts.tigris_at(ts.default_tigris(), "run")
    defaults = dict(tig.config, **{"leader-width": tig.flags.get("leader-width")})
    rel = None
    if draw:
        png = vt.figure(cols, defaults, os.path.join(figures_dir, "variants.png"))
        log(f"report: wrote {png}")
        rel = os.path.relpath(png, out)
    return vt.render(cols, defaults, rel, md_cell)


def write_report(csvs, out, figures_dir=None, draw=True, title=None, log=ed.note, dse_dir=None,
                 variants=None, command=None, redundancy=None, headline=None, accounting=None):
    """REPORT.md from sweep CSVs; `redundancy`: a `tigris ref --redundancy` sweep's CSV, whose
    claims (both conventions) come after the others (the variants do not change them);
    `headline`: (registrations CSV, odometry CSV) of reproduce, the paper's headline claims;
    `accounting`: (Variant, its `tigris run` CSVs, its registrations CSV or None) of the paper's
    accounting, every claim's column beside the default's."""
    sw = ed.Sweep(csvs)
    claims = all_claims(sw)
    dse = (dse_dir, dse_data.read_dse(dse_dir)) if dse_dir else None
    figs = skipped = None
    figures_dir = figures_dir or os.path.join(out, "figures")
    if draw:
        from . import plots
        figs, skipped = plots.make_figures(sw, figures_dir, log=log, footer=plots.sweep_footer(csvs, sys.argv))
    os.makedirs(out, exist_ok=True)
    robust = variants_section(variant_columns(claims, variants), figures_dir, out, draw, log) \
        if variants else None
    claims = claims + own_claims(redundancy, headline)
    paper = None
    if accounting:
        v, acsvs, areg = accounting
        paper = (v, {c.cid: c for c in variant_claims(v, acsvs) + own_claims(redundancy, headline, areg)})
    path = os.path.join(out, "REPORT.md")
    core.atomic_write(path, render(sw, claims, figs, skipped, fig_rel=out, title=title, dse=dse, robust=robust,
                                   command=command, paper=paper))
    log(f"report: wrote {path}")
    return path, claims


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", nargs="+", help="sweep CSVs")
    ap.add_argument("--out", required=True, help="folder for REPORT.md")
    ap.add_argument("--figures", help="folder for the figures (default OUT/figures)")
    ap.add_argument("--no-figures", action="store_true", help="the claim table only")
    ap.add_argument("--title", help="the report's heading")
    ap.add_argument("--dse", metavar="DIR", help="a `tigris pipeline-dse` folder: adds the section-3 claims")
    a = ap.parse_args(argv)
    for p in a.csv:
        if not os.path.isfile(p):
            ap.exit(2, f"report: no such CSV: {p}\n")
    try:
        write_report(a.csv, a.out, a.figures, not a.no_figures, a.title, dse_dir=a.dse)
    except (ValueError, OSError) as e:
        ap.exit(2, f"report: {e}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
