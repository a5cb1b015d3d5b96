"""Test helpers: sweep CSVs made by hand, in the column contract of tigris_sweep.py.

flatten(stats) turns a stats.json into the contract's stats columns (every scalar leaf by its
dotted path, except `config` and lists); write_csv writes `point`, the setting columns, `status`,
`error`, `wall_seconds`, then the stats columns. fake_stats(...) makes a small stats.json-shaped
dict whose figures follow from a few numbers, so tests can state the values they expect.
This is not a sweep runner: it runs nothing.
"""
import csv
import json


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


def write_csv(path, rows, setting_columns=None):
    """rows: dicts with `settings` (spec name -> value), `stats` (dict or None) and optional
    `status` / `error`. Setting columns in first-seen order unless given."""
    setting_columns = list(setting_columns or [])
    flat = []
    for r in rows:
        for c in r["settings"]:
            if c not in setting_columns:
                setting_columns.append(c)
        flat.append(flatten(r["stats"]) if r.get("stats") else {})
    stat_columns = []
    for f in flat:
        for c in f:
            if c not in stat_columns:
                stat_columns.append(c)
    header = ["point"] + setting_columns + ["status", "error", "wall_seconds"] + stat_columns
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for i, (r, f) in enumerate(zip(rows, flat)):
            s = r["settings"]
            w.writerow([i] + [_cell(s.get(c, "")) for c in setting_columns]
                       + [r.get("status", "ok"), r.get("error", ""), 1.0]
                       + [_cell(f.get(c, "")) for c in stat_columns])
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
               ru_stalls=None, su_stalls=None, clock_mhz=500.0, area=(8.38, 7.19)):
    """A stats.json-shaped dict. nodes: nodes visited per query (split into top and leaf points
    by leaf_fraction); split: energy shares by component (sum 1); traffic: bytes by buffer
    (node_cache: read bytes, no fill); accuracy: the `accuracy` block of approximate runs."""
    canonical = top_height == full_height
    split = split or {"pe": 0.5, "ru": 0.02, "sram_read": 0.3, "sram_write": 0.1,
                      "node_cache": 0.03, "leader_buffer": 0.0, "dram": 0.02, "leakage": 0.03}
    traffic = traffic or {"points": 5e7, "node_cache": 2e7, "queries": 4e6, "query_stack": 2e7,
                          "results": 1e7}
    leaf = 0.0 if canonical else nodes * queries * leaf_fraction
    top = nodes * queries - leaf
    seconds = cycles / (clock_mhz * 1e6)
    s = {
        "command": "run", "cycles": cycles, "seconds": seconds, "queries": queries,
        "verdict": "match", "lower_bound_cycles": cycles / 4,
        "power_w": energy_pj * 1e-12 / seconds,
        "energy_pj": dict({k: v * energy_pj for k, v in split.items()}, total=energy_pj),
        "area_mm2": {"sram": area[0], "logic": area[1], "total": area[0] + area[1]},
        "tree": {"full_height": full_height, "top_height": top_height, "points": points,
                 "leaves": 2 ** top_height, "nonempty_leaves": 0 if canonical else 2 ** top_height,
                 "leaf_set_mean": 0.0 if canonical else (points - 2 ** top_height + 1) / 2 ** top_height},
        "visits": {"top": top, "leaf_points": leaf, "follower_points": 0, "leader_checks": 0,
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
