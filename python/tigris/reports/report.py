#!/usr/bin/python3
"""REPORT.md from sweep CSVs: the paper's claims (docs/model.md, §9 and §14), measured.

    python3 -m tigris report CSV... --out DIR [--figures DIR | --no-figures] [--title TEXT]

Writes DIR/REPORT.md: a table of every claim (the paper's value, the measured value, whether the
direction holds, whether the size is within 2x, and an explanation made only of facts the sweep
measured), how each claim is measured, and the figures of plots.py (made into DIR/figures unless
--figures names another folder or --no-figures). Claims whose rows the CSVs lack say which
sweep they need. Nothing here is tuned toward the paper's numbers.
"""
import argparse
import os
import sys

from .. import core
from ..data import binary, dse_data
from ..data import evaldata as ed
from ..data.evaldata import num
from .claims import Claim, NO_CHANGE
from . import variants as vt
from .algorithm import claims_redundancy, claims_redundancy_conventions
from .energy import claims_energy
from .evaluation import (claims_acc_kd, claims_approx, claims_headline, claims_height, claims_node_cache,
                         claims_optimizations, claims_units)
from .pipeline import pipeline_section
from .tables import claim_table, md_cell, speed_text

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
         "Generated by `tigris/reports/report.py` from " + ", ".join(
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
    """The default's claims and each variant's, as tigris/reports/variants.py's columns. variants:
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
    tig = binary.tigris_at(binary.default_tigris(), "run")
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
