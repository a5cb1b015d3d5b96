#!/usr/bin/python3
"""Figures of a sweep: `tigris plot SWEEP_DIR|CSV... [--out DIR] [--y COLUMN ...] [--which NAME ...]`.

For each swept key, a figure of the headline figures (cycles, energy, power; --y chooses other
sweep.csv columns) against it, each axis from zero: sweep_<key>.png and .svg. With several SWEEPs
each figure's name carries its sweep's, sweep_<key>-<name>.png (the sweep folder's name, or the
CSV's without .csv; sweep_<key>-<name>-<n>.png, n its place on the command line, when two share a
name): two sweeps of one key never write one file. The other swept keys give one line per
combination when there are at most six; otherwise they are held at the model's default (or their
first value) and the title says so. Then the paper's figures (tigris/reports/plots.py: redundancy, units,
height, optimizations, memory_traffic, approx) that the sweep's settings cover.

Every figure names its workload and the settings all its points share; an axis whose values vary
by less than 5% is drawn from zero and labelled "flat". A footer says what made it: this command
line and commit, and each sweep.csv's SHA-256 with the command line and commit of the sweep
that wrote it (its folder's manifest.json). The output folder holds manifest.json, must be new,
empty or an earlier plot's folder, and its earlier figures are replaced. The default is the first
SWEEP's own: SWEEP_DIR/plots (also for SWEEP_DIR/sweep.csv), NAME-plots beside any other CSV
NAME.csv; it is replaced only when it holds the figures of the same SWEEPs, else refused (give
--out). A SWEEP whose folder a run is still writing (a sweep extending it) is refused, naming the
run. Runs on Debian's python3 with python3-matplotlib (`tigris plot` starts /usr/bin/python3).
Exit status 0 when at least one figure was written, 2 otherwise (also for a --y column without
numbers).
"""
import argparse
import csv
import io
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("tigris plot: error: matplotlib is missing from this python3 (Debian: apt-get install "
             "python3-matplotlib; `tigris plot` uses /usr/bin/python3)")

from .. import core  # noqa: E402
from ..data import evaldata as ed  # noqa: E402
from ..reports import figure_truth, plots  # noqa: E402

PROG = "tigris plot"
MAX_LINES = 6
HEADLINE = [("cycles", "cycles", 1.0), ("energy_pj.total", "energy (uJ)", 1e-6), ("power_w", "power (W)", 1.0)]


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def say(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)


OUTPUTS = ["sweep_*.png", "sweep_*.svg"] + [f"{n}.{e}" for n in plots.FIGURES for e in ("png", "svg")]


def csv_of(arg):
    try:                        # a sweep still running rewrites its sweep.csv as it ends
        core.refuse_if_written(arg, "SWEEP")
    except core.Refused as e:
        die(str(e))
    if os.path.isdir(arg):
        path = os.path.join(arg, "sweep.csv")
        if not os.path.lexists(path):
            die(f"{arg} holds no sweep.csv (a sweep folder is what `tigris sweep SPEC --out DIR` writes)")
    elif not os.path.lexists(arg):
        die(f"no such sweep folder or CSV: {arg}")
    else:
        path = arg
    try:
        core.check_input(path, "a sweep CSV", core.MAX_SETTINGS_BYTES)
    except core.Refused as e:
        die(str(e))
    return path


def safe(name):
    return "".join(ch if ch.isalnum() or ch in "._-" else "_" for ch in name)


def default_out(arg, path):
    """SWEEP/plots for a sweep folder (or its sweep.csv), NAME-plots beside another CSV: two
    CSVs of one folder never share a default folder."""
    if os.path.isdir(arg):
        return os.path.join(arg, "plots")
    d, base = os.path.split(path)
    return os.path.join(d, "plots" if base == "sweep.csv" else safe(os.path.splitext(base)[0]) + "-plots")


def source_names(args, paths):
    """Each SWEEP's name in its figures' names when several are plotted: the folder's name (a
    CSV's name without .csv; a sweep.csv: its folder's), numbered when two share one."""
    names = []
    for arg, path in zip(args, paths):
        full = os.path.abspath(arg if os.path.isdir(arg) else path)
        if not os.path.isdir(arg) and os.path.basename(full) == "sweep.csv":
            full = os.path.dirname(full)
        names.append(safe(os.path.splitext(os.path.basename(full))[0] if os.path.isfile(full)
                          else os.path.basename(full)) or "sweep")
    if len(set(names)) < len(names):
        names = [f"{n}-{i}" for i, n in enumerate(names, 1)]
    return names


def read(path):
    """(columns, rows as dicts, swept keys) of one sweep.csv."""
    try:
        r = csv.reader(io.StringIO(core.read_text_input(path, "a sweep CSV"), newline=""))
        cols = next(r, None) or []
        rows = [dict(zip(cols, cells)) for cells in r if cells]
    except csv.Error as e:
        die(f"{path}: {e}")
    except core.Refused as e:
        die(str(e))
    if "status" not in cols or "point" not in cols:
        die(f"{path}: no `point` and `status` columns: not a sweep CSV")
    swept = cols[cols.index("point") + 1:cols.index("status")]
    side = os.path.join(os.path.dirname(os.path.abspath(path)), "sweep.json")
    if os.path.lexists(side):
        try:
            info = core.read_json_input(side, "the sweep.json beside the CSV")
        except core.Refused as e:
            die(str(e))
        if isinstance(info, dict) and info.get("columns") == cols and isinstance(info.get("swept_keys"), list):
            swept = info["swept_keys"]
    return cols, rows, swept


def number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def default_of(key):
    name = ed.SPEC_NAMES.get(key)
    v = ed.DEFAULTS.get(name) if name else None
    return None if v is None else str(v)


def sweep_figure(key, rows, swept, ys, workload):
    others = [k for k in swept if k != key]
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r.get(k, "") for k in others), []).append(r)
    held = ""
    if len(groups) > MAX_LINES:
        pick = []
        for i, k in enumerate(others):
            vals = [g[i] for g in groups]
            d = default_of(k)
            pick.append(next((v for v in vals if number(v) is not None and number(d) is not None
                              and number(v) == number(d)), vals[0]))
        held = ", ".join(f"{k}={v}" for k, v in zip(others, pick))
        groups = {tuple(pick): groups.get(tuple(pick), [])}
    xs_all = [r.get(key, "") for r in rows]
    numeric = all(number(x) is not None for x in xs_all)
    order = sorted(set(xs_all), key=number) if numeric else list(dict.fromkeys(xs_all))
    fig, axes = plt.subplots(1, len(ys), figsize=(5.2 * len(ys), 4.2), squeeze=False)
    axes = axes[0]
    for n, (combo, rs) in enumerate(groups.items()):
        rs = sorted(rs, key=lambda r: order.index(r.get(key, "")))
        label = ", ".join(f"{k}={v}" for k, v in zip(others, combo)) if others and not held else None
        for ax, (col, ylabel, f) in zip(axes, ys):
            pts = [(r.get(key, ""), number(r.get(col))) for r in rs]
            pts = [(x if not numeric else number(x), y * f) for x, y in pts if y is not None]
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=plots.COLORS[n % len(plots.COLORS)],
                    label=label)
    for ax, (col, ylabel, f) in zip(axes, ys):
        ax.set_xlabel(key)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if numeric and len(order) > 2 and max(number(x) for x in order) / max(1e-300, min(number(x) for x in order)) >= 8 \
                and min(number(x) for x in order) > 0:
            ax.set_xscale("log", base=2)
        if numeric and len(order) <= 10:
            ax.set_xticks([number(x) for x in order])
            ax.set_xticklabels(order)
            ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter(useOffset=False))
        # Magnitudes from zero, so a ratio reads as a ratio (a 6% change never fills a panel).
        lo, hi = ax.get_ylim()
        if lo > 0:
            ax.set_ylim(0, hi * 1.05)
    if any(ax.get_legend_handles_labels()[0] for ax in axes[:1]):
        axes[0].legend(fontsize=8)
    fig.suptitle(f"{', '.join(y[1] for y in ys)} against {key}" + (f" (others held at {held})" if held else ""),
                 fontsize=12)
    sampled = figure_truth.sampled_note(rows)
    notes = figure_truth.guard_flat(fig) + sampled
    figure_truth.name_workload(fig, "\n".join([workload] + sampled))
    return fig, notes


def plot_main(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n\n".join(__doc__.split("\n\n")[1:]))
    ap.add_argument("sweeps", nargs="+", metavar="SWEEP", help="a sweep folder (with sweep.csv) or a sweep CSV")
    core.role(ap.add_argument("--out", metavar="DIR", help="folder for the figures (default: SWEEP/plots, or "
                              "NAME-plots beside a CSV NAME.csv)"), "out_folder")
    ap.add_argument("--y", nargs="+", metavar="COLUMN",
                    help="sweep.csv columns to plot against each swept key (default: cycles energy_pj.total power_w)")
    ap.add_argument("--which", nargs="+", metavar="NAME", choices=["sweep"] + list(plots.FIGURES),
                    help="only these figures: sweep (the swept-key figures) or a paper figure: "
                         + ", ".join(plots.FIGURES))
    ap.add_argument("--list-flags", action="store_true", help="Print this command's flags as JSON (flag, type, "
                    "default, meaning) for tools, and exit")
    core.list_flags(ap, "plot", argv)
    a = ap.parse_args(argv)
    paths = [csv_of(s) for s in a.sweeps]
    seen = {}
    for arg, path in zip(a.sweeps, paths):
        if os.path.realpath(path) in seen:
            die(f"SWEEP {seen[os.path.realpath(path)]} and {arg} are one sweep CSV ({path}): give it once")
        seen[os.path.realpath(path)] = arg
    out = a.out or default_out(a.sweeps[0], paths[0])
    try:
        sw = ed.Sweep(paths)
    except (ValueError, OSError, core.Refused) as e:
        die(str(e))
    workload = ed.workload_text(sw)
    tables = [(path,) + read(path) for path in paths] if not a.which or "sweep" in a.which else []
    for path, cols, rows, swept in tables:     # every column checked before the folder is touched
        ys = [(c, c, 1.0) for c in a.y] if a.y else HEADLINE
        missing = [c for c, _, _ in ys if c not in cols]
        if missing:
            die(f"{path} has no column {', '.join(missing)} (its columns: {', '.join(cols[:12])}, ...)")
        ok = [r for r in rows if r.get("status") == "ok"]
        for c, _, _ in ys:
            vals = [r.get(c, "") for r in ok]
            if ok and not any(number(v) is not None for v in vals):
                example = next((v for v in vals if v), "")
                die(f"{path}: column {c} holds no number among the {len(ok)} ok point(s)"
                    + (f" (e.g. {example!r})" if example else " (it is empty)") + ": nothing to plot against "
                    "the swept keys; --y takes numeric columns")
    # Every figure's name before the folder is touched: one path, one figure.
    names, stems = source_names(a.sweeps, paths), {}
    for i, (path, cols, rows, swept) in enumerate(tables):
        for key in swept:
            stem = "sweep_" + safe(key) + (f"-{names[i]}" if len(paths) > 1 else "")
            if stem in stems.values():
                other = next(p for (p, _), st in stems.items() if st == stem)
                die(f"{other} and {path} would both write {stem}.png: plot them one at a time (with --out)")
            stems[path, key] = stem
    folder = core.OutFolder(out, "plot", OUTPUTS)
    try:                        # a default folder holding another input's figures is kept
        folder.claim(settings={"sweeps": [os.path.abspath(p) for p in paths]}, resume=False,
                     input_paths=[("SWEEP", p) for p in paths], only_same=not a.out)
    except core.Refused as e:
        die(str(e) + ("" if a.out else f"\n({out} is the default --out of SWEEP {a.sweeps[0]})"))
    rc = 2
    try:
        rc = draw(a, paths, tables, stems, sw, workload, out, plots.sweep_footer(paths, folder.argv))
        return rc
    finally:
        folder.finish(rc)


def draw(a, paths, tables, stems, sw, workload, out, footer):
    written = []
    if not a.which or "sweep" in a.which:
        for path, cols, rows, swept in tables:
            ok = [r for r in rows if r.get("status") == "ok"]
            if len(ok) < len(rows):
                say(f"{path}: {len(rows) - len(ok)} point(s) not ok (mismatch or error) left out")
            ys = [(c, c, 1.0) for c in a.y] if a.y else HEADLINE
            missing = [c for c, _, _ in ys if c not in cols]
            if missing:
                die(f"{path} has no column {', '.join(missing)} (its columns: {', '.join(cols[:12])}, ...)")
            if not swept:
                say(f"{path}: sweeps no key (a list of points): no swept-key figure")
            for key in swept:
                if len({r.get(key) for r in ok}) < 2:
                    say(f"{path}: {key} takes one value among the ok points: no figure")
                    continue
                fig, notes = sweep_figure(key, ok, swept, ys, workload)
                core.add_footer(fig, footer)
                stem = os.path.join(out, stems[path, key])
                core.save_figure(fig, stem + ".png", dpi=110)
                core.save_figure(fig, stem + ".svg")
                plt.close(fig)
                written.append(stem + ".png")
                say(f"wrote {stem}.png and .svg" + (f" ({'; '.join(notes)})" if notes else ""))
    paper = [w for w in (a.which or plots.FIGURES) if w != "sweep"]
    if paper:
        def log(msg):
            if not msg.startswith("plots: skipped"):
                say(msg[len("plots: "):] if msg.startswith("plots: ") else msg)
        try:
            made, skipped = plots.make_figures(sw, out, paper if a.which else None, log=log, footer=footer)
        except plots.Skip as e:
            die(f"cannot make {e}")
        written += [m[0] for m in made.values()]
        if skipped:
            say(f"paper figures this sweep does not cover: {', '.join(skipped)} (python3 -m tigris figures --help says "
                "what each needs)")
    if not written:
        die("no figure could be made from " + ", ".join(paths))
    return 0


def main(argv):
    """The command: plot_main with a refused input or folder said in one line, exit 2."""
    try:
        return plot_main(argv)
    except core.Refused as e:
        die(str(e))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
