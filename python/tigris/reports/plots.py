#!/usr/bin/python3
"""The paper's evaluation figures from sweep CSVs (docs/sweeps.md).

    python3 -m tigris figures CSV... --out DIR [--which NAME ...]

Writes DIR/<name>.png and DIR/<name>.svg for every figure whose settings the CSVs sweep:

  redundancy       two-stage redundancy vs leaf-set size, NN and radius (paper section 4.1, Fig. 3)
  units            RU x SU x PE: search time and power (Fig. 13)
  height           top-tree height vs search time and energy (Fig. 14)
  optimizations    No-Opt / Bypass / +Forward / MQMN: speed-up and power (Fig. 11)
  memory_traffic   on-chip memory traffic by buffer with and without the Node Cache (Fig. 12)
  approx           approximation threshold vs visits, cycles and accuracy (section 4.3, 6.3)

A figure picks the rows it needs by the settings they sweep (the other settings held at one
value: the largest such group); a figure whose settings are not swept is skipped with a message,
or is an error (exit 2) when named with --which. Rows whose status is not ok are left out.
Each figure's footer says what drew it and from what (tigris/core/provenance.py): this command
line and, for each CSV, its SHA-256 and the command line and commit in the manifest.json of its
sweep folder.
"""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

from .. import core  # noqa: E402
from ..data import evaldata as ed  # noqa: E402
from . import figure_truth  # noqa: E402
from ..data.evaldata import num  # noqa: E402

# The paper's redundancy at leaf-set size 32 (KITTI; section 4.1), drawn for comparison only.
PAPER_REDUNDANCY_32 = {"nn": 35.0, "radius": 3.0}
COLORS = plt.rcParams["axes.prop_cycle"].by_key()["color"]


class Skip(Exception):
    """The CSVs do not hold what a figure needs."""


def _need_columns(sw, name, any_of=(), all_of=()):
    """any_of: setting columns (one must be swept or set); all_of: stats columns."""
    missing = [c for c in all_of if not sw.has_column(c)]
    if any_of and not any(c in sw.setting_columns for c in any_of):
        missing.insert(0, " or ".join(any_of))
    if missing:
        raise Skip(f"{name}: the CSVs have no column {', '.join(missing)}")


def _exact(e):
    return e["approx"] is None


def _series(rows):
    out = {}
    for r in rows:
        out.setdefault(ed.search_label(r["eff"]), []).append(r)
    return out


def _new_figure(ncols, nrows=1, width=5.6, height=4.3):
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows), squeeze=False)
    return fig, [a for row in axes for a in row]


def _scale(ax, values, axis="y"):
    """Log scale when the values span more than 10x, else linear; plain tick labels either way."""
    vals = [v for v in values if v is not None and v > 0]
    fmt = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
    if vals and max(vals) / min(vals) > 10:
        (ax.set_yscale if axis == "y" else ax.set_xscale)("log")
        target = ax.yaxis if axis == "y" else ax.xaxis
        target.set_major_formatter(fmt)
        target.set_minor_formatter(matplotlib.ticker.NullFormatter())
    else:
        target = ax.yaxis if axis == "y" else ax.xaxis
        target.set_major_formatter(matplotlib.ticker.ScalarFormatter(useOffset=False))


def _finish(fig, title, notes):
    fig.suptitle(title, fontsize=12)
    fig.tight_layout()
    fig.notes = notes
    return fig


# ---------------------------------------------------------------- redundancy (paper Fig. 3)

def fig_redundancy(sw):
    _need_columns(sw, "redundancy", any_of=("height", "tree.top_height"),
                  all_of=("tree.leaf_set_mean",))
    rows, msg = ed.select(sw.ok, {"height", "mode", "radius", "k"}, where=_exact)
    notes = [msg] if msg else []
    series = {}
    for label, rs in _series(rows).items():
        canon = [r for r in rs if r["eff"]["height"] == ed.CANONICAL]
        two = sorted((r for r in rs if r["eff"]["height"] != ed.CANONICAL
                      and (num(r, "tree.leaf_set_mean") or 0) > 0),
                     key=lambda r: num(r, "tree.leaf_set_mean"))
        if canon and two:
            series[label] = (canon[0], two)
    if not series:
        raise Skip("redundancy: needs, for one search, a canonical-tree row (height full) and a "
                   "two-stage row (a numeric height), exact search")
    fig, (a, b) = _new_figure(2)
    for i, (label, (canon, two)) in enumerate(series.items()):
        c = COLORS[i % len(COLORS)]
        base = ed.nodes_per_query(canon)
        xs = [1.0] + [num(r, "tree.leaf_set_mean") for r in two]
        ys = [base] + [ed.nodes_per_query(r) for r in two]
        a.plot(xs, [y / base for y in ys], "o-", color=c, label=f"{label} (measured)")
        b.plot(xs, ys, "o-", color=c, label=label)
        mode = canon["eff"]["mode"]
        if mode in PAPER_REDUNDANCY_32:
            a.plot([32], [PAPER_REDUNDANCY_32[mode]], "x", color=c, markersize=9, mew=2,
                   label=f"{label}: paper, KITTI ({PAPER_REDUNDANCY_32[mode]:g}x at 32)")
    for ax in (a, b):
        ax.set_xscale("log", base=2)
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.set_xlabel("leaf-set size (points per top-tree leaf; 1 = canonical tree)")
        ax.grid(True, which="both", alpha=0.3)
    _scale(a, [y for l in a.get_lines() for y in l.get_ydata()])
    a.axhline(1.0, color="grey", lw=0.8, ls="--")
    a.set_ylabel("redundancy (nodes visited / canonical tree's)")
    a.set_title("(a) redundancy ratio")
    _scale(b, [y for l in b.get_lines() for y in l.get_ydata()])
    b.set_ylabel("nodes visited per query (top-tree nodes + leaf points)")
    b.set_title("(b) nodes visited per query")
    a.legend(fontsize=8)
    b.legend(fontsize=8)
    return _finish(fig, "Two-stage KD-tree redundancy vs leaf-set size (exact search)", notes)


# ---------------------------------------------------------------- RU x SU x PE (Fig. 13)

def fig_units(sw):
    _need_columns(sw, "units", any_of=("fe.recursion_units", "be.search_units", "be.pes_per_su"),
                  all_of=("seconds", "power_w"))
    rows, msg = ed.select(sw.ok, {"ru", "su", "pe"}, where=_exact)
    notes = [msg] if msg else []
    rus = sorted({r["eff"]["ru"] for r in rows})
    cfgs = sorted({(r["eff"]["su"], r["eff"]["pe"]) for r in rows})
    if len(rows) < 2:
        raise Skip("units: needs at least two RU / SU / PE configurations")
    fig, (a, b) = _new_figure(2, width=6.2)
    for i, ru in enumerate(rus):
        c = COLORS[i % len(COLORS)]
        rs = sorted((r for r in rows if r["eff"]["ru"] == ru), key=lambda r: (r["eff"]["su"], r["eff"]["pe"]))
        a.scatter([num(r, "power_w") for r in rs], [1e3 * num(r, "seconds") for r in rs],
                  color=c, label=f"{ru} RU", s=22)
        b.plot([cfgs.index((r["eff"]["su"], r["eff"]["pe"])) for r in rs],
               [1e3 * num(r, "seconds") for r in rs], "o-", color=c, label=f"{ru} RU", ms=4)
    d = ed.find(rows, ru=64, su=32, pe=32)
    if d is not None:
        a.scatter([num(d, "power_w")], [1e3 * num(d, "seconds")], marker="*", s=220,
                  facecolor="none", edgecolor="black", label="64 RU, 32 SU x 32 PE (paper's choice)")
        b.plot([cfgs.index((32, 32))], [1e3 * num(d, "seconds")], "*", ms=15, mfc="none",
               mec="black", label="paper's choice")
    a.set_xlabel("power (W)")
    a.set_ylabel("KD-tree search time (ms)")
    a.set_title("(a) performance vs power")
    b.set_xticks(range(len(cfgs)))
    b.set_xticklabels([f"{s}x{p}" for s, p in cfgs], rotation=70, fontsize=7)
    b.set_xlabel("SU x PE per SU")
    b.set_ylabel("KD-tree search time (ms)")
    b.set_title("(b) performance by configuration")
    times = [1e3 * num(r, "seconds") for r in rows]
    for ax in (a, b):
        _scale(ax, times)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    return _finish(fig, "Sensitivity to the number of RUs, SUs and PEs per SU", notes)


# ---------------------------------------------------------------- top height (Fig. 14)

def fig_height(sw):
    _need_columns(sw, "height", any_of=("height", "tree.top_height"),
                  all_of=("seconds", "energy_pj.total"))
    rows, msg = ed.select(sw.ok, {"height", "mode", "radius", "k"}, where=_exact)
    notes = [msg] if msg else []
    series = {}
    for label, rs in _series(rows).items():
        if len({r["eff"]["height"] for r in rs if r["eff"]["height"] != ed.CANONICAL}) >= 2:
            series[label] = rs
    if not series:
        raise Skip("height: needs at least two numeric top heights for one search")
    fig, axes = _new_figure(len(series))
    for ax, (label, rs) in zip(axes, series.items()):
        two = sorted((r for r in rs if r["eff"]["height"] != ed.CANONICAL), key=lambda r: r["eff"]["height"])
        canon = [r for r in rs if r["eff"]["height"] == ed.CANONICAL]
        xs = [r["eff"]["height"] for r in two]
        t = [1e3 * num(r, "seconds") for r in two]
        e = [num(r, "energy_pj.total") / 1e6 for r in two]
        ax.plot(xs, t, "o-", color=COLORS[0], label="search time")
        best = min(range(len(t)), key=lambda i: t[i])
        ax.plot([xs[best]], [t[best]], "o", ms=12, mfc="none", mec=COLORS[0],
                label=f"fastest: height {xs[best]}")
        ax2 = ax.twinx()
        ax2.plot(xs, e, "s--", color=COLORS[1], label="energy")
        if canon:
            h = int(num(canon[0], "tree.full_height") or max(xs) + 2)
            ax.plot([h], [1e3 * num(canon[0], "seconds")], "D", color=COLORS[0],
                    label=f"canonical tree (Acc-KD, height {h})")
            ax2.plot([h], [num(canon[0], "energy_pj.total") / 1e6], "D", color=COLORS[1])
        ax.set_xlabel("top-tree height")
        ax.set_ylabel("KD-tree search time (ms)", color=COLORS[0])
        ax2.set_ylabel("energy (uJ)", color=COLORS[1])
        _scale(ax, t + [1e3 * num(r, "seconds") for r in canon])
        _scale(ax2, e + [num(r, "energy_pj.total") / 1e6 for r in canon])
        ax.set_title(label)
        ax.grid(True, which="both", alpha=0.3)
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = ax2.get_legend_handles_labels()
        ax.legend(h1 + h2, l1 + l2, fontsize=8)
    return _finish(fig, "Search time and energy vs top-tree height", notes)


# ---------------------------------------------------------------- optimisations (Fig. 11)

VARIANTS = {(False, False, "mqsn"): "No-Opt", (True, False, "mqsn"): "Bypass",
            (True, True, "mqsn"): "+Forward", (True, True, "mqmn"): "MQMN"}


def variant_name(eff):
    key = (eff["bypass"], eff["forward"], eff["policy"])
    if key in VARIANTS:
        return VARIANTS[key]
    return (f"{eff['policy'].upper()}, " + ("bypass" if eff["bypass"] else "no bypass") + ", "
            + ("forward" if eff["forward"] else "no forward"))


def optimization_rows(sw):
    rows, msg = ed.select(sw.ok, {"bypass", "forward", "policy"}, where=_exact)
    order = list(VARIANTS.values())
    rows = sorted(rows, key=lambda r: (order.index(variant_name(r["eff"]))
                                       if variant_name(r["eff"]) in order else len(order),
                                       variant_name(r["eff"])))
    return rows, msg


def fig_optimizations(sw):
    _need_columns(sw, "optimizations", any_of=("fe.bypassing", "fe.forwarding", "be.issue_policy"),
                  all_of=("cycles", "power_w"))
    rows, msg = optimization_rows(sw)
    notes = [msg] if msg else []
    if len(rows) < 2:
        raise Skip("optimizations: needs at least two of No-Opt / Bypass / +Forward / MQMN")
    names = [variant_name(r["eff"]) for r in rows]
    ref = rows[names.index("No-Opt")] if "No-Opt" in names else rows[0]
    ref_name = variant_name(ref["eff"])
    speed = [num(ref, "cycles") / num(r, "cycles") for r in rows]
    power = [num(r, "power_w") for r in rows]
    fig, (a,) = _new_figure(1, width=6.4)
    bars = a.bar(range(len(rows)), speed, color=COLORS[0], width=0.55, label=f"speed-up over {ref_name}")
    for bar, s in zip(bars, speed):
        a.annotate(f"{s:.2f}x", (bar.get_x() + bar.get_width() / 2, s), ha="center", va="bottom", fontsize=8)
    a.set_xticks(range(len(rows)))
    a.set_xticklabels(names)
    a.set_xlabel("accelerator variant (exact search, top height %s)" % rows[0]["eff"]["height"])
    a.set_ylabel(f"speed-up over {ref_name} (x)")
    a2 = a.twinx()
    a2.plot(range(len(rows)), power, "D-", color=COLORS[1], label="power")
    a2.set_ylabel("power (W)", color=COLORS[1])
    a2.set_ylim(0, max(power) * 1.25)
    a.set_ylim(0, max(speed) * 1.25)
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = a2.get_legend_handles_labels()
    a.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper left")
    a.grid(True, axis="y", alpha=0.3)
    a.set_title(ed.search_label(rows[0]["eff"]))
    return _finish(fig, "Architectural optimisations: speed-up and power", notes)


# ---------------------------------------------------------------- memory traffic (Fig. 12)

def traffic_label(eff):
    tree = "Acc-KD" if eff["height"] == ed.CANONICAL else f"Acc-2SKD (h {eff['height']})"
    if eff["nc_bytes"] == 0:
        nc = "no Node Cache"
    elif eff["nc_bytes"] == ed.DEFAULTS["nc_bytes"]:
        nc = "Node Cache"
    else:
        nc = f"Node Cache {eff['nc_bytes'] / 1024:g} KiB"
    return f"{tree}\n{nc}"


def traffic_rows(sw):
    rows, msg = ed.select(sw.ok, {"nc_bytes", "height"}, where=_exact)
    per_height = {}
    for r in rows:
        per_height.setdefault(r["eff"]["height"], set()).add(r["eff"]["nc_bytes"])
    keep = [r for r in rows if len(per_height[r["eff"]["height"]]) > 1]
    if len(keep) < len(rows):
        msg = "; ".join(x for x in (msg, f"{len(rows) - len(keep)} row(s) at heights without both "
                                    "Node Cache settings left out") if x)
    rows = sorted(keep, key=lambda r: (r["eff"]["height"] == ed.CANONICAL,
                                       str(r["eff"]["height"]), -r["eff"]["nc_bytes"]))
    return rows, msg


def fig_memory_traffic(sw):
    _need_columns(sw, "memory_traffic", any_of=("node_cache.bytes",), all_of=("buffers.points.read_bytes",))
    rows, msg = traffic_rows(sw)
    notes = [msg] if msg else []
    if len({r["eff"]["nc_bytes"] for r in rows}) < 2:
        raise Skip("memory_traffic: needs rows with and without the Node Cache (node_cache.bytes 0)")
    traffic = [ed.buffer_traffic(r, sw.columns) for r in rows]
    bufs = [b for b in ed.BUFFER_LABELS if any(t.get(b) for t in traffic)]
    bufs += sorted({b for t in traffic for b in t if b not in bufs and t[b]})
    fig, (a, b) = _new_figure(2, width=max(5.0, 1.2 * len(rows) + 1.6))
    x = range(len(rows))
    bottom_p, bottom_b = [0.0] * len(rows), [0.0] * len(rows)
    for i, buf in enumerate(bufs):
        vals = [t.get(buf, 0.0) for t in traffic]
        pct = [100 * v / sum(t.values()) if sum(t.values()) else 0 for v, t in zip(vals, traffic)]
        lab = ed.BUFFER_LABELS.get(buf, buf)
        bars = a.bar(x, pct, bottom=bottom_p, color=COLORS[i % len(COLORS)], label=lab, width=0.6)
        if buf == "points":
            for bar, p, y0 in zip(bars, pct, bottom_p):
                a.annotate(f"{p:.0f}%", (bar.get_x() + bar.get_width() / 2, y0 + p / 2),
                           ha="center", va="center", fontsize=8, color="white")
        b.bar(x, [v / 1e6 for v in vals], bottom=bottom_b, color=COLORS[i % len(COLORS)], label=lab, width=0.6)
        bottom_p = [p0 + p for p0, p in zip(bottom_p, pct)]
        bottom_b = [b0 + v / 1e6 for b0, v in zip(bottom_b, vals)]
    labels = [traffic_label(r["eff"]) for r in rows]
    for ax in (a, b):
        ax.set_xticks(list(x))
        ax.set_xticklabels(labels, fontsize=8)
        ax.set_xlabel("configuration (exact %s search)" % ed.search_label(rows[0]["eff"]))
        ax.grid(True, axis="y", alpha=0.3)
    a.set_ylabel("share of on-chip memory traffic (%)")
    a.set_ylim(0, 100)
    a.set_title("(a) traffic distribution by buffer")
    b.set_ylabel("on-chip memory traffic (MB read + written)")
    b.set_title("(b) traffic by buffer")
    b.legend(fontsize=8)
    return _finish(fig, "Memory traffic by buffer, with and without the Node Cache", notes)


# ---------------------------------------------------------------- approximate search

def fig_approx(sw):
    _need_columns(sw, "approx", any_of=("approx-thd",), all_of=("cycles",))
    rows, msg = ed.select(sw.ok, {"approx", "mode", "radius", "k"})
    notes = [msg] if msg else []
    series = {l: sorted(rs, key=lambda r: r["eff"]["approx"] or 0.0) for l, rs in _series(rows).items()
              if any(r["eff"]["approx"] is not None for r in rs)}
    if not series:
        raise Skip("approx: needs rows with an approximation threshold (approx-thd)")
    fig, (a, b, c, d) = _new_figure(2, 2, width=5.6, height=3.9)
    any_nn = False
    rel_all = True
    for i, (label, rs) in enumerate(series.items()):
        col = COLORS[i % len(COLORS)]
        xs = [r["eff"]["approx"] or 0.0 for r in rs]
        a.plot(xs, [ed.nodes_per_query(r) for r in rs], "o-", color=col, label=label)
        ex = [r for r in rs if r["eff"]["approx"] is None]
        if ex:
            b.plot(xs, [num(r, "cycles") / num(ex[0], "cycles") for r in rs], "o-", color=col, label=label)
        else:
            rel_all = False
            b.plot(xs, [num(r, "cycles") for r in rs], "o-", color=col, label=f"{label} (cycles)")
        radius = rs[0]["eff"]["mode"] == "radius"
        acc = []
        for r in rs:
            if r["eff"]["approx"] is None:
                acc.append(1.0)
            else:
                acc.append(num(r, "accuracy.recall" if radius else "accuracy.exact_match_fraction"))
        c.plot(xs, acc, "o-", color=col,
               label=f"{label}: " + ("recall" if radius else "queries with the exact answer"))
        if not radius:
            any_nn = True
            d.plot(xs, [0.0 if r["eff"]["approx"] is None else num(r, "accuracy.mean_extra_distance_m")
                        for r in rs], "o-", color=col, label=f"{label}: mean")
            d.plot(xs, [0.0 if r["eff"]["approx"] is None else num(r, "accuracy.max_extra_distance_m")
                        for r in rs], "^:", color=col, label=f"{label}: max")
    xl = "approximation threshold thd (m); 0 = exact search"
    a.set_ylabel("nodes visited per query")
    a.set_title("(a) visits (top nodes, leaf points, leader checks, follower points)", fontsize=9)
    b.set_ylabel("cycles / exact search's cycles" if rel_all else "cycles")
    b.set_title("(b) simulated cycles" + (", relative to exact search" if rel_all else ""))
    c.set_ylabel("accuracy (fraction)")
    c.set_ylim(-0.02, 1.02)
    c.set_title("(c) accuracy against exact search")
    d.set_ylabel("extra distance to the neighbour (m)")
    d.set_title("(d) NN/kNN distance error")
    if not any_nn:
        d.text(0.5, 0.5, "no NN/kNN rows", ha="center", va="center", transform=d.transAxes)
    for ax in (a, b, c, d):
        ax.set_xlabel(xl)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    return _finish(fig, "Approximate search: threshold vs visits, cycles and accuracy", notes)


FIGURES = {
    "redundancy": (fig_redundancy, "Two-stage redundancy vs leaf-set size (paper Fig. 3)"),
    "units": (fig_units, "RU x SU x PE: search time and power (paper Fig. 13)"),
    "height": (fig_height, "Top-tree height vs search time and energy (paper Fig. 14)"),
    "optimizations": (fig_optimizations, "No-Opt / Bypass / +Forward / MQMN: speed-up and power (paper Fig. 11)"),
    "memory_traffic": (fig_memory_traffic, "Memory traffic by buffer with and without the Node Cache (paper Fig. 12)"),
    "approx": (fig_approx, "Approximation threshold vs visits, cycles and accuracy"),
}


def build(name, sw):
    """The Figure for `name` (raises Skip when the sweep lacks its rows)."""
    return FIGURES[name][0](sw)


def sweep_footer(paths, argv):
    """The footer of a figure drawn by argv (a command line) from sweep CSVs: each one's folder
    holds the manifest.json of the tigris sweep that wrote it."""
    made = [core.provenance(os.path.dirname(os.path.abspath(p)), command="sweep", files=[p]) for p in paths]
    return core.footer_lines(made, drawn=core.provenance(argv=argv))


def make_figures(sw, out, which=None, log=ed.note, footer=None):
    """Writes the figures; returns {name: (png, svg, notes)} and {name: skip reason}.
    Named figures (`which`) that cannot be made raise Skip. footer: the lines that say what
    made them (sweep_footer), none without."""
    os.makedirs(out, exist_ok=True)
    made, skipped = {}, {}
    for name in (which or FIGURES):
        try:
            fig = build(name, sw)
        except Skip as e:
            if which:
                raise
            skipped[name] = str(e)
            log(f"plots: skipped {e}")
            continue
        png, svg = os.path.join(out, name + ".png"), os.path.join(out, name + ".svg")
        sampled = figure_truth.sampled_note(getattr(sw, "ok", []))
        fig.notes = getattr(fig, "notes", []) + figure_truth.guard_flat(fig) + sampled
        figure_truth.name_workload(fig, "\n".join([ed.workload_text(sw)] + sampled))
        if footer:
            core.add_footer(fig, footer)
        core.save_figure(fig, png, dpi=110)
        core.save_figure(fig, svg)
        notes = getattr(fig, "notes", [])
        plt.close(fig)
        made[name] = (png, svg, notes)
        log(f"plots: wrote {png} and .svg" + (f" ({'; '.join(notes)})" if notes else ""))
    return made, skipped


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="figures: " + ", ".join(FIGURES))
    ap.add_argument("csv", nargs="+", help="sweep CSVs (tigris/tools/sweep.py's DIR/sweep.csv)")
    ap.add_argument("--out", required=True, help="folder for the PNG and SVG files")
    ap.add_argument("--which", nargs="+", choices=list(FIGURES), metavar="NAME",
                    help="only these figures (an error when one cannot be made): " + ", ".join(FIGURES))
    a = ap.parse_args(argv)
    for p in a.csv:
        if not os.path.isfile(p):
            ap.exit(2, f"plots: no such CSV: {p}\n")
    try:
        sw = ed.Sweep(a.csv)
    except (ValueError, OSError) as e:
        ap.exit(2, f"plots: {e}\n")
    if sw.not_ok:
        ed.note(f"plots: {len(sw.not_ok)} row(s) not ok (mismatch/error) left out")
    try:
        made, _ = make_figures(sw, a.out, a.which, footer=sweep_footer(
            a.csv, sys.argv if argv is None else [sys.argv[0]] + list(argv)))
    except Skip as e:
        ap.exit(2, f"plots: cannot make {e}\n")
    if not made:
        ap.exit(2, "plots: no figure could be made from these CSVs\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
