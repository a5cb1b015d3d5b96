#!/usr/bin/python3
"""tigris pipeline-dse: the paper's section 3. Samples the registration pipeline's design space
(its Table 1), runs every point as `tigris odometry` over one sequence through tigris sweep
(locally or as one Slurm job array), and finds the Pareto frontiers of error against time.

  tigris pipeline-dse [--space FILE] [--samples N] [--seed S] [--pairs N | --sequence DIR
                      [--frames A:B]] [--jobs N | --slurm ...] [--out DIR]

Writes into DIR:
  sequence/          the synthetic drive (--pairs N + 1 frames; not with --sequence)
  spec.json, sweep/  the sweep spec and the sweep folder (points/<id>/, sweep.csv); a rerun resumes
  points.csv         every point: knobs, status, seconds per pair, errors, KD-tree share, stages,
                     its Pareto point name ("dp" column: F1..Fn, empty off the frontiers)
  fig4.png           error against time, translation (a) and rotation (b), frontiers and F1..Fn
  fig5.png           the Pareto points' time across the stages (a), KD-tree search against the rest (b)
  pareto/Fi.json     each Pareto point's pipeline configuration (tigris register --config)
  dse.json           all of it as data, with the paper's section-3 claims measured and the stages
                     in the pipeline's order ("stage_order": the binary's `tigris register --list-stages`)
  REPORT.md          those claims against the paper (direction / within 2x, measured explanations),
                     the figures and the Pareto points: the section `tigris reproduce --dse DIR` adds
                     to its report
The Pareto points are F1..Fn ("frontier point") by time: not DPn, which are the paper's own design
points (its DP4 and DP7 are the presets dp4 and dp7), nor the sampled points P001..PN. Folders of
earlier versions name them DP1..DPn: `tigris reproduce --dse` reads those as F1..Fn.
Each figure's footer says what made it (tigris/core/provenance.py, from DIR/manifest.json): this
command line, the commit, the sample's size and seed, the space file's and the sequence's SHA-256
and a digest of the settings.

Sampling: the default space has some 440,000 points, so a full factorial is out of reach; the
tool draws a seeded Latin-hypercube-like sample over the knobs' levels (each level of each knob
about equally often, the knobs shuffled independently), drops repeats and draws again until N
points differ. A space smaller than N runs as a full factorial. The presets named in the space's
"anchors" always run too. Errors are the mean relative pose error per pair (translation m,
rotation deg) against the sequence's ground truth: a short sequence has no 100 m segment for
KITTI's metrics. Time is the mean registration seconds per pair measured in `tigris register`.
DIR holds manifest.json (docs/architecture.md): a rerun resumes only with the same sequence,
frames and space (file contents included), otherwise it says what changed and stops; DIR must be
new, empty or a folder of an earlier pipeline-dse (a file it did not write is refused).
Exit codes: 0 done (also with failed points: they are recorded), 1 no point converged (no
frontier), 2 bad arguments, space or folder, 3 Slurm submission failed, 128 + a signal when
interrupted.
"""
import argparse, csv, io, json, math, os, random, re, shlex, subprocess, sys

from .. import core
from ..data.binary import SpecError, default_tigris
from ..data.dse_data import PARETO, pareto_number
from ..data.spec import Spec
from ..reports.pipeline import pipeline_section
from .sweep import joined_sbatch_args

HERE = os.path.dirname(os.path.realpath(__file__))
PROG = "tigris pipeline-dse"
DEFAULT_SPACE = os.path.join(HERE, "pipeline_space.json")
# The stages (the paper's seven of its Figure 5a, and outlier removal, a stage of this pipeline
# the paper does not have) come from the binary the exploration runs: `tigris register
# --list-stages` read as the paper's rows [(title, key, time)] (core.paper_stages: ICP is one stage
# of the pipeline; its KD-tree searches are RPCE, the rest is transformation estimation).
# dse.json records their titles in order ("stage_order"), so a reader needs no binary.
MAX_DISTINCT = 1_000_000
# Each point is a whole odometry run; the sweep reads a spec of at most 16 MiB (~450 bytes a point).
MAX_SAMPLES = 10_000
OUTPUTS = ["sequence-*/", "spec.json", "sweep/", "points.csv", "fig4.png", "fig5.png", "pareto/", "dse.json",
           "REPORT.md"]


class Bad(core.Refused):
    """A bad argument or space file: printed, exit 2."""


def say(msg):
    print(f"{PROG}: {msg}", file=sys.stderr, flush=True)


# ----------------------------------------------------------------------------------------------
# The design space

def load_space(path):
    space = core.read_json_input(path, "--space")
    if not isinstance(space, dict):
        raise Bad(f"{path}: a space is a JSON object with base, anchors, knobs")
    for k in space:
        if k not in ("comment", "base", "anchors", "knobs"):
            raise Bad(f"{path}: unknown top-level key '{k}' (allowed: comment, base, anchors, knobs)")
    if not isinstance(space.get("base", {}), dict):
        raise Bad(f"{path}: base: must be an object of tigris odometry flags")
    anchors = space.get("anchors", [])
    if not (isinstance(anchors, list) and all(a in ("dp4", "dp7") for a in anchors)) \
            or len(set(anchors)) != len(anchors):
        raise Bad(f"{path}: anchors: must be a list of distinct presets (dp4, dp7)")
    knobs = space.get("knobs")
    if not isinstance(knobs, list) or not knobs:
        raise Bad(f"{path}: knobs: must be a non-empty list of {{\"key\", \"values\"[, \"when\", \"stage\"]}}")
    seen = {}
    for i, k in enumerate(knobs):
        where = f"{path}: knobs[{i}]"
        if not isinstance(k, dict) or not isinstance(k.get("key"), str) or "." not in k["key"]:
            raise Bad(f"{where}: needs \"key\": a dotted pipeline key (tigris register --list-config)")
        if k["key"] in seen:
            raise Bad(f"{where}: '{k['key']}' is already knobs[{seen[k['key']]}]")
        vals = k.get("values")
        if not isinstance(vals, list) or not vals or any(isinstance(v, (dict, list)) or v is None for v in vals):
            raise Bad(f"{where} ('{k['key']}'): \"values\" must be a non-empty list of numbers, text or booleans")
        if len(set(map(json.dumps, vals))) != len(vals):
            raise Bad(f"{where} ('{k['key']}'): a value is listed twice")
        when = k.get("when", {})
        if not isinstance(when, dict):
            raise Bad(f"{where} ('{k['key']}'): \"when\" must be an object {{earlier knob: value or [values]}}")
        for ck, cv in when.items():
            if ck not in seen:
                raise Bad(f"{where} ('{k['key']}'): \"when\" names '{ck}', which is not an earlier knob")
            allowed = cv if isinstance(cv, list) else [cv]
            bad = [v for v in allowed if not any(same(v, w) for w in knobs[seen[ck]]["values"])]
            if bad:
                raise Bad(f"{where} ('{k['key']}'): \"when\" {ck} = {bad[0]!r} is not one of its values")
        for extra in k:
            if extra not in ("key", "values", "when", "stage"):
                raise Bad(f"{where}: unknown field '{extra}' (allowed: key, values, when, stage)")
        seen[k["key"]] = i
    return space


def same(a, b):
    """Equal values of one type: true is not 1."""
    return type(a) is type(b) and a == b or (isinstance(a, (int, float)) and isinstance(b, (int, float))
                                             and not isinstance(a, bool) and not isinstance(b, bool) and a == b)


def applies(knob, point):
    for ck, cv in (knob.get("when") or {}).items():
        if ck not in point or not any(same(point[ck], v) for v in (cv if isinstance(cv, list) else [cv])):
            return False
    return True


def canonical(knobs, raw):
    """A drawn point with the knobs that do not apply to it left out (so repeats compare equal)."""
    p = {}
    for k in knobs:
        if applies(k, p) and k["key"] in raw:
            p[k["key"]] = raw[k["key"]]
    return p


def enumerate_space(knobs, limit=MAX_DISTINCT):
    """Every distinct point (conditions applied), or None when there are more than `limit`."""
    out = []

    def walk(i, p):
        if len(out) > limit:
            return
        if i == len(knobs):
            out.append(dict(p))
            return
        if not applies(knobs[i], p):
            walk(i + 1, p)
            return
        for v in knobs[i]["values"]:
            p[knobs[i]["key"]] = v
            walk(i + 1, p)
            del p[knobs[i]["key"]]
    walk(0, {})
    return None if len(out) > limit else out


def count_space(knobs):
    """The number of distinct points, without listing them: a knob no later "when" names only
    multiplies, so only the knobs conditions name are branched on."""
    named = {ck for k in knobs for ck in (k.get("when") or {})}

    def walk(i, p):
        if i == len(knobs):
            return 1
        k = knobs[i]
        if not applies(k, p):
            return walk(i + 1, p)
        if k["key"] not in named:
            return len(k["values"]) * walk(i + 1, p)
        total = 0
        for v in k["values"]:
            p[k["key"]] = v
            total += walk(i + 1, p)
            del p[k["key"]]
        return total
    return walk(0, {})


def space_size(knobs, n=MAX_DISTINCT):
    """The number of distinct points, and the points themselves when there are no more than n."""
    size = count_space(knobs)
    return size, (enumerate_space(knobs) if size <= n else None)


def sample(knobs, n, seed):
    """n distinct points: a full factorial when the space has no more; else a Latin-hypercube-like
    draw over the levels (each knob's levels equally often, shuffled per knob), repeats dropped
    and redrawn. Returns (points, how)."""
    size, every = space_size(knobs, n)
    if every is not None:
        return every, f"full factorial ({size} points: the space has no more than --samples {n})"
    rng = random.Random(seed)
    points, seen, draws = [], set(), 0
    while len(points) < n and draws < 50:
        draws += 1
        cols = {}
        for k in knobs:
            col = (k["values"] * (-(-n // len(k["values"]))))[:n]
            rng.shuffle(col)
            cols[k["key"]] = col
        for i in range(n):
            p = canonical(knobs, {key: col[i] for key, col in cols.items()})
            tag = json.dumps(p, sort_keys=True)
            if tag not in seen and len(points) < n:
                seen.add(tag)
                points.append(p)
    return points, (f"seeded Latin-hypercube-like sample of {len(points)} of {size:,} points "
                    f"(seed {seed}; each knob's levels about equally often)")


# ----------------------------------------------------------------------------------------------
# Pareto frontiers

def pareto(items):
    """Indices of the non-dominated items of [(x, y), ...] (both minimised), ordered by x. Of
    items equal in both, the first is on the frontier and the others are not."""
    front = []
    for i, (x, y) in enumerate(items):
        if any((x2 <= x and y2 <= y and (x2 < x or y2 < y)) or ((x2, y2) == (x, y) and j < i)
               for j, (x2, y2) in enumerate(items)):
            continue
        front.append(i)
    return sorted(front, key=lambda i: (items[i][0], items[i][1]))


def number_dps(points, fronts):
    """F1..Fn (PARETO): the points on any frontier, by time (then translation error)."""
    on = sorted({i for f in fronts for i in f},
                key=lambda i: (points[i]["seconds_per_pair"], points[i]["rpe_translation_m"], i))
    return {i: f"{PARETO}{k}" for k, i in enumerate(on, 1)}


# ----------------------------------------------------------------------------------------------
# Reading the sweep

def num(v):
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


def stage_seconds(row, stages):
    """Mean seconds per pair of each of the paper's rows `stages` (core.paper_stages) of a sweep
    row: a whole stage's seconds, a part's KD-tree search seconds (RPCE) or the rest of them
    (transformation estimation)."""
    out = {}
    for title, key, time in stages:
        total = num(row.get(f"stages.{key}.per_pair_mean.seconds"))
        search = num(row.get(f"stages.{key}.per_pair_mean.kdtree_search_seconds"))
        out[title] = (total if time == "seconds" else search if time == "kdtree_search"
                      else total - search if total is not None and search is not None else None)
    return out


def stage_search_seconds(row, stages):
    """Mean seconds per pair of KD-tree search inside each of the paper's rows `stages`: a part
    that is the rest of its stage's seconds has none."""
    out = {}
    for title, key, time in stages:
        search = num(row.get(f"stages.{key}.per_pair_mean.kdtree_search_seconds"))
        out[title] = search if time != "rest" else 0.0 if search is not None else None
    return out


def read_points(out, names, stages):
    sweep = core.read_json_input(os.path.join(out, "sweep", "sweep.json"), "the sweep's results")
    if not (isinstance(sweep, dict) and isinstance(sweep.get("rows"), list) and isinstance(sweep.get("swept_keys"), list)):
        raise Bad(f"{out}/sweep/sweep.json: not what tigris sweep writes (rows, swept_keys)")
    by_id = {r["point"]: r for r in sweep["rows"]}
    points = []
    for name, sweep_id, knobs in names:
        r = by_id.get(sweep_id, {})
        p = {"point": name, "sweep_id": sweep_id, "knobs": knobs, "status": r.get("status", "error"),
             "error": r.get("error") or "", "seconds_per_pair": num(r.get("seconds_per_pair")),
             "rpe_translation_m": num(r.get("rpe.mean_translation_m")),
             "rpe_rotation_deg": num(r.get("rpe.mean_rotation_deg")),
             "kdtree_share": num(r.get("totals.kdtree_share")), "stages": stage_seconds(r, stages),
             "stage_kdtree_seconds": stage_search_seconds(r, stages),
             "not_converged_pairs": r.get("not_converged_pairs"), "pairs": r.get("pairs"),
             "values": {k: r.get(k) for k in sweep["swept_keys"] if "." in k}}
        p["valid"] = p["status"] == "ok" and None not in (p["seconds_per_pair"], p["rpe_translation_m"],
                                                          p["rpe_rotation_deg"])
        points.append(p)
    return points


# ----------------------------------------------------------------------------------------------
# Outputs

def write_points_csv(path, points, knob_keys, stage_order):
    """points.csv; stage_order: the stages' titles in order (the paper's rows' titles)."""
    cols = ["point", "dp", "status", "seconds_per_pair", "rpe_translation_m", "rpe_rotation_deg",
            "kdtree_share", "on_translation_frontier", "on_rotation_frontier"] + knob_keys + \
           [f"{t} s" for t in stage_order] + ["pairs", "not_converged_pairs", "error", "sweep_id"]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for p in points:
        row = dict(p, **{k: p["values"].get(k) for k in knob_keys}, **{f"{t} s": p["stages"].get(t) for t in stage_order})
        w.writerow(["" if row.get(c) is None else str(row[c]).lower() if isinstance(row[c], bool) else row[c]
                    for c in cols])
    core.atomic_write(path, buf.getvalue())


def write_configs(out, points, dps):
    pdir = os.path.join(out, "pareto")
    os.makedirs(pdir, exist_ok=True)
    for f in os.listdir(pdir):                   # a rerun's frontier replaces the last one (DPi: older names)
        if re.fullmatch(rf"(?:DP|{PARETO})\d+\.json", f):
            os.remove(os.path.join(pdir, f))
    paths = {}
    for i, dp in dps.items():
        d = os.path.join(out, "sweep", "points", points[i]["sweep_id"], "pairs")
        config = None
        for pair in sorted(os.listdir(d)) if os.path.isdir(d) else []:
            try:
                reg = core.read_json_input(os.path.join(d, pair, "registration.json"))
            except core.Refused as e:
                say(f"warning: {e}")
                continue
            config = reg.get("config") if isinstance(reg, dict) else None
            if isinstance(config, dict):
                break
        if not isinstance(config, dict):
            say(f"warning: {dp} ({points[i]['point']}): no readable registration.json under {d}: "
                "no configuration file written")
            paths[i] = None
            continue
        config.pop("inject", None)               # error injection is not a design choice
        paths[i] = os.path.join(pdir, f"{dp}.json")
        core.write_json(paths[i], config)
    return paths


# Where a label may go, in points from its marker: beside it first, then further out on a leader
# line, so a cluster of frontier points (several within a second and a few per cent of error)
# still gets one readable label each.
NEAR = [(7, 5), (7, -5), (-7, 5), (-7, -5)]
FAR = [(dx, dy) for dy in (18, -22, 30, -34, 42, -46, 54, -58, 66, -70) for dx in (26, -26, 60, -60)]


def place_labels(fig, ax, items):
    """Annotates items [(x, y, text, style)] in order, each at the first offset whose text box is
    clear of every label placed so far, every marker and the legend, and inside the axes."""
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    taken = [ax.get_legend().get_window_extent(renderer)] if ax.get_legend() else []
    for x, y, _, _ in items:
        px, py = ax.transData.transform((x, y))
        taken.append(Bbox.from_extents(px - 5, py - 5, px + 5, py + 5))
    for x, y, text, style in items:
        chosen = None
        for dx, dy in NEAR + FAR:  # a leader on every label: in a cluster, which marker is whose shows
            ann = ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy),
                              ha="left" if dx > 0 else "right", va="bottom" if dy > 0 else "top", zorder=6,
                              arrowprops=dict(arrowstyle="-", lw=0.6, color=style.get("color", "k"),
                                              shrinkA=0, shrinkB=3), **style)
            ann.update_positions(renderer)
            box = Text.get_window_extent(ann, renderer)  # the text alone: its leader may cross markers
            if (frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
                    and not any(box.overlaps(t) for t in taken)):
                chosen = box
                break
            ann.remove()
        if chosen is None:  # nowhere clear: beside the marker, as before
            ann = ax.annotate(text, (x, y), textcoords="offset points", xytext=NEAR[0], zorder=6, **style)
            ann.update_positions(renderer)
            chosen = Text.get_window_extent(ann, renderer)
        taken.append(chosen)


def plot(out, points, fronts, dps, title, footer=(), stage_order=None):
    """fig4.png and fig5.png; footer: the lines that say what made them (core.footer_lines);
    stage_order: fig5's stages (titles) bottom to top, by default the order of the Pareto
    points' "stages" (read_points writes them in the pipeline's order)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ..reports import figure_truth  # noqa: F401  (svg text, flat-axis guard)

    ok = [p for p in points if p["valid"]]
    bad = [p for p in points if not p["valid"] and p["seconds_per_pair"] is not None
           and p["rpe_translation_m"] is not None]
    failed = len(points) - len(ok) - len(bad)
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 5.2))
    labels = {}
    for ax, key, front, what in ((axes[0], "rpe_translation_m", fronts[0], "translation (m)"),
                                 (axes[1], "rpe_rotation_deg", fronts[1], "rotation (deg)")):
        ax.scatter([p["seconds_per_pair"] for p in ok], [p[key] for p in ok], s=14, color="0.6",
                   label=f"design points ({len(ok)})", zorder=2)
        if bad:
            ax.scatter([p["seconds_per_pair"] for p in bad], [p[key] for p in bad], s=22, marker="x",
                       color="C3", label=f"some pair not converged ({len(bad)}, not on the frontier)", zorder=2)
        fx = [points[i]["seconds_per_pair"] for i in front]
        fy = [points[i][key] for i in front]
        ax.step(fx, fy, where="post", color="C0", lw=1.2, zorder=3)
        ax.scatter(fx, fy, s=30, color="C0", label=f"Pareto frontier (its points among {PARETO}1..{PARETO}{len(dps)}, "
                   "by time)", zorder=4)
        presets = [p for p in points if p["point"].startswith("preset") and p["valid"]]
        for k, p in enumerate(presets):
            ax.scatter([p["seconds_per_pair"]], [p[key]], s=70, facecolors="none", edgecolors="k",
                       marker="s", zorder=5, label=None if k else "the presets (anchors)")
        labels[ax] = ([(points[i]["seconds_per_pair"], points[i][key], dps[i], dict(fontsize=9, color="C0", weight="bold"))
                       for i in sorted(front, key=lambda i: points[i]["seconds_per_pair"])]
                      + [(p["seconds_per_pair"], p[key], p["point"].split("=")[1] + " preset", dict(fontsize=8))
                         for p in presets])
        ax.set_yscale("log")
        ax.set_xlim(0, max([p["seconds_per_pair"] for p in ok + bad] + [1]) * 1.08)
        ax.set_xlabel("registration time, mean seconds per pair")
        ax.set_ylabel(f"mean relative pose error per pair, {what}, log scale")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_title(f"({'ab'[key == 'rpe_rotation_deg']}) {what.split()[0]} error against time")
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Pipeline design space: {len(points)} points" + (f", {failed} failed (no result)" if failed else ""))
    figure_truth.name_workload(fig, title)
    core.add_footer(fig, footer)
    for ax, items in labels.items():  # after the layout is final: placement works in pixels
        place_labels(fig, ax, items)
    core.save_figure(fig, os.path.join(out, "fig4.png"), dpi=110)
    plt.close(fig)

    order = sorted(dps, key=lambda i: pareto_number(dps[i]))
    labels = [dps[i] + (f"\n{points[i]['point'].split('=')[1]} preset" if points[i]["point"].startswith("preset")
                        else f"\n{points[i]['point']}") for i in order]
    if stage_order is None:
        stage_order = []
        for i in order:
            stage_order += [s for s in points[i]["stages"] if s not in stage_order]
    fig, (a, b) = plt.subplots(2, 1, figsize=(max(8.5, 0.75 * len(order) + 5), 8.2))
    bottom = [0.0] * len(order)
    for k, title_s in enumerate(stage_order):
        vals = []
        for i in order:
            st = points[i]["stages"]
            total = sum(v for v in st.values() if v) or 1
            vals.append(100 * (st.get(title_s) or 0) / total)
        a.bar(labels, vals, bottom=bottom, color=plt.cm.tab10(k), label=title_s)
        bottom = [x + y for x, y in zip(bottom, vals)]
    a.set_ylim(0, 100)
    a.set_ylabel("share of registration time (%)")
    a.set_title("(a) time across the stages (RPCE: ICP's KD-tree searches)")
    a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside: the bars' labels stay clear
    kd = [100 * (points[i]["kdtree_share"] or 0) for i in order]
    b.bar(labels, kd, color="C3", label="KD-tree search")
    b.bar(labels, [100 - x for x in kd], bottom=kd, color="0.75", label="other")
    for x, v in enumerate(kd):
        b.text(x, v / 2, f"{v:.0f}%", ha="center", va="center", fontsize=8, color="white")
    for y in (50, 85):
        b.axhline(y, ls="--", color="k", lw=0.8)
    b.text(len(order) - 0.5, 86, "paper: 50-85%", ha="right", va="bottom", fontsize=8)
    b.set_ylim(0, 100)
    b.set_ylabel("share of registration time (%)")
    b.set_title("(b) KD-tree search against the rest")
    b.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("The Pareto points' time distribution")
    figure_truth.name_workload(fig, title)
    core.add_footer(fig, footer)
    core.save_figure(fig, os.path.join(out, "fig5.png"), dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------

def report_lines(summary, out):
    """(DIR/REPORT.md's lines, the claims): the paper's section-3 claims against this
    exploration, in the words and verdicts of `tigris reproduce`'s report (which adds the same
    section with --dse DIR)."""
    lines, claims = pipeline_section(summary, out, out, standalone=True)
    held = [c for c in claims if c.direction]
    lines[3:3] = [f"The claims below are measured on this exploration's Pareto points; the direction "
                  f"holds for {len(held)} of {sum(c.direction is not None for c in claims)} "
                  "(docs/registration.md explains the space and the stages)."]
    return lines, claims


def parse_args(argv):
    argv = joined_sbatch_args(argv)
    ap = argparse.ArgumentParser(prog=PROG, description="The paper's section 3: samples the registration "
                                 "pipeline's design space, runs every point as tigris odometry over one sequence "
                                 "(locally or as one Slurm job array) and finds the Pareto frontiers of error "
                                 "against time (docs/registration.md).",
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[7:]))
    core.role(ap.add_argument("--space", default=DEFAULT_SPACE, metavar="FILE",
                              help="design space JSON (default: tigris/tools/pipeline_space.json, every Table 1 knob "
                              "this pipeline has)"), "input")
    ap.add_argument("--samples", type=int, default=100, metavar="N",
                    help="points drawn from the space, besides the anchors (default %(default)s; a small N "
                    "for a quick look)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the sample and of the synthetic drive "
                    "(default %(default)s)")
    src = ap.add_mutually_exclusive_group()
    src.add_argument("--pairs", type=int, default=None, metavar="N",
                     help="length of the synthetic sequence in pairs (default 10)")
    core.role(src.add_argument("--sequence", metavar="DIR", help="a KITTI-layout folder instead of a synthetic "
                               "drive"), "input")
    ap.add_argument("--frames", metavar="A:B", help="with --sequence: the frames to register")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                    help="points run at once locally (default %(default)s)")
    core.role(ap.add_argument("--tigris", default=os.environ.get("TIGRIS") or default_tigris(),
                              help="tigris binary"), "input")
    ap.add_argument("--slurm", action="store_true", help="run the points as one Slurm job array")
    for opt in ("partition", "time", "mem", "chunk"):
        ap.add_argument(f"--{opt}", help=f"with --slurm: the sweep's --{opt}")
    ap.add_argument("--sbatch-arg", action="append", default=[], help="with --slurm: one raw sbatch argument")
    core.role(ap.add_argument("--out", default="tigris-dse", metavar="DIR", help="output folder (default "
                              "%(default)s); a rerun into it resumes"), "out_folder")
    ap.add_argument("--list-flags", action="store_true", help="Print this command's flags as JSON (flag, type, "
                    "default, meaning) for tools, and exit")
    core.list_flags(ap, "pipeline-dse", argv)
    a = ap.parse_args(argv)
    if a.samples < 1 or a.samples > MAX_SAMPLES:
        ap.error(f"--samples {a.samples}: must be 1 .. {MAX_SAMPLES:,} (each point is a whole odometry run; "
                 "explore more with several --out folders and other --seed values)")
    if a.frames is not None:
        m = re.fullmatch(r"(\d+):(\d+)", a.frames)
        if not m or int(m.group(1)) >= int(m.group(2)):
            ap.error(f"--frames must be A:B, the first and the last frame (A < B), got '{a.frames}'")
    if a.pairs is not None and not 1 <= a.pairs <= 20000:
        ap.error("--pairs must be 1 .. 20000")
    if a.frames and not a.sequence:
        ap.error("--frames needs --sequence (a synthetic sequence has --pairs)")
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    used = [o for o in ("partition", "time", "mem", "chunk") if getattr(a, o)] + (["sbatch-arg"] if a.sbatch_arg else [])
    if used and not a.slurm:
        ap.error(f"--{', --'.join(used)} need(s) --slurm")
    a.pairs = 10 if a.pairs is None and not a.sequence else a.pairs
    return a


def run_sweep(cmd, env=None):
    """The sweep driver as a child: a signal to this process stops it (SIGTERM to its group),
    and it stops its points and keeps the finished ones before this returns."""
    return core.run_child(cmd, grace=2 * core.KILL_AFTER, env=env)  # its own children get their 5 s first


def check_sequence(a):
    """--sequence and --frames, before anything is written: (folder, (first, last) or None)."""
    seq = os.path.abspath(a.sequence)
    if not os.path.isdir(seq):
        raise Bad(f"--sequence {a.sequence}: no such folder")
    if not os.path.lexists(os.path.join(seq, "poses.txt")):
        raise Bad(f"--sequence {a.sequence}: no poses.txt: the errors need a ground truth")
    core.check_input(os.path.join(seq, "poses.txt"), "--sequence's ground truth", core.MAX_SETTINGS_BYTES)
    velo = os.path.join(seq, "velodyne")
    scans = sum(1 for n in os.listdir(velo if os.path.isdir(velo) else seq) if re.fullmatch(r"\d+\.bin", n))
    frames = None
    if a.frames:
        frames = tuple(int(x) for x in a.frames.split(":"))
        if frames[1] >= scans:
            raise Bad(f"--frames {a.frames}: the sequence has frames 0..{scans - 1}")
    return seq, frames


def explore_main(argv):
    a = parse_args(argv)
    tigris = os.path.abspath(a.tigris)
    if not (os.path.isfile(tigris) and os.access(tigris, os.X_OK)):
        raise Bad(f"no tigris binary at {tigris} (give --tigris)")
    space = load_space(a.space)
    knobs = space["knobs"]
    out = os.path.abspath(a.out)
    folder = core.OutFolder(out, "pipeline-dse", OUTPUTS, argv=argv)
    inputs = [core.input_identity("space", a.space, "--space", core.MAX_SETTINGS_BYTES)]
    paths = [("--space", a.space)]
    if a.sequence:
        seq, frames = check_sequence(a)
        inputs += core.sequence_inputs("sequence", seq, frames)
        paths.append(("--sequence", seq))
        settings = {"sequence": seq, "frames": a.frames}
    else:
        settings = {"synthetic_pairs": a.pairs, "synthetic_seed": a.seed}
    drawn, how = sample(knobs, a.samples, a.seed)
    stages = core.paper_stages(core.pipeline_stages(tigris))   # the binary's stages, as the paper's rows
    folder.claim(settings=settings, inputs=inputs, input_paths=paths)
    return folder.run(lambda: explore(a, argv, tigris, stages, space, knobs, out, drawn, how))


def explore(a, argv, tigris, stages, space, knobs, out, drawn, how):
    """stages: the paper's rows [(title, key, time)] of the binary's stages (core.paper_stages)."""
    if a.sequence:
        seq = os.path.abspath(a.sequence)
        where = f"{seq}" + (f" frames {a.frames}" if a.frames else "")
    else:
        # Named by its settings: another drive is another base, which the sweep will not mix in.
        seq = os.path.join(out, f"sequence-{a.pairs}pairs-seed{a.seed}")
        rc = core.run_child([tigris, "synth", "--frames", str(a.pairs + 1), "--seed", str(a.seed), "--out", seq],
                            stdout=subprocess.DEVNULL)   # a complete drive is only checked
        if rc != 0:
            raise Bad(f"tigris synth failed (exit {rc})")
        where = f"synthetic drive (seed {a.seed}, {a.pairs} pairs)"
    say(f"{how}; anchors {', '.join(space.get('anchors', [])) or 'none'}; on the {where}")
    base = dict(space.get("base", {}), sequence=seq)
    if a.frames:
        base["frames"] = a.frames
    pts = [{"preset": p} for p in space.get("anchors", [])] + drawn
    names = [f"preset={p}" for p in space.get("anchors", [])] + [f"P{k:03d}" for k in range(1, len(drawn) + 1)]
    spec = {"comment": f"{PROG}: {how}", "command": "odometry", "base": base, "points": pts}
    spec_path = os.path.join(out, "spec.json")
    core.write_json(spec_path, spec)
    args = [spec_path, "--out", os.path.join(out, "sweep"), "--tigris", tigris, "--jobs", str(a.jobs)]
    if a.slurm:
        args.append("--slurm")
        for opt in ("partition", "time", "mem", "chunk"):
            if getattr(a, opt):
                args += [f"--{opt}", str(getattr(a, opt))]
        args += [f"--sbatch-arg={s}" for s in a.sbatch_arg]
    sweep, env = core.python_module_command("sweep", args)     # python3 -m tigris sweep
    say(f"{len(pts)} points: {shlex.join(sweep)}")
    rc = run_sweep(sweep, env)
    if rc == 2:
        raise Bad(f"the sweep refused {spec_path} (its message above names the point; points[k] is "
                  "anchor k, or sample P(k - anchors + 1)): fix the space, or use another --out for "
                  "another sequence or base")
    if rc == 3:
        say("error: Slurm did not take the job array (sbatch's message above)")
        return 3
    if rc not in (0, 1):
        say(f"the sweep stopped (exit {rc}); finished points are kept: rerun the same command to resume")
        return rc
    try:
        ids = [p["id"] for p in Spec(spec_path, tigris).expand()]
    except SpecError as e:
        raise Bad(str(e))
    if len(ids) != len(pts):
        raise Bad(f"{spec_path}: {len(pts) - len(ids)} points repeat another (the sweep ran each once)")
    points = read_points(out, [(n, i, p) for n, i, p in zip(names, ids, pts)], stages)
    stage_order = [title for title, _, _ in stages]
    valid = [k for k, p in enumerate(points) if p["valid"]]
    for stale in ("fig4.png", "fig5.png", "dse.json", "points.csv", "REPORT.md"):
        if os.path.exists(os.path.join(out, stale)):
            os.remove(os.path.join(out, stale))
    fronts = [[valid[j] for j in pareto([(points[k]["seconds_per_pair"], points[k][e]) for k in valid])]
              for e in ("rpe_translation_m", "rpe_rotation_deg")]
    dps = number_dps(points, fronts)
    for k, p in enumerate(points):
        p["dp"] = dps.get(k, "")
        p["on_translation_frontier"], p["on_rotation_frontier"] = k in fronts[0], k in fronts[1]
    knob_keys = [k["key"] for k in knobs]
    write_points_csv(os.path.join(out, "points.csv"), points, knob_keys, stage_order)
    if not valid:
        first = next((p for p in points if p["error"]), points[0])
        say(f"error: no point converged on every pair with errors to compare (e.g. {first['point']}: "
            f"{first['status']} {first['error'] or ''}); {out}/points.csv lists them, no frontier")
        return 1
    configs = write_configs(out, points, dps)
    title = f"{where}; base {json.dumps(space.get('base', {}))}"
    footer = core.footer_lines(core.provenance(out, command="pipeline-dse"),
                               details=[f"{len(drawn)} sampled points, seed {a.seed}"])
    plot(out, points, fronts, dps, title, footer, stage_order)
    summary = {"command_line": f"{PROG} {shlex.join(argv)}", "space_file": os.path.abspath(a.space), "space": space,
               "sampling": how, "seed": a.seed, "sequence": where, "points": len(points),
               "ok": sum(p["status"] == "ok" for p in points),
               "not_converged": sum(p["status"] == "not_converged" for p in points),
               "failed": sum(p["status"] == "error" for p in points),
               "frontier_translation": [points[i]["point"] for i in fronts[0]],
               "frontier_rotation": [points[i]["point"] for i in fronts[1]],
               "stage_order": stage_order,           # the titles of each point's "stages", in order
               "dps": [dict({k: points[i][k] for k in ("point", "seconds_per_pair", "rpe_translation_m",
                                                         "rpe_rotation_deg", "kdtree_share", "stages",
                                                         "stage_kdtree_seconds", "values")},
                            dp=dps[i], config=configs[i]) for i in sorted(dps, key=lambda i: pareto_number(dps[i]))],
               "presets": {p["point"].split("=")[1]: {k: p[k] for k in ("status", "seconds_per_pair", "rpe_translation_m",
                                                                          "rpe_rotation_deg", "kdtree_share", "dp")}
                           for p in points if p["point"].startswith("preset=")}}
    # The section-3 claims as the report measures them, once (reports/pipeline.py).
    lines, measured = report_lines(summary, out)
    summary["claims"] = [c.record() for c in measured]
    core.write_json(os.path.join(out, "dse.json"), summary)
    core.atomic_write(os.path.join(out, "REPORT.md"), "\n".join(lines))
    print(f"{'Pareto':6} {'point':14} {'s/pair':>7} {'RPE m':>8} {'RPE deg':>8} {'KD-tree':>7}  frontier")
    for d in summary["dps"]:
        i = next(k for k, p in enumerate(points) if p["point"] == d["point"])
        d_kd = d["kdtree_share"]
        on = "+".join(w for w, f in (("translation", fronts[0]), ("rotation", fronts[1])) if i in f)
        print(f"{d['dp']:6} {d['point']:14} {d['seconds_per_pair']:7.2f} {d['rpe_translation_m']:8.4f} "
              f"{d['rpe_rotation_deg']:8.4f} {'   -' if d_kd is None else f'{100 * d_kd:6.1f}%'}  {on}")
    for c in measured:
        holds = {True: "holds", False: "does not hold", None: "not measured"}[c.direction]
        print(f"{c.text}: {c.measured} (paper: {c.paper}; the direction {holds})")
    print(f"{summary['ok']} ok, {summary['not_converged']} not converged, {summary['failed']} failed of {len(points)}; "
          f"wrote {out}/points.csv, fig4.png, fig5.png, pareto/{PARETO}*.json, dse.json, REPORT.md")
    return 0


def main(argv):
    """The command: explore_main, its stops and errors said in one line with an exit code
    (core.run_command)."""
    core.handle_stop_signals()
    return core.run_command(lambda: explore_main(argv), say, "the sweep and its points stopped; finished points "
                            "are kept: rerun the same command to resume", also=(ValueError,))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
