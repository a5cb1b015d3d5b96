#!/usr/bin/python3
"""tigris/reports/plots.py: every figure from small hand-made CSVs (axes labels, titles, legends, PNG and
SVG files), rows picked by the settings swept, skipped figures, the command line, and the footer
saying what made a figure (tigris/core/provenance.py) in plots.py's and tigris plot's figures.
Run: python3 python/tests/test_plots.py (needs Debian's python3-matplotlib)."""
import hashlib
import json
import os
import shutil
import sys
import tempfile
import unittest

from common import footer_clear, run_tool, main

try:
    import matplotlib  # noqa: F401
    HAVE_MPL = True
except ImportError:
    HAVE_MPL = False
    if os.environ.get("TIGRIS_REQUIRE_MPL"):  # ctest: deps.sh installs it, so its absence is a failure
        sys.exit("matplotlib missing for " + sys.executable + ": apt-get install python3-matplotlib")

import plot_fixtures as fx  # noqa: E402
from tigris import core  # noqa: E402
from tigris.data import evaldata as ed  # noqa: E402

if HAVE_MPL:
    from tigris.reports import plots


def texts(fig):
    """Every axis label, title and legend entry of a figure."""
    out = [fig._suptitle.get_text()] if fig._suptitle else []
    for ax in fig.axes:
        out += [ax.get_xlabel(), ax.get_ylabel(), ax.get_title()]
        leg = ax.get_legend()
        if leg:
            out += [t.get_text() for t in leg.get_texts()]
    return out


@unittest.skipUnless(HAVE_MPL, "matplotlib missing: apt-get install python3-matplotlib, run with /usr/bin/python3")
class Figures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.csvs = fx.hand_made_csvs(os.path.join(cls.tmp.name, "csv"))
        cls.sw = ed.Sweep(list(cls.csvs.values()))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def build(self, name, sw=None):
        fig = plots.build(name, sw or self.sw)
        self.addCleanup(plots.plt.close, fig)
        return fig

    def assertLabelled(self, fig):
        for ax in fig.axes:
            if ax.get_xlabel() or ax.get_ylabel():
                self.assertTrue(ax.get_ylabel(), "an axis without a y label")
        self.assertTrue(fig._suptitle.get_text())

    def test_redundancy(self):
        fig = self.build("redundancy")
        a, b = fig.axes[:2]
        self.assertIn("leaf-set size", a.get_xlabel())
        self.assertIn("redundancy", a.get_ylabel())
        self.assertIn("nodes visited per query", b.get_ylabel())
        self.assertEqual(a.get_title(), "(a) redundancy ratio")
        t = texts(fig)
        self.assertIn("NN (measured)", t)
        self.assertIn("radius 0.30 m (measured)", t)
        self.assertIn("NN: paper, KITTI (35x at 32)", t)
        # NN curve: canonical at 1 (ratio 1), then the two-stage sizes in order
        nn = a.get_lines()[0]
        self.assertAlmostEqual(list(nn.get_ydata())[0], 1.0)
        self.assertEqual(sorted(nn.get_xdata()), list(nn.get_xdata()))
        self.assertAlmostEqual(list(nn.get_ydata())[-1], 8.0)  # 400 / 50 at leaf-set 449
        self.assertLabelled(fig)

    def test_units(self):
        fig = self.build("units")
        a, b = fig.axes[:2]
        self.assertEqual(a.get_xlabel(), "power (W)")
        self.assertEqual(a.get_ylabel(), "KD-tree search time (ms)")
        self.assertEqual(b.get_xlabel(), "SU x PE per SU")
        self.assertEqual([t.get_text() for t in b.get_xticklabels()], ["16x32", "32x32", "64x32"])
        t = texts(fig)
        for ru in (16, 32, 64, 128):
            self.assertIn(f"{ru} RU", t)
        self.assertIn("Sensitivity to the number of RUs, SUs and PEs per SU", t)

    def test_height(self):
        fig = self.build("height")
        titles = [ax.get_title() for ax in fig.axes]
        self.assertIn("NN", titles)
        ax = fig.axes[titles.index("NN")]
        self.assertEqual(ax.get_xlabel(), "top-tree height")
        self.assertEqual(ax.get_ylabel(), "KD-tree search time (ms)")
        self.assertIn("energy (uJ)", [x.get_ylabel() for x in fig.axes])
        t = texts(fig)
        self.assertIn("fastest: height 10", t)
        self.assertIn("canonical tree (Acc-KD, height 17)", t)
        # radius has one numeric height less than needed? it has two: a panel of its own
        self.assertIn("radius 0.30 m", titles)

    def test_optimizations(self):
        fig = self.build("optimizations")
        a = fig.axes[0]
        self.assertEqual([t.get_text() for t in a.get_xticklabels()], ["No-Opt", "Bypass", "+Forward", "MQMN"])
        self.assertEqual(a.get_ylabel(), "speed-up over No-Opt (x)")
        self.assertEqual(fig.axes[1].get_ylabel(), "power (W)")
        heights = [p.get_height() for p in a.patches]
        self.assertAlmostEqual(heights[0], 1.0)
        self.assertAlmostEqual(heights[3], 130000 / 20000)
        self.assertIn("power", texts(fig))

    def test_memory_traffic(self):
        fig = self.build("memory_traffic")
        a, b = fig.axes[:2]
        self.assertEqual(a.get_ylabel(), "share of on-chip memory traffic (%)")
        self.assertEqual(b.get_ylabel(), "on-chip memory traffic (MB read + written)")
        labels = [t.get_text() for t in a.get_xticklabels()]
        self.assertEqual(labels, ["Acc-2SKD (h 10)\nNode Cache", "Acc-2SKD (h 10)\nno Node Cache",
                                  "Acc-KD\nNode Cache", "Acc-KD\nno Node Cache"])
        # The Point Buffer's share is the first stack: 25% with, 50% without the cache
        pb = [p.get_height() for p in a.patches[:4]]
        self.assertAlmostEqual(pb[0], 25.0)
        self.assertAlmostEqual(pb[1], 50.0)
        self.assertIn("Point Buffer", texts(fig))
        # heights-nn rows (other heights, one Node Cache setting) are left out, with a note
        self.assertTrue(any("without both Node Cache settings" in n for n in fig.notes))

    def test_approx(self):
        fig = self.build("approx")
        a, b, c, d = fig.axes[:4]
        for ax in (a, b, c, d):
            self.assertEqual(ax.get_xlabel(), "approximation threshold thd (m); 0 = exact search")
        self.assertEqual(a.get_ylabel(), "nodes visited per query")
        self.assertEqual(b.get_ylabel(), "cycles / exact search's cycles")
        self.assertEqual(c.get_ylabel(), "accuracy (fraction)")
        self.assertEqual(d.get_ylabel(), "extra distance to the neighbour (m)")
        self.assertEqual(list(a.get_lines()[0].get_xdata()), [0.0, 0.6, 1.2])
        self.assertEqual(list(a.get_lines()[0].get_ydata()), [200.0, 100.0, 50.0])
        self.assertEqual(list(c.get_lines()[0].get_ydata()), [1.0, 0.3, 0.1])
        self.assertIn("NN: queries with the exact answer", texts(fig))

    def test_files_png_and_svg(self):
        out = os.path.join(self.tmp.name, "figs")
        made, skipped = plots.make_figures(self.sw, out, log=lambda m: None)
        self.assertEqual(set(made), set(plots.FIGURES))
        self.assertEqual(skipped, {})
        for name, (png, svg, _) in made.items():
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
            with open(svg) as f:
                text = f.read()
            self.assertIn("<svg", text)
        with open(made["units"][1]) as f:
            self.assertIn("Sensitivity to the number of RUs", f.read())

    def test_settings_first_layout(self):
        """CSVs with every setting before `status` give the same figures."""
        csvs = fx.hand_made_csvs(os.path.join(self.tmp.name, "csv2"), layout="settings-first")
        sw = ed.Sweep(list(csvs.values()))
        self.assertEqual(len(sw.ok), len(self.sw.ok))
        fig = self.build("optimizations", sw)
        self.assertEqual([t.get_text() for t in fig.axes[0].get_xticklabels()],
                         ["No-Opt", "Bypass", "+Forward", "MQMN"])

    def test_sidecar_and_stats_prefix(self):
        """sweep.json names the base columns; `stats.queries` is the query count."""
        d = os.path.join(self.tmp.name, "side")
        os.makedirs(d)
        p = fx.write_csv(os.path.join(d, "sweep.csv"),
                         [{"settings": {"height": h}, "stats": fx.fake_stats(top_height=h, queries=500)}
                          for h in (8, 10)], sidecar=True)
        with open(p) as f:
            header = f.readline().strip().split(",")
        self.assertIn("stats.queries", header)
        self.assertEqual(header.index("cloud"), header.index("wall_seconds") + 1)
        sw = ed.Sweep([p])
        self.assertEqual(ed.num(sw.ok[0], "queries"), 500)
        self.assertEqual(sw.ok[0]["eff"]["mode"], "nn")
        self.assertIn("mode", sw.setting_columns)


@unittest.skipUnless(HAVE_MPL, "matplotlib missing")
class Skipping(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.csvs = fx.hand_made_csvs(self.tmp.name)

    def test_only_optimizations(self):
        sw = ed.Sweep([self.csvs["optimizations"]])
        log = []
        made, skipped = plots.make_figures(sw, os.path.join(self.tmp.name, "o"), log=log.append)
        self.assertEqual(set(made), {"optimizations"})
        self.assertIn("the CSVs have no column height or tree.top_height", skipped["redundancy"])
        self.assertIn("fe.recursion_units", skipped["units"])
        self.assertIn("node_cache.bytes", skipped["memory_traffic"])
        self.assertIn("approx-thd", skipped["approx"])
        self.assertTrue(any(m.startswith("plots: skipped redundancy:") for m in log))

    def test_redundancy_needs_canonical(self):
        rows = [{"settings": {"height": h}, "stats": fx.fake_stats(top_height=h)} for h in (8, 10)]
        sw = ed.Sweep([fx.write_csv(os.path.join(self.tmp.name, "h.csv"), rows)])
        with self.assertRaises(plots.Skip) as e:
            plots.build("redundancy", sw)
        self.assertIn("canonical-tree row (height full)", str(e.exception))
        plots.plt.close("all")

    def test_which_missing_is_an_error(self):
        sw = ed.Sweep([self.csvs["optimizations"]])
        with self.assertRaises(plots.Skip):
            plots.make_figures(sw, os.path.join(self.tmp.name, "w"), which=["units"], log=lambda m: None)

    def test_not_ok_rows_left_out(self):
        rows = [{"settings": {"fe.forwarding": False}, "stats": fx.fake_stats(cycles=120000)},
                {"settings": {"fe.forwarding": True}, "stats": None, "status": "error", "error": "boom"}]
        sw = ed.Sweep([fx.write_csv(os.path.join(self.tmp.name, "e.csv"), rows)])
        self.assertEqual(len(sw.not_ok), 1)
        with self.assertRaises(plots.Skip) as e:
            plots.build("optimizations", sw)
        self.assertIn("at least two", str(e.exception))


def sweep_folder(d, csv_path, commit="5c40187850da"):
    """A sweep folder as tigris sweep leaves it: sweep.csv (a copy of csv_path) and the manifest
    (in the format of tigris/core/folders.py)."""
    os.makedirs(d)
    shutil.copy(csv_path, os.path.join(d, "sweep.csv"))
    m = {"tigris_manifest": 1, "command": "sweep", "argv": ["/opt/tigris/bin/tigris", "sweep", "spec.json", "--out", d],
         "cwd": "/", "commit": commit, "settings": {"spec": "spec.json"}, "inputs": [], "outputs": ["sweep.csv"],
         "status": "done"}
    with open(os.path.join(d, "manifest.json"), "w") as f:
        json.dump(m, f)
    with open(os.path.join(d, "sweep.csv"), "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()[:12]


def svg_text(path):
    """The text of an SVG (svg.fonttype none: text stays text), its entities undone."""
    import html
    with open(path, encoding="utf-8") as f:
        return html.unescape(f.read())


@unittest.skipUnless(HAVE_MPL, "matplotlib missing")
class Footer(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.csvs = fx.hand_made_csvs(os.path.join(self.tmp.name, "csv"))

    def test_make_figures_footer(self):
        """Every paper figure carries the footer it is given, inside the figure, under its axes."""
        sw_dir = os.path.join(self.tmp.name, "sw")
        sha = sweep_folder(sw_dir, self.csvs["units"])
        csv_path = os.path.join(sw_dir, "sweep.csv")
        footer = plots.sweep_footer([csv_path], ["tigris/reports/plots.py", csv_path, "--out", "figs"])
        self.assertEqual(footer[0].split(core.SEP)[0], f"drawn by plots.py {csv_path} --out figs")
        self.assertEqual(footer[1], f"from {os.path.realpath(csv_path)} (sha256 {sha}), made by tigris sweep "
                                    f"spec.json --out {sw_dir} (commit 5c40187850da; "
                                    f"settings sha256 {core.digest({'spec': 'spec.json'})[:12]})")
        sw = ed.Sweep(list(self.csvs.values()))
        seen = {}
        real_save = core.save_figure
        core.save_figure = lambda fig, path, **kw: (seen.__setitem__(os.path.basename(path), footer_clear(fig)),
                                                    real_save(fig, path, **kw))
        try:
            made, _ = plots.make_figures(sw, os.path.join(self.tmp.name, "figs"), log=lambda m: None, footer=footer)
        finally:
            core.save_figure = real_save
        self.assertEqual(set(made), set(plots.FIGURES))
        for name in plots.FIGURES:
            for ext in ("png", "svg"):
                text = seen[f"{name}.{ext}"]
                # narrow figures shorten the middle of the line; these parts stay
                self.assertTrue(text.startswith("drawn by plots.py "), (name, text))
                self.assertIn(f"sw/sweep.csv (sha256 {sha}), made ", text)
                self.assertIn("(commit 5c40187850da; settings sha256 ", text)
            self.assertIn("drawn by plots.py", svg_text(made[name][1]))
        # Without a footer, none.
        fig = plots.build("units", sw)
        self.assertIsNone(core.footer_text(fig))
        plots.plt.close(fig)

    def test_tigris_plot_footer(self):
        """tigris plot's figures, the swept-key ones and the paper's: its own command line and
        commit, and the sweep's CSV with the command line and commit of the sweep that wrote it."""
        sw_dir = os.path.join(self.tmp.name, "sw")
        sha = sweep_folder(sw_dir, self.csvs["units"])
        out = os.path.join(self.tmp.name, "plots")
        env = dict(os.environ, TIGRIS_COMMIT="fd523df8c13c-dirty")
        env.pop("TIGRIS", None)                  # the manifest says "tigris" then
        p = run_tool("plot", sw_dir, "--out", out, "--which", "sweep", "units", env=env, timeout=300)
        self.assertEqual(p.returncode, 0, p.stderr)
        svgs = sorted(f for f in os.listdir(out) if f.endswith(".svg"))
        self.assertIn("units.svg", svgs)
        self.assertTrue(any(f.startswith("sweep_") for f in svgs), svgs)
        with open(os.path.join(out, "manifest.json")) as f:
            manifest = json.load(f)
        self.assertEqual(manifest["commit"], "fd523df8c13c-dirty")
        for f in svgs:
            text = svg_text(os.path.join(out, f))
            self.assertIn('id="tigris-footer"', text)
            self.assertIn(f"drawn by tigris plot {sw_dir} --out {out} --which sweep units", text)
            self.assertIn("commit fd523df8c13c-dirty", text)
            self.assertIn(f"(sha256 {sha}), made by tigris sweep spec.json", text)
            self.assertIn("(commit 5c40187850da", text)


@unittest.skipUnless(HAVE_MPL, "matplotlib missing")
class CommandLine(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.csvs = fx.hand_made_csvs(self.tmp.name)

    def run_plots(self, *args):
        return run_tool("figures", *args)

    def test_which(self):
        out = os.path.join(self.tmp.name, "f")
        p = self.run_plots(self.csvs["heights-nn"], "--out", out, "--which", "height", "redundancy")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(sorted(os.listdir(out)), ["height.png", "height.svg", "redundancy.png", "redundancy.svg"])

    def test_which_missing_exit_2(self):
        p = self.run_plots(self.csvs["heights-nn"], "--out", os.path.join(self.tmp.name, "g"), "--which", "units")
        self.assertEqual(p.returncode, 2)
        self.assertIn("plots: cannot make units: the CSVs have no column", p.stderr)

    def test_skips_are_messages(self):
        p = self.run_plots(self.csvs["heights-nn"], "--out", os.path.join(self.tmp.name, "h"))
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("plots: skipped units:", p.stderr)
        self.assertIn("plots: wrote", p.stderr)

    def test_bad_input(self):
        p = self.run_plots(os.path.join(self.tmp.name, "nope.csv"), "--out", self.tmp.name)
        self.assertEqual(p.returncode, 2)
        self.assertIn("no such CSV", p.stderr)
        bad = os.path.join(self.tmp.name, "bad.csv")
        with open(bad, "w") as f:
            f.write("a,b\n1,2\n")
        p = self.run_plots(bad, "--out", self.tmp.name)
        self.assertEqual(p.returncode, 2)
        self.assertIn("no `status` column", p.stderr)
        p = self.run_plots(self.csvs["units"], "--out", self.tmp.name, "--which", "nonsense")
        self.assertEqual(p.returncode, 2)


if __name__ == "__main__":
    main(__file__)
