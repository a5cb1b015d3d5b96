"""Test helpers: sweep CSVs made by hand, in the column contract of tigris/tools/sweep.py.

flatten(stats) turns a stats.json into the contract's stats columns (every scalar leaf by its
dotted path, except `config` and lists); write_csv writes them in tigris/tools/sweep.py's layout
(or with every setting first). fake_stats(...) makes a small stats.json-shaped dict whose
figures follow from a few numbers, so tests can state the values they expect; hand_made_csvs
writes one CSV per experiment with such values. This is not a sweep runner: it runs nothing.
"""
import csv
import json
import os


def flatten(stats, prefix="", out=None):
    out = {} if out is None else out
    for k, v in stats.items():
        if not prefix and k == "config":
            continue
        path = prefix + k
        if isinstance(v, dict):
            flatten(v, path + ".", out)
        elif isinstance(v, list):
            continue
        elif isinstance(v, bool):
            out[path] = "true" if v else "false"
        else:
            out[path] = v
    return out


def write_csv(path, rows, layout="driver", base=(), sidecar=False):
    """rows: dicts with `settings` (spec name -> value), `stats` (dict or None) and optional
    `status` / `error`.

    layout "driver" (tigris/tools/sweep.py's): `point`, the swept keys, `status`, `error`,
    `wall_seconds`, then cloud, queries, mode and the `base` keys, then the stats; a stat whose
    path a setting column takes is written `stats.<path>` (`stats.queries`). Unset values are
    written as the driver does for cloud/queries/mode (`synthetic`, `nn`), else empty.
    sidecar: also write sweep.json beside the CSV (its `columns`, `swept_keys`, `base_keys`).
    layout "settings-first": every setting column before `status`, the stats after."""
    base = [b for b in ("cloud", "queries", "mode") if layout == "driver"] + \
        [b for b in base if b not in ("cloud", "queries", "mode")]
    swept = []
    flat = []
    for r in rows:
        for c in r["settings"]:
            if c not in swept and c not in base:
                swept.append(c)
        flat.append(flatten(r["stats"]) if r.get("stats") else {})
    fixed = {"point", "status", "error", "wall_seconds"} | set(swept) | set(base)
    stat_columns = []
    for i, f in enumerate(flat):
        renamed = {}
        for c, v in f.items():
            c = f"stats.{c}" if c in fixed and layout == "driver" else c
            renamed[c] = v
            if c not in stat_columns:
                stat_columns.append(c)
        flat[i] = renamed
    defaults = {"cloud": "synthetic", "queries": "synthetic", "mode": "nn"} if layout == "driver" else {}
    if layout == "driver":
        header = ["point"] + swept + ["status", "error", "wall_seconds"] + base + stat_columns
    else:
        header = ["point"] + swept + base + ["status", "error", "wall_seconds"] + stat_columns
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for i, (r, f) in enumerate(zip(rows, flat)):
            s = dict(r["settings"])
            cells = {"point": f"p{i}", "status": r.get("status", "ok"), "error": r.get("error", ""),
                     "wall_seconds": 1.0}
            for c in swept + base:
                cells[c] = s.get(c, defaults.get(c, ""))
            cells.update(f)
            w.writerow([_cell(cells.get(c, "")) for c in header])
    if sidecar:
        side = os.path.join(os.path.dirname(os.path.abspath(path)), "sweep.json")
        with open(side, "w") as fh:
            json.dump({"columns": header, "swept_keys": swept, "base_keys": base}, fh)
    return path


def _cell(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    return v


def load_stats(path):
    with open(path) as f:
        return json.load(f)


def fake_stats(cycles=100000, energy_pj=4e8, queries=1000, ru=64, su=32, pe=32, policy="mqsn",
               top_height=10, full_height=17, points=115200, nodes=200.0, leaf_fraction=0.9,
               split=None, traffic=None, accuracy=None, ru_busy=0.5, su_busy=0.5,
               ru_stalls=None, su_stalls=None, clock_mhz=500.0, area=(8.38, 7.19), lower_bound=None):
    """A stats.json-shaped dict. nodes: nodes visited per query (split into top and leaf points
    by leaf_fraction; the leaf points are the PE distances); split: energy shares by component
    (sum 1); traffic: bytes by buffer (node_cache: read bytes, no fill); accuracy: the `accuracy`
    block of approximate runs; lower_bound: `lower_bound_cycles`, by default the model's ideal
    machine: max(top nodes / RU, PE distances / (SU x PE))."""
    canonical = top_height == full_height
    split = split or {"pe": 0.5, "ru": 0.02, "sram_read": 0.3, "sram_write": 0.1,
                      "node_cache": 0.03, "leader_buffer": 0.0, "dram": 0.02, "leakage": 0.03}
    traffic = traffic or {"points": 2.5e7, "node_cache": 2.5e7, "queries": 1e7, "query_stack": 2e7,
                          "results": 2e7}
    leaf = 0.0 if canonical else nodes * queries * leaf_fraction
    top = nodes * queries - leaf
    seconds = cycles / (clock_mhz * 1e6)
    s = {
        "command": "run", "cycles": cycles, "seconds": seconds, "queries": queries,
        "verdict": "match",
        "lower_bound_cycles": lower_bound if lower_bound is not None else max(top / ru, leaf / (su * pe)),
        "power_w": energy_pj * 1e-12 / seconds,
        "energy_pj": dict({k: v * energy_pj for k, v in split.items()}, total=energy_pj),
        "area_mm2": {"sram": area[0], "logic": area[1], "total": area[0] + area[1]},
        "tree": {"full_height": full_height, "top_height": top_height, "points": points,
                 "leaves": 2 ** top_height, "nonempty_leaves": 0 if canonical else 2 ** top_height,
                 "leaf_set_mean": 0.0 if canonical else (points - 2 ** top_height + 1) / 2 ** top_height},
        "visits": {"top": top, "leaf_points": leaf, "follower_points": 0, "leader_checks": 0, "pe_distances": leaf,
                   "pruned": top / 2, "per_query": {"nodes": {"mean": nodes}}},
        "units": {
            "recursion_units": {"count": ru, "busy_cycles": ru_busy * ru * cycles,
                                "stall_cycles": dict(ru_stalls or {"sram": 0.1 * ru * cycles}),
                                "utilization": ru_busy},
            "search_units": {"count": su, "pes_per_su": pe, "issue_policy": policy,
                             "busy_cycles": su_busy * su * cycles,
                             "stall_cycles": dict(su_stalls or {"issue_search": 0.01 * su * cycles}),
                             "utilization": su_busy, "pe_utilization": su_busy / 2},
        },
        "buffers": {}, "per_unit_list": [1, 2],
        "config": {"fe": {"recursion_units": ru}},
    }
    # The model's bottleneck summary, reduced to its head (testbench/bottleneck.cpp computes it).
    occ = {k: (u["busy_cycles"] + sum(u["stall_cycles"].values())) / (u["count"] * cycles)
           for k, u in s["units"].items()}
    head = ("front-end (RU) bound" if occ["recursion_units"] >= occ["search_units"]
            else "back-end (SU) bound")
    s["bottleneck"] = {"summary": f"{head}: RUs {100 * occ['recursion_units']:.0f}% occupied; "
                                  f"SUs {100 * occ['search_units']:.0f}% occupied"}
    for b, v in traffic.items():
        if b == "node_cache":
            s["buffers"][b] = {"read_bytes": v, "fill_bytes": 0, "hits": 1, "misses": 1, "policy": "lru"}
        else:
            s["buffers"][b] = {"read_bytes": v / 2, "write_bytes": v / 2}
    s["buffers"]["dram"] = {"write_bytes": 12 * queries, "read_bytes": 0}
    if accuracy:
        s["accuracy"] = dict(accuracy)
        s["leaders"] = {"leaders": 10, "followers": queries - 10, "leader_buffer_full": 0}
    return s


def hand_made_csvs(folder, layout="driver"):
    """One small CSV per experiment, every value chosen by hand (see the comments); returns
    {name: path}. Expected claims (report.py):
      redundancy NN: ratios 1.5 @27, 2.0 @55, 4.0 @112, 8.0 @449 -> about 1.6x at 32: direction
        yes, within 2x of 35 no.
      redundancy radius: 3.0 @27 then 2.5 @112 (falls) -> direction no; about 2.9x at 32: within
        2x of 3 yes.
      bypass: 130000 -> 115000 cycles, +13.0%: yes / yes. forwarding: 115000 -> 100000, +15.0%:
        yes / yes. MQMN: 100000 -> 20000 cycles, 5.00x: yes / no (beyond 2x).
      best height NN: 10 (h8 300000, h10 100000, h11 120000, h12 150000): yes / yes.
      Acc-KD vs Acc-2SKD NN: 150000 / 100000 = 1.50x: yes / no (paper 5.3x).
      Node Cache: Point Buffer 50% of traffic without, 25% with: yes; energy 4.2e8 -> 4.0e8,
        4.8% saved: yes / yes.
      energy split (default row): PE 50% (rank 1), DRAM 2% vs 0.2% -> within 2x no."""
    os.makedirs(folder, exist_ok=True)
    out = {}

    def row(settings, **kw):
        return {"settings": settings, "stats": fake_stats(**kw)}

    # heights, NN: nodes per query; canonical 50
    nn = [row({"height": "full"}, top_height=17, nodes=50.0, cycles=150000, energy_pj=5e8),
          row({"height": 8}, top_height=8, nodes=400.0, cycles=300000, energy_pj=9e8),
          row({"height": 10}, top_height=10, nodes=200.0, cycles=100000, energy_pj=4e8),
          row({"height": 11}, top_height=11, nodes=100.0, cycles=120000, energy_pj=4.5e8),
          row({"height": 12}, top_height=12, nodes=75.0, cycles=150000, energy_pj=5e8)]
    out["heights-nn"] = write_csv(os.path.join(folder, "heights-nn.csv"), nn, layout)
    # heights, radius 0.3 (base columns): canonical 100, h12 300 (3.0x), h10 250 (2.5x)
    rad = [row({"height": "full", "mode": "radius", "radius": 0.3}, top_height=17, nodes=100.0,
               cycles=900000, energy_pj=8e9),
           row({"height": 12, "mode": "radius", "radius": 0.3}, top_height=12, nodes=300.0,
               cycles=800000, energy_pj=8e9),
           row({"height": 10, "mode": "radius", "radius": 0.3}, top_height=10, nodes=250.0,
               cycles=700000, energy_pj=8e9)]
    out["heights-radius"] = write_csv(os.path.join(folder, "heights-radius.csv"), rad, layout,
                                      base=("radius",))
    opt = lambda b, f, p: {"fe.bypassing": b, "fe.forwarding": f, "be.issue_policy": p}  # noqa: E731
    ops = [row(opt(False, False, "mqsn"), cycles=130000, energy_pj=4e8),
           row(opt(True, False, "mqsn"), cycles=115000, energy_pj=4e8),
           row(opt(True, True, "mqsn"), cycles=100000, energy_pj=4e8),
           row(opt(True, True, "mqmn"), policy="mqmn", cycles=20000, energy_pj=4e8)]
    out["optimizations"] = write_csv(os.path.join(folder, "optimizations.csv"), ops, layout)
    with_nc = None  # fake_stats' default: Point Buffer 25% of 1e8 bytes
    no_nc = {"points": 5e7, "node_cache": 0, "queries": 1e7, "query_stack": 2e7, "results": 2e7}
    ncs = [row({"node_cache.bytes": 131072, "height": 10}, traffic=with_nc, energy_pj=4e8),
           row({"node_cache.bytes": 0, "height": 10}, traffic=no_nc, energy_pj=4.2e8),
           row({"node_cache.bytes": 131072, "height": "full"}, top_height=17, traffic=no_nc,
               cycles=150000, energy_pj=5e8),
           row({"node_cache.bytes": 0, "height": "full"}, top_height=17, traffic=no_nc,
               cycles=150000, energy_pj=5e8)]
    out["node-cache"] = write_csv(os.path.join(folder, "node-cache.csv"), ncs, layout)
    units = []
    for ru in (16, 32, 64, 128):
        for su in (16, 32, 64):
            # front-end bound below 64 RU: the back-end barely matters there
            cyc = 400000 * 16 / ru if ru < 64 else 100000 * (32 / su) ** 0.5 * (64 / ru) ** 0.1
            units.append(row({"fe.recursion_units": ru, "be.search_units": su}, ru=ru, su=su,
                             cycles=round(cyc), energy_pj=4e8 * (ru + su) / 96))
    out["units"] = write_csv(os.path.join(folder, "units.csv"), units, layout)
    acc = lambda f, d: {"exact_match_fraction": f, "mean_extra_distance_m": d,  # noqa: E731
                        "max_extra_distance_m": 5 * d, "missing_neighbors": 0}
    apx = [row({}, nodes=200.0),
           row({"approx-thd": 0.6}, nodes=100.0, accuracy=acc(0.3, 0.1)),
           row({"approx-thd": 1.2}, nodes=50.0, cycles=90000, accuracy=acc(0.1, 0.2))]
    out["approx-nn"] = write_csv(os.path.join(folder, "approx-nn.csv"), apx, layout)
    return out
