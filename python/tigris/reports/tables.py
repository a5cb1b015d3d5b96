"""The claim table of REPORT.md (Markdown), which the report and the pipeline section share."""
from .claims import xf
from . import variants as vt


def md_cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


def speed_text(c):
    """A speed claim's ratios as the table and summary show them: "cycles / work / ideal"."""
    show = lambda v: xf(v) if v is not None else "n/a"  # noqa: E731
    return " / ".join(show(c.speed[k]) for k in ("cycles", "work", "ideal"))


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
