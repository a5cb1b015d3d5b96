"""Figures that are true at a glance, applied to every figure the tools write.

An axis whose plotted values vary by less than FLAT (5%) of their size would otherwise be
auto-scaled until a 0.04% wobble fills the panel and looks like a cliff. Such an axis is drawn
from zero and says "flat" with the actual spread. Every figure names what it shows, and says when
its points were sampled (sim.sampling: estimated figures).
"""
import math

import matplotlib

# SVG text stays text: searchable, selectable and checked by the tests.
matplotlib.rcParams["svg.fonttype"] = "none"

FLAT = 0.05  # spread / size below which an axis counts as flat (drawn from zero)


def _values(ax):
    vals = []
    for line in ax.get_lines():
        for y in line.get_ydata():
            try:
                f = float(y)
            except (TypeError, ValueError):
                continue
            if math.isfinite(f):
                vals.append(f)
    return vals


def guard_flat(fig):
    """Draws each flat y axis from zero with a "flat" label; returns the labels it added."""
    added = []
    for ax in fig.axes:
        if ax.get_yscale() != "linear":
            continue
        vals = _values(ax)
        if len(vals) < 2:
            continue
        lo, hi = min(vals), max(vals)
        size = max(abs(lo), abs(hi))
        if size == 0 or hi - lo >= FLAT * size:
            continue
        spread = 100 * (hi - lo) / size
        if lo >= 0:
            ax.set_ylim(0, hi * 1.15)
        else:
            ax.set_ylim(lo * 1.15, 0) if hi <= 0 else None
        label = ax.get_ylabel() or "values"
        text = f"flat: {label} within {spread:.2g}% (axis from 0)"
        ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=9,
                bbox=dict(boxstyle="round", fc="lightyellow", ec="0.6"))
        added.append(text)
    return added


def name_workload(fig, text):
    """Adds the workload and fixed settings under the figure's title."""
    title = fig._suptitle.get_text() if fig._suptitle is not None else ""
    fig.suptitle(f"{title}\n{text}" if title else text, fontsize=11)
    fig.tight_layout()


def sampled_note(rows):
    """[a note] when rows of a sweep CSV were sampled runs (sim.sampling): their cycles and energy
    are estimates; [] otherwise."""
    sampled = [r for r in rows if str(r.get("sampling.sampled", "")).strip().lower() in ("true", "1")]
    if not sampled:
        return []
    widths = []
    for r in sampled:
        try:
            widths.append(float(r.get("sampling.relative_half_width") or 0))
        except ValueError:
            pass
    most = f", 95% intervals within +-{100 * max(widths):.1f}%" if widths else ""
    return [f"{len(sampled)} of {len(rows)} points sampled (sim.sampling): their cycles and energy are estimates{most}"]
