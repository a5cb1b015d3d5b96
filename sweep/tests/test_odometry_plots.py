#!/usr/bin/python3
"""sweep/odometry_plots.py (tigris odometry's figures) on hand-made run folders: a trajectory with
KITTI segments, a short one (per-pair errors instead, said so), one without a ground truth, and
a missing metrics.json (exit 2 naming the file).
Run: python3 sweep/tests/test_odometry_plots.py (needs Debian's python3-matplotlib)."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(os.path.dirname(HERE), "odometry_plots.py")

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


def plot(d):
    return subprocess.run([sys.executable, SCRIPT, d], capture_output=True, text=True, timeout=120)


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

    def test_missing_metrics(self):
        with tempfile.TemporaryDirectory() as d:
            p = plot(d)
            self.assertEqual(p.returncode, 2)
            self.assertIn(os.path.join(d, "metrics.json"), p.stderr)


if __name__ == "__main__":
    unittest.main()
