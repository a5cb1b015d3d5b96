"""The paper's section 3 measured: the registration pipeline's design space, from a `tigris
pipeline-dse` folder."""
import os

from ..data import dse_data
from .claims import Claim, pct, within_2x
from .tables import claim_table


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


BIG3 = ("normal estimation", "descriptor calculation", "RPCE")  # the paper's three largest stages
NEEDS_DPS = "a pipeline-dse with at least one Pareto point"


def claim_kdtree_share(dps, order, how):
    """KD-tree search takes 50-85% of the time on every Pareto point."""
    c = Claim("pipe_kd", "3", "KD-tree search takes 50-85% of the time on every Pareto point", "50-85%", how)
    if not dps:
        return c.missing(NEEDS_DPS)
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
        top = max((s for s in order if s not in BIG3), key=lambda s: sh[s])
        expl += f", where {top} takes {pct(sh[top], 0)}"
    expl += f"; highest {hi[1]['dp']} {pct(hi[0], 0)}"
    if below:
        expl += f"; below 50%: {', '.join(d['dp'] for d in below)}"
    return c.set(f"{pct(lo[0], 0)}-{pct(hi[0], 0)}", not below, within_2x(lo[0], 0.5) and within_2x(hi[0], 0.85),
                 expl)


def claim_big3(dps, order, how):
    """Normal estimation, descriptors and RPCE take over 90% of the time."""
    c = Claim("pipe_big3", "3", "normal estimation, descriptors and RPCE take over 90% of the time", "> 90%", how)
    if not dps:
        return c.missing(NEEDS_DPS)
    big = [(sum(_shares(d, order).get(s, 0) for s in BIG3), d) for d in dps]
    v, d = min(big, key=lambda t: t[0])
    sh = _shares(d, order)
    rest = sorted((s for s in order if s not in BIG3), key=lambda s: -sh[s])[:2]
    return c.set(f"at least {pct(v, 0)} (lowest {d['dp']})", v > 0.9, within_2x(v, 0.9),
                 f"{d['dp']} ({d['point']}), the largest of the rest: " + ", ".join(f"{s} {pct(sh[s], 0)}" for s in rest)
                 + " (outlier removal is a stage this pipeline has and the paper's does not)")


def claim_no_dominant(dps, order, how):
    """No single stage dominates across the Pareto points. The paper's sense: no stage is an
    acceleration target for every DP (normal estimation is about 80% of DP8 and under 30% of
    DP1-2). Tested as: no stage takes over half the time on every Pareto point; the largest
    stage per DP is reported beside it."""
    c = Claim("pipe_no_dominant", "3", "no single stage dominates across the Pareto points", "no single stage", how)
    if not dps:
        return c.missing(NEEDS_DPS)
    tops = {}
    for d in dps:
        sh = _shares(d, order)
        tops.setdefault(max(order, key=lambda s: sh[s]), []).append(d["dp"])
    low = {s: min(_shares(d, order)[s] for d in dps) for s in order}
    high = {s: max(_shares(d, order)[s] for d in dps) for s in order}
    majority = [s for s in order if low[s] > 0.5]
    return c.set("largest stage: " + "; ".join(f"{s} on {len(v)} of {len(dps)}" for s, v in tops.items()),
                 not majority, None,
                 "; ".join(f"{s} takes {pct(low[s], 0)}-{pct(high[s], 0)}" for s in tops)
                 + (f"; {', '.join(majority)} over half the time on every Pareto point" if majority else
                    "; no stage takes over half the time on every Pareto point")
                 + " (paper: normal estimation under 30% in DP1-2, about 80% in DP8)")


def claim_presets(dse, how):
    """The paper's DP4 is performance-oriented, its DP7 accuracy-oriented (the presets dp4, dp7)."""
    c = Claim("pipe_presets", "3", "the paper's DP4 (preset dp4) is performance-oriented, its DP7 (preset dp7) "
              "accuracy-oriented", "DP4 faster, DP7 more accurate", how)
    p4, p7 = (dse.get("presets") or {}).get("dp4"), (dse.get("presets") or {}).get("dp7")
    figs = ("seconds_per_pair", "rpe_translation_m", "rpe_rotation_deg")
    if not (p4 and p7 and all(p.get("status") == "ok" and all(isinstance(p.get(f), (int, float)) for f in figs)
                              for p in (p4, p7))):
        return c.missing("the dp4 and dp7 anchors of a pipeline-dse, both converged")
    faster = p4["seconds_per_pair"] < p7["seconds_per_pair"]
    better = p7["rpe_translation_m"] < p4["rpe_translation_m"] and p7["rpe_rotation_deg"] < p4["rpe_rotation_deg"]
    where = lambda p: f"Pareto point {p['dp']}" if p.get("dp") else "not on a frontier"  # noqa: E731
    return c.set(f"dp4 {p4['seconds_per_pair']:.2f} s, {p4['rpe_translation_m'] * 1e3:.2f} mm, "
                 f"{p4['rpe_rotation_deg']:.4f} deg; dp7 {p7['seconds_per_pair']:.2f} s, "
                 f"{p7['rpe_translation_m'] * 1e3:.2f} mm, {p7['rpe_rotation_deg']:.4f} deg",
                 faster and better, None,
                 f"dp7 takes {p7['seconds_per_pair'] / p4['seconds_per_pair']:.1f}x dp4's time; "
                 f"dp4: {where(p4)}, dp7: {where(p7)}")


def claims_pipeline(dse):
    """The paper's section-3 claims against a pipeline-dse's Pareto points (its dse.json), the
    stages in its order (dse_data.stage_order)."""
    order = dse_data.stage_order(dse)
    dps = [d for d in dse.get("dps", []) if _shares(d, order)]
    how = (f"`tigris pipeline-dse` ({dse.get('sampling')}; {dse.get('points')} points on the {dse.get('sequence')}): "
           "the Pareto points (DP1..DPn) of mean registration seconds per pair against mean relative pose error "
           "(translation, rotation); stage times per pair from `tigris register`, RPCE = ICP's KD-tree searches")
    return [claim_kdtree_share(dps, order, how), claim_big3(dps, order, how), claim_no_dominant(dps, order, how),
            claim_presets(dse, how)]


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
