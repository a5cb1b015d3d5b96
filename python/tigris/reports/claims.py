"""The claim record (Claim) and its rules: the paper's figures (PAPER), a size within 2x, a
speed claim's work bound, and the formatting every section's claims share."""
import csv
import os

from ..data import evaldata as ed
from ..data.evaldata import num


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

    def record(self):
        """The claim as JSON data (dse.json's "claims"), its verdict as REPORT.md words it."""
        return {"id": self.cid, "section": self.section, "claim": self.text, "paper": self.paper,
                "measured": self.measured, "direction_holds": self.direction, "within_2x": self.within,
                "explanation": self.explanation}


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


def per_search(settings, rows, measure, missing):
    """A claim the paper makes per search: measure(s, a, b) for each search setting s whose two
    rows (rows(s) -> (a, b)) the sweep has; [missing] (a Claim saying what it needs) when none."""
    out = []
    for s in settings:
        a, b = rows(s)
        if a is not None and b is not None:
            out.append(measure(s, a, b))
    return out or [missing]


def label(s):
    return ed.search_label(s)


def short_bound(row):
    return ed.bound_facts(row)



def ok_rows(paths):
    """The ok rows of a CSV, or of several in order (a list: None and missing files skipped)."""
    out = []
    for path in paths if isinstance(paths, (list, tuple)) else [paths]:
        if path and os.path.isfile(path):
            with open(path, newline="") as f:
                out += [r for r in csv.DictReader(f) if r.get("status") == "ok"]
    return out


def fnum(row, col):
    """A CSV cell as a float, None when missing or not a number."""
    try:
        return float(row[col])
    except (KeyError, TypeError, ValueError):
        return None
