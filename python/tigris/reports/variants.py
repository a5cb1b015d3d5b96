"""Design variants: details the paper leaves open, and which of its claims survive them.

A variant is a set of configuration keys (and, for approximate NN, a leader result width) that
the paper does not fix, with the reason a real Tigris might have chosen it. The shipped ones are
presets (presets/NAME.json with a "variant" in its "//preset" member; `tigris presets` lists
them), so `tigris run --config NAME` runs the same machine. `tigris reproduce
--variants` runs the claim experiments under each variant beside the default configuration;
this module writes each variant's specs, then turns the per-variant claims of report.py into a
robustness matrix (claim x variant: the measured value and its verdict), a classification per
claim (holds everywhere / depends on a named detail, and in which direction / fails
everywhere, with the default's measured reason) and a figure of the matrix. An accounting (a
preset whose "//preset" has "accounting": `paper-accounting`) is loaded the same way
(accounting()) but is no design variant: reproduce runs it always, REPORT.md's second column.

User variants come from a JSON file (`--variants-file`), a list of objects or {"variants": [...]}:
    {"name": "dram-4x", "set": {"dram.bytes_per_cycle": 204.8},
     "why": "an HBM stack for the results", "experiments": ["heights-radius"]}
`set`: configuration keys (`tigris run --list-config`) applied to every run of the variant; a key
an experiment already sweeps keeps its other values, its value at the model's default becomes the
variant's. `leader_width`: `--leader-width` of the approximate runs (exact runs refuse it; it needs
`"leader.scope": "every_leaf"` in `set`).
`experiments`: the experiments the variant can change (default: all); the others' rows are taken
from the default configuration's sweeps, so list only those you know the keys leave alone.
"""
import itertools
import json
import math
import os
import re

from .. import core
from ..data import binary

NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]{0,62}$")
DEFAULT = "default"
VARIANT_FILE = "variant.json"  # in DIR/variants/<name>/: the definition its results belong to


class VariantError(ValueError):
    """A bad variant definition; the message names the file and the variant."""


class Variant:
    def __init__(self, name, why, set=None, leader_width=None, experiments=None, accel_config=None):
        self.name, self.why = name, why
        self.set = dict(set or {})
        self.leader_width = leader_width
        self.experiments = list(experiments) if experiments is not None else None
        # A preset file the accelerator-in-the-loop points of `register` experiments run with
        # (--accel-config): an accounting's, whose keys apply to the registrations' jobs too.
        self.accel_config = accel_config

    def keys(self):
        """The detail this variant changes: its configuration keys (and leader-width)."""
        return sorted(self.set) + (["leader-width"] if self.leader_width is not None else [])

    def values(self):
        return [self.set[k] for k in sorted(self.set)] + \
            ([self.leader_width] if self.leader_width is not None else [])

    def as_json(self):
        d = {"name": self.name, "why": self.why}
        if self.set:
            d["set"] = self.set
        if self.leader_width is not None:
            d["leader_width"] = self.leader_width
        if self.experiments is not None:
            d["experiments"] = self.experiments
        return d

    def describe(self):
        parts = [f"`{k}={_show(v)}`" for k, v in sorted(self.set.items())]
        if self.leader_width is not None:
            parts.append(f"`--leader-width {self.leader_width}` (approximate runs)")
        return ", ".join(parts)


def _show(v):
    return json.dumps(v) if isinstance(v, (bool, str)) else f"{v:g}" if isinstance(v, float) else str(v)


# The details the paper leaves open (docs/model.md says what the default assumes for each) are
# shipped presets (presets/NAME.json, PREFIX/share/tigris/presets beside this package; `tigris
# presets` lists them): an accelerator configuration whose "//preset" member has a "variant". The
# default column is the model's default configuration: 0 top levels replicated, DRAM 51.2
# bytes/cycle, 128 Point Buffer banks and ports, a 128 KiB Node Cache, leaders checked at a query's
# first leaf (the authors' code), a Leader Check counting leaders still searching (wait).
def shipped_presets():
    """The folder of the shipped presets, as the binary the tools run lists them (`tigris presets
    --json`), in a build tree as in an install."""
    try:
        return binary.tigris_at(binary.default_tigris()).presets_dir
    except binary.SpecError as e:
        raise VariantError(f"the shipped presets: {e}")


def builtin(presets_dir=None):
    """The shipped presets that are design variants, in name order (numbers numerically). The
    files are plain JSON (no comments: this reads them too); `tigris presets` checks every key
    and value, reproduce the experiments they name; a bad one is a VariantError naming it."""
    folder = presets_dir or shipped_presets()
    try:
        names = sorted((f[:-5] for f in os.listdir(folder) if f.endswith(".json")), key=natural)
    except OSError as e:
        raise VariantError(f"the presets folder {folder} cannot be read ({e.strerror}): the variants are "
                           "its files (share/tigris/presets beside the package)")
    out = []
    for name in names:
        path = os.path.join(folder, name + ".json")
        d, meta = _read_preset(path)
        if not isinstance(meta.get("variant"), dict):
            continue
        var = meta["variant"]
        lw, exps = var.get("leader_width"), var.get("experiments")
        if set(var) - {"experiments", "leader_width"} or \
                lw is not None and (not isinstance(lw, int) or isinstance(lw, bool) or lw < 0) or \
                exps is not None and not (isinstance(exps, list) and exps and all(isinstance(e, str) for e in exps)):
            raise VariantError(f"{path}: \"//preset\".\"variant\" takes \"experiments\" (a list of names) and "
                               f"\"leader_width\" (an integer >= 0), got {json.dumps(var)}")
        sets = core.dotted(d)
        # leader.width is the configuration key of --leader-width: on the approximate points only
        # (an exact run has no leaders), as "leader_width" did before it was a key.
        if "leader.width" in sets:
            lw = sets.pop("leader.width")
        out.append(Variant(name, meta.get("why", ""), sets, lw, exps))
    return out


def _read_preset(path):
    """(the preset's JSON, its "//preset" member or {}); a VariantError naming an unreadable file."""
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        raise VariantError(f"{path}: not a readable preset ({e})")
    meta = d.get("//preset") if isinstance(d, dict) else None
    return d, meta if isinstance(meta, dict) else {}


def accounting(name, presets_dir=None):
    """The shipped preset NAME whose "//preset" has an "accounting" (docs/model.md, "Two
    accountings"; `paper-accounting`) as a Variant of every experiment: `tigris reproduce` runs
    it beside the default always, registrations included (its file is their --accel-config). It
    is not a design variant: the robustness matrix is about details the paper leaves open,
    under the default accounting."""
    path = os.path.join(presets_dir or shipped_presets(), name + ".json")
    d, meta = _read_preset(path)
    if not isinstance(meta.get("accounting"), str):
        raise VariantError(f"{path}: not an accounting preset (its \"//preset\" has no \"accounting\")")
    return Variant(name, meta.get("why", ""), core.dotted(d), accel_config=path)


def is_accounting(name):
    try:
        return bool(accounting(name))
    except VariantError:
        return False


def natural(name):
    """A sort key with numbers in numeric order: top-6 before top-10."""
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


def by_name():
    return {v.name: v for v in builtin()}


def check_value(key, v, info):
    """Why `v` cannot be `key`'s value ('' when it can), from `--list-config --json`'s entry."""
    kind = info.get("type") if isinstance(info, dict) else None
    if isinstance(v, float) and not math.isfinite(v):
        return "must be finite"
    if kind == "bool":
        return "" if isinstance(v, bool) else "must be true or false"
    if kind == "enum":
        return "" if v in info.get("values", []) else f"must be one of {', '.join(info.get('values', []))}"
    if kind in ("integer", "bytes", "number"):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or kind != "number" and v != int(v):
            return f"must be {'a number' if kind == 'number' else 'an integer'}"
        lo, hi = info.get("min"), info.get("max")
        if lo is not None and v < lo or hi is not None and v > hi:
            return f"must be in {_show(lo) if lo is not None else '-inf'}..{_show(hi) if hi is not None else 'inf'}"
    return ""


def load(path, known_experiments, key_info, flag_keys=()):
    """User variants from a JSON file; errors name the file and the variant (VariantError).
    key_info: `tigris run --list-config --json`'s entries by key (type, range, values);
    flag_keys: keys the experiments set through a flag (e.g. tree.top_height by --height), which
    a variant may not set too."""
    try:
        data = core.read_json_input(path, "--variants-file")
    except core.Refused as e:
        raise VariantError(f"unreadable --variants-file: {e}")
    if isinstance(data, dict):
        data = data.get("variants")
    if not isinstance(data, list):
        raise VariantError(f"{path}: expected a list of variants or {{\"variants\": [...]}}")
    out = []
    for i, d in enumerate(data):
        where = f"{path}: variants[{i}]"
        if not isinstance(d, dict):
            raise VariantError(f"{where}: must be an object")
        unknown = sorted(set(d) - {"name", "why", "set", "leader_width", "experiments"})
        if unknown:
            raise VariantError(f"{where}: unknown field(s) {', '.join(unknown)} (name, why, set, "
                               "leader_width, experiments)")
        name = d.get("name")
        if not isinstance(name, str) or not NAME_RE.match(name) or name == DEFAULT:
            raise VariantError(f"{where}: \"name\" must be 1-63 letters, digits, '.', '_', '+' or '-' "
                               f"(not \"{DEFAULT}\"), got {json.dumps(name)}")
        if any(v.name == name for v in out):
            raise VariantError(f"{where}: the name {name!r} is taken by an earlier variant of the file")
        where = f"{path}: variant {name!r}"
        s = d.get("set", {})
        if not isinstance(s, dict):
            raise VariantError(f"{where}: \"set\" must be an object {{\"dotted.key\": value}}")
        for k, v in s.items():
            if k not in key_info:
                import difflib
                near = difflib.get_close_matches(k, list(key_info), 1)
                raise VariantError(f"{where}: \"set\": unknown configuration key {k!r}"
                                   + (f" (did you mean {near[0]!r}?)" if near else
                                      " (tigris run --list-config lists them)"))
            if k in flag_keys:
                raise VariantError(f"{where}: \"set\": {k!r} is what the experiments sweep through a "
                                   "flag (e.g. --height): a variant cannot fix it")
            if not isinstance(v, (int, float, str, bool)):
                raise VariantError(f"{where}: \"set\"[{k!r}] must be a number, string or boolean")
            why = check_value(k, v, key_info[k])
            if why:
                raise VariantError(f"{where}: \"set\"[{k!r}] = {json.dumps(v)}: {why} "
                                   "(tigris run --list-config)")
        lw = d.get("leader_width")
        if lw is not None and (not isinstance(lw, int) or isinstance(lw, bool) or not 0 <= lw <= 4096):
            raise VariantError(f"{where}: \"leader_width\" must be an integer 0..4096, got {json.dumps(lw)}")
        if lw is not None and s.get("leader.scope") != "every_leaf":
            raise VariantError(f"{where}: \"leader_width\" is a width of every_leaf's local lists: give "
                               "\"set\": {\"leader.scope\": \"every_leaf\"} too")
        if not s and lw is None:
            raise VariantError(f"{where}: changes nothing (give \"set\" or \"leader_width\")")
        exps = d.get("experiments")
        if exps is not None:
            if not isinstance(exps, list) or not exps or not all(isinstance(e, str) for e in exps):
                raise VariantError(f"{where}: \"experiments\" must be a non-empty list of names")
            bad = [e for e in exps if e not in known_experiments]
            if bad:
                raise VariantError(f"{where}: \"experiments\": not an experiment: {', '.join(bad)} "
                                   f"({', '.join(known_experiments)})")
        why = d.get("why", "")
        if not isinstance(why, str):
            raise VariantError(f"{where}: \"why\" must be text")
        out.append(Variant(name, why or "(user variant)", s, lw, exps))
    return out


def choose(names, user, source="the variants file"):
    """The variants to run: the built-in list and the user's (a user name may not repeat a
    built-in one), all of them or those `names` lists."""
    table = by_name()
    for v in user:
        if v.name in table or is_accounting(v.name):  # its results would share the folder
            raise VariantError(f"{source}: variant {v.name!r} has the name of a built-in variant "
                               "or accounting (tigris reproduce --help lists them): give it another name")
        table[v.name] = v
    if not names:
        return list(table.values())
    bad = [n for n in names if n not in table]
    if any(is_accounting(n) for n in bad):
        raise VariantError(f"--variants: {', '.join(n for n in bad if is_accounting(n))} is an accounting, not a "
                           "design variant: tigris reproduce measures every claim under it always")
    if bad:
        raise VariantError(f"--variants: unknown variant(s) {', '.join(bad)} ({', '.join(table)})")
    return [table[n] for n in dict.fromkeys(names)]


# ---------------------------------------------------------------------------------- the specs

def affects(variant, exp_name, spec):
    """Whether the variant can change this experiment's rows."""
    if variant.experiments is not None and exp_name not in variant.experiments:
        return False
    if spec.get("command", "run") == "register":  # its accelerator points, through --accel-config
        return variant.accel_config is not None and bool(_accel_points(spec))
    if spec.get("command", "run") != "run":  # the golden model alone: no accelerator to vary
        return False
    if not variant.set:  # a leader width only: experiments with approximate runs
        return any("approx-thd" in p for p in _own_points(spec)) or "approx-thd" in spec.get("base", {})
    return True


def _own_points(spec):
    g = spec.get("grid") or {}
    own = [dict(zip(g, c)) for c in itertools.product(*g.values())] if g else []
    return own + list(spec.get("points") or [])


def _accel_points(spec):
    """A `register` spec's points with the accelerator in the loop (search accel, accel-approx)."""
    base = spec.get("base", {}).get("search", "")
    return [p for p in _own_points(spec) if str(p.get("search", base)).startswith("accel")]


def apply(spec, variant, defaults):
    """The experiment's spec under the variant. A key the experiment sweeps or sets keeps its
    values, except that its value at the model's default (`defaults`) becomes the variant's (the
    Node Cache experiment's [default, 0] becomes [variant, 0]); a key it does not name goes into
    base.set. A leader width goes on every point with an approximation threshold, so the grid
    is written out as points. A `register` spec keeps its accelerator points only, each with
    the variant's --accel-config (the others, on the CPU, are the default's)."""
    spec = json.loads(json.dumps(spec))
    if spec.get("command") == "register":
        points = _accel_points(spec)
        spec.pop("grid", None)
        spec["points"] = [dict(p, **{"accel-config": variant.accel_config}) for p in points]
        return spec
    base = spec.setdefault("base", {})
    named = set(base) | set(base.get("set", {})) | set(spec.get("grid") or {}) | \
        {k for p in spec.get("points") or [] for k in p} | \
        {k for p in spec.get("points") or [] for k in p.get("set", {})}

    def swap(k, v):
        return variant.set[k] if k in variant.set and v == defaults.get(k) else v

    for k, v in variant.set.items():
        if k not in named:
            base.setdefault("set", {})[k] = v
    for holder in [base, base.get("set", {})] + list(spec.get("points") or []) + \
            [p.get("set", {}) for p in spec.get("points") or []]:
        for k in list(holder):
            if k in variant.set:
                holder[k] = swap(k, holder[k])
    for k, vals in (spec.get("grid") or {}).items():
        if k in variant.set:
            spec["grid"][k] = list(dict.fromkeys(swap(k, v) for v in vals))
    if variant.leader_width is not None:
        pts = _own_points(spec)
        spec.pop("grid", None)
        approx_base = "approx-thd" in base
        spec["points"] = [dict(p, **{"leader-width": variant.leader_width})
                          if "approx-thd" in p or approx_base else p for p in pts]
    return spec


def overrides(variant, spec_names):
    """evaldata.DEFAULTS overrides under which the variant's rows are 'the default': its keys
    that the report knows by an effective name (node_cache.bytes -> nc_bytes, leader width)."""
    o = {spec_names[k]: v for k, v in variant.set.items() if k in spec_names}
    if variant.leader_width is not None:
        o["leader_width"] = variant.leader_width
    return o


def assumed_columns(variant):
    """Setting columns the rows of the default's sweeps are read with when the variant shares
    them (experiments it leaves alone): its keys at its values."""
    return {k: v if isinstance(v, str) else _show(v) for k, v in variant.set.items()}


# ----------------------------------------------------------------------- matrix, verdicts, classes

HOLDS, DIRECTION_ONLY, SIZE_ONLY, FAILS, WORK_RATIO, NO_TEST, NOT_MEASURED = (
    "holds", "direction only", "size only", "fails", "work ratio", "no test", "not measured")
VERDICTS = [HOLDS, DIRECTION_ONLY, SIZE_ONLY, FAILS, WORK_RATIO, NO_TEST, NOT_MEASURED]  # the legend's order
SCORE = {HOLDS: 3, DIRECTION_ONLY: 2, SIZE_ONLY: 1, FAILS: 0}
# What each verdict means, in the figure's legend and REPORT.md's text alike (render, figure).
MEANING = {HOLDS: "every test the claim has passes",
           DIRECTION_ONLY: "the direction holds, the size is off from the paper's by more than 2x",
           SIZE_ONLY: "within 2x of the paper's number, the direction does not hold",
           FAILS: "every test fails",
           WORK_RATIO: "the paper's speed-up is within 2x of the ratio of work but above the ideal "
                       "machine's ratio: no machine of this size running both searches at its bound reaches it as a speed-up",
           NO_TEST: "measured, but no direction test and no paper number",
           NOT_MEASURED: "no value"}
# A colour of its own per verdict: direction only (a miss in size) is amber, never a shade of
# the holds' green, so no cell reads as a hold that is not one.
COLOURS = {HOLDS: "#1a9850", DIRECTION_ONLY: "#f5a623", SIZE_ONLY: "#9ecae1", FAILS: "#d73027",
           WORK_RATIO: "#762a83", NO_TEST: "#bdbdbd", NOT_MEASURED: "#ffffff"}
COLOUR_NAMES = {HOLDS: "green", DIRECTION_ONLY: "amber", SIZE_ONLY: "light blue", FAILS: "red",
                WORK_RATIO: "purple", NO_TEST: "grey", NOT_MEASURED: "white, hatched"}
TEXT_COLOURS = {HOLDS: "white", FAILS: "white", WORK_RATIO: "white"}  # the cell's value: black on the others


def verdict(claim):
    """One word for a claim's two tests: holds (every test it has passes), direction only, size
    only, fails (every test fails), no test (neither applies), not measured; work ratio before
    them all when the paper's speed-up is a ratio of work no machine of its size reaches
    (report.speed_bound), whatever the cycles measured."""
    if claim is None or claim.measured == "not measured":
        return NOT_MEASURED
    if getattr(claim, "work_ratio", False):
        return WORK_RATIO
    d, w = claim.direction, claim.within
    if d is None and w is None:
        return NO_TEST
    if (d is None or d) and (w is None or w):
        return HOLDS
    if d is not None and w is not None and d != w:
        return DIRECTION_ONLY if d else SIZE_ONLY
    return FAILS


class Column:
    """One configuration's claims: `default` or a variant (None for the default)."""
    def __init__(self, name, variant, claims):
        self.name, self.variant = name, variant
        self.claims = {c.cid: c for c in claims}
        self.order = [c.cid for c in claims]


def _number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def classify(cid, columns, defaults):
    """(class, text) of one claim over the columns (the first is the default). Classes: holds
    everywhere, fails everywhere (the same failing verdict in every measured column; "(direction
    holds)" or "(size within 2x)" when that verdict is direction only or size only), depends
    (the verdict changes: on which detail, at which values, in which direction), one
    configuration only (the others did not measure it), no test, not measured."""
    cells = [(col, verdict(col.claims.get(cid))) for col in columns]
    measured = [(col, v) for col, v in cells if v not in (NOT_MEASURED, NO_TEST)]
    missing = [col.name for col, v in cells if v == NOT_MEASURED]
    tail = f" Not measured under {', '.join(missing)}." if missing and measured else ""
    if not measured:
        if any(v == NO_TEST for _, v in cells):
            return "no test", "measured, but the claim has no direction test and no paper number." + tail
        return "not measured", "not measured under any variant." + tail
    if len(measured) == 1 and len(columns) > 1:
        col, v = measured[0]
        return "one configuration only", (f"{v} at {col.name} ({col.claims[cid].measured}), not measured "
                                          "under any other configuration: no robustness to speak of." + tail)
    vals = [col.claims[cid].measured for col, _ in measured]
    span = vals[0] if len(set(vals)) == 1 else f"{vals[0]} (default) ... " + \
        ", ".join(f"{col.name} {col.claims[cid].measured}" for col, _ in measured[1:])
    kinds = {v for _, v in measured}
    if kinds == {HOLDS}:
        return "holds everywhere", f"holds under all {len(measured)} configurations measured ({span})." + tail
    if len(kinds) == 1:
        v = next(iter(kinds))
        what = {FAILS: "fails", DIRECTION_ONLY: "the direction holds but the size misses",
                SIZE_ONLY: "the size is within 2x but the direction does not hold",
                WORK_RATIO: "the paper's number is a work ratio beyond the ideal machine's"}[v]
        first = measured[0][0]  # the default when it is measured
        cls = "a work ratio everywhere" if v == WORK_RATIO else "fails everywhere" + \
            {FAILS: "", DIRECTION_ONLY: " (direction holds)", SIZE_ONLY: " (size within 2x)"}[v]
        return cls, (f"{what} under all {len(measured)} configurations ({span}). "
                                    f"Measured reason at {'the default' if first is columns[0] else first.name}: "
                                    f"{first.claims[cid].explanation}." + tail)
    return "depends", depends_text(cid, columns, defaults) + tail


def _value(key, v):
    """A detail's value as the report shows it: the default leader width (0) means k."""
    return "k" if key == "leader-width" and v == 0 else _show(v)


def depends_text(cid, columns, defaults):
    """Which details change the verdict: variants grouped by the keys they set, each group's
    verdicts along its values with the default's, and the direction when it is monotone (a
    group of several keys, as banks and ports, has one when its keys rise together)."""
    base = columns[0]
    bv = verdict(base.claims.get(cid))
    groups = {}
    for col in columns[1:]:
        groups.setdefault(tuple(col.variant.keys()), []).append(col)
    parts = []
    for keys, cols in groups.items():
        series = [(tuple(defaults.get(k) for k in keys), base.name, bv, base.claims.get(cid))]
        series += [(tuple(col.variant.values()), col.name, verdict(col.claims.get(cid)), col.claims.get(cid))
                   for col in cols]
        if len({v for _, _, v, _ in series if v not in (NOT_MEASURED, NO_TEST)}) <= 1:
            continue
        nums = [tuple(_number(x) for x in s[0]) for s in series]
        ordered = all(None not in n for n in nums)
        if ordered:
            series = [s for _, s in sorted(zip(nums, series), key=lambda t: t[0])]
            nums = sorted(nums)
            ordered = all(all(a[j] <= b[j] for a, b in zip(nums, nums[1:])) for j in range(len(keys)))
        steps = "; ".join(f"{s[2]} at {'/'.join(_value(k, x) for k, x in zip(keys, s[0]))}"
                          f"{' (default)' if s[1] == base.name else ''} ({s[3].measured if s[3] else '-'})"
                          for s in series)
        direction = ""
        scores = [SCORE.get(s[2]) for s in series]
        name = " + ".join(keys)
        if ordered and None not in scores:
            if all(a <= b for a, b in zip(scores, scores[1:])):
                direction = f": better as {name} {'rise' if len(keys) > 1 else 'rises'}"
            elif all(a >= b for a, b in zip(scores, scores[1:])):
                direction = f": better as {name} {'fall' if len(keys) > 1 else 'falls'}"
            else:
                direction = ": not monotone"
        parts.append(f"`{name}`{direction} ({steps})")
    if not parts:
        return "the verdict changes, but not along any one detail."
    return "depends on " + "; ".join(parts) + "."


def matrix(columns, defaults):
    """Rows [(index, claim at the default (or the first column that has it), [(verdict, value)], class, text)]."""
    order = list(columns[0].order)
    for col in columns[1:]:
        order += [c for c in col.order if c not in order]
    rows = []
    for i, cid in enumerate(order, 1):
        first = next(col.claims[cid] for col in columns if cid in col.claims)
        cells = [(verdict(col.claims.get(cid)), col.claims[cid].measured if cid in col.claims else "-")
                 for col in columns]
        cls, text = classify(cid, columns, defaults)
        rows.append((i, first, cells, cls, text))
    return rows


def _cell(v, value):
    return f"{value} · {v}" if v not in (NOT_MEASURED,) else "not measured"


def render(columns, defaults, figure_rel=None, md_cell=str):
    """The REPORT.md section: the variants, the matrix, the classification."""
    rows = matrix(columns, defaults)
    counts = {}
    for r in rows:
        counts[r[3]] = counts.get(r[3], 0) + 1
    L = ["## Robustness: the claims under design variants", "",
         "Each variant changes details the paper leaves open; every claim experiment ran under "
         "each (rows the variant cannot change are the default's). A cell is the measured value "
         "and its verdict (its colour in the figure): "
         + ", ".join(f"*{k}* ({COLOUR_NAMES[k]}: {MEANING[k]})" for k in VERDICTS) + ".", "",
         "| variant | keys | why it is plausible |", "|---|---|---|",
         f"| {DEFAULT} | the model's defaults | the configuration of the table above |"]
    for col in columns[1:]:
        v = col.variant
        scope = f" (runs only {', '.join(v.experiments)})" if v.experiments else ""
        L.append(f"| {col.name} | {md_cell(v.describe())}{scope} | {md_cell(v.why)} |")
    L += ["", "Classification: " + ", ".join(f"{n} {k}" for k, n in sorted(counts.items(), key=lambda t: -t[1]))
          + f" (of {len(rows)} claims).", ""]
    head = ["#", "claim"] + [c.name for c in columns] + ["class"]
    L += ["| " + " | ".join(head) + " |", "|" + "|".join(["---:"] + ["---"] * (len(head) - 1)) + "|"]
    for i, c, cells, cls, _ in rows:
        L.append("| " + " | ".join([str(i), md_cell(c.text)] + [md_cell(_cell(v, val)) for v, val in cells]
                                   + [f"**{cls}**" if cls == "depends" else cls]) + " |")
    L.append("")
    if figure_rel:
        L += [f"![the claims under the design variants]({figure_rel})", ""]
    L += ["### Per claim", ""]
    for i, c, _, cls, text in rows:
        L.append(f"- #{i} {md_cell(c.text)}: **{cls}**: {md_cell(text)}")
    L.append("")
    return L


def wrap(text, width, lines=2):
    """text in at most `lines` lines of about `width` characters (words kept whole): the width
    grows until it fits, so nothing is cut."""
    import textwrap
    while True:
        out = textwrap.wrap(text, width, break_long_words=False, break_on_hyphens=False) or [""]
        if len(out) <= lines:
            return out
        width += 2


LABEL_CHARS = 64  # a claim's label longer than this goes on two lines of about half its length
VALUE_CHARS = 18  # a cell's value: up to two lines of this many, its parenthesis left out
CELL_W, CELL_H = 1.15, 0.34  # inches


def cell_text(value):
    """A measured value as its cell shows it: the text before a parenthesis (REPORT.md's matrix
    has it whole), on up to two lines, an ellipsis when even those are too short."""
    v = str(value)
    if " (" in v and not v.startswith("("):
        v = v[:v.index(" (")]
    import textwrap
    out = textwrap.wrap(v, VALUE_CHARS, break_long_words=True, break_on_hyphens=False) or [""]
    if len(out) > 2:
        out = [out[0], out[1][:VALUE_CHARS - 1] + "\u2026"]
    return "\n".join(out)


def claim_label(i, claim, cls):
    """The figure's label of claim #i: its whole text on one or two lines ("*" when its verdict
    depends on a variant)."""
    text = f"#{i} {claim.text}" + (" *" if cls == "depends" else "")
    return text if len(text) <= LABEL_CHARS else "\n".join(wrap(text, -(-len(text) // 2) + 4))


def default_footer(columns):
    """The footer of a figure drawn by this process (tigris reproduce, tigris/reports/report.py) from the
    claims it measured: its command line, the commit, the configurations."""
    import sys
    return core.footer_lines(core.provenance(argv=sys.argv),
                             details=[f"{len(columns)} configurations: {', '.join(c.name for c in columns)}"])


def figure(columns, defaults, path, footer=None):
    """The matrix as a picture: claims by configurations, each cell coloured by its verdict
    (COLOURS, with a legend of what each means) and its measured value written in it; every
    claim's label whole (wrapped onto two lines), the figure as wide as its labels need.
    footer: the lines that say what made it (core.footer_lines), default_footer(columns) when
    None, none when empty. Returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch, Rectangle
    rows = matrix(columns, defaults)
    kinds = VERDICTS
    grid = [[kinds.index(v) for v, _ in cells] for _, _, cells, _, _ in rows]
    ncol, nrow = len(columns), len(rows)
    fig, ax = plt.subplots(figsize=(4.5 + CELL_W * ncol, 1.6 + CELL_H * nrow))
    ax.imshow(grid, cmap=ListedColormap([COLOURS[k] for k in kinds]), vmin=-0.5,
              vmax=len(kinds) - 0.5, aspect="auto", interpolation="nearest")
    for y, (_, _, cells, _, _) in enumerate(rows):
        for x, (v, val) in enumerate(cells):
            if v == NOT_MEASURED:  # hatched: a white cell alone would vanish between white lines
                ax.add_patch(Rectangle((x - 0.5, y - 0.5), 1, 1, fill=False, hatch="///", edgecolor="0.55", lw=0))
            ax.text(x, y, cell_text(val) if v != NOT_MEASURED else "-", ha="center", va="center", fontsize=6,
                    linespacing=1.1, color=TEXT_COLOURS.get(v, "black"))
    ax.set_xticks(range(ncol))
    ax.set_xticklabels([c.name for c in columns], rotation=35, ha="right", fontsize=8)
    ax.set_yticks(range(nrow))
    ax.set_yticklabels([claim_label(i, c, cls) for i, c, _, cls, _ in rows], fontsize=6.5, linespacing=1.05)
    ax.set_xticks([x - 0.5 for x in range(1, ncol)], minor=True)
    ax.set_yticks([y - 0.5 for y in range(1, nrow)], minor=True)
    ax.grid(which="minor", color="white", linewidth=1)
    ax.axvline(0.5, color="black", linewidth=1.5)  # the default | the variants
    ax.tick_params(which="minor", length=0)
    legend = ax.legend(handles=[Patch(facecolor=COLOURS[k], hatch="///" if k == NOT_MEASURED else None,
                                      edgecolor="0.55" if k in (NOT_MEASURED, NO_TEST) else COLOURS[k],
                                      label="\n".join(wrap(f"{k}: {MEANING[k]}", 32, lines=4)))
                                for k in kinds],
                       loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=7, title="verdict", title_fontsize=7,
                       labelspacing=0.9)
    ax.set_title("The paper's claims under design variants (* = the verdict depends on a variant)",
                 fontsize=9)
    # The size from what the labels take, measured: the cells keep their size, the labels, the
    # legend and the footer get the room they need (the layout below fits them in it).
    renderer = fig.canvas.get_renderer()
    inch = lambda b, side: (b.width if side else b.height) / fig.dpi  # noqa: E731
    left = max(inch(t.get_window_extent(renderer), 1) for t in ax.get_yticklabels()) + 0.3
    right = inch(legend.get_window_extent(renderer), 1) + 0.3
    below = max(inch(t.get_window_extent(renderer), 0) for t in ax.get_xticklabels()) + 0.25
    lines = default_footer(columns) if footer is None else footer
    foot = 0.45 if lines else 0.0
    width = max(left + CELL_W * ncol + right, inch(ax.title.get_window_extent(renderer), 1) + left + 0.4)
    height = max(0.45 + CELL_H * nrow + below + foot, inch(legend.get_window_extent(renderer), 0) + below + foot + 0.6)
    fig.set_size_inches(width, height)
    if lines:
        core.add_footer(fig, lines)   # lays the figure out above it
    else:
        fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    core.save_figure(fig, path, dpi=110)
    plt.close(fig)
    return path
