#!/usr/bin/python3
"""tigris/tools/reproduce.py: the sweep specs of the paper's experiments (full and --quick) and of
the paper's accounting beside them, the driver command lines (local and Slurm), argument errors,
and the run -> figures -> REPORT.md flow with a stand-in driver (so no tigris run is needed),
the paper's accounting's column and counts included.
Run: python3 python/tests/test_reproduce.py"""
import json
import os
import shutil
import tempfile
import textwrap
import unittest

from common import HERE, run_tool, main
from tigris.reports import variants
from tigris.tools import reproduce

# A stand-in for tigris/tools/sweep.py (plot_fixtures.py is copied beside it): expands the spec (grid product, then points, over base) and
# writes sweep.csv of hand-made stats in the driver's layout; `collect DIR` keeps the CSV.
FAKE_DRIVER = textwrap.dedent('''\
    import itertools, json, os, sys
    import plot_fixtures as fx
    if sys.argv[1] == "collect":
        sys.exit(0 if os.path.isfile(os.path.join(sys.argv[2], "sweep.csv")) else 1)
    spec = json.load(open(sys.argv[1]))
    out = sys.argv[sys.argv.index("--out") + 1]
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "argv.json"), "w") as f:
        json.dump(sys.argv[1:], f)
    open(os.path.join(out, "plan.json"), "w").write("{{}}")
    base = dict(spec.get("base", {{}}))
    base.update(base.pop("set", {{}}))
    grid = spec.get("grid", {{}})
    own = [dict(zip(grid, c)) for c in itertools.product(*grid.values())] + spec.get("points", [])
    rows = []
    for o in own:
        s = dict(base, **o)
        h = s.get("height", 10)
        kw = dict(top_height=17 if h == "full" else h, ru=s.get("fe.recursion_units", 64),
                  su=s.get("be.search_units", 32), pe=s.get("be.pes_per_su", 32),
                  policy=s.get("be.issue_policy", "mqsn"))
        kw["cycles"] = 1e5 * 64 / kw["ru"] + 1e3 * abs(kw["top_height"] - 10) + (
            0 if s.get("fe.forwarding", True) else 5e3)
        kw["nodes"] = 60.0 if h == "full" else 60.0 + 2 ** max(0, 17 - kw["top_height"]) / 2
        if kw["policy"] == "mqmn":  # a design variant's DRAM bandwidth speeds MQMN up, and so does
            kw["cycles"] /= (s.get("dram.bytes_per_cycle", 51.2) / 51.2) ** 0.5  # the paper's accounting
            kw["cycles"] /= 2 if s.get("dram.writeback") == "off_critical_path" else 1
        if "approx-thd" in s:
            kw["accuracy"] = {{"exact_match_fraction": 0.5, "mean_extra_distance_m": 0.1,
                               "max_extra_distance_m": 1.0, "recall": 0.9, "precision": 1.0}}
            kw["nodes"] /= 3
        if s.get("dram.bytes_per_cycle") == 7.5:  # a variant whose every point fails
            rows.append({{"settings": s, "stats": None, "status": "error", "error": "refused"}})
            continue
        rows.append({{"settings": s, "stats": fx.fake_stats(**kw)}})
    fx.write_csv(os.path.join(out, "sweep.csv"), rows,
                 base=[k for k in base if k not in ("cloud", "queries", "mode")], sidecar=True)
''').format()


def product_size(spec):
    g = spec.get("grid", {})
    n = 1
    for v in g.values():
        n *= len(v)
    return (n if g else 0) + len(spec.get("points", []))


PAPER_KEYS = {"dram.writeback": "off_critical_path", "energy.charge_result_dram": False,
              "result_buffer.leader_lists": "resident"}


class Specs(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def specs(self, *args):
        out = tempfile.mkdtemp(dir=self.tmp.name)
        self.assertEqual(reproduce.main(["--out", out, "--specs-only"] + list(args)), 0)
        d = os.path.join(out, "specs")
        specs = {}
        for f in sorted(os.listdir(d)):
            with open(os.path.join(d, f)) as fh:
                specs[f[:-5]] = json.load(fh)
        return specs

    def test_full_set(self):
        s = self.specs()
        self.assertEqual(set(s), {"heights-nn", "heights-radius", "units", "optimizations",
                                  "node-cache", "approx-nn", "approx-radius", "redundancy", "registrations",
                                  "odometry-approx"})
        # The headline claims: whole registrations per preset and back-end, odometry exact and approximate.
        self.assertEqual(s["registrations"]["grid"], {"preset": ["dp4", "dp7"],
                                                      "search": ["flann", "exact", "accel", "accel-approx"]})
        self.assertEqual(s["odometry-approx"]["grid"]["search"], ["exact", "approx"])
        # The accuracy cost in the authors' convention too: their leaf sizes, an unbounded leader list.
        self.assertEqual([(p["preset"], p["search"], p["search.rpce_leaf_size"], p["search.normals_leaf_size"])
                          for p in s["odometry-approx"]["points"]], [("dp4", "approx", 32, 64), ("dp7", "approx", 32, 64)])
        # The golden model's redundancy in both conventions, at the heights bracketing leaf-set 32.
        self.assertEqual(s["redundancy"]["command"], "ref")
        self.assertEqual(s["redundancy"]["base"], {"redundancy": True})
        self.assertEqual(sorted({p["height"] for p in s["redundancy"]["points"]}), [11, 12])
        self.assertEqual(product_size(s["units"]), 64)
        self.assertEqual(s["units"]["grid"]["fe.recursion_units"], [16, 32, 64, 128])
        self.assertEqual(s["heights-nn"]["grid"]["height"], ["full"] + list(range(4, 16)))
        self.assertEqual(s["heights-radius"]["base"], {"mode": "radius", "radius": 0.3})
        self.assertEqual(s["optimizations"]["points"][0],
                         {"fe.bypassing": False, "fe.forwarding": False, "be.issue_policy": "mqsn"})
        self.assertEqual(s["optimizations"]["points"][3]["be.issue_policy"], "mqmn")
        self.assertEqual(s["node-cache"]["grid"], {"node_cache.bytes": [131072, 0], "height": [10, "full"]})
        self.assertIn({}, s["approx-nn"]["points"])  # the exact run
        self.assertIn(1.2, s["approx-nn"]["grid"]["approx-thd"])
        self.assertIn(0.12, s["approx-radius"]["grid"]["approx-thd"])  # 0.4 r
        for spec in s.values():
            self.assertNotIn("cloud", spec["base"])
            self.assertTrue(spec["comment"].startswith("tigris/tools/reproduce.py:"))

    def test_paper_accounting_always(self):
        """Without --variants too, every experiment the accounting can change runs under the
        preset paper-accounting (its keys in base.set); the registrations' accelerator points with
        the preset as --accel-config; the golden model's experiments share the default's rows;
        --quick leaves out the RU x SU x PE grids."""
        def accounting(*args):
            out = tempfile.mkdtemp(dir=self.tmp.name)
            self.assertEqual(reproduce.main(["--out", out, "--specs-only"] + list(args)), 0)
            d = os.path.join(out, "variants", "paper-accounting")
            with open(os.path.join(d, "variant.json")) as f:
                self.assertEqual(json.load(f)["set"], PAPER_KEYS)
            specs = {}
            for f in sorted(os.listdir(os.path.join(d, "specs"))):
                with open(os.path.join(d, "specs", f)) as fh:
                    specs[f[:-5]] = json.load(fh)
            return specs
        full = accounting()
        self.assertEqual(set(full), {"heights-nn", "heights-radius", "units", "optimizations", "node-cache",
                                     "approx-nn", "approx-radius", "registrations"})  # not redundancy, odometry
        default = self.specs()
        for name, spec in full.items():
            if name != "registrations":
                self.assertEqual(spec["base"]["set"], PAPER_KEYS, name)
                self.assertEqual(spec.get("grid"), default[name].get("grid"), name)
        preset = os.path.join(variants.shipped_presets(), "paper-accounting.json")   # as the binary lists them
        self.assertEqual(full["registrations"]["points"],
                         [{"preset": p, "search": s, "accel-config": preset}
                          for p in ("dp4", "dp7") for s in ("accel", "accel-approx")])
        self.assertTrue(os.path.isfile(preset))
        quick = accounting("--quick")
        self.assertEqual(set(quick), {"heights-nn", "heights-radius", "optimizations", "node-cache", "approx-nn",
                                      "approx-radius", "registrations"})

    def test_quick_is_smaller(self):
        full = sum(product_size(v) for v in self.specs().values())
        q = self.specs("--quick")
        self.assertIn("units-su", q)
        self.assertIn("units-pe", q)
        self.assertNotIn("units", q)
        quick = sum(product_size(v) for v in q.values())
        self.assertLess(quick, 0.6 * full)
        self.assertIn(11, q["heights-nn"]["grid"]["height"])   # leaf-set 32 is bracketed
        self.assertIn(12, q["heights-radius"]["grid"]["height"])

    def test_workload_paths_are_absolute(self):
        a = os.path.join(self.tmp.name, "a.bin")
        b = os.path.join(self.tmp.name, "b.bin")
        for p in (a, b):
            open(p, "wb").close()
        old = os.getcwd()
        os.chdir(self.tmp.name)
        try:
            s = self.specs("--cloud", "a.bin", "--queries", "b.bin", "--only", "optimizations")
        finally:
            os.chdir(old)
        self.assertEqual(list(s), ["optimizations"])
        self.assertEqual(s["optimizations"]["base"]["cloud"], a)
        self.assertEqual(s["optimizations"]["base"]["queries"], b)

    def test_driver_command(self):
        a = reproduce.parse_args(["--jobs", "3", "--tigris", "/x/tigris"])
        cmd, env = reproduce.driver_command("s.json", "dir", a)
        # -P: the working folder does not go first on sys.path (a tigris.py there would shadow the package)
        self.assertEqual(cmd[1:], ["-P", "-m", "tigris", "sweep", "s.json", "--out", "dir", "--tigris", "/x/tigris",
                                   "--jobs", "3"])
        self.assertEqual(env["PYTHONPATH"].split(os.pathsep)[0],            # python3 -m finds the package
                         os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(reproduce.__file__)))))
        a = reproduce.parse_args(["--slurm", "--partition", "p", "--time", "1:00:00", "--chunk", "4",
                                  "--sbatch-arg", "--qos=low", "--no-wait"])
        cmd, _ = reproduce.driver_command("s.json", "dir", a)
        self.assertEqual(cmd[8:], ["--slurm", "--partition", "p", "--time", "1:00:00", "--chunk", "4",
                                   "--sbatch-arg=--qos=low", "--no-wait"])

    def test_argument_errors(self):
        def err(*args):
            p = run_tool("reproduce", "--specs-only", "--out", os.path.join(self.tmp.name, "e"), *args)
            self.assertEqual(p.returncode, 2, p.stderr)
            return p.stderr
        self.assertIn("need --slurm", err("--partition", "p"))
        self.assertIn("no such file", err("--cloud", "/nonexistent.bin", "--queries", "/nonexistent.bin"))
        self.assertIn("not an experiment of the quick set", err("--quick", "--only", "units"))
        self.assertIn("invalid choice", err("--only", "nonsense"))


class Flow(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.driver = os.path.join(self.tmp.name, "fake_sweep.py")
        with open(self.driver, "w") as f:
            f.write(FAKE_DRIVER)
        shutil.copy(os.path.join(HERE, "plot_fixtures.py"), self.tmp.name)

    def test_run_then_report(self):
        out = os.path.join(self.tmp.name, "out")
        p = run_tool("reproduce", "--quick", "--out", out, "--driver", self.driver, "--jobs", "2")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("claims measured", p.stderr)
        with open(os.path.join(out, "sweeps", "units-su", "argv.json")) as f:
            argv = json.load(f)
        self.assertEqual(argv[-2:], ["--jobs", "2"])
        with open(os.path.join(out, "REPORT.md")) as f:
            text = f.read()
        self.assertIn("(--quick)", text.splitlines()[0])
        self.assertIn("| # | model.md | claim | paper | default machine | verdict | paper's accounting | verdict | "
                      "speed-up: cycles / work / ideal |", text)
        self.assertIn("top height ~10 is best (NN)", text)
        # The paper's accounting ran beside the default (no units grids in --quick), MQMN 2x faster under it.
        self.assertIn("the paper's accounting: 7 sweeps", p.stderr)
        acc = os.path.join(out, "variants", "paper-accounting", "sweeps")
        self.assertEqual(sorted(os.listdir(acc)), ["approx-nn", "approx-radius", "heights-nn", "heights-radius",
                                                   "node-cache", "optimizations", "registrations"])
        mqmn = next(x for x in text.splitlines() if x.startswith("| ") and "MQMN ~2x faster" in x)
        self.assertIn("| 2x | 1.00x | fails | 2.00x | holds | 1.00x (paper's accounting 2.00x) / 1.00x / 1.00x |", mqmn)
        summary = text.split("## Summary: what reproduces", 1)[1].split("## Claims", 1)[0]
        first = summary.strip().splitlines()[0]
        self.assertRegex(first, r"^- \*\*Default machine: \d+ of \d+ hold, \d+ direction only, \d+ fail, \d+ a work "
                                r"ratio, \d+ without a verdict; the paper's accounting \(`paper-accounting`\): \d+ of \d+ hold")
        self.assertIn("MQMN ~2x faster than MQSN (+Forward -> MQMN, speed-up), NN: fails -> holds (2.00x)", summary)
        self.assertRegex(summary, r"\*\*\d+ still fail under the paper's accounting\*\*")
        knee = next(x for x in text.splitlines() if x.startswith("| ") and "knee in RU count" in x)
        self.assertIn("| not measured | not measured |", knee)  # --quick: no units grid under the accounting
        self.assertNotIn("| paper-accounting |", text)          # not a column of the robustness matrix
        try:
            import matplotlib  # noqa: F401
            self.assertIn("![units](figures/units.png)", text)
        except ImportError:
            pass
        # --report-only re-collects and reports without running
        os.remove(os.path.join(out, "REPORT.md"))
        p = run_tool("reproduce", "--quick", "--out", out, "--driver", self.driver, "--report-only")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn(" collect ", p.stderr)
        self.assertTrue(os.path.isfile(os.path.join(out, "REPORT.md")))

    def test_variants_run_then_report(self):
        out = os.path.join(self.tmp.name, "out")
        p = run_tool("reproduce", "--quick", "--out", out, "--driver", self.driver, "--variants", "dram-8x",
                     "every-leaf-w4")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("dram-8x (8 sweeps), every-leaf-w4 (1 sweeps)", p.stderr)
        self.assertTrue(os.path.isfile(os.path.join(out, "variants", "dram-8x", "sweeps", "units-su", "sweep.csv")))
        self.assertEqual(os.listdir(os.path.join(out, "variants", "every-leaf-w4", "sweeps")), ["approx-nn"])
        with open(os.path.join(out, "variants", "dram-8x", "variant.json")) as f:
            self.assertEqual(json.load(f)["set"], {"dram.bytes_per_cycle": 409.6})
        with open(os.path.join(out, "REPORT.md")) as f:
            text = f.read()
        self.assertIn("| # | claim | default | dram-8x | every-leaf-w4 | class |", text)
        mqmn = next(x for x in text.splitlines() if x.startswith("| ") and "MQMN ~2x faster" in x and "· " in x)
        self.assertIn("1.00x · fails | 2.83x · holds | 1.00x · fails | **depends** |", mqmn)  # no gain: not within 2x
        self.assertIn("`dram.bytes_per_cycle`: better as dram.bytes_per_cycle rises", text)
        self.assertIn("![the claims under the design variants](figures/variants.png)", text)
        self.assertTrue(os.path.isfile(os.path.join(out, "figures", "variants.png")))

    def test_a_variant_whose_runs_all_fail_exits_1_after_the_report(self):
        out = os.path.join(self.tmp.name, "out")
        mine = os.path.join(self.tmp.name, "mine.json")
        with open(mine, "w") as f:
            json.dump([{"name": "odd-nc", "set": {"dram.bytes_per_cycle": 7.5}, "experiments": ["units-su"]}], f)
        p = run_tool("reproduce", "--quick", "--out", out, "--driver", self.driver, "--variants", "odd-nc",
                     "--variants-file", mine)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("every run of variant(s) odd-nc failed", p.stderr)
        with open(os.path.join(out, "REPORT.md")) as f:
            self.assertIn("| # | claim | default | odd-nc | class |", f.read())

    def test_missing_driver(self):
        p = run_tool("reproduce", "--out", os.path.join(self.tmp.name, "x"), "--driver",
                     os.path.join(self.tmp.name, "none.py"))
        self.assertEqual(p.returncode, 2)
        self.assertIn("the sweep driver", p.stderr)


if __name__ == "__main__":
    main(__file__)
