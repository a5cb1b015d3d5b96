#!/usr/bin/python3
"""The figures of a `tigris odometry` run.

    tigris/reports/odometry_plots.py OUT

Reads OUT/trajectory.csv, OUT/pairs.csv and OUT/metrics.json and writes
  OUT/trajectory.png  top view (x forward, y left of the first frame's sensor, metres, equal
                      axes) of the estimated trajectory and, when there is one, the ground truth,
                      and below it their height (z up of the first frame) against the frame: a
                      drift in pitch shows there and not in the top view;
  OUT/errors.png      the KITTI devkit's errors against segment length and against speed
                      (translation %, rotation deg/m); without a segment of 100 m (a short
                      trajectory) or a ground truth, the per-pair relative pose error instead,
                      and the figure says why.
Each figure's footer says what made it (tigris/core/provenance.py), from OUT/manifest.json: the
tigris odometry command line, the commit, the sequence (or synthetic drive), frames, preset and
back-end, the inputs' SHA-256 and a digest of the settings.
Exit 2 with a message naming the file when an input is missing or malformed.
"""
import csv
import io
import math
import os
import sys

from .. import core

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def fail(msg):
    print(f"odometry_plots: {msg}", file=sys.stderr)
    sys.exit(2)


def read_csv(path):
    try:
        return list(csv.DictReader(io.StringIO(core.read_text_input(path), newline="")))
    except core.Refused as e:
        fail(str(e))
    except csv.Error as e:
        fail(f"{path}: {e}")


def num(row, key, path):
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        fail(f"{path}: no number in column {key!r} of row {row}")


def trajectory(out, traj, metrics, footer):
    path = os.path.join(out, "trajectory.csv")
    est = [(num(r, "est_x", path), num(r, "est_y", path)) for r in traj]
    gt = [(num(r, "gt_x", path), num(r, "gt_y", path)) for r in traj]
    frames = [num(r, "frame", path) for r in traj]
    est_z = [num(r, "est_z", path) for r in traj]
    gt_z = [num(r, "gt_z", path) for r in traj]
    has_gt = all(math.isfinite(x) and math.isfinite(y) for x, y in gt)
    fig, (ax, hz) = plt.subplots(2, 1, figsize=(6.4, 8.4), gridspec_kw={"height_ratios": [3, 1]})
    if has_gt:
        ax.plot([p[0] for p in gt], [p[1] for p in gt], "-", color="0.3", lw=2.0, label="ground truth")
    ax.plot([p[0] for p in est], [p[1] for p in est], "-", color="C1", lw=1.2, label="estimate")
    ax.plot([est[0][0]], [est[0][1]], "ko", ms=5, label=f"frame {traj[0]['frame']}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m, forward at the first frame)")
    ax.set_ylabel("y (m, left)")
    k = metrics.get("kitti") or {}
    title = f"{len(est)} frames"
    if k and not k.get("too_short"):
        title += f": {k['t_err_percent']:.2f}% translation, {k['r_err_deg_per_m']:.4f} deg/m (KITTI)"
    elif has_gt:
        title += f", {k.get('trajectory_length_m', 0):.1f} m: shorter than 100 m, no KITTI metrics"
    ax.set_title(title, fontsize=10)
    ax.grid(True, lw=0.3)
    ax.legend(loc="best", fontsize=8)
    if has_gt:
        hz.plot(frames, gt_z, "-", color="0.3", lw=2.0, label="ground truth")
    hz.plot(frames, est_z, "-", color="C1", lw=1.2, label="estimate")
    span = max(est_z + (gt_z if has_gt else [])) - min(est_z + (gt_z if has_gt else []))
    if span < 0.5:  # a flat drive stays flat on the plot: at least 0.5 m of height shown
        mid = (max(est_z + (gt_z if has_gt else [])) + min(est_z + (gt_z if has_gt else []))) / 2
        hz.set_ylim(mid - 0.25, mid + 0.25)
    hz.set_xlabel("frame")
    hz.set_ylabel("z (m, up at the first frame)")
    hz.grid(True, lw=0.3)
    core.add_footer(fig, footer)
    core.save_figure(fig, os.path.join(out, "trajectory.png"), dpi=120)
    plt.close(fig)


def binned(segs, key, edges):
    """Mean of `key` per speed bin [edges[i], edges[i+1]) in km/h, bins with a segment only."""
    xs, ys = [], []
    for lo, hi in zip(edges, edges[1:]):
        vals = [s[key] for s in segs if lo <= s["speed_m_per_s"] * 3.6 < hi]
        if vals:
            xs.append((lo + hi) / 2)
            ys.append(sum(vals) / len(vals))
    return xs, ys


def from_zero(ax, ys):
    """A y axis from 0 with room above the highest point (no point on the frame's edge)."""
    top = max([y for y in ys if math.isfinite(y)] or [0.0])
    ax.set_ylim(0, top * 1.15 if top > 0 else 1.0)


def errors(out, pairs, metrics, footer):
    k = metrics.get("kitti") or {}
    segs = k.get("segment_list") or []
    fig, axes = plt.subplots(2, 2, figsize=(9.6, 6.4))
    if segs:
        per_len = [p for p in k["per_length"] if p["segments"] > 0]
        lengths = [p["length_m"] for p in per_len]
        edges = list(range(0, 100, 5))
        for row, (key, label) in enumerate((("t_err_percent", "translation error (%)"),
                                            ("r_err_deg_per_m", "rotation error (deg/m)"))):
            ax = axes[row][0]
            ys = [p[key] for p in per_len]
            ax.plot(lengths, ys, "o-", color="C0")
            ax.set_xlabel("segment length (m)")
            ax.set_ylabel(label)
            from_zero(ax, ys)
            ax = axes[row][1]
            xs, ys = binned(segs, key, edges)
            ax.plot(xs, ys, "o-", color="C1")
            ax.set_xlabel("speed (km/h, 5 km/h bins)")
            ax.set_ylabel(label)
            from_zero(ax, ys)
        fig.suptitle(f"KITTI devkit errors over {len(segs)} segments (100..800 m, one every 10 frames)", fontsize=10)
    else:
        path = os.path.join(out, "pairs.csv")
        rows = [r for r in pairs if r.get("rpe_translation_m") not in (None, "", "nan")]
        why = "the trajectory is shorter than 100 m: no KITTI segment" if k else "no ground truth (no poses.txt)"
        if rows:
            x = [int(r["target"]) for r in rows]
            for row, (key, label) in enumerate((("rpe_translation_m", "relative pose error (m)"),
                                                ("rpe_rotation_deg", "relative pose error (deg)"))):
                ax = axes[row][0]
                ys = [num(r, key, path) for r in rows]
                ax.plot(x, ys, "o-", color="C0")
                ax.set_xlabel("pair (target frame)")
                ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
                ax.set_ylabel(label)
                from_zero(ax, ys)
        for row in range(2):
            axes[row][1].axis("off")
        axes[0][1].text(0.0, 0.5, why + ":\nper-pair errors instead", fontsize=10, va="center")
        fig.suptitle("per-pair relative pose error", fontsize=10)
    core.add_footer(fig, footer)
    core.save_figure(fig, os.path.join(out, "errors.png"), dpi=120)
    plt.close(fig)


def flag(flags, name):
    """The value after `name` in a list of flags, else None."""
    return next((flags[i + 1] for i in range(len(flags) - 1) if flags[i] == name), None)


def run_details(settings, argv):
    """What the footer adds to the command line (argv) from the settings tigris odometry records
    in its manifest: the sequence or synthetic drive, its seed, the frames, the preset and the
    back-end (its `register_flags` are what every pair's tigris register gets), each unless argv
    gives it itself."""
    s = settings if isinstance(settings, dict) else {}
    given = {a.split("=", 1)[0] for a in argv or [] if a.startswith("--")}
    parts = []
    if s.get("synthetic"):
        if "--synthetic" not in given or "--seed" not in given:
            parts.append(f"synthetic drive of {s['synthetic']} frames, seed {s.get('seed')}")
    elif s.get("sequence") and "--sequence" not in given:
        parts.append(f"sequence {s['sequence']}")
    frames = s.get("frames")
    if "--frames" not in given and isinstance(frames, list) and len(frames) == 2:
        parts.append(f"frames {frames[0]}..{frames[1]}")
    flags = [str(f) for f in s["register_flags"]] if isinstance(s.get("register_flags"), list) else []
    if flags:
        sets = [flags[i + 1] for i in range(len(flags) - 1) if flags[i] == "--set"]
        backend = flag(flags, "--search") or next((x.split("=", 1)[1] for x in sets
                                                   if x.startswith("search.backend=")), None)
        if not backend:    # both presets search exactly; a --config file may say otherwise
            backend = "as in --config" if flag(flags, "--config") else "exact"
        said = [f"preset {flag(flags, '--preset') or '?'}" if "--preset" not in given else "",
                f"back-end {backend}" if "--search" not in given else ""]
        if any(said):
            parts.append(", ".join(x for x in said if x))
    return parts


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or argv[0].startswith("-"):
        print(__doc__.strip())
        return 0 if len(argv) == 1 else 2
    out = argv[0]
    path = os.path.join(out, "metrics.json")
    try:
        metrics = core.read_json_input(path)
    except core.Refused as e:
        fail(str(e))
    if not isinstance(metrics, dict):
        fail(f"{path}: not the metrics of tigris odometry (a JSON object)")
    traj = read_csv(os.path.join(out, "trajectory.csv"))
    if not traj:
        fail(f"{os.path.join(out, 'trajectory.csv')}: no rows")
    prov = core.provenance(out, command="odometry")
    footer = core.footer_lines(prov, details=run_details(prov["settings"], prov["argv"]))
    trajectory(out, traj, metrics, footer)
    errors(out, read_csv(os.path.join(out, "pairs.csv")), metrics, footer)
    print(f"odometry_plots: wrote {os.path.join(out, 'trajectory.png')} and {os.path.join(out, 'errors.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
