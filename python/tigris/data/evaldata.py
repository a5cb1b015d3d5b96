"""Sweep CSVs -> rows with their effective settings (shared by plots.py and report.py).

A `sweep.csv` of tigris/tools/sweep.py (docs/sweeps.md): `point`, the swept keys by their spec
name, `status` (ok|mismatch|error), `error`, `wall_seconds`, the base settings (cloud, queries,
mode, the base's keys), then every scalar leaf of the point's stats.json (except `config` and
lists) by its dotted path; a stat whose path a setting column takes is written `stats.<path>`
(`stats.queries`, the query count). sweep.json beside the CSV names the swept and base keys.
CSVs with every setting before `status` are read too.

Several CSVs may be read together (columns are united). Every row gets `eff`: its effective
settings under short names (mode, radius, k, height, ru, su, pe, policy, bypass, forward,
nc_bytes, approx, cloud, queries, plus any other setting column by its own name). A setting a CSV
does not name (or leaves empty) takes the model's default (DEFAULTS); machine sizes and the issue
policy come from the stats when present (they are what ran). Rows with the same effective
settings are kept once (runs are deterministic).
"""
import collections.abc
import contextlib
import csv
import io
import math
import os
import sys

from typing import Any, Callable, Iterable, Optional

from .. import core
from . import binary

Row = dict[str, Any]  # a CSV row: column -> text, plus `_csv`, `_set` and (ok rows) `eff`
Eff = dict[str, Any]  # a row's effective settings: name -> value (defaults filled in)

# Spec column -> effective name; the model's defaults of these, asked of the tigris binary, are
# DEFAULTS below.
SPEC_NAMES = {
    "mode": "mode", "radius": "radius", "k": "k", "height": "height", "tree.top_height": "height",
    "fe.recursion_units": "ru", "be.search_units": "su", "be.pes_per_su": "pe",
    "be.issue_policy": "policy", "fe.bypassing": "bypass", "fe.forwarding": "forward",
    "node_cache.bytes": "nc_bytes", "approx-thd": "approx", "cloud": "cloud", "queries": "queries",
    "leader-width": "leader_width", "leader.scope": "scope", "leader.in_flight": "in_flight",
}


class _ModelDefaults(collections.abc.Mapping):
    """The model's defaults by effective name, read once from the tigris binary's own lists
    (`tigris run --list-flags` and `--list-config --json`, via tigris sweep), so no copy of them
    lives here. The binary is the one tigris sweep would use ($TIGRIS, or this tree's build)."""
    def __init__(self):
        self._d, self._radius, self._k = None, None, None
        self._over = {}

    @contextlib.contextmanager
    def overridden(self, values):
        """Within the block, `values` (effective name -> value) are the defaults: rows of a
        design variant (tigris/reports/variants.py) whose keys differ from the model's are then its
        'default configuration', so the claims find them."""
        self._load()
        old, self._over = self._over, dict(self._over, **values)
        try:
            yield self
        finally:
            self._over = old

    @property
    def radius(self):  # --radius
        self._load()
        return self._radius

    @property
    def k(self):  # --k
        self._load()
        return self._k

    def _load(self):
        if self._d is None:
            path = binary.default_tigris()
            try:
                run = binary.tigris_at(path, "run")
            except binary.SpecError as e:
                raise RuntimeError(f"the model's defaults come from the tigris binary: {e}") from None
            d = {"cloud": "", "queries": "", "radius": None, "k": None, "approx": None}
            for col, name in SPEC_NAMES.items():
                if "." in col and col in run.config:
                    d[name] = run.config[col]
            d["mode"] = run.flags["mode"]
            d["leader_width"] = int(run.flags["leader-width"])
            d["height"] = parse_height(str(d["height"]))
            self._radius, self._k = float(run.flags["radius"]), int(run.flags["k"])
            self._d = d
        return self._d

    def __getitem__(self, key):
        d = self._load()
        return self._over[key] if key in self._over else d[key]

    def __iter__(self):
        return iter(self._load())

    def __len__(self):
        return len(self._load())


DEFAULTS = _ModelDefaults()


# Columns of the contract that are neither settings nor stats.
META = ("point", "status", "error", "wall_seconds")
# Stats that name what ran (preferred over the spec column).
STAT_SETTINGS = {"ru": "units.recursion_units.count", "su": "units.search_units.count",
                 "pe": "units.search_units.pes_per_su", "policy": "units.search_units.issue_policy"}
CANONICAL = "full"
# Run flags and configuration blocks: how a base column after `wall_seconds` is told from a stat
# when no sweep.json says which columns are settings.
RUN_FLAGS = {"cloud", "queries", "mode", "seed", "k", "radius", "max-nn", "height", "split-axis",
             "approx-thd", "leader-capacity", "leader-width", "config"}
CONFIG_BLOCKS = {"clock_mhz", "tree", "fe", "be", "leader", "node_cache", "sram", "result_buffer",
                 "dram", "stall", "cost", "energy", "area"}


def note(msg: str) -> None:
    print(msg, file=sys.stderr)


def is_empty(v: Any) -> bool:
    return v is None or (isinstance(v, str) and v.strip().lower() in ("", "none", "null", "nan"))


def num(row: Row, col: str) -> Optional[float]:
    """A float from a row's column, None when missing, empty or not a number."""
    v = row.get(col)
    if is_empty(v):
        return None
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return None if math.isnan(f) else f


def parse_bool(v: Any) -> bool:
    s = str(v).strip().lower()
    if s in ("true", "1", "yes", "on"):
        return True
    if s in ("false", "0", "no", "off"):
        return False
    raise ValueError(f"not a boolean: {v!r}")


def parse_height(v: Any) -> int | str:
    s = str(v).strip().lower()
    if s in ("full", "-1", "-1.0"):
        return CANONICAL
    return int(float(s))


def parse_number(v: Any) -> int | float:
    f = float(v)
    return int(f) if f.is_integer() else f


def _approx(v: Any, mode: str, radius: Optional[float]) -> Optional[float]:
    s = str(v).strip().lower()
    if s in ("exact", "false", "off"):
        return None
    if s == "default":  # tigris run: 1.2 m for nn/knn, 0.4 r for radius
        return 0.4 * (radius if radius is not None else DEFAULTS.radius) if mode == "radius" else 1.2
    return float(s)


def setting_positions(path: str, cols: list[str]) -> set[int]:
    """Indexes of a CSV's setting columns: `point` and the swept keys before `status`; the base
    settings (cloud, queries, mode, base keys), which tigris/tools/sweep.py writes after
    `wall_seconds`, named by the sweep.json beside the CSV, or else the columns right after
    `wall_seconds` that look like run flags or configuration keys."""
    st = cols.index("status")
    pos = set(range(st))
    meta = [i for i, c in enumerate(cols) if c in META]
    start = max(meta) + 1 if meta else st + 1
    side = os.path.join(os.path.dirname(os.path.abspath(path)), "sweep.json")
    base = None
    if os.path.lexists(side):
        info = core.read_json_input(side, "the sweep.json beside the CSV")   # damaged: an error naming it
        if isinstance(info, dict) and info.get("columns") == cols:
            base = set(info.get("base_keys") or []) | set(info.get("swept_keys") or [])
    if base is not None:
        return pos | {i for i, c in enumerate(cols) if i >= start and c in base}
    for i in range(start, len(cols)):
        c = cols[i]
        head = c.split(".")[0]
        if c in RUN_FLAGS or ("." in c and head in CONFIG_BLOCKS and head != "tree") or \
                c in ("tree.top_height", "tree.split_axis") and "tree.full_height" not in cols[start:i]:
            pos.add(i)
        else:
            break
    return pos


class Sweep:
    """Rows of one or more sweep CSVs. rows: every row (dicts of strings, plus `_csv`), ok: the
    rows with status ok, deduplicated, each with `eff`; setting_columns: the settings named."""

    def __init__(self, paths: Iterable[str], assume: Optional[dict[str, str]] = None) -> None:
        """assume: setting column -> value for rows whose CSV lacks that column (a design
        variant's keys, on the default's rows of experiments the variant leaves alone)."""
        self.paths = list(paths)
        assume = dict(assume or {})
        self.rows, self.columns, self.setting_columns = [], [], []
        for p in self.paths:
            with io.StringIO(core.read_text_input(p, "a sweep CSV"), newline="") as f:
                r = csv.reader(f)
                cols = next(r, None) or []
                if "status" not in cols:
                    raise ValueError(f"{p}: no `status` column (not a sweep CSV)")
                settings = setting_positions(p, cols)
                for c in assume:
                    if c not in self.setting_columns and c not in cols:
                        self.setting_columns.append(c)
                for i, c in enumerate(cols):
                    if i in settings:
                        if c not in META and c not in self.setting_columns:
                            self.setting_columns.append(c)
                    elif c not in self.columns:
                        self.columns.append(c)
                for line, cells in enumerate(r, 2):
                    if not cells:
                        continue
                    if len(cells) != len(cols):
                        raise ValueError(f"{p}:{line}: {len(cells)} fields, the header has {len(cols)}")
                    row = {c: v for i, (c, v) in enumerate(zip(cols, cells)) if i not in settings}
                    row["_set"] = {c: v for i, (c, v) in enumerate(zip(cols, cells)) if i in settings}
                    for c, v in assume.items():
                        row["_set"].setdefault(c, v)
                    # A stat whose name a setting takes is written `stats.<path>`.
                    for c in list(row):
                        if c.startswith("stats.") and c[6:] not in row:
                            row[c[6:]] = row[c]
                    row["point"] = row["_set"].get("point", "")
                    row["_csv"] = p
                    self.rows.append(row)
        for c in list(self.columns):
            if c.startswith("stats.") and c[6:] not in self.columns:
                self.columns.append(c[6:])
        self.not_ok = [r for r in self.rows if r.get("status", "").strip() != "ok"]
        # Other setting columns are compared raw; one that holds a single value everywhere is
        # part of the base run, not a variation.
        others = [c for c in self.setting_columns if c not in SPEC_NAMES]
        self.varied_others = [c for c in others
                              if len({(r["_set"].get(c) or "").strip() for r in self.rows}) > 1]
        self.ok, seen = [], set()
        for r in self.rows:
            if r.get("status", "").strip() != "ok":
                continue
            try:
                r["eff"] = self.effective(r)
            except ValueError as e:
                note(f"plots: {r['_csv']} point {r.get('point')}: skipped, {e}")
                continue
            key = self.key(r["eff"])
            if key in seen:
                continue
            seen.add(key)
            self.ok.append(r)

    def has_column(self, col: str) -> bool:
        return col in self.columns or col in self.setting_columns

    def effective(self, row: Row) -> Eff:
        eff = dict(DEFAULTS)
        raw = {}
        settings = row["_set"]
        for col, name in SPEC_NAMES.items():
            v = settings.get(col)
            if not is_empty(v):
                raw[name] = v.strip()
        if "mode" in raw:
            eff["mode"] = raw["mode"].lower()
        if eff["mode"] == "radius":
            eff["radius"] = float(raw["radius"]) if "radius" in raw else DEFAULTS.radius
        if eff["mode"] == "knn":
            eff["k"] = int(float(raw["k"])) if "k" in raw else DEFAULTS.k
        if "height" in raw:
            eff["height"] = parse_height(raw["height"])
        for name in ("ru", "su", "pe", "nc_bytes"):
            if name in raw:
                eff[name] = parse_number(raw[name])
        if "policy" in raw:
            eff["policy"] = raw["policy"].lower()
        for name in ("bypass", "forward"):
            if name in raw:
                eff[name] = parse_bool(raw[name])
        if "approx" in raw:
            eff["approx"] = _approx(raw["approx"], eff["mode"], eff["radius"])
        if "leader_width" in raw:  # an approximate run's; exact rows keep the default
            eff["leader_width"] = int(float(raw["leader_width"]))
        for name in ("scope", "in_flight"):
            if name in raw:
                eff[name] = raw[name].strip().lower()
        for name in ("cloud", "queries"):  # tigris/tools/sweep.py writes `synthetic` for the built-in pair
            eff[name] = "" if raw.get(name, "") == "synthetic" else raw.get(name, "")
        for name, col in STAT_SETTINGS.items():
            v = row.get(col)
            if not is_empty(v):
                eff[name] = v.strip().lower() if name == "policy" else parse_number(v)
        if "height" not in raw and num(row, "tree.top_height") is not None:
            eff["height"] = int(num(row, "tree.top_height"))
        # A canonical tree: no leaf sets (the stats say so whatever the spec wrote).
        if num(row, "tree.leaf_set_mean") == 0 and num(row, "tree.nonempty_leaves") == 0:
            eff["height"] = CANONICAL
        for c in self.varied_others:
            eff[c] = (settings.get(c) or "").strip()
        return eff

    @staticmethod
    def key(eff: Eff) -> tuple[tuple[str, str], ...]:
        return tuple(sorted((k, repr(v)) for k, v in eff.items()))

    def workloads(self) -> list[tuple[str, str]]:
        if self.ok:
            return sorted({(r["eff"]["cloud"], r["eff"]["queries"]) for r in self.ok})
        # No ok row (every point failed, or its figures are not numbers): the CSV's own settings.
        raw = lambda r, c: (r["_set"].get(c) or "").strip()  # noqa: E731
        return sorted({("" if raw(r, "cloud") == "synthetic" else raw(r, "cloud"),
                        "" if raw(r, "queries") == "synthetic" else raw(r, "queries")) for r in self.rows})


def workload_text(sw: Sweep) -> str:
    """What a sweep ran on, for figure titles: its workloads and the settings every row shares."""
    names = []
    for cloud, queries in sw.workloads() or [("", "")]:
        if not cloud and not queries:
            names.append("built-in synthetic pair")
        else:
            names.append(f"cloud {os.path.basename(cloud) or 'built-in'}, queries "
                         + (os.path.basename(queries) if queries else "the cloud itself"))
    fixed = []
    for c in sw.setting_columns:
        if c in ("cloud", "queries", "point"):
            continue
        vals = {(r["_set"].get(c) or "").strip() for r in sw.rows}
        if len(vals) == 1 and next(iter(vals)):
            fixed.append(f"{c}={next(iter(vals))}")
    return "; ".join(names) + (" | " + ", ".join(fixed) if fixed else "")


def default_value(name: str, eff: Eff) -> Any:
    """The default of an effective setting, given the row's mode."""
    if name == "radius":
        return DEFAULTS.radius if eff.get("mode") == "radius" else None
    if name == "k":
        return DEFAULTS.k if eff.get("mode") == "knn" else None
    return DEFAULTS.get(name, "")


def n_default(eff: Eff) -> int:
    return sum(1 for k, v in eff.items() if v == default_value(k, eff))


def select(rows: Iterable[Row], axes: Iterable[str],
           where: Optional[Callable[[Eff], bool]] = None) -> tuple[list[Row], str]:
    """The rows that vary only along `axes`: rows are grouped by their other effective settings
    and the largest group wins (ties: the group closer to the defaults). `where(eff)` filters
    first. Returns (rows, note) where note says what was left out."""
    rows = [r for r in rows if where is None or where(r["eff"])]
    groups = {}
    for r in rows:
        other = tuple(sorted((k, repr(v)) for k, v in r["eff"].items() if k not in axes))
        groups.setdefault(other, []).append(r)
    if not groups:
        return [], ""
    best = max(groups.values(), key=lambda g: (len(g), n_default(g[0]["eff"])))
    left = len(rows) - len(best)
    msg = ""
    if left:
        fixed = {k: v for k, v in best[0]["eff"].items() if k not in axes}
        diff = sorted({k for g in groups.values() if g is not best for r in g
                       for k, v in r["eff"].items() if k not in axes and fixed.get(k) != v})
        msg = f"{left} row(s) with other settings ({', '.join(diff)}) left out"
    return best, msg


def find(rows: Iterable[Row], **want: Any) -> Optional[Row]:
    """The row whose effective settings are the defaults except `want` (keys: effective names;
    radius/k follow the mode). Other setting columns must be empty, unless they hold one value
    in all `rows` (a base key of the sweeps; so do cloud and queries). None when absent."""
    rows = list(rows)
    constant = {k for k in (rows[0]["eff"] if rows else {})
                if k not in want and (k not in DEFAULTS or k in ("cloud", "queries"))
                and len({repr(r["eff"].get(k)) for r in rows}) == 1}
    for r in rows:
        eff = r["eff"]
        ok = True
        for k, v in eff.items():
            if k in constant:
                continue
            target = want[k] if k in want else default_value(k, {"mode": want.get("mode", "nn")})
            if k in ("radius", "approx") and v is not None and target is not None:
                if abs(float(v) - float(target)) > 1e-9:
                    ok = False
                    break
            elif v != target:
                ok = False
                break
        if ok:
            return r
    return None


def nodes_per_query(row: Row) -> Optional[float]:
    """Nodes visited per query: top-tree nodes + leaf-set points + follower points + leader
    checks (every distance computation; `visits.per_query.nodes.mean`)."""
    v = num(row, "visits.per_query.nodes.mean")
    if v is not None:
        return v
    q = num(row, "queries")
    parts = [num(row, c) or 0.0 for c in ("visits.top", "visits.leaf_points",
                                          "visits.follower_points", "visits.leader_checks")]
    if not q or num(row, "visits.top") is None:
        return None
    return sum(parts) / q


def buffer_traffic(row: Row, columns: Iterable[str]) -> dict[str, float]:
    """On-chip memory traffic in bytes by buffer: read + write bytes of every `buffers.<b>`
    (the Node Cache: read + fill bytes), DRAM excluded. Buffers found from the column names."""
    out = {}
    for c in columns:
        parts = c.split(".")
        if len(parts) == 3 and parts[0] == "buffers" and parts[1] != "dram" and \
                parts[2] in ("read_bytes", "write_bytes", "fill_bytes"):
            v = num(row, c)
            if v is not None:
                out[parts[1]] = out.get(parts[1], 0.0) + v
    return out


BUFFER_LABELS = {"points": "Point Buffer", "node_cache": "Node Cache", "queries": "Query Buffer",
                 "query_stack": "Query Stack", "results": "Result Buffer",
                 "leader_buffer": "Leader Buffer"}


def search_label(eff: Eff) -> str:
    if eff["mode"] == "radius":
        return f"radius {eff['radius']:.2f} m"
    if eff["mode"] == "knn":
        return f"kNN k={eff['k']}"
    return "NN"


def fmt_bytes(b: float) -> str:
    return f"{b / 1e6:,.1f} MB"


def bound_facts(row: Row) -> str:
    """What bounds a run: the `bottleneck.summary` the model wrote into its stats.json (the one
    classification, testbench/bottleneck.cpp); points of an older tigris lack it."""
    text = row.get("bottleneck.summary")
    return text if isinstance(text, str) and text else "bottleneck not recorded (a run of an older tigris)"
