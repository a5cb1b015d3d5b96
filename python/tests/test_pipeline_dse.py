#!/usr/bin/python3
"""tigris pipeline-dse and sweeps of registrations: the pipeline's stages as the binary lists
them, the Pareto computation against hand-made points, the sample, bad spaces, a register sweep's
columns, and a tiny design space end to end with a Pareto point's configuration run again through
`tigris register --config`.

    python3 python/tests/test_pipeline_dse.py --tigris build/bin/tigris [--keep]
"""
import json, os, subprocess

from common import (main, LIST_STAGES, LIST_STAGES_OUTPUT, PAPER_STAGES, PAPER_TITLES, Workdir, footer_clear, options,
                    read_csv, run_tool, sweep, tool_command, write_spec)
from tigris import core
from tigris.data import dse_data
from tigris.reports.pipeline import pipeline_section
from tigris.tools import pipeline_dse as dse
from tigris.tools import sweep as ts

A = options()


def test_list_stages():
    """`tigris register --list-stages` of the binary under test is the list the tests build their
    synthetic stage data from (common.LIST_STAGES_OUTPUT), read by the core as the paper's rows.
    Never skipped: a binary without the flag fails here (every tool reading the stages needs it)."""
    p = subprocess.run([A.tigris, "register", "--list-stages"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, f"{A.tigris} register --list-stages: exit {p.returncode}: {p.stderr}"
    assert json.loads(p.stdout) == json.loads(LIST_STAGES_OUTPUT), p.stdout
    stages = core.pipeline_stages(A.tigris)
    assert stages == LIST_STAGES, stages
    assert core.paper_stages(stages) == PAPER_STAGES
    # The sweep's headline: per stage, in the binary's order, as before the list moved to the binary.
    reg = ts.tigris_at(A.tigris, "register").headline
    assert reg[reg.index("kdtree_work.distances_and_neighbors") + 1:] == \
        [f"stages.{s['key']}.{f}" for s in stages for f in ("seconds", "search_seconds", "searches")], reg
    odo = ts.tigris_at(A.tigris, "odometry").headline
    assert odo[-3:] == ["stages.icp.per_pair_mean.seconds", "stages.icp.per_pair_mean.kdtree_search_seconds",
                        "stages.icp.per_pair_mean.searches"], odo


def test_pareto():
    # (time, error): 0 and 3 are the frontier; 1 is dominated by 0 (slower, same error); 2 by 3;
    # 4 equals 3 in both (a duplicate: only the first is on the frontier); 5 ties 0 in time but
    # has a larger error (dominated); 6 is the fastest but worst (on the frontier).
    pts = [(2.0, 0.5), (3.0, 0.5), (9.0, 0.3), (5.0, 0.1), (5.0, 0.1), (2.0, 0.9), (1.0, 2.0)]
    assert dse.pareto(pts) == [6, 0, 3], dse.pareto(pts)
    assert dse.pareto([]) == []
    assert dse.pareto([(1.0, 1.0)]) == [0]
    assert dse.pareto([(1.0, 1.0), (1.0, 1.0), (1.0, 1.0)]) == [0]
    # A strictly better point in one figure and equal in the other dominates.
    assert dse.pareto([(1.0, 1.0), (1.0, 0.5)]) == [1]
    assert dse.pareto([(1.0, 1.0), (0.5, 1.0)]) == [1]
    # Pareto point names: the union of both frontiers by time, F1..Fn (not DPn: the paper's
    # design points and the presets dp4, dp7; not Pn: the sampled points P001..).
    points = [{"seconds_per_pair": t, "rpe_translation_m": e} for t, e in ((3, 1), (1, 5), (2, 2))]
    assert dse.number_dps(points, [[1, 2], [0, 1]]) == {1: "F1", 2: "F2", 0: "F3"}


def test_old_names():
    """A dse.json of an earlier version names its Pareto points DP1..DPn: read as F1..Fn."""
    assert [dse_data.pareto_name(n) for n in ("DP2", "DP14", "F2", "", "dp4", "DP", "P002", None)] == \
        ["F2", "F14", "F2", "", "dp4", "DP", "P002", None]
    assert dse_data.pareto_number("DP10") == 10 and dse_data.pareto_number("F3") == 3
    old = {"dps": [{"dp": "DP1", "point": "P011", "config": "/x/pareto/DP1.json"}, {"dp": "DP2", "point": "P013"}],
           "presets": {"dp4": {"dp": "", "status": "ok"}, "dp7": {"dp": "DP2", "status": "ok"}}, "points": 3}
    new = dse_data.renamed(old)
    assert [d["dp"] for d in new["dps"]] == ["F1", "F2"], new
    assert new["dps"][0]["config"] == "/x/pareto/DP1.json"          # a file's path stays what it is
    assert new["presets"]["dp7"]["dp"] == "F2" and new["presets"]["dp4"]["dp"] == "" and new["points"] == 3
    assert old["dps"][0]["dp"] == "DP1", "the reader's copy is renamed, not the caller's"
    assert dse_data.renamed(new) == new and dse_data.renamed(None) is None


SPACE = [{"key": "a.m", "values": ["x", "y"]},
         {"key": "a.x", "values": [1, 2, 3], "when": {"a.m": "x"}},
         {"key": "b.r", "values": [0.1, 0.2, 0.3, 0.4]}]


def test_sample():
    size, every = dse.space_size(SPACE)
    assert size == (3 + 1) * 4 == len(every), size              # a.x only under a.m = x
    pts, how = dse.sample(SPACE, 6, seed=7)
    assert "Latin" in how and len(pts) == 6
    assert len({json.dumps(p, sort_keys=True) for p in pts}) == 6, "repeats"
    assert all(("a.x" in p) == (p["a.m"] == "x") for p in pts), pts
    assert pts == dse.sample(SPACE, 6, seed=7)[0], "the same seed draws the same points"
    assert pts != dse.sample(SPACE, 6, seed=8)[0]
    # Levels about equally often: the first draw has each of b.r's 4 levels twice in 8 points;
    # repeats (after the conditions) are drawn again, which may move a level by one.
    eight, _ = dse.sample(SPACE, 8, seed=3)
    counts = {v: sum(p["b.r"] == v for p in eight) for v in (0.1, 0.2, 0.3, 0.4)}
    assert len(eight) == 8 and 1 <= min(counts.values()) and max(counts.values()) <= 3, counts
    # Counted without listing: the default space.
    space = dse.load_space(dse.DEFAULT_SPACE)
    assert dse.count_space(space["knobs"]) == 4 * (3 + 2 + 3) * 2 * 3 * 2 * (3 + 3) * 2 * 3 * 2 * 2 * 4 * 2
    # A condition on a boolean is not met by 1.
    flags = [{"key": "a.f", "values": [True, False]}, {"key": "a.n", "values": [1, 2], "when": {"a.f": True}}]
    assert dse.count_space(flags) == 3 and not dse.applies(flags[1], {"a.f": 1})
    full, how = dse.sample(SPACE, 50, seed=1)
    assert len(full) == 16 and how.startswith("full factorial"), how


def hand_made_points(n=6):
    """Design points as read_points makes them, with frontiers and DPs: plot()'s input."""
    points = []
    for k in range(n):
        t, e = 1.0 + k, 0.05 / (1 + k) + 0.002 * (k % 2)
        stages = {title: 0.1 * (j + 1) * t / 3.6 for j, title in enumerate(PAPER_TITLES)}
        points.append({"point": f"P{k + 1:03d}", "valid": True, "status": "ok", "seconds_per_pair": t,
                       "rpe_translation_m": e, "rpe_rotation_deg": 2 * e, "kdtree_share": 0.6, "stages": stages})
    fronts = [dse.pareto([(p["seconds_per_pair"], p[key]) for p in points])
              for key in ("rpe_translation_m", "rpe_rotation_deg")]
    return points, fronts, dse.number_dps(points, fronts)


def test_figures_footer():
    """fig4 and fig5 carry the footer: the command line in DIR/manifest.json and the commit,
    the sample's seed, the space file's SHA-256, below the axes and inside the figure."""
    import hashlib
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from tigris import core
    with Workdir(A, "dse-footer") as d:
        space = write_spec(d, {"knobs": [{"key": "icp.max_iterations", "values": [2, 10]}]}, "space.json")
        out = os.path.join(d, "out")
        argv = ["--space", space, "--samples", "6", "--seed", "5", "--out", out]
        old = os.environ.get("TIGRIS_COMMIT")
        os.environ["TIGRIS_COMMIT"] = "0123456789ab-dirty"
        try:
            folder = core.OutFolder(out, "pipeline-dse", dse.OUTPUTS, argv=argv)
            folder.claim(settings={"synthetic_pairs": 2, "synthetic_seed": 5},
                         inputs=[core.input_identity("space", space)])
            folder.finish(0)
        finally:
            os.environ.pop("TIGRIS_COMMIT") if old is None else os.environ.__setitem__("TIGRIS_COMMIT", old)
        saved = []
        real_save = core.save_figure
        # Checked as saved: inside the figure, under every axes (tick labels included); every text drawn.
        drawn = []

        def all_texts(fig):
            out = [t.get_text() for t in fig.texts]
            for ax in fig.axes:
                out += [t.get_text() for t in ax.texts + ax.get_xticklabels()]
                out += [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else []
            return out
        core.save_figure = lambda fig, path, **kw: (saved.append((os.path.basename(path), footer_clear(fig))),
                                                    drawn.append((os.path.basename(path), all_texts(fig))),
                                                    real_save(fig, path, **kw))
        try:
            points, fronts, dps = hand_made_points()
            footer = core.footer_lines(core.provenance(out, command="pipeline-dse"), details=["6 sampled points, seed 5"])
            dse.plot(out, points, fronts, dps, "synthetic drive (seed 5, 2 pairs)", footer, list(PAPER_TITLES))
        finally:
            core.save_figure = real_save
        assert [s_[0] for s_ in saved] == ["fig4.png", "fig5.png"], saved
        # The Pareto points drawn by their names, F1..Fn: no DPn anywhere in either figure.
        names = sorted(dps.values(), key=dse_data.pareto_number)
        assert names == [f"F{k}" for k in range(1, len(names) + 1)] and len(names) >= 2, names
        assert all(t in drawn[1][1] for t in PAPER_TITLES), drawn[1]    # fig5's legend: every stage
        for name, texts in drawn:
            assert not any("DP" in t for t in texts), (name, [t for t in texts if "DP" in t])
            for n in names:
                assert any(t == n or t.startswith(n + "\n") for t in texts), (name, n, texts)
        sha = hashlib.sha256(open(space, "rb").read()).hexdigest()[:12]
        for name, text in saved:
            assert text and text.startswith("made by tigris pipeline-dse --space"), (name, text)
            for want in ("--samples 6 --seed 5", "commit 0123456789ab-dirty", "6 sampled points, seed 5",
                         "space /", f"space.json (sha256 {sha})", "settings sha256 "):
                assert want in text, (name, want, text)
        plt.close("all")


def test_bad_space():
    with Workdir(A, "dse-space") as d:
        cases = [({"knobs": []}, "knobs: must be a non-empty list"),
                 ({"knobs": [{"key": "normals", "values": [1]}]}, "dotted pipeline key"),
                 ({"knobs": [{"key": "a.b", "values": [1, 1]}]}, "a value is listed twice"),
                 ({"knobs": [{"key": "a.b", "values": [1], "when": {"c.d": 1}}]}, "not an earlier knob"),
                 ({"knobs": [{"key": "a.b", "values": [1]}], "anchors": ["dp9"]}, "anchors"),
                 ({"knobs": [{"key": "a.b", "values": [1]}], "anchors": ["dp4", "dp4"]}, "distinct presets"),
                 ({"knobs": [{"key": "a.b", "values": [1]}, {"key": "a.c", "values": [1], "when": [{"a.b": 1}]}]},
                  "\"when\" must be an object"),
                 ({"knob": []}, "unknown top-level key 'knob'")]
        for k, (space, want) in enumerate(cases):
            path = write_spec(d, space, f"space{k}.json")
            p = run_tool("pipeline-dse", "--space", path, "--tigris", A.tigris, "--out", os.path.join(d, "out"),
                         timeout=60)
            assert p.returncode == 2 and want in p.stderr and path in p.stderr, (space, p.returncode, p.stderr)
        bad = write_spec(d, {"knobs": [{"key": "icp.max_iterations", "values": [0, 5]}], "anchors": []}, "bad.json")
        p = run_tool("pipeline-dse", "--space", bad, "--pairs", "1", "--samples", "2", "--tigris", A.tigris,
                     "--out", os.path.join(d, "out"), timeout=300)
        assert p.returncode == 2 and "out of range" in p.stderr, p.stderr[-2000:]


def test_no_valid_point():
    """Every point fails on a sequence of two tiny random clouds: exit 1, said so, points.csv kept."""
    with Workdir(A, "dse-fail") as d:
        from common import write_cloud
        seq = os.path.join(d, "seq")
        os.makedirs(os.path.join(seq, "velodyne"))
        for i in (0, 1):
            write_cloud(os.path.join(seq, "velodyne", f"{i:06d}.bin"), 60, i + 1)
        with open(os.path.join(seq, "poses.txt"), "w") as f:
            f.write("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n")
        space = write_spec(d, {"anchors": [], "knobs": [{"key": "icp.max_iterations", "values": [2, 10]}]}, "space.json")
        out = os.path.join(d, "out")
        p = run_tool("pipeline-dse", "--space", space, "--samples", "2", "--sequence", seq,
                     "--tigris", A.tigris, "--out", out, timeout=300)
        assert p.returncode == 1 and "no point converged" in p.stderr, (p.returncode, p.stderr[-2000:])
        cols, rows = read_csv(os.path.join(out, "points.csv"))
        assert len(rows) == 2 and all(r["status"] != "ok" for r in rows), rows
        assert not os.path.exists(os.path.join(out, "fig4.png"))
        p = run_tool("pipeline-dse", "--space", space, "--sequence", d, "--tigris", A.tigris, "--out", out,
                     timeout=60)
        assert p.returncode == 2 and "no poses.txt" in p.stderr, p.stderr


def test_register_sweep():
    with Workdir(A, "reg-sweep") as d:
        spec = write_spec(d, {"command": "register", "grid": {"icp.max_iterations": [3, 10]}})
        out = os.path.join(d, "out")
        p = sweep(A, spec, "--out", out, "--jobs", "2", "--tigris", A.tigris, check=0)
        assert "converged" in p.stderr and "error m" in p.stderr, p.stderr
        cols, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert cols[:3] == ["point", "icp.max_iterations", "status"], cols[:5]
        head = ts.tigris_at(A.tigris, "register").headline    # then the headline, the stages' in their order
        assert cols[3:3 + len(head)] == head and cols[3 + len(head)] == "error", cols[:3 + len(head) + 1]
        for c in ("error.translation_m", "seconds", "kdtree_share", "stages.icp.searches", "source", "preset"):
            assert c in cols, c
        assert [r["status"] for r in rows] == ["ok", "ok"]
        # More ICP iterations search more in ICP, the other stages the same.
        assert int(rows[1]["stages.icp.searches"]) > int(rows[0]["stages.icp.searches"])
        assert rows[0]["stages.normals.searches"] == rows[1]["stages.normals.searches"]
        bad = write_spec(d, {"command": "register", "grid": {"icp.max_iteration": [3]}}, "bad.json")
        p = sweep(A, bad, "--check", "--tigris", A.tigris, check=2)
        assert "did you mean 'icp.max_iterations'" in p.stderr and "register --list-config" not in p.stderr, p.stderr
        p = sweep(A, write_spec(d, {"command": "odometry", "grid": {"icp.max_iterations": [0]},
                                    "base": {"sequence": d}}, "bad2.json"), "--check", "--tigris", A.tigris, check=2)
        assert "out of range" in p.stderr, p.stderr
        p = sweep(A, write_spec(d, {"command": "plan"}, "bad3.json"), "--check", "--tigris", A.tigris, check=2)
        assert "not a tigris command a sweep runs" in p.stderr, p.stderr


def test_tiny_dse():
    with Workdir(A, "dse") as d:
        space = write_spec(d, {"base": {"preset": "dp4"}, "anchors": [],
                               "knobs": [{"key": "icp.max_iterations", "values": [2, 10]},
                                         {"key": "icp.error", "values": ["point_to_point", "point_to_plane"]}]},
                           "space.json")
        out = os.path.join(d, "dse")
        cmd, env = tool_command("pipeline-dse", "--space", space, "--samples", "3", "--pairs", "1", "--jobs", "2",
                                "--tigris", A.tigris, "--out", out)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=env)
        assert p.returncode == 0, p.stderr[-3000:]
        cols, rows = read_csv(os.path.join(out, "points.csv"))
        assert [r["point"] for r in rows] == ["P001", "P002", "P003"], rows
        assert all(r["status"] == "ok" and float(r["seconds_per_pair"]) > 0 for r in rows), rows
        summary = json.load(open(os.path.join(out, "dse.json")))
        assert summary["points"] == 3 and "Latin" in summary["sampling"]
        # The stages in the binary's order: dse.json's stage_order, every point's, points.csv's columns.
        order = [title for title, _, _ in core.paper_stages(core.pipeline_stages(A.tigris))]
        assert summary["stage_order"] == order, summary["stage_order"]
        assert all(list(d_["stages"]) == order == list(d_["stage_kdtree_seconds"]) for d_ in summary["dps"])
        assert [c for c in cols if c.endswith(" s")] == [f"{t} s" for t in order], cols
        # The frontier from the CSV's own numbers: every DP undominated, every other point dominated.
        for err, front in (("rpe_translation_m", "on_translation_frontier"), ("rpe_rotation_deg", "on_rotation_frontier")):
            xy = [(float(r["seconds_per_pair"]), float(r[err])) for r in rows]
            on = {rows[i]["point"] for i in dse.pareto(xy)}
            assert on == {r["point"] for r in rows if r[front] == "true"}, (err, on)
        dps = {r["dp"]: r for r in rows if r["dp"]}
        assert set(dps) == {d_["dp"] for d_ in summary["dps"]} and dps, dps
        assert sorted(os.listdir(os.path.join(out, "pareto"))) == sorted(f"{k}.json" for k in dps)
        with open(os.path.join(out, "REPORT.md")) as fh:
            md = fh.read()
        assert "| 1 | §3 | KD-tree search takes 50-85% of the time on every Pareto point |" in md, md
        assert "![error against time](fig4.png)" in md and f"| {summary['dps'][0]['dp']} | " in md, md
        assert [d_["dp"] for d_ in summary["dps"]] == [f"F{k}" for k in range(1, len(dps) + 1)], summary["dps"]
        assert "| Pareto point | design point |" in md and "| F1 | " in md and "| DP1 |" not in md, md
        for f in ("fig4.png", "fig5.png"):
            with open(os.path.join(out, f), "rb") as fh:
                assert fh.read(8) == b"\x89PNG\r\n\x1a\n", f
        # F1's configuration through tigris register --config: the same pipeline, the same transform.
        dp1 = dps["F1"]
        cfg = os.path.join(out, "pareto", "F1.json")
        seq = os.path.join(out, "sequence-1pairs-seed1", "velodyne")
        again = os.path.join(d, "again")
        p = subprocess.run([A.tigris, "register", "--config", cfg, "--source", os.path.join(seq, "000001.bin"),
                            "--target", os.path.join(seq, "000000.bin"), "--out", again],
                           capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stderr
        ran = json.load(open(os.path.join(again, "registration.json")))
        pair = json.load(open(os.path.join(out, "sweep", "points", dp1["sweep_id"], "pairs", "000000",
                                           "registration.json")))
        written = json.load(open(cfg))
        assert {k: v for k, v in ran["config"].items() if k != "inject"} == written
        assert ran["config"] == pair["config"]
        assert ran["transform"] == pair["transform"], (ran["transform"], pair["transform"])
        assert str(written["icp"]["max_iterations"]) == dp1["icp.max_iterations"]
        # A rerun resumes: nothing runs again, the same points.
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
        assert p.returncode == 0 and "3 finished earlier" in p.stderr, p.stderr[-2000:]
        assert read_csv(os.path.join(out, "points.csv"))[1] == rows
        # A folder of an earlier version (DPn names, pareto/DPn.json): its report reads F1..Fn, and
        # a rerun into it replaces the old configuration files.
        with open(os.path.join(out, "dse.json")) as fh:
            old = json.load(fh)
        for d_ in old["dps"]:
            d_["dp"] = "DP" + d_["dp"][1:]
        with open(os.path.join(out, "dse.json"), "w") as fh:
            json.dump(old, fh)
        lines, claims = pipeline_section(dse_data.read_dse(out), out, out, standalone=True)
        md = "\n".join(lines)
        assert "| F1 | " in md and "| DP1 |" not in md, md
        os.rename(cfg, os.path.join(out, "pareto", "DP1.json"))
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
        assert p.returncode == 0, p.stderr[-2000:]
        assert sorted(os.listdir(os.path.join(out, "pareto"))) == sorted(f"{k}.json" for k in dps)


if __name__ == "__main__":
    main(__file__)
