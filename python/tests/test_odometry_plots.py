#!/usr/bin/python3
"""tigris/reports/odometry_plots.py (tigris odometry's figures) on hand-made run folders: a trajectory with
KITTI segments, a short one (per-pair errors instead, said so), one without a ground truth, a
missing metrics.json (exit 2 naming the file), and the footer saying what made the figures (from
OUT/manifest.json; without one, the commit from TIGRIS_COMMIT).
Run: python3 python/tests/test_odometry_plots.py (needs Debian's python3-matplotlib)."""
import contextlib
import hashlib
import json
import math
import os
import sys
import tempfile
import unittest

from common import footer_clear, run_tool, main

SCRIPT = "tigris odometry-plots"   # its sys.argv[0] when run as python3 -m tigris odometry-plots

try:
    import matplotlib  # noqa: F401
    HAVE_MPL = True
except ImportError:
    HAVE_MPL = False
    if os.environ.get("TIGRIS_REQUIRE_MPL"):
        sys.exit("matplotlib missing for " + sys.executable + ": apt-get install python3-matplotlib")


def make_run(d, frames, gt=True, segments=True):
    with open(os.path.join(d, "trajectory.csv"), "w") as f:
        f.write("frame,est_x,est_y,est_z,gt_x,gt_y,gt_z\n")
        for i in range(frames):
            x, y = 60 * math.sin(0.01 * i), 60 * (1 - math.cos(0.01 * i))
            g = f"{x},{y},0" if gt else "nan,nan,nan"
            f.write(f"{i},{1.01 * x},{1.02 * y},0,{g}\n")
    with open(os.path.join(d, "pairs.csv"), "w") as f:
        f.write("pair,source,target,status,seconds,kdtree_seconds,kdtree_share,searches,rpe_translation_m,rpe_rotation_deg\n")
        for i in range(frames - 1):
            rpe = f"{0.01 + 0.001 * (i % 3)},{0.02}" if gt else "nan,nan"
            f.write(f"{i},{i + 1},{i},converged,1,0.5,0.5,100,{rpe}\n")
    m = {"ground_truth": None} if not gt else {"kitti": {
        "t_err_percent": 1.5 if segments else None, "r_err_deg_per_m": 0.0015 if segments else None,
        "too_short": not segments, "trajectory_length_m": 240 if segments else 40,
        "per_length": [{"length_m": L, "segments": 3 if segments and L < 300 else 0,
                        "t_err_percent": 1.4 if segments and L < 300 else None,
                        "r_err_deg_per_m": 0.0014 if segments and L < 300 else None} for L in range(100, 900, 100)],
        "segment_list": [{"first_frame": 10 * k, "length_m": L, "speed_m_per_s": 3.0 + k, "t_err_percent": 1.4,
                          "r_err_deg_per_m": 0.0014} for k in range(3) for L in (100, 200)] if segments else []}}
    with open(os.path.join(d, "metrics.json"), "w") as f:
        json.dump(m, f)


def write_manifest(d, argv, settings, inputs, commit=None):
    """OUT/manifest.json as tigris odometry writes it (core/out_folder.cpp)."""
    m = {"tigris_manifest": 1, "command": "odometry", "argv": argv, "cwd": "/", "settings": settings,
         "inputs": inputs, "outputs": ["trajectory.png", "errors.png"], "status": "running"}
    if commit:
        m["commit"] = commit
    with open(os.path.join(d, "manifest.json"), "w") as f:
        json.dump(m, f)


def plot(d, env=None):
    return run_tool("odometry-plots", d, timeout=120, env=None if env is None else dict(os.environ, **env))


def footers(d, commit_env=None):
    """{figure: its footer} from odometry_plots.main() run here on d, each checked (as it is saved)
    to lie inside the figure and under every axes."""
    from tigris import core
    from tigris.reports import odometry_plots
    saved, real_save, argv = {}, core.save_figure, sys.argv
    old = os.environ.pop("TIGRIS_COMMIT", None)
    if commit_env:
        os.environ["TIGRIS_COMMIT"] = commit_env
    core.save_figure = lambda fig, path, **kw: (saved.__setitem__(os.path.basename(path), footer_clear(fig)),
                                                real_save(fig, path, **kw))
    sys.argv = [SCRIPT, d]
    try:
        with open(os.devnull, "w") as null, contextlib.redirect_stdout(null):
            odometry_plots.main()
    finally:
        core.save_figure, sys.argv = real_save, argv
        os.environ.pop("TIGRIS_COMMIT", None)
        if old is not None:
            os.environ["TIGRIS_COMMIT"] = old
    return saved


@unittest.skipUnless(HAVE_MPL, "python3-matplotlib is not installed")
class OdometryPlots(unittest.TestCase):
    def check_pngs(self, d):
        for name in ("trajectory.png", "errors.png"):
            path = os.path.join(d, name)
            self.assertTrue(os.path.getsize(path) > 10000, name)
            with open(path, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_with_segments(self):
        with tempfile.TemporaryDirectory() as d:
            make_run(d, 400)
            p = plot(d)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.check_pngs(d)

    def test_short_and_without_ground_truth(self):
        for gt in (True, False):
            with tempfile.TemporaryDirectory() as d:
                make_run(d, 40, gt=gt, segments=False)
                p = plot(d)
                self.assertEqual(p.returncode, 0, p.stderr)
                self.check_pngs(d)

    def test_footer_from_the_manifest(self):
        seq = "/data/kitti/dataset/sequences/00"
        scans = [{"role": f"scan {i:06d}", "path": f"{seq}/velodyne/{i:06d}.bin", "bytes": 10,
                  "sha256": hashlib.sha256(bytes([i])).hexdigest()} for i in range(41)]
        settings = {"sequence": seq, "frames": [0, 40], "register_flags": ["--preset", "dp7", "--max-work", "1e+12"]}
        argv = ["/work/build/bin/tigris", "odometry", "--sequence", seq, "--out", "runs/00"]
        joint = hashlib.sha256("".join(s["sha256"] + "\n" for s in scans).encode()).hexdigest()[:12]
        digest = hashlib.sha256(json.dumps(settings, sort_keys=True, separators=(",", ":")).encode()).hexdigest()[:12]
        for gt, segments in ((True, True), (False, False)):
            with tempfile.TemporaryDirectory() as d:
                make_run(d, 400 if segments else 40, gt=gt, segments=segments)
                write_manifest(d, argv, settings, scans, commit="5c40187850da-dirty")
                got = footers(d, commit_env="not-this-one")
                self.assertEqual(set(got), {"trajectory.png", "errors.png"})
                parts = [f"made by tigris odometry --sequence {seq} --out runs/00", "commit 5c40187850da-dirty",
                         "frames 0..40", "preset dp7, back-end exact",
                         f"41 inputs in {seq}/velodyne, sha256 of their sha256s {joint}", f"settings sha256 {digest}"]
                # errors.png is wide enough for every part whole, in two lines
                self.assertEqual(got["errors.png"].replace("\n", " · ").split(" · "), parts)
                # trajectory.png is narrower: the inputs' folder is shortened in its middle
                t = got["trajectory.png"]
                self.assertEqual(len(t.split("\n")), 2, t)
                for part in parts[:4] + [f"sha256 of their sha256s {joint}", parts[-1]]:
                    self.assertIn(part, t)

    def test_footer_synthetic_and_without_manifest(self):
        with tempfile.TemporaryDirectory() as d:
            make_run(d, 40, segments=False)
            write_manifest(d, ["tigris", "odometry", "--synthetic", "41", "--search", "flann", "--out", d],
                           {"synthetic": 41, "seed": 1, "frames": "", "register_flags":
                            ["--preset", "dp4", "--search", "flann"], "compare": False}, [])
            for text in footers(d, commit_env="abcdef012345").values():   # no commit recorded: the binary's
                self.assertTrue(text.startswith(f"made by tigris odometry --synthetic 41 --search flann --out {d} · "))
                self.assertEqual(text.replace("\n", " · ").split(" · ")[1:4],
                                 ["commit abcdef012345", "synthetic drive of 41 frames, seed 1", "preset dp4"])
            os.remove(os.path.join(d, "manifest.json"))
            for text in footers(d).values():
                self.assertEqual(text, f"made by an unrecorded command (no manifest.json in {os.path.abspath(d)})"
                                       " · commit unknown")
            p = plot(d, env={"TIGRIS_COMMIT": "abcdef012345"})   # as tigris odometry runs it
            self.assertEqual(p.returncode, 0, p.stderr)
            self.check_pngs(d)

    def test_missing_metrics(self):
        with tempfile.TemporaryDirectory() as d:
            p = plot(d)
            self.assertEqual(p.returncode, 2)
            self.assertIn(os.path.join(d, "metrics.json"), p.stderr)


if __name__ == "__main__":
    main(__file__)
