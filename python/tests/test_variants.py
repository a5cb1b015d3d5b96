#!/usr/bin/python3
"""tigris/reports/variants.py and `reproduce --variants`: verdicts and the classification of claims over
design variants (from hand-made claims and hand-made CSVs), the variants' specs, user variants
and their errors, and a small variant run end to end with tigris (the synthetic pair).
Run: python3 python/tests/test_variants.py [--tigris PATH] (pytest)"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from common import footer_clear, tool_command, main

# The binary under test (conftest.py's --tigris), also for the tools' own binary lookup.
TIGRIS = os.environ.get("TIGRIS_TEST_BINARY")
if TIGRIS:
    os.environ["TIGRIS"] = TIGRIS

import plot_fixtures as fx  # noqa: E402
from tigris.data import evaldata as ed  # noqa: E402
from tigris.reports import report  # noqa: E402
from tigris.reports import claims as cl  # noqa: E402
from tigris.tools import reproduce  # noqa: E402
from tigris.reports import variants as vt  # noqa: E402

DEFAULTS = {"dram.bytes_per_cycle": 51.2, "node_cache.bytes": 131072, "leader-width": 0,
            "fe.top_levels_replicated": 0}


# `tigris run --list-config --json`'s entries for the keys the tests use.
KEY_INFO = {"dram.bytes_per_cycle": {"type": "number", "min": 0.001, "max": 1e6, "default": 51.2},
            "node_cache.bytes": {"type": "bytes", "min": 0, "default": 131072},
            "node_cache.policy": {"type": "enum", "values": ["fifo", "lru"], "default": "lru"},
            "fe.forwarding": {"type": "bool", "default": True},
            "fe.top_levels_replicated": {"type": "integer", "min": 0, "max": 16, "default": 0},
            "tree.top_height": {"type": "integer", "min": 1, "max": 24, "default": 10}}


def claim(cid, measured, direction, within, explanation="facts"):
    c = cl.Claim(cid, "9", f"claim {cid}", "1x", "how")
    return c.set(measured, direction, within, explanation)


def col(name, variant, *claims):
    return vt.Column(name, variant, list(claims))


class Verdicts(unittest.TestCase):
    def test_verdict(self):
        self.assertEqual(vt.verdict(claim("a", "1", True, True)), vt.HOLDS)
        self.assertEqual(vt.verdict(claim("a", "1", True, None)), vt.HOLDS)
        self.assertEqual(vt.verdict(claim("a", "1", None, True)), vt.HOLDS)
        self.assertEqual(vt.verdict(claim("a", "1", True, False)), vt.DIRECTION_ONLY)
        self.assertEqual(vt.verdict(claim("a", "1", False, True)), vt.SIZE_ONLY)
        self.assertEqual(vt.verdict(claim("a", "1", False, False)), vt.FAILS)
        self.assertEqual(vt.verdict(claim("a", "1", False, None)), vt.FAILS)
        self.assertEqual(vt.verdict(claim("a", "1", None, None)), vt.NO_TEST)
        self.assertEqual(vt.verdict(cl.Claim("a", "9", "t", "p", "h")), vt.NOT_MEASURED)
        self.assertEqual(vt.verdict(None), vt.NOT_MEASURED)
        for d, w in ((True, True), (True, False), (False, False)):  # a work ratio whatever its cycles say
            c = claim("a", "1", d, w)
            c.work_ratio = True
            self.assertEqual(vt.verdict(c), vt.WORK_RATIO)


class Classify(unittest.TestCase):
    def setUp(self):
        self.d2 = vt.Variant("dram-2x", "", set={"dram.bytes_per_cycle": 102.4})
        self.d8 = vt.Variant("dram-8x", "", set={"dram.bytes_per_cycle": 409.6})
        self.nc = vt.Variant("nc-512k", "", set={"node_cache.bytes": 524288})

    def cols(self, base, d2, d8, nc):
        return [col("default", None, base), col("dram-2x", self.d2, d2), col("dram-8x", self.d8, d8),
                col("nc-512k", self.nc, nc)]

    def test_holds_everywhere(self):
        cols = self.cols(*(claim("x", f"{v}x", True, True) for v in (1.1, 1.2, 1.3, 1.1)))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "holds everywhere")
        self.assertIn("all 4 configurations", text)

    def test_fails_everywhere_gives_the_defaults_reason(self):
        cols = self.cols(claim("x", "1.00x", False, False, "write-back bound: 95% stalled"),
                         claim("x", "1.01x", False, False, "other"),
                         claim("x", "1.00x", False, False, "other"),
                         claim("x", "1.00x", False, False, "other"))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "fails everywhere")
        self.assertIn("Measured reason at the default: write-back bound: 95% stalled", text)
        self.assertIn("dram-2x 1.01x", text)

    def test_direction_only_everywhere_is_a_fail_with_its_words(self):
        cols = self.cols(*(claim("x", "1.5x", True, False) for _ in range(4)))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "fails everywhere (direction holds)")
        self.assertIn("the direction holds but the size misses", text)

    def test_depends_names_the_detail_and_direction(self):
        cols = self.cols(claim("x", "1.00x", False, False), claim("x", "1.40x", True, False),
                         claim("x", "4.80x", True, True), claim("x", "1.00x", False, False))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "depends")
        self.assertIn("`dram.bytes_per_cycle`: better as dram.bytes_per_cycle rises", text)
        self.assertIn("fails at 51.2 (default) (1.00x); direction only at 102.4 (1.40x); holds at 409.6 (4.80x)", text)
        self.assertNotIn("node_cache", text)  # the Node Cache's verdict equals the default's

    def test_depends_falling_and_not_monotone(self):
        cols = self.cols(claim("x", "a", True, True), claim("x", "b", True, True),
                         claim("x", "c", True, True), claim("x", "d", False, False))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertIn("`node_cache.bytes`: better as node_cache.bytes falls", text)
        cols = self.cols(claim("x", "a", True, True), claim("x", "b", False, False),
                         claim("x", "c", True, True), claim("x", "d", True, True))
        self.assertIn("`dram.bytes_per_cycle`: not monotone", vt.classify("x", cols, DEFAULTS)[1])

    def test_two_keys_rising_together_have_a_direction(self):
        banks = {"sram.points.banks": 128, "sram.points.ports": 128}
        lo = vt.Variant("pb-64", "", set={"sram.points.banks": 64, "sram.points.ports": 64})
        hi = vt.Variant("pb-256", "", set={"sram.points.banks": 256, "sram.points.ports": 256})
        cols = [col("default", None, claim("x", "1.0x", False, False)), col("pb-256", hi, claim("x", "2.0x", True, True)),
                col("pb-64", lo, claim("x", "0.9x", False, False))]
        text = vt.classify("x", cols, dict(DEFAULTS, **banks))[1]
        self.assertIn("`sram.points.banks + sram.points.ports`: better as sram.points.banks + sram.points.ports rise "
                      "(fails at 64/64 (0.9x); fails at 128/128 (default) (1.0x); holds at 256/256 (2.0x))", text)
        odd = vt.Variant("pb-odd", "", set={"sram.points.banks": 256, "sram.points.ports": 64})
        cols.append(col("pb-odd", odd, claim("x", "1.5x", True, True)))
        text = vt.classify("x", cols, dict(DEFAULTS, **banks))[1]
        self.assertIn("`sram.points.banks + sram.points.ports` (", text)  # the keys move apart: no direction

    def test_leader_width_default_reads_k(self):
        lw4 = vt.Variant("leader-width-4", "", leader_width=4)
        cols = [col("default", None, claim("x", "1x", False, False)), col("leader-width-4", lw4, claim("x", "2x", True, True))]
        self.assertIn("(fails at k (default) (1x); holds at 4 (2x))", vt.classify("x", cols, DEFAULTS)[1])

    def test_fails_everywhere_names_where_its_reason_comes_from(self):
        cols = self.cols(cl.Claim("x", "9", "t", "p", "h"), claim("x", "1x", False, False, "bound A"),
                         claim("x", "1x", False, False, "bound B"), claim("x", "1x", False, False, "bound C"))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "fails everywhere")
        self.assertIn("Measured reason at dram-2x: bound A", text)

    def test_a_work_ratio_everywhere(self):
        cs = [claim("x", f"{v}x", True, False) for v in (1.3, 1.2, 1.3, 1.3)]
        for c in cs:
            c.work_ratio = True
        cls, text = vt.classify("x", self.cols(*cs), DEFAULTS)
        self.assertEqual(cls, "a work ratio everywhere")
        self.assertIn("the paper's number is a work ratio beyond the ideal machine's under all 4", text)

    def test_not_measured_somewhere(self):
        cols = self.cols(claim("x", "1x", True, True), cl.Claim("x", "9", "t", "p", "h"),
                         claim("x", "1x", True, True), claim("x", "1x", True, True))
        cls, text = vt.classify("x", cols, DEFAULTS)
        self.assertEqual(cls, "holds everywhere")
        self.assertIn("Not measured under dram-2x", text)

    def test_matrix_and_render(self):
        cols = self.cols(claim("x", "1.00x", False, False), claim("x", "1.40x", True, False),
                         claim("x", "4.80x", True, True), claim("x", "1.00x", False, False))
        cols[0].claims["y"] = claim("y", "2x", True, True)
        cols[0].order.append("y")
        rows = vt.matrix(cols, DEFAULTS)
        self.assertEqual([r[3] for r in rows], ["depends", "one configuration only"])  # y: the default only
        md = "\n".join(vt.render(cols, DEFAULTS, "figures/variants.png"))
        self.assertIn("| 1 | claim x | 1.00x · fails | 1.40x · direction only | 4.80x · holds | 1.00x · fails | **depends** |", md)
        self.assertIn("| 2 | claim y | 2x · holds | not measured | not measured | not measured | one configuration only |", md)
        self.assertIn("![the claims under the design variants](figures/variants.png)", md)
        self.assertIn("| dram-8x | `dram.bytes_per_cycle=409.6` |", md)


class Figure(unittest.TestCase):
    """variants.png: a colour per verdict (direction only never a shade of holds), every claim's
    label whole and inside the figure, the legend and REPORT.md's text in the same words, and
    the provenance footer."""
    LONG = ("at 16-32 RU the front-end bounds the run: more SU x PE helps only marginally (back-end "
            "scaling gain at the fewest RU / at 64 RU), and a few more words to need a third line")

    def draw(self, cols, footer=None):
        """Draws the figure; returns (fig as saved, drawn: its pixels, the matrix' rows)."""
        from tigris import core
        import matplotlib
        matplotlib.use("Agg")
        import numpy as np
        saved = []
        real = core.save_figure

        def keep(fig, path, **kw):
            fig.canvas.draw()
            saved.append((fig, np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy() / 255.0))
            real(fig, path, **kw)
        core.save_figure = keep
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp)
        try:
            path = vt.figure(cols, DEFAULTS, os.path.join(tmp, "figures", "variants.png"), footer=footer)
        finally:
            core.save_figure = real
        self.assertTrue(os.path.getsize(path) > 5000)
        self.assertEqual(len(saved), 1)
        return saved[0][0], saved[0][1], vt.matrix(cols, DEFAULTS)

    def columns(self, n_claims=14):
        """Every verdict, a long claim text and a long value; two variants."""
        d8 = vt.Variant("dram-8x", "", set={"dram.bytes_per_cycle": 409.6})
        nc = vt.Variant("nc-512k", "", set={"node_cache.bytes": 524288})
        kinds = [(True, True), (True, False), (False, True), (False, False), (None, None)]
        base, a, b = [], [], []
        for k in range(n_claims):
            d, w = kinds[k % len(kinds)]
            text = self.LONG if k == 2 else f"claim {k} with a text of some length (NN; value at leaf-set {k})"
            base.append(cl.Claim(f"c{k}", "9", text, "1x", "h").set(
                "1.03x at 16 RU vs 1.69x at 64 RU (16x16 -> 128x128)" if k == 2 else f"{k}.0x", d, w, "x"))
            d2, w2 = kinds[(k + 1) % len(kinds)]
            a.append(cl.Claim(f"c{k}", "9", text, "1x", "h").set(f"{k}.5x", d2, w2, "x"))
            if k % 3:
                b.append(cl.Claim(f"c{k}", "9", text, "1x", "h").set(f"{k}.7x", d, w, "x"))
        return [col("default", None, *base), col("dram-8x", d8, *a), col("nc-512k", nc, *b)]

    def test_a_colour_per_verdict(self):
        from matplotlib.colors import rgb_to_hsv, to_rgb
        colours = {k: to_rgb(vt.COLOURS[k]) for k in vt.VERDICTS}
        self.assertEqual(len(set(colours.values())), len(vt.VERDICTS), "two verdicts share a colour")
        # Direction only is not a shade of holds' green: another hue, far apart in RGB.
        h_holds, h_dir = rgb_to_hsv(colours[vt.HOLDS])[0], rgb_to_hsv(colours[vt.DIRECTION_ONLY])[0]
        self.assertGreater(min(abs(h_holds - h_dir), 1 - abs(h_holds - h_dir)) * 360, 60)
        self.assertGreater(sum((x - y) ** 2 for x, y in zip(colours[vt.HOLDS], colours[vt.DIRECTION_ONLY])) ** 0.5, 0.5)
        # and not a shade of fails' red either
        self.assertGreater(sum((x - y) ** 2 for x, y in zip(colours[vt.FAILS], colours[vt.DIRECTION_ONLY])) ** 0.5, 0.35)
        # Each cell is drawn in its verdict's colour (read from the pixels, off the value's text).
        fig, pixels, rows = self.draw(self.columns())
        ax = fig.axes[0]
        seen = set()
        for y, (_, _, cells, _, _) in enumerate(rows):
            for x, (v, _) in enumerate(cells):
                px, py = ax.transData.transform((x - 0.38, y - 0.3))
                got = pixels[int(round(pixels.shape[0] - py)), int(round(px))]
                want = colours[v] if v != vt.NOT_MEASURED else None
                if want is not None:
                    self.assertLess(max(abs(g - w) for g, w in zip(got, want)), 0.03, (y, x, v, got, want))
                    seen.add(v)
        self.assertEqual(seen, {vt.HOLDS, vt.DIRECTION_ONLY, vt.SIZE_ONLY, vt.FAILS, vt.NO_TEST})
        # The legend: every verdict in its colour, with what it means.
        legend = ax.get_legend()
        texts = [t.get_text().replace("\n", " ") for t in legend.get_texts()]
        self.assertEqual(texts, [f"{k}: {vt.MEANING[k]}" for k in vt.VERDICTS])
        for patch, k in zip(legend.get_patches(), vt.VERDICTS):
            self.assertEqual(tuple(patch.get_facecolor()[:3]), colours[k], k)

    def test_legend_and_markdown_agree(self):
        md = "\n".join(vt.render(self.columns(), DEFAULTS, "figures/variants.png"))
        self.assertIn("*direction only* (amber: the direction holds, the size is off from the paper's by more "
                      "than 2x)", md)
        for k in vt.VERDICTS:
            self.assertIn(f"*{k}* ({vt.COLOUR_NAMES[k]}: {vt.MEANING[k]})", md)
        import matplotlib.colors as mc
        self.assertEqual(mc.to_hex(vt.COLOURS[vt.DIRECTION_ONLY]), mc.to_hex("#f5a623"))  # amber, as its name says

    def test_labels_whole_and_inside(self):
        cols = self.columns(30)
        fig, _, rows = self.draw(cols, footer=["made by tigris reproduce --variants", "commit 0123abc"])
        fig.canvas.draw()                    # measured as drawn at the figure's own dpi
        ax = fig.axes[0]
        box = fig.bbox
        inside = lambda b: b.x0 >= 0 and b.y0 >= 0 and b.x1 <= box.width and b.y1 <= box.height  # noqa: E731
        labels = ax.get_yticklabels()
        self.assertEqual(len(labels), len(rows))
        extents = []
        for t, (i, c, _, cls, _) in zip(labels, rows):
            text = t.get_text()
            self.assertEqual(text.replace("\n", " "), f"#{i} {c.text}" + (" *" if cls == "depends" else ""))
            self.assertLessEqual(text.count("\n"), 1, text)          # two lines at most
            self.assertNotIn("\u2026", text)                          # nothing cut
            e = t.get_window_extent()
            self.assertTrue(inside(e), (text, e, box))
            extents.append(e)
        for a, b in zip(extents, extents[1:]):                       # no label runs into the next
            self.assertFalse(a.overlaps(b), (a, b))
        long = next(t.get_text() for t in labels if "more SU x PE" in t.get_text())
        self.assertEqual(long.count("\n"), 1, long)
        for t in ax.get_xticklabels() + [ax.title]:
            self.assertTrue(inside(t.get_window_extent()), t.get_text())
        self.assertTrue(inside(ax.get_legend().get_window_extent()))
        self.assertTrue(inside(ax.get_tightbbox()))
        foot = footer_clear(fig)             # inside the figure, under the axes and their labels
        self.assertTrue(foot.startswith("made by tigris reproduce --variants") and "commit 0123abc" in foot, foot)
        # A value too long for its cell: its parenthesis left out, the rest on two lines.
        cell = next(t.get_text() for t in ax.texts if t.get_text().startswith("1.03x"))
        self.assertEqual(cell, "1.03x at 16 RU vs\n1.69x at 64 RU")

    def test_default_footer_names_the_command(self):
        import matplotlib.pyplot as plt
        old = sys.argv
        sys.argv = ["/x/tigris/tools/reproduce.py", "--variants", "dram-8x", "--out", "repro"]
        try:
            fig, _, _ = self.draw(self.columns(3))
        finally:
            sys.argv = old
        from tigris import core
        text = core.footer_text(fig)
        self.assertTrue(text.startswith("made by reproduce.py --variants dram-8x --out repro"), text)
        self.assertIn("3 configurations: default, dram-8x, nc-512k", text)
        plt.close("all")


class Specs(unittest.TestCase):
    def test_node_cache_grid_takes_the_variants_size(self):
        exps = reproduce.experiments(False)
        nc = vt.by_name()["nc-512k"]
        spec = vt.apply(exps["node-cache"][1], nc, DEFAULTS)
        self.assertEqual(spec["grid"]["node_cache.bytes"], [524288, 0])
        self.assertNotIn("set", spec["base"])
        spec = vt.apply(exps["optimizations"][1], nc, DEFAULTS)
        self.assertEqual(spec["base"]["set"], {"node_cache.bytes": 524288})
        self.assertEqual(spec["points"], exps["optimizations"][1]["points"])

    def test_leader_width_goes_on_approximate_points_only(self):
        exps = reproduce.experiments(False)
        lw = vt.by_name()["every-leaf-w4"]
        self.assertFalse(vt.affects(lw, "heights-nn", exps["heights-nn"][1]))
        self.assertFalse(vt.affects(lw, "approx-radius", exps["approx-radius"][1]))
        self.assertTrue(vt.affects(lw, "approx-nn", exps["approx-nn"][1]))
        spec = vt.apply(exps["approx-nn"][1], lw, DEFAULTS)
        self.assertNotIn("grid", spec)
        self.assertIn({}, spec["points"])
        approx = [p for p in spec["points"] if "approx-thd" in p]
        self.assertEqual(len(approx), len(exps["approx-nn"][1]["grid"]["approx-thd"]))
        self.assertTrue(all(p["leader-width"] == 4 for p in approx))
        self.assertEqual(spec["base"]["set"], {"leader.scope": "every_leaf"})

    def test_built_in_list(self):
        names = vt.by_name()
        for n in ("top-6", "top-10", "dram-2x", "dram-8x", "pb-banks-64", "pb-banks-256", "nc-32k",
                  "nc-512k", "every-leaf", "every-leaf-w4", "finished-only"):
            self.assertIn(n, names)
            self.assertTrue(names[n].why)
        self.assertNotIn("paper-accounting", names)  # an accounting, not a design variant of the matrix

    def test_paper_accounting(self):
        """The preset paper-accounting as a variant of every experiment: its keys in base.set of
        the `tigris run` experiments, the registrations' accelerator points with its file as
        --accel-config, the golden model's experiments left alone; its keys are no experiment's
        axis, so it needs no model defaults to apply."""
        v = vt.accounting("paper-accounting")
        self.assertEqual(v.set, {"dram.writeback": "off_critical_path", "energy.charge_result_dram": False,
                                 "result_buffer.leader_lists": "resident"})
        self.assertEqual(v.accel_config, os.path.join(vt.shipped_presets(), "paper-accounting.json"))
        self.assertTrue(v.why)
        for quick in (False, True):
            for name, (_, spec) in reproduce.experiments(quick).items():
                golden = spec.get("command") in ("ref", "odometry")
                self.assertEqual(vt.affects(v, name, spec), not golden, name)
                for k in v.set:
                    self.assertNotIn(f'"{k}"', json.dumps(spec), name)
        reg = vt.apply(reproduce.experiments(True)["registrations"][1], v, {})
        self.assertEqual(reg["points"], [{"preset": "dp4", "search": s, "accel-config": v.accel_config}
                                         for s in ("accel", "accel-approx")])
        self.assertNotIn("grid", reg)
        with self.assertRaises(vt.VariantError) as e:
            vt.accounting("dram-8x")
        self.assertIn("not an accounting preset", str(e.exception))
        with self.assertRaises(vt.VariantError) as e:
            vt.choose(["paper-accounting"], [])
        self.assertIn("is an accounting, not a design variant", str(e.exception))
        with self.assertRaises(vt.VariantError) as e:
            vt.choose([], [vt.Variant("paper-accounting", "", set={"dram.bytes_per_cycle": 1})])
        self.assertIn("has the name of a built-in variant or accounting", str(e.exception))

    def test_user_variants_and_their_errors(self):
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp)
        exps = list(reproduce.experiments(False))

        def load(obj):
            p = os.path.join(tmp, "v.json")
            with open(p, "w") as f:
                f.write(obj if isinstance(obj, str) else json.dumps(obj))
            return vt.load(p, exps, KEY_INFO, {"tree.top_height"})
        v = load({"variants": [{"name": "dram-4x", "set": {"dram.bytes_per_cycle": 204.8}, "why": "HBM",
                                "experiments": ["heights-radius"]}]})
        self.assertEqual((v[0].name, v[0].set, v[0].experiments), ("dram-4x", {"dram.bytes_per_cycle": 204.8},
                                                                    ["heights-radius"]))
        for bad, msg in (("{", "unreadable"), ({"x": 1}, "expected a list"),
                         ([{"name": "a b", "set": {"dram.bytes_per_cycle": 1}}], "\"name\" must be"),
                         ([{"name": "default", "set": {"dram.bytes_per_cycle": 1}}], "\"name\" must be"),
                         ([{"name": "a", "set": {"dram.bytes_per_cycl": 1}}], "did you mean 'dram.bytes_per_cycle'"),
                         ([{"name": "a"}], "changes nothing"),
                         ([{"name": "a", "leader_width": -1}], "leader_width"),
                         ([{"name": "a", "leader_width": 4}], "give \"set\": {\"leader.scope\": \"every_leaf\"} too"),
                         ([{"name": "a", "set": {"dram.bytes_per_cycle": 1}, "experiments": ["nope"]}],
                          "not an experiment: nope"),
                         ([{"name": "a", "set": {"dram.bytes_per_cycle": 1}, "colour": 1}], "unknown field"),
                         ([{"name": "a", "set": {"fe.top_levels_replicated": 20}}], "must be in 0..16"),
                         ([{"name": "a", "set": {"fe.top_levels_replicated": 2.5}}], "must be an integer"),
                         ([{"name": "a", "set": {"node_cache.bytes": "big"}}], "must be an integer"),
                         ([{"name": "a", "set": {"node_cache.bytes": True}}], "must be an integer"),
                         # JSON has no Infinity: refused by the reader (core.read_json_input), naming it
                         ('[{"name": "a", "set": {"dram.bytes_per_cycle": Infinity}}]', "Infinity is not a JSON number"),
                         ([{"name": "a", "set": {"node_cache.policy": "mru"}}], "must be one of fifo, lru"),
                         ([{"name": "a", "set": {"fe.forwarding": 1}}], "must be true or false"),
                         ([{"name": "a", "set": {"tree.top_height": 12}}], "through a flag"),
                         ([{"name": "a", "set": {"fe.forwarding": False}}, {"name": "a", "leader_width": 4}],
                          "the name 'a' is taken")):
            with self.assertRaises(vt.VariantError) as e:
                load(bad)
            self.assertIn(msg, str(e.exception))
            self.assertIn("v.json", str(e.exception))
        with self.assertRaises(vt.VariantError) as e:
            vt.choose([], [vt.Variant("dram-8x", "", set={"dram.bytes_per_cycle": 1})])
        self.assertIn("has the name of a built-in variant", str(e.exception))
        self.assertEqual(load([{"name": "a", "set": {"node_cache.policy": "fifo", "fe.forwarding": False,
                                                      "node_cache.bytes": 0, "dram.bytes_per_cycle": 3}}])[0].set,
                         {"node_cache.policy": "fifo", "fe.forwarding": False, "node_cache.bytes": 0,
                          "dram.bytes_per_cycle": 3})
        with self.assertRaises(vt.VariantError) as e:
            vt.choose(["dram-9x"], [])
        self.assertIn("unknown variant(s) dram-9x", str(e.exception))


def add_column(path, name, value, replace=None):
    """Adds a base setting column after `mode` (or rewrites it), as the driver writes a
    variant's base key; replace: {old: new} for its values."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head = rows[0]
    if name in head:
        i = head.index(name)
        for r in rows[1:]:
            r[i] = (replace or {}).get(r[i], r[i])
    else:
        i = head.index("mode") + 1
        head.insert(i, name)
        for r in rows[1:]:
            r.insert(i, value)
    with open(path, "w", newline="") as f:
        csv.writer(f).writerows(rows)


def set_cells(path, match, col, value):
    """Sets `col` to value in the rows whose cells include every (column, value) of match."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head = rows[0]
    for r in rows[1:]:
        if all(r[head.index(c)] == v for c, v in match.items()):
            r[head.index(col)] = value
    with open(path, "w", newline="") as f:
        csv.writer(f).writerows(rows)


class HandMadeCsvs(unittest.TestCase):
    """The claims of plot_fixtures.hand_made_csvs under three variants whose CSVs are edited by
    hand: the classification follows from the values written."""
    def test_classification_from_csvs(self):
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp)
        base = fx.hand_made_csvs(os.path.join(tmp, "default"))
        # dram-8x: every CSV carries the key; MQMN at 50,000 cycles: 2.00x, within 2x of the paper
        d8 = fx.hand_made_csvs(os.path.join(tmp, "dram-8x"))
        for p in d8.values():
            add_column(p, "dram.bytes_per_cycle", "409.6")
        set_cells(d8["optimizations"], {"be.issue_policy": "mqmn"}, "cycles", "50000")
        # nc-512k: the Node Cache experiment at 512 KiB, the others with the key as a base column
        nc = fx.hand_made_csvs(os.path.join(tmp, "nc-512k"))
        for name, p in nc.items():
            add_column(p, "node_cache.bytes", "524288", replace={"131072": "524288"})
        # every-leaf-w4 runs approx-nn only: its approximate rows at 100 nodes/query
        lw_dir = os.path.join(tmp, "every-leaf-w4")
        os.makedirs(lw_dir)
        lw_csv = os.path.join(lw_dir, "approx-nn.csv")
        shutil.copy(base["approx-nn"], lw_csv)
        add_column(lw_csv, "leader-width", "4")
        add_column(lw_csv, "leader.scope", "every_leaf")
        set_cells(lw_csv, {"approx-thd": "1.2"}, "visits.per_query.nodes.mean", "100.0")
        set_cells(lw_csv, {"approx-thd": ""}, "leader-width", "")
        lw_all = [p for n, p in base.items() if n != "approx-nn"] + [lw_csv]
        v = vt.by_name()
        claims = report.all_claims(ed.Sweep(list(base.values())))
        cols = report.variant_columns(claims, [("dram-8x", v["dram-8x"], list(d8.values())),
                                               ("nc-512k", v["nc-512k"], list(nc.values())),
                                               ("every-leaf-w4", v["every-leaf-w4"], lw_all)])
        rows = {c.cid: (cells, cls, text) for _, c, cells, cls, text in vt.matrix(cols, DEFAULTS)}
        cells, cls, text = rows["mqmn-speed-nn"]
        self.assertEqual([x[0] for x in cells], [vt.DIRECTION_ONLY, vt.HOLDS, vt.DIRECTION_ONLY, vt.DIRECTION_ONLY])
        self.assertEqual(cells[1][1], "2.00x")
        self.assertEqual(cls, "depends")
        self.assertIn("`dram.bytes_per_cycle`: better as dram.bytes_per_cycle rises", text)
        self.assertEqual(rows["bypass-nn"][1], "holds everywhere")
        self.assertEqual(rows["acc2skd-vs-acckd-nn"][1], "fails everywhere (direction holds)")  # 1.50x
        self.assertIn("Measured reason at the default: Acc-KD 150,000 cycles", rows["acc2skd-vs-acckd-nn"][2])
        # the Node Cache claims are measured under nc-512k: its rows are that variant's default
        for cid in ("pb-share-with-nc-nn", "nc-energy-nn"):
            self.assertNotEqual(rows[cid][0][2][0], vt.NOT_MEASURED, cid)
            self.assertEqual(rows[cid][0][2][1], rows[cid][0][0][1], cid)
        # approximate NN under every_leaf, leader width 4: 1 - 100/200 = 50% instead of 75%, the rest shared
        cells = rows["approx-visits-nn"][0]
        self.assertEqual((cells[0][1], cells[3][1]), ("-75.0%", "-50.0%"))
        self.assertEqual(rows["bypass-nn"][0][3], rows["bypass-nn"][0][0])


class EndToEnd(unittest.TestCase):
    """A small variant run with tigris on the built-in synthetic pair: two variants over the
    optimizations and Node Cache experiments (quick), then REPORT.md's matrix and its figure."""
    def test_small_variant_run(self):
        tigris = TIGRIS or os.environ.get("TIGRIS")
        if not tigris:
            from tigris.tools import sweep as ts
            tigris = ts.default_tigris()
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp)
        out = os.path.join(tmp, "out")
        user = os.path.join(tmp, "mine.json")
        with open(user, "w") as f:
            json.dump([{"name": "slow-nc", "set": {"node_cache.bytes": 16384}, "why": "a small cache",
                        "experiments": ["node-cache"]}], f)
        cmd, env = tool_command("reproduce", "--quick", "--only", "optimizations", "node-cache", "--variants",
                                "dram-8x", "slow-nc", "--variants-file", user, "--out", out, "--jobs", "2",
                                "--tigris", tigris)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=env)
        self.assertEqual(p.returncode, 0, p.stderr[-3000:])
        self.assertIn("2 variant(s)", p.stderr)
        with open(os.path.join(out, "variants", "dram-8x", "specs", "optimizations.json")) as f:
            self.assertEqual(json.load(f)["base"]["set"], {"dram.bytes_per_cycle": 409.6})
        with open(os.path.join(out, "variants", "slow-nc", "specs", "node-cache.json")) as f:
            self.assertEqual(json.load(f)["grid"]["node_cache.bytes"], [16384, 0])
        self.assertFalse(os.path.exists(os.path.join(out, "variants", "slow-nc", "specs", "optimizations.json")))
        with open(os.path.join(out, "variants", "dram-8x", "sweeps", "optimizations", "sweep.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual({r["status"] for r in rows}, {"ok"})
        self.assertEqual({r["dram.bytes_per_cycle"] for r in rows}, {"409.6"})
        with open(os.path.join(out, "REPORT.md")) as f:
            text = f.read()
        self.assertIn("## Robustness: the claims under design variants", text)
        self.assertIn("| # | claim | default | dram-8x | slow-nc | class |", text)  # no paper-accounting column
        with open(os.path.join(out, "variants", "paper-accounting", "sweeps", "optimizations", "sweep.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual({(r["status"], r["dram.writeback"], r["result_buffer.leader_lists"]) for r in rows},
                         {("ok", "off_critical_path", "resident")})
        self.assertTrue(all(float(r["visits.pe_distances"]) > 0 and float(r["lower_bound_cycles"]) > 0 for r in rows))
        line = next(x for x in text.splitlines() if x.startswith("| ") and "bypassing helps" in x and "· " not in x)
        self.assertNotIn("not measured", line)   # both columns measured, and its cycle / work / ideal ratios
        self.assertRegex(line, r"\| [0-9.]+x( \(paper's accounting [0-9.]+x\))? / 1\.00x / 1\.00x \|")
        line = next(x for x in text.splitlines() if x.startswith("| ") and "bypassing helps" in x
                    and "· " in x)
        self.assertNotIn("not measured", line)
        nc = next(x for x in text.splitlines() if x.startswith("| ") and "the Node Cache saves energy" in x
                  and "· " in x)
        self.assertNotIn("not measured", nc)
        self.assertTrue(os.path.getsize(os.path.join(out, "figures", "variants.png")) > 10000)
        # a rerun with another definition under the same name is refused: the results would mix
        with open(user, "w") as f:
            json.dump([{"name": "slow-nc", "set": {"node_cache.bytes": 8192}}], f)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
        self.assertEqual(p.returncode, 2)
        self.assertIn("holds results of variant 'slow-nc'", p.stderr)


if __name__ == "__main__":
    main(__file__)
