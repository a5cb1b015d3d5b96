#!/usr/bin/python3
"""tigris_sweep: runs a sweep spec of `tigris run`, `ref`, `register` or `odometry` points
locally or as one Slurm job array, and collects one CSV (docs/sweeps.md).

  python3 -m sweep.tigris_sweep SPEC.json --out DIR [--jobs N] [--tigris PATH] [--check]
                  [--slurm [--partition P] [--time T] [--mem M] [--chunk K]
                           [--sbatch-arg ARG ...] [--no-wait]]
  python3 -m sweep.tigris_sweep collect DIR      re-collect DIR/sweep.csv and DIR/sweep.json

Python 3 standard library only, with the package's core (folders, inputs, child processes);
Slurm tasks run this same module as `_task TASKFILE INDEX`. The folder is held for the run and
recorded in DIR/manifest.json (docs/architecture.md, "The shared core").
Exit codes: 0 every point ok, 1 some point mismatched or failed (the CSV is still written),
2 bad spec, arguments or sweep folder, 3 Slurm submission failed, 128 + the signal when
interrupted (130 SIGINT, 129 SIGHUP, 143 SIGTERM; finished points kept).
"""
import argparse, csv, datetime, difflib, hashlib, io, itertools, json, math, os, re, shlex
import shutil, signal, socket, subprocess, sys, tempfile, time
from decimal import Decimal
from typing import Any, Callable

from . import core

PROG = "tigris_sweep"
TOP_KEYS = ("command", "base", "grid", "points", "comment")
PER_RUN = "per-run output files are not swept"
NOT_SWEEPABLE = {"out": "the sweep gives every point its own --out", "help": "", "list-config": "", "list-flags": "",
                 "json": "", "stats-schema": "",
                 "set": "write configuration keys as dotted keys (or under \"set\" in base/points)",
                 "vcd": PER_RUN, "timeline": PER_RUN, "timeline-queries": PER_RUN,
                 "schedule": "tigris run does not replay", "dump-results": PER_RUN, "dump-schedule": PER_RUN,
                 "record-trace": PER_RUN, "compare": "a point is one registration; sweep \"search\" instead",
                 "accel-set": "set accelerator keys in an --accel-config file",
                 "slurm": "the sweep's own --slurm runs the points", "no-wait": "", "partition": "",
                 "chunk": "", "sbatch-arg": "", "mem": "", "time": ""}


class Command:
    """What a sweep point runs: a tigris sub-command, the file its result is in, and how that
    result reads (ok / mismatch / not_converged)."""
    def __init__(self, name, result, files, folders, fixed, required, config_from, headline, stage_columns=None):
        self.name, self.result, self.files, self.folders = name, result, files, folders
        self.fixed = fixed                       # always a column, so a CSV tells what ran
        self.required = required                 # a flag its --help must list (is it tigris?)
        self.config_from = config_from           # the sub-command whose --list-config has its keys
        self.headline = headline                 # sweep.csv's first columns after status
        # (prefix, fields): headline columns per pipeline stage after those, `{prefix}.{field}`
        # with the stage's key in the prefix, the stages as the binary lists them (Tigris.headline)
        self.stage_columns = stage_columns
        self.paths = files + folders
        # the flag that takes the accelerator's configuration: a file, or a preset's name
        self.preset_flag = "config" if name == "run" else "accel-config" if config_from == "register" else None

    def headline_of(self, stages):
        """The headline with the columns of `stages` (core.pipeline_stages), in their order."""
        if not self.stage_columns:
            return list(self.headline)
        prefix, fields = self.stage_columns
        return list(self.headline) + [f"{prefix.format(key=s['key'])}.{f}" for s in stages for f in fields]

    def status(self, rc, result):
        """(status, message) of a finished process; None: it gave no result (an error)."""
        if not isinstance(result, dict):
            return None
        if self.name == "ref":
            return ("ok", "") if rc == 0 else None
        if self.name == "run":
            verdict = result.get("verdict")
            if rc == 0 and verdict == "match":
                return "ok", ""
            return ("mismatch", "mismatch") if rc in (0, 1) and verdict == "mismatch" else None
        if rc not in (0, 1):
            return None
        if self.name == "register":
            st = result.get("status")
            return ("ok", "") if st == "converged" else ("not_converged", f"registration {st}")
        bad = result.get("not_converged_pairs")
        if not isinstance(bad, int):
            return None
        return ("ok", "") if bad == 0 else ("not_converged", f"{bad} of {result.get('pairs')} pairs not converged")


COMMANDS = {
    "run": Command("run", "stats.json", ("cloud", "queries", "config"), (), ("cloud", "queries", "mode"),
                   "cloud", "run", [
                       "cycles", "seconds", "energy_pj.total", "power_w", "area_mm2.total",
                       "units.recursion_units.utilization", "units.search_units.utilization",
                       "units.search_units.pe_utilization", "bottleneck.bound", "bottleneck.cause",
                       "bottleneck.share", "lower_bound_cycles", "verdict", "accuracy.exact_match_fraction",
                       "accuracy.mean_extra_distance_m", "accuracy.recall", "accuracy.precision",
                       "sampling.sampled", "sampling.simulated", "sampling.relative_half_width"]),
    # The golden model alone (no configuration keys: its flags are its settings).
    "ref": Command("ref", "stats.json", ("cloud", "queries", "schedule"), (), ("cloud", "queries", "mode"),
                   "cloud", None, ["visits.top", "visits.leaf_points", "tree.leaf_set_mean",
                                   "redundancy.model.ratio", "redundancy.authors.ratio"]),
    "register": Command("register", "registration.json",
                        ("source", "target", "config", "ground-truth", "kitti-poses", "accel-config"), (),
                        ("source", "target", "preset", "search"), "source", "register", [
                            "error.translation_m", "error.rotation_deg", "seconds", "kdtree_seconds",
                            "kdtree_share", "kdtree_work.distances_and_neighbors"],
                        ("stages.{key}", ("seconds", "search_seconds", "searches"))),
    "odometry": Command("odometry", "metrics.json", ("config", "accel-config"), ("sequence",),
                        ("sequence", "preset", "search"), "sequence", "register", [
                            "rpe.mean_translation_m", "rpe.mean_rotation_deg", "kitti.t_err_percent",
                            "kitti.r_err_deg_per_m", "ate.rmse_m", "seconds_per_pair", "pairs", "not_converged_pairs",
                            "totals.seconds", "totals.kdtree_search_seconds", "totals.kdtree_share"],
                        ("stages.{key}.per_pair_mean", ("seconds", "kdtree_search_seconds", "searches"))),
}
WALL = "wall_seconds"
# Flags that tigris applies over a configuration key: a spec giving both would run the flag's
# value while the CSV shows the key's, so one spelling only.
PIPELINE_FLAG_KEYS = {"height": "search.top_height", "approx-thd": "search.nn_thd", "inject-kth": "inject.rpce_kth"}
FLAG_KEYS = {"run": {"height": "tree.top_height", "split-axis": "tree.split_axis",
                     "leader-capacity": "leader.capacity_per_leaf"},
             "ref": {}, "register": PIPELINE_FLAG_KEYS, "odometry": PIPELINE_FLAG_KEYS}
MAX_POINTS = 100_000                                 # a spec's points, counted before expanding
MAX_SPEC_BYTES = 16 << 20
# The sweep folder's own entries (its manifest's outputs); `tigris plot DIR` writes DIR/plots.
OUTPUTS = ["plan.json", "points/", "sweep.csv", "sweep.json", "slurm/", "plots/"]
# The sweep's files in a point's folder, which the point's tigris (the folder's owner) leaves alone.
POINT_FILES = ["point.json", "stdout.txt", "stderr.txt"]


class SpecError(core.Refused):
    """A bad spec, argument or sweep folder: printed, exit 2."""


def say(line):
    try:
        print(line, file=sys.stderr, flush=True)
    except OSError:                              # a hung-up terminal must not stop the clean-up
        pass


def die(msg, code=2):
    say(f"{PROG}: error: {msg}")
    sys.exit(code)


def note(msg):
    say(f"{PROG}: {msg}")


write_text, write_json = core.atomic_write, core.write_json


def read_json(path):
    """A JSON object from one of the sweep's own files; None when missing, damaged or not an
    object (a point whose point.json is damaged is run again)."""
    try:
        obj = core.read_json_input(path)
    except core.Refused:
        return None
    return obj if isinstance(obj, dict) else None


def now():
    return datetime.datetime.now().astimezone().isoformat(timespec="milliseconds")


def cli_value(v):
    """A spec value as tigris reads it: booleans true/false, numbers in plain decimal."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        r = repr(v)
        return format(Decimal(r), "f") if "e" in r or "E" in r else r
    return str(v)


def csv_value(v):
    return "" if v is None else cli_value(v)


def typed(text):
    """A default from tigris's help text as a JSON-like value."""
    if text in ("true", "false"):
        return text == "true"
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


# ----------------------------------------------------------------------------------------------
# The tigris binary: its run flags and configuration keys, with their defaults

def is_preset_name(v: str) -> bool:
    """A configuration value naming a preset, as tigris reads it: no '/' and no .json ending."""
    return "/" not in v and not v.endswith(".json")


def default_tigris() -> str:
    """$TIGRIS (the binary that started this tool), else the binary of the prefix or build tree
    this package sits in (PREFIX/share/tigris/sweep -> PREFIX/bin/tigris), else the source
    tree's build/bin/tigris."""
    if os.environ.get("TIGRIS"):
        return os.environ["TIGRIS"]
    beside = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bin", "tigris")
    if os.path.isfile(beside) and os.access(beside, os.X_OK):
        return os.path.normpath(beside)
    repo = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
    return os.path.join(repo, "build", "bin", "tigris")


def tigris_at(path: str, command: str = "run", _seen: dict = {}) -> "Tigris":
    """The Tigris of a binary and sub-command, asked once per process (the spec fuzz test
    validates thousands)."""
    key = (os.path.abspath(path), command)
    if key not in _seen:
        _seen[key] = Tigris(key[0], COMMANDS[command])
    return _seen[key]


class Tigris:
    """A tigris binary's flags and configuration keys for one sub-command, as the binary lists
    them for tools (`tigris COMMAND --list-flags`, `tigris COMMAND --list-config --json`), so the
    sweep never carries a copy of them."""
    def __init__(self, path: str, command: "Command" = COMMANDS["run"]) -> None:
        self.path, self.command = os.path.abspath(path), command
        self._headline = None                    # the headline columns, when first asked (headline)
        if not (os.path.isfile(self.path) and os.access(self.path, os.X_OK)):
            raise SpecError(f"tigris binary not found or not executable: {self.path} "
                            "(give --tigris PATH or set $TIGRIS)")
        self.flags = {}                          # flag -> default (None: no default)
        self.switches = set()                    # flags without a value (`--redundancy`): true or false
        for f in self._ask_json(command.name, "--list-flags").get("flags", []):
            self.flags[f["flag"]] = typed(f["default"]) if f.get("default") not in (None, "") else None
            if f.get("takes_value") is False:
                self.switches.add(f["flag"])
        self.config = {}                         # configuration key -> default
        self.key_info = {}                       # configuration key -> its entry (type, unit, range, doc)
        keys = self._ask_json(command.config_from, "--list-config", "--json").get("keys", []) \
            if command.config_from else []
        for k in keys:
            self.config[k["key"]] = k["default"]
            self.key_info[k["key"]] = k
        if command.required not in self.flags or (command.config_from and not self.config):
            raise SpecError(f"{self.path} does not look like tigris: `tigris {command.name} --list-flags` "
                            "and `--list-config --json` gave no flags or keys")

    @property
    def headline(self) -> list[str]:
        """sweep.csv's headline columns for this command: a registration's per-stage columns
        for the pipeline's stages as this binary lists them (`tigris register --list-stages`,
        core.pipeline_stages), asked when first needed: before a sweep runs its points (a binary
        that cannot list them is refused then, not after the points ran) and by collect."""
        if self._headline is None:
            stages = core.pipeline_stages(self.path) if self.command.stage_columns else []
            self._headline = self.command.headline_of(stages)
        return self._headline

    def preset_file(self, name: str, error: Callable[[str], Exception]) -> str:
        """The file of the binary's preset `name` (`tigris presets --json`); error(msg) when
        there is none."""
        if not hasattr(self, "_presets"):
            self._presets = {p["name"]: p["file"] for p in self._ask_json("presets", "--json").get("presets", [])}
        if name not in self._presets:
            near = difflib.get_close_matches(name, list(self._presets), 1)
            raise error(f"no preset named '{name}'" + (f" (did you mean '{near[0]}'?)" if near else "") +
                        f"; presets: {', '.join(sorted(self._presets))}; a file needs a '/' or a .json name")
        return self._presets[name]

    def _ask_json(self, sub: str, *flags: str) -> Any:
        text = self._ask(sub, *flags)
        try:
            return json.loads(text)
        except ValueError as e:
            raise SpecError(f"{self.path} {sub} {' '.join(flags)} did not print JSON ({e}): is it tigris "
                            "of this source tree?")

    def _ask(self, sub: str, *flags: str) -> str:
        what = " ".join(flags)
        try:
            p = core.capture([self.path, sub, *flags], timeout=60)
        except (OSError, subprocess.TimeoutExpired) as e:
            raise SpecError(f"cannot run {self.path} {sub} {what}: {e}")
        if p.returncode != 0:
            raise SpecError(f"{self.path} {sub} {what} failed (exit {p.returncode}): {p.stderr.strip()}")
        return p.stdout


# ----------------------------------------------------------------------------------------------
# The spec: {"base": {...}, "grid": {key: [values]}, "points": [{...}]}

class Spec:
    """A sweep spec read and checked against the binary: its base, grid and points, each key
    canonical and each value typed as the binary takes it (errors name the spec's location)."""
    def __init__(self, path: str, tigris_path: str) -> None:
        self.given, self.path = path, os.path.abspath(path)
        self.dir = os.path.dirname(self.path)
        self.names = {}                          # canonical key -> spelling in the spec
        self.where = {}                          # canonical key -> spec locations
        raw = core.read_json_input(path, "the spec", MAX_SPEC_BYTES, "a sweep spec is at most "
                                   f"{MAX_SPEC_BYTES >> 20} MiB: split the sweep")
        self.raw = raw
        if not isinstance(raw, dict):
            raise SpecError(f"{path}: the spec must be a JSON object with base, grid, points")
        for k in raw:
            if k not in TOP_KEYS:
                raise SpecError(self._at(k, f"unknown top-level key (allowed: {', '.join(TOP_KEYS)})"))
        command = raw.get("command", "run")
        if command not in COMMANDS:
            raise SpecError(self._at("command", f"{json.dumps(command)[:60]} is not a tigris command a sweep "
                                     f"runs (allowed: {', '.join(COMMANDS)}; default run)"))
        self.command = COMMANDS[command]
        self.tig = tigris_at(tigris_path, command)
        self.kind = f"{command} flag"            # how error messages name a flag
        if not isinstance(raw.get("comment", ""), str):
            raise SpecError(self._at("comment", "must be text"))
        self.base = self._settings(raw.get("base", {}), "base")
        grid = raw.get("grid", {})
        if not isinstance(grid, dict):
            raise SpecError(self._at("grid", "must be an object {key: [values, ...]}"))
        self.grid = {}
        for key, values in grid.items():
            loc = f"grid[\"{key}\"]"
            if key == "set":
                raise SpecError(self._at(loc, "write configuration keys in the grid as dotted keys"))
            canon = self._key(key, loc)
            if not isinstance(values, list):
                raise SpecError(self._at(loc, "must be a list of values"))
            if not values:
                raise SpecError(self._at(loc, "is an empty list: the grid would have no points"))
            if len(values) > MAX_POINTS:
                raise SpecError(self._at(loc, f"has {len(values):,} values, more than a sweep's "
                                         f"{MAX_POINTS:,} points: split the sweep"))
            self.grid[canon] = [self._value(canon, v, f"{loc}[{i}]") for i, v in enumerate(values)]
        points = raw.get("points", [])
        if not isinstance(points, list):
            raise SpecError(self._at("points", "must be a list of objects"))
        if len(points) > MAX_POINTS:
            raise SpecError(self._at("points", f"has {len(points):,} points, more than the limit of "
                                     f"{MAX_POINTS:,}: split the sweep"))
        self.points = [self._settings(p, f"points[{i}]") for i, p in enumerate(points)]
        if "points" in raw and not points and not grid:
            raise SpecError(self._at("points", "is empty and there is no grid: nothing to run"))
        # Counted before the cross product is built: a big grid is refused, not expanded.
        self.count = (math.prod(len(v) for v in self.grid.values()) if self.grid else 0) + len(self.points)
        if self.count > MAX_POINTS:
            shape = " x ".join(str(len(v)) for v in self.grid.values())
            more = f" + {len(self.points):,} points" if self.grid and self.points else ""
            raise SpecError(f"{path}: {self.count:,} points ({f'grid {shape}' if shape else 'points'}{more}), "
                            f"more than the limit of {MAX_POINTS:,}: split the sweep")
        for flag, key in FLAG_KEYS[command].items():
            if flag in self.where and key in self.where:
                raise SpecError(f"{path}: '{self.names[flag]}' ({', '.join(self.where[flag])}) and "
                                f"'{self.names[key]}' ({', '.join(self.where[key])}) set one thing "
                                f"two ways (tigris {command}'s --{flag} overrides {key}, so the CSV would "
                                "show values that did not run): use one spelling")
        self.swept = list(self.grid)             # grid keys, then the points' keys
        for p in self.points:
            self.swept += [k for k in p if k not in self.swept]

    def _at(self, loc, msg):
        loc = loc if len(loc) <= 200 else loc[:200] + "..."
        return f"{self.given}: {loc}: {msg}"

    def _key(self, key, loc):
        """A spec key's canonical name (flag or configuration key); unknown keys are errors."""
        if not isinstance(key, str) or not key:
            raise SpecError(self._at(loc, "empty key"))
        if len(key) > 200:
            raise SpecError(self._at(loc, "unknown key (longer than 200 characters)"))
        flag = key.replace("_", "-")
        if "." not in key and flag in NOT_SWEEPABLE:
            raise SpecError(self._at(loc, f"'{key}' cannot be set in a sweep spec"
                                     + (f": {NOT_SWEEPABLE[flag]}" if NOT_SWEEPABLE[flag] else "")))
        if "." not in key and flag in self.tig.flags:
            canon = flag
        elif key in self.tig.config:
            canon = key
        else:
            kind = "configuration key" if "." in key else self.kind
            listing = f"tigris {self.command.config_from} --list-config"
            pool = list(self.tig.config) if "." in key else [f for f in self.tig.flags if f not in NOT_SWEEPABLE]
            near = difflib.get_close_matches(flag if "." not in key else key, pool, 1, 0.6)
            # A configuration key without its block: recursion_units -> fe.recursion_units.
            blocks = [c for c in self.tig.config if c.split(".")[-1] == key or c.endswith("." + key)]
            if "." not in key and blocks:
                near = blocks[:1] if len(blocks) == 1 else near
                if len(blocks) > 1:
                    raise SpecError(self._at(loc, f"unknown {self.kind} '{key}': configuration keys carry their "
                                             f"block; did you mean one of {', '.join(blocks)}?"))
            hint = f" (did you mean '{near[0]}'?)" if near else (
                f" ({self.kind}s: {', '.join(pool)}; configuration keys are dotted, see "
                f"`{listing}`)" if "." not in key else f" (see `{listing}`)")
            raise SpecError(self._at(loc, f"unknown {kind} '{key}'{hint}"))
        self.names.setdefault(canon, key)
        self.where.setdefault(canon, []).append(loc)
        return canon

    def _value(self, canon, v, loc):
        if isinstance(v, (dict, list)) or v is None:
            got = {dict: "an object", list: "a list", type(None): "null"}[type(v)]
            raise SpecError(self._at(loc, f"'{self.names[canon]}' needs a number, text or boolean, got {got}"))
        if isinstance(v, float) and not math.isfinite(v):
            raise SpecError(self._at(loc, "needs a finite number"))
        if isinstance(v, str):                   # it becomes an argument and a CSV cell
            if len(v) > 4096:
                raise SpecError(self._at(loc, f"'{self.names[canon]}' is longer than 4096 characters"))
            if "\0" in v:
                raise SpecError(self._at(loc, f"'{self.names[canon]}' contains a NUL character"))
            try:
                v.encode("utf-8")
            except UnicodeEncodeError:
                raise SpecError(self._at(loc, f"'{self.names[canon]}' is not valid Unicode text "
                                         "(a lone surrogate escape)"))
        if canon in self.tig.switches and not isinstance(v, bool):
            raise SpecError(self._at(loc, f"{self.kind} '{self.names[canon]}' is a switch: true or false"))
        if canon in self.tig.flags and canon not in self.tig.switches and isinstance(v, bool):
            raise SpecError(self._at(loc, f"{self.kind} '{self.names[canon]}' takes a number or text, not a boolean"))
        if canon in self.command.paths and canon in self.tig.flags:
            what = "folder" if canon in self.command.folders else "file"
            if not isinstance(v, str) or not v.strip():
                raise SpecError(self._at(loc, f"'{self.names[canon]}' needs a {what} name, got {json.dumps(v)}"))
            if canon == self.command.preset_flag and is_preset_name(v):
                # Kept as written (the CSV's cell, the point's name), resolved in args().
                self.tig.preset_file(v, lambda msg: SpecError(self._at(loc, msg)))
                return v
            full = os.path.join(self.dir, v)
            if not (os.path.isdir(full) if what == "folder" else os.path.isfile(full)):
                raise SpecError(self._at(loc, f"no such {what}: {full} (relative paths are relative to "
                                         "the spec's folder)"))
        return v

    def _settings(self, obj, loc):
        if not isinstance(obj, dict):
            raise SpecError(self._at(loc, "must be an object"))
        out = {}
        for key, v in obj.items():
            if key == "set":
                if not isinstance(v, dict):
                    raise SpecError(self._at(f"{loc}.set", "must be an object {\"dotted.key\": value}"))
                for sk, sv in v.items():
                    sloc = f"{loc}.set[\"{sk}\"]"
                    canon = self._key(sk, sloc)
                    if canon not in self.tig.config:
                        raise SpecError(self._at(sloc, f"'{sk}' is a {self.kind}: put it beside \"set\", not in it"))
                    if canon in out:
                        raise SpecError(self._at(sloc, f"'{sk}' is set twice in {loc}"))
                    out[canon] = self._value(canon, sv, sloc)
                continue
            kloc = f"{loc}[\"{key}\"]"
            canon = self._key(key, kloc)
            if canon in out:
                raise SpecError(self._at(kloc, f"'{key}' is set twice in {loc}"))
            out[canon] = self._value(canon, v, kloc)
        return out

    def args(self, params: dict[str, Any]) -> list[str]:
        """tigris arguments of a point: flags, then --set, each sorted (stable for resume)."""
        a = []
        for k in sorted(k for k in params if k in self.tig.flags):
            v = params[k]
            if k in self.tig.switches:
                a += [f"--{k}"] if v else []
                continue
            if k == self.command.preset_flag and is_preset_name(v):
                v = self.tig.preset_file(v, SpecError)
            a += [f"--{k}", os.path.join(self.dir, v) if k in self.command.paths else cli_value(v)]
        for k in sorted(k for k in params if k not in self.tig.flags):
            a += ["--set", f"{k}={cli_value(params[k])}"]
        return a

    def expand(self) -> list[dict[str, Any]]:
        """Every point in a stable order: the grid's cross product (first key outermost), then
        `points`; each over base. A point repeating an earlier one is dropped."""
        own = [dict(zip(self.grid, combo)) for combo in itertools.product(*self.grid.values())] \
            if self.grid else ([] if self.points else [{}])
        own += self.points
        pts, seen, ids = [], set(), {}
        for o in own:
            params = dict(self.base)
            params.update(o)
            if self.command.name == "run" and "queries" in params and "cloud" not in params:
                raise SpecError(f"{self.given}: 'queries' ({', '.join(self.where['queries'])}) without "
                                "'cloud': tigris run refuses --queries without --cloud (a cloud alone "
                                "is searched in itself)")
            args = self.args(params)
            if tuple(args) in seen:
                continue
            seen.add(tuple(args))
            pid = ",".join(f"{k}={_id_value(k, o[k], self.command.preset_flag)}" for k in sorted(o)) or "base"
            pts.append({"id": pid, "own": o, "params": params, "args": args})
            ids.setdefault(pid, []).append(pts[-1])
        for pid, same in ids.items():            # names that sanitise alike or are too long
            if len(same) > 1 or len(pid) > 150:
                for p in same:
                    h = hashlib.sha1(json.dumps(p["args"]).encode()).hexdigest()[:10]
                    p["id"] = f"{pid[:120]}~{h}"
        return pts


def _id_value(key, v, preset_flag=None):
    """A point's name for a value: a path's file name; for the preset flag, a preset's name and a
    file's relative path as written (./top-6: ._top-6), so the two never read alike."""
    if key == preset_flag and not os.path.isabs(v):
        s = v
    else:
        s = os.path.basename(v) if any(key in c.paths for c in COMMANDS.values()) else cli_value(v)
    return re.sub(r"[^A-Za-z0-9._+-]", "_", s) or "_"


# ----------------------------------------------------------------------------------------------
# Child processes: core.pool and core.spawn (own process groups, stopped with the driver)


# ----------------------------------------------------------------------------------------------
# One point: `tigris run ARGS --out DIR/points/<id>`, recorded in point.json

def point_dir(out, pid):
    return os.path.join(out, "points", pid)


def plan_command(plan):
    return COMMANDS.get(plan.get("command", "run"), COMMANDS["run"])


def finished(out, pt, command):
    """A point is finished when its point.json says so (for these arguments) and its result
    (stats.json, registration.json or metrics.json) exists."""
    d = point_dir(out, pt["id"])
    pj = read_json(os.path.join(d, "point.json"))
    return bool(pj and pj.get("finished") and pj.get("args") == pt["args"]
                and os.path.isfile(os.path.join(d, command.result)))


class PointRun:
    def __init__(self, out, tigris, pt, command):
        self.out, self.tigris, self.pt, self.command = out, tigris, pt, command
        self.dir = point_dir(out, pt["id"])
        self.cmd = [tigris, command.name] + pt["args"] + ["--out", self.dir]

    def start(self):
        os.makedirs(self.dir, exist_ok=True)
        for f in ("point.json", self.command.result):
            if os.path.exists(os.path.join(self.dir, f)):
                os.remove(os.path.join(self.dir, f))
        self.started, self.t0 = now(), time.monotonic()
        with open(os.path.join(self.dir, "stdout.txt"), "w") as so, \
                open(os.path.join(self.dir, "stderr.txt"), "w") as se:
            # The point's tigris owns its --out; the sweep's own files there are named to it.
            self.proc = core.spawn(self.cmd, parent_files=POINT_FILES, stdout=so, stderr=se,
                                   stdin=subprocess.DEVNULL, cwd=self.dir)
        return self.proc

    def finish(self, rc):
        wall = time.monotonic() - self.t0
        try:
            with open(os.path.join(self.dir, "stderr.txt"), errors="replace") as f:
                err_lines = [l for l in re.split(r"[\r\n]", f.read()) if l.strip()]
        except OSError:
            err_lines = []
        result = read_json(os.path.join(self.dir, self.command.result))
        got = self.command.status(rc, result)
        picked = [l for l in err_lines if "error" in l.lower() or "DEADLOCK" in l or "mismatch" in l.lower()]
        msg = (picked or err_lines or [""])[-1].strip()
        if got and got[0] == "mismatch":
            status = "mismatch"
            msg = next((l.strip() for l in err_lines if "queries with other results" in l), msg) or "mismatch"
        elif got:
            status, msg = got
        elif rc < 0:
            try:
                sig = signal.Signals(-rc).name
            except ValueError:
                sig = str(-rc)
            status, msg = "error", f"killed by signal {sig}" + (f": {msg}" if msg else "")
        elif rc == 0:
            status, msg = "error", f"exit 0 but no readable {self.command.result} with a result"
        else:
            status, msg = "error", msg or f"exit {rc} and nothing on stderr"
        rec = {"id": self.pt["id"], "params": self.pt["own"], "args": self.pt["args"],
               "command": self.cmd, "command_line": shlex.join(self.cmd), "exit_code": rc,
               "status": status, "error": msg, "stderr_tail": "\n".join(err_lines[-20:])[-4000:],
               "wall_seconds": round(wall, 3), "started_at": self.started, "ended_at": now(),
               "host": socket.gethostname(), "finished": status in ("ok", "mismatch", "not_converged")}
        if os.environ.get("SLURM_JOB_ID"):
            rec["slurm"] = {k: os.environ.get(f"SLURM_{k.upper()}") for k in
                            ("array_job_id", "array_task_id", "job_id")}
        write_json(os.path.join(self.dir, "point.json"), rec)
        return rec


def progress_line(spec_names, pt, rec, k, n):
    shown = " ".join(f"{spec_names.get(key, key)}={cli_value(v)}" for key, v in pt["own"].items()) or pt["id"]
    cmd = rec.get("command") if isinstance(rec.get("command"), list) else []
    ok_word = {"run": "match", "ref": "done"}.get(cmd[1] if len(cmd) > 1 else "run", "converged")
    what = ok_word if rec["status"] == "ok" else f"{rec['status'].upper()}: {rec['error']}"
    return f"[{k}/{n}] {shown} ... {rec['wall_seconds']:.1f} s, {what}"


# ----------------------------------------------------------------------------------------------
# The dry check: every point's flags and keys, before anything runs

def dry_args(tig, args, missing):
    """The arguments that check a point's flags and configuration without running it: tigris
    validates them before it reads the workload, so the point gets an input that does not exist.
    An odometry point is checked as a registration with the flags the two share."""
    name = tig.command.name
    inputs = {"run": ("cloud",), "ref": ("cloud",), "register": ("source", "target"), "odometry": ()}[name]
    if name == "odometry":
        reg = tigris_at(tig.path, "register")
        keep, a, i = (set(reg.flags) - set(NOT_SWEEPABLE)) | {"set"}, [], 0
        while i < len(args):                     # "--flag value" pairs, as Spec.args writes them
            if args[i][2:] in keep:
                a += args[i:i + 2]
            i += 2
        name, inputs = "register", ("source", "target")
    else:
        a = list(args)
    for f in inputs:
        if f"--{f}" in a:
            i = a.index(f"--{f}")
            del a[i:i + 2]
        a += [f"--{f}", missing]
    return [tig.path, name] + a + ["--out", os.path.dirname(missing)]


def dry_check(spec, tig, pts, out, jobs):
    """Every point's flags and configuration, checked by tigris itself (dry_args): the expected
    'no such file' error means all was accepted."""
    missing = os.path.join(out, ".dry-check-no-such-folder", "cloud.bin")
    problems = {}
    n, k, t0, shown = len(pts), [0], time.monotonic(), [time.monotonic()]

    def launch(pt):
        return core.spawn(dry_args(tig, pt["args"], missing), stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL)

    def done(pt, p, rc):
        k[0] += 1
        if time.monotonic() - shown[0] >= 5:     # ~0.1 s a point: a big grid takes minutes
            shown[0] = time.monotonic()
            left = (shown[0] - t0) / k[0] * (n - k[0])
            note(f"dry check: checked {k[0]:,} of {n:,} points (about {left:.0f} s left)")
        err = p.stderr.read().strip()
        if rc == 2 and missing in err or rc in (0, 1):
            return
        lines = [l for l in err.splitlines() if l.strip() and not l.startswith("Run with --help")]
        line = next((l for l in lines if "error" in l), lines[0] if lines else f"exit {rc}")
        problems.setdefault(line, []).append(pt)

    core.pool(pts, jobs, launch, done)
    if problems:
        msgs = []
        for line, bad in problems.items():
            keys = [k for k in bad[0]["params"] if k in line or f"--{k}" in line]
            where = "; ".join(f"'{spec.names[k]}' at {', '.join(spec.where[k])}" for k in keys if k in spec.where)
            msgs.append(f"{spec.given}: point {bad[0]['id']}"
                        + (f" and {len(bad) - 1} more" if len(bad) > 1 else "")
                        + f": tigris rejects it: {line}" + (f" [{where}]" if where else ""))
        raise SpecError("\n".join(msgs))


# ----------------------------------------------------------------------------------------------
# The sweep folder: plan.json (the points), points/<id>/, sweep.csv, sweep.json

def make_plan(spec, tig, pts):
    fixed = spec.command.fixed
    keys = set(spec.swept) | set(spec.base) | set(fixed)
    defaults = {k: (tig.config.get(k) if k in tig.config else tig.flags.get(k)) for k in keys}
    defaults.update({k: "synthetic" for k in ("cloud", "queries", "source", "target") if k in keys})
    base_cols = [k for k in fixed if k not in spec.swept] + \
                [k for k in spec.base if k not in spec.swept and k not in fixed]
    return {"format": 1, "command": spec.command.name, "spec_file": spec.path, "spec": spec.raw, "tigris": tig.path,
            "base_args": spec.args(spec.base), "swept": spec.swept, "base_columns": base_cols,
            "names": {k: spec.names.get(k, k) for k in keys}, "defaults": defaults,
            "config_keys": [k for k in keys if k in tig.config], "points": pts}


def check_folder(out, plan):
    old = read_json(os.path.join(out, "plan.json"))
    if old is None:
        if os.path.isdir(os.path.join(out, "points")) and os.listdir(os.path.join(out, "points")):
            raise SpecError(f"{out} holds point folders but no plan.json: not a sweep folder of this "
                            "driver; use another --out")
        return
    if not os.path.lexists(os.path.join(out, core.MANIFEST)):
        raise SpecError(f"{out} is the folder of a sweep by an earlier tigris (plan.json, no {core.MANIFEST}): "
                        "whether its points read the same inputs cannot be checked; use another --out, or "
                        "remove it to sweep afresh")
    if old.get("command", "run") != plan["command"]:
        raise SpecError(f"{out} holds a sweep of tigris {old.get('command', 'run')} points, this spec runs "
                        f"tigris {plan['command']}: use another --out")
    if old.get("base_args") != plan["base_args"]:
        raise SpecError(f"{out} holds a sweep with another base (there: {shlex.join(old.get('base_args') or [])}; "
                        f"now: {shlex.join(plan['base_args'])}); its results would mix with these. "
                        "Use another --out, or delete that folder")
    if old.get("tigris") != plan["tigris"]:
        note(f"warning: {out} was swept with {old.get('tigris')}; points it finished are kept, "
             f"new ones run with {plan['tigris']}")
    ids = {p["id"] for p in plan["points"]}
    stale = [p["id"] for p in old.get("points", []) if p["id"] not in ids]
    if stale:
        note(f"{len(stale)} point folder(s) of an earlier spec are not in this one and are left out "
             f"of the CSV (e.g. {stale[0]})")


def flatten(obj, prefix=""):
    """Scalar leaves of stats.json as (dotted path, value); lists and `config` left out."""
    for k, v in obj.items():
        path = f"{prefix}{k}"
        if isinstance(v, dict):
            if path != "config":
                yield from flatten(v, path + ".")
        elif not isinstance(v, list):
            yield path, v


def ordered_union(cols, keys):
    """Adds keys missing from cols, each after its predecessor in `keys` (a stable order)."""
    have, prev = set(cols), None
    for k in keys:
        if k not in have:
            cols.insert(cols.index(prev) + 1 if prev is not None else len(cols), k)
            have.add(k)
        prev = k


def param_value(plan, pt, key, stats):
    if key in pt["params"]:
        return pt["params"][key]
    tree = stats.get("tree") if isinstance(stats, dict) else None
    if key == "height" and isinstance(tree, dict) and "top_height" in tree:
        return tree["top_height"]                # the effective height (a small cloud clamps 10)
    if key == "queries" and "cloud" in pt["params"]:
        return pt["params"]["cloud"]             # a cloud alone is searched in itself
    if key in plan["config_keys"] and isinstance(stats, dict):
        node = stats.get("config")
        for part in key.split("."):
            node = node.get(part) if isinstance(node, dict) else None
        if node is not None and not isinstance(node, (dict, list)):
            return node
    return plan["defaults"].get(key)


def odometry_row(d, metrics):
    """An odometry point's figures: metrics.json, the mean seconds per pair, and the pipeline
    configuration its pairs ran (from the first pair's registration.json, for the CSV's keys)."""
    row = dict(metrics)
    totals, pairs = metrics.get("totals"), metrics.get("pairs")
    if isinstance(totals, dict) and isinstance(pairs, int) and pairs > 0 \
            and isinstance(totals.get("seconds"), (int, float)):
        row["seconds_per_pair"] = totals["seconds"] / pairs
    try:
        first = sorted(os.listdir(os.path.join(d, "pairs")))
    except OSError:
        first = []
    for name in first[:1]:
        reg = read_json(os.path.join(d, "pairs", name, "registration.json"))
        if isinstance(reg, dict) and isinstance(reg.get("config"), dict):
            row["config"] = reg["config"]
    return row


def read_plan(out):
    """DIR/plan.json as this driver writes it; a damaged one is an error naming it."""
    plan = read_json(os.path.join(out, "plan.json"))
    if not plan:
        raise SpecError(f"{out}/plan.json is missing or unreadable: not a sweep folder")
    strs = lambda v: isinstance(v, list) and all(isinstance(x, str) for x in v)  # noqa: E731
    names = plan.get("names")
    bad = next((k for k, ok in (
        ("names", isinstance(names, dict) and all(isinstance(v, str) for v in names.values())),
        ("swept", strs(plan.get("swept"))), ("base_columns", strs(plan.get("base_columns"))),
        ("config_keys", strs(plan.get("config_keys"))), ("defaults", isinstance(plan.get("defaults"), dict)),
        ("points", isinstance(plan.get("points"), list))) if not ok), None)
    if bad is None and any(k not in names for k in plan["swept"] + plan["base_columns"]):
        bad = "names"
    if bad is None and not (isinstance(plan.get("command", "run"), str) and plan.get("command", "run") in COMMANDS):
        bad = "command"
    for p in plan.get("points") if bad is None else []:
        if not (isinstance(p, dict) and isinstance(p.get("id"), str) and strs(p.get("args"))
                and isinstance(p.get("params"), dict) and isinstance(p.get("own"), dict)
                and re.fullmatch(r"[A-Za-z0-9._+=,~-]+", p["id"]) and p["id"].strip(".")):
            bad = f"point {json.dumps(p)[:100]}"
            break
    if bad is not None:
        raise SpecError(f"{out}/plan.json is damaged (its {bad} is not what this driver writes); run "
                        "the sweep's command again to rewrite it")
    return plan


def collect_command(out):
    """`collect DIR`: not while a driver sweeps into DIR (it rewrites sweep.csv when it ends)."""
    read_plan(out)
    folder = core.OutFolder(out, "sweep", OUTPUTS)
    folder.attach(legacy="plan.json")
    try:
        return collect(out)
    finally:
        folder.release()


SUMMARY_ROWS = 40
# The summary table's columns after the swept keys and status: (title, column, scale, format).
SUMMARY = {
    "run": [("cycles", "cycles", 1, "{:,.0f}"), ("+-% (sampled)", "sampling.relative_half_width", 100, "{:.2f}"),
            ("time ms", "seconds", 1e3, "{:.3g}"),
            ("energy uJ", "energy_pj.total", 1e-6, "{:.3g}"), ("power W", "power_w", 1, "{:.3g}"),
            ("RU%", "units.recursion_units.utilization", 100, "{:.0f}"),
            ("SU%", "units.search_units.utilization", 100, "{:.0f}"),
            ("PE%", "units.search_units.pe_utilization", 100, "{:.0f}"), ("bound", "bottleneck.bound", None, "")],
    "ref": [("top nodes", "visits.top", None, ""), ("leaf points", "visits.leaf_points", None, ""),
            ("leaf set", "tree.leaf_set_mean", 1, "{:.1f}"), ("redundancy (model)", "redundancy.model.ratio", 1, "{:.2f}"),
            ("redundancy (authors)", "redundancy.authors.ratio", 1, "{:.2f}")],
    "register": [("seconds", "seconds", 1, "{:.3g}"), ("KD-tree %", "kdtree_share", 100, "{:.0f}"),
                 ("error m", "error.translation_m", 1, "{:.3g}"), ("error deg", "error.rotation_deg", 1, "{:.3g}")],
    "odometry": [("s/pair", "seconds_per_pair", 1, "{:.3g}"), ("KD-tree %", "totals.kdtree_share", 100, "{:.0f}"),
                 ("RPE m", "rpe.mean_translation_m", 1, "{:.3g}"), ("RPE deg", "rpe.mean_rotation_deg", 1, "{:.3g}"),
                 ("t_err %", "kitti.t_err_percent", 1, "{:.3g}")],
}


def summary_table(rows, swept, command="run"):
    """The sweep's key columns as an aligned table (the first SUMMARY_ROWS points)."""
    def num(r, c, scale, fmt):
        v = r.get(c)
        if scale is None:
            return str(v or "-")
        return fmt.format(v * scale) if isinstance(v, (int, float)) and not isinstance(v, bool) else "-"
    cols = ["point"] + swept + ["status"] + [t for t, *_ in SUMMARY[command]]
    table = []
    for r in rows[:SUMMARY_ROWS]:
        table.append([str(r.get("point"))] + [csv_value(r.get(k)) for k in swept] + [str(r.get("status"))]
                     + [num(r, c, scale, fmt) for _, c, scale, fmt in SUMMARY[command]])
    width = [max(len(c), *(len(t[i]) for t in table)) if table else len(c) for i, c in enumerate(cols)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(cols, width)).rstrip()]
    lines += ["  ".join(v.ljust(w) for v, w in zip(t, width)).rstrip() for t in table]
    if len(rows) > SUMMARY_ROWS:
        lines.append(f"... {len(rows) - SUMMARY_ROWS} more points in sweep.csv")
    return "\n".join(lines)


def headline(out, plan, command):
    """The headline columns of a sweep's CSV: a registration's per-stage columns from the
    binary that swept it (plan.json's tigris: Tigris.headline)."""
    if not command.stage_columns:
        return command.headline
    tigris = plan.get("tigris")
    try:
        if not isinstance(tigris, str) or not tigris:
            raise SpecError(f"{out}/plan.json names no tigris binary")
        return tigris_at(tigris, command.name).headline
    except core.Refused as e:
        raise SpecError(f"{out}: the headline columns of a sweep of tigris {command.name} are the pipeline's "
                        f"stages as the binary that swept it lists them: {e}")


def collect(out):
    plan = read_plan(out)
    job = read_json(os.path.join(out, "slurm", "job.json")) or {}
    chunks = [c if isinstance(c, list) else [] for c in job.get("chunks")] if isinstance(job.get("chunks"), list) else []
    names, command = plan["names"], plan_command(plan)
    param_cols = [names[k] for k in plan["swept"]] + [names[k] for k in plan["base_columns"]]
    fixed = {"point", "status", "error", WALL} | set(param_cols)
    rows, stat_cols, counts = [], [], {"ok": 0, "mismatch": 0, "not_converged": 0, "error": 0}
    for pt in plan["points"]:
        d = point_dir(out, pt["id"])
        pj = read_json(os.path.join(d, "point.json"))
        if pj and pj.get("args") != pt["args"]:
            pj = None                            # an earlier spec's run of this name
        stats = read_json(os.path.join(d, command.result)) if pj and pj.get("finished") else None
        if pj and pj.get("finished") and not isinstance(stats, dict):
            pj = dict(pj, status="error", error=f"{command.result} missing or unreadable")
        if isinstance(stats, dict) and command.name == "odometry":
            stats = odometry_row(d, stats)
        if pj is None:
            task = next((i for i, c in enumerate(chunks) if pt["id"] in c), None)
            why = (f"no result: Slurm job {job.get('job')} task {task} did not finish it (log "
                   f"{out}/slurm/{job.get('job')}_{task}.out)" if task is not None else "not run (yet)")
            pj = {"status": "error", "error": why, "wall_seconds": None}
        status = pj.get("status") if pj.get("status") in counts and pj.get("finished") else "error"
        row = {"point": pt["id"]}
        for k in plan["swept"]:
            row[names[k]] = param_value(plan, pt, k, stats)
        row.update(status=status, error=pj.get("error", ""), wall_seconds=pj.get("wall_seconds"))
        for k in plan["base_columns"]:
            row[names[k]] = param_value(plan, pt, k, stats)
        keys = []
        for path, v in flatten(stats or {}):
            col = f"stats.{path}" if path in fixed else path
            row[col] = v
            keys.append(col)
        ordered_union(stat_cols, keys)
        counts[status] += 1
        rows.append(row)
    head = [c for c in headline(out, plan, command) if c in stat_cols]
    columns = ["point"] + [names[k] for k in plan["swept"]] + ["status"] + head + ["error", WALL] + \
              [names[k] for k in plan["base_columns"]] + [c for c in stat_cols if c not in head]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for r in rows:
        w.writerow([csv_value(r.get(c)) for c in columns])
    write_text(os.path.join(out, "sweep.csv"), buf.getvalue())
    write_json(os.path.join(out, "sweep.json"),
               {"spec_file": plan.get("spec_file"), "spec": plan.get("spec"), "tigris": plan.get("tigris"),
                "columns": columns, "swept_keys": [names[k] for k in plan["swept"]],
                "base_keys": [names[k] for k in plan["base_columns"]],
                "rows": [{c: r.get(c) for c in columns} for r in rows]})
    say(summary_table(rows, [names[k] for k in plan["swept"]], command.name))
    told = ", ".join(f"{n} {s.replace('_', ' ')}" for s, n in counts.items() if n or s in ("ok", "error"))
    note(f"{len(rows)} points: {told}; {os.path.join(out, 'sweep.csv')}")
    return 0 if counts["ok"] == len(rows) else 1


# ----------------------------------------------------------------------------------------------
# Back-ends

def run_local(plan, todo, out, jobs, names):
    n, k = len(todo), [0]

    def launch(pt):
        r = PointRun(out, plan["tigris"], pt, plan_command(plan))
        runs[pt["id"]] = r
        return r.start()

    def done(pt, p, rc):
        rec = runs.pop(pt["id"]).finish(rc)
        k[0] += 1
        say(progress_line(names, pt, rec, k[0], n))

    runs = {}
    core.pool(todo, jobs, launch, done)


def run_slurm(a, plan, todo, out, names):
    if not shutil.which("sbatch"):
        raise core.SlurmFailed("--slurm: sbatch not found on PATH (is Slurm installed and SLURM_CONF set?)")
    chunks = [[p["id"] for p in todo[i:i + a.chunk]] for i in range(0, len(todo), a.chunk)]
    sdir = os.path.join(out, "slurm")
    os.makedirs(sdir, exist_ok=True)
    stamp = time.strftime("%Y%m%d-%H%M%S") + f"-{os.getpid()}"
    tasks = os.path.join(sdir, f"tasks-{stamp}.json")
    write_json(tasks, {"dir": out, "chunks": chunks})
    script = os.path.join(sdir, f"array-{stamp}.sh")
    # python3 -m sweep.tigris_sweep on the node, the package found by its absolute folder.
    task, env = core.python_module_command("tigris_sweep", ["_task", tasks])
    write_text(script, "#!/bin/sh\n# One task of a tigris_sweep job array: runs its chunk of points.\n"
               f"PYTHONPATH={shlex.quote(env['PYTHONPATH'])}\nexport PYTHONPATH\n"
               f"exec {shlex.join(task)} \"$SLURM_ARRAY_TASK_ID\"\n")
    os.chmod(script, 0o755)
    cmd = ["sbatch", "--parsable", f"--array=0-{len(chunks) - 1}", "--job-name=tigris-sweep",
           f"--output={sdir}/%A_%a.out", f"--chdir={out}"]
    for opt in ("partition", "time", "mem"):
        if getattr(a, opt):
            cmd.append(f"--{opt}={getattr(a, opt)}")
    cmd += (a.sbatch_arg or []) + [script]
    job = core.sbatch(cmd)
    write_json(os.path.join(sdir, "job.json"), {"job": job, "tasks": tasks, "chunks": chunks,
                                                 "command": cmd, "submitted_at": now()})
    note(f"submitted Slurm job array {job}: {len(chunks)} task(s) for {len(todo)} point(s); "
         f"logs {sdir}/{job}_<task>.out")
    if a.no_wait:
        print(f"job {job}\ncollect when it has finished: {collect_command_line(out)}")
        return False
    left, k, misses = {p["id"]: p for p in todo}, 0, 0
    try:
        while left:
            active = core.squeue_active(job)          # asked before the scan: no point is missed
            for pid in list(left):
                rec = read_json(os.path.join(point_dir(out, pid), "point.json"))
                if rec and rec.get("args") == left[pid]["args"]:
                    k += 1
                    say(progress_line(names, left.pop(pid), rec, k, len(todo)))
            if active == []:
                break
            misses = misses + 1 if active is None else 0
            if misses > 30:
                die(f"squeue cannot report job {job}; collect later with: {PROG} collect {out}", 3)
            time.sleep(1.0)
    except KeyboardInterrupt:
        core.scancel(job)
        note(f"interrupted: cancelled Slurm job {job}; finished points are kept")
        raise
    if left:
        note(f"Slurm job {job} ended with {len(left)} point(s) unfinished (see {sdir}/{job}_*.out)")
    return True


def collect_command_line(out):
    """The command that collects `out` again: `tigris sweep collect DIR` when the binary ran this
    ($TIGRIS), else this module with the package on PYTHONPATH."""
    if os.environ.get("TIGRIS"):
        return f"{shlex.quote(os.environ['TIGRIS'])} sweep collect {shlex.quote(out)}"
    cmd, env = core.python_module_command("tigris_sweep", ["collect", out])
    return f"PYTHONPATH={shlex.quote(env['PYTHONPATH'])} {shlex.join(cmd)}"


def run_task(tasks_file, index):
    """A Slurm array task: its chunk of points, run exactly as the local back-end runs them."""
    t = read_json(tasks_file)
    plan = read_json(os.path.join(t["dir"], "plan.json")) if t else None
    if not plan:
        die(f"_task: cannot read {tasks_file} or its plan.json")
    by_id = {p["id"]: p for p in plan["points"]}
    chunk = t["chunks"][int(index)]
    for k, pid in enumerate(chunk, 1):
        pt = by_id[pid]
        if finished(t["dir"], pt, plan_command(plan)):
            print(f"[{k}/{len(chunk)}] {pid}: finished earlier, skipped", flush=True)
            continue
        r = PointRun(t["dir"], plan["tigris"], pt, plan_command(plan))
        proc = r.start()
        try:
            rc = core.wait(proc)
        except KeyboardInterrupt as e:
            core.stop_groups([proc])
            sys.exit(core.exit_status(e))
        print(progress_line(plan["names"], pt, r.finish(rc), k, len(chunk)), flush=True)
    return 0


# ----------------------------------------------------------------------------------------------

def joined_sbatch_args(argv):
    """`--sbatch-arg --qos=x` as `--sbatch-arg=--qos=x` (argparse would take --qos=x for a flag)."""
    fixed, i = [], 0
    while i < len(argv):
        if argv[i] == "--sbatch-arg" and i + 1 < len(argv):
            fixed.append(f"--sbatch-arg={argv[i + 1]}")
            i += 2
        else:
            fixed.append(argv[i])
            i += 1
    return fixed


def parse_args(argv):
    fixed = joined_sbatch_args(argv)
    ap = argparse.ArgumentParser(
        prog=os.path.basename(sys.argv[0]), description="Runs the points of a sweep spec (`tigris run`, "
        "or `tigris register` / `tigris odometry` with \"command\") "
        "and collects DIR/sweep.csv and DIR/sweep.json (docs/sweeps.md).",
        epilog="`%(prog)s collect DIR` collects a folder again (after --no-wait). Exit codes: 0 every "
        "point ok, 1 a point mismatched or failed, 2 bad spec, arguments or folder, 3 sbatch failed, "
        "128 + the signal when interrupted (130 SIGINT, 129 SIGHUP, 143 SIGTERM).")
    ap.add_argument("spec", metavar="SPEC.json", help="sweep spec: {\"base\", \"grid\", \"points\"}")
    core.role(ap.add_argument("--out", metavar="DIR", help="sweep folder (points/<id>/, sweep.csv, "
                              "sweep.json); rerunning into it resumes"), "out_folder")
    ap.add_argument("--check", action="store_true", help="validate the spec and dry-check its points, "
                    "run nothing, make no folder (with --out: also that DIR would resume it)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                    help="points run at once locally (and dry checks) (default: %(default)s)")
    core.role(ap.add_argument("--tigris", metavar="PATH", help="tigris binary (default: the one beside this "
                              "script, else $TIGRIS, else build/bin/tigris of the repository)"), "input")
    ap.add_argument("--slurm", action="store_true", help="run the points as one Slurm job array")
    ap.add_argument("--partition", metavar="P", help="sbatch --partition")
    ap.add_argument("--time", metavar="T", help="sbatch --time (per array task)")
    ap.add_argument("--mem", metavar="M", help="sbatch --mem (per array task)")
    ap.add_argument("--chunk", type=int, default=1, metavar="K", help="points per array task (default 1)")
    ap.add_argument("--sbatch-arg", action="append", metavar="ARG",
                    help="one more raw sbatch argument, repeatable: --sbatch-arg --qos=low")
    ap.add_argument("--no-wait", action="store_true", help="return after submitting; print the job id "
                    "and the collect command")
    ap.add_argument("--list-flags", action="store_true", help="Print this command's flags as JSON (flag, type, "
                    "default, meaning) for tools, and exit")
    core.list_flags(ap, "sweep", argv)
    a = ap.parse_args(fixed)
    a.argv = list(argv)
    if a.out is None and not a.check:
        ap.error("the following arguments are required: --out")
    if a.out is not None and not a.out.strip():
        ap.error("--out is empty: give the sweep folder (an empty path would be the current folder)")
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    if a.chunk < 1:
        ap.error("--chunk must be at least 1")
    if not a.slurm:
        used = [o for o, v in (("--partition", a.partition), ("--time", a.time), ("--mem", a.mem),
                               ("--chunk", a.chunk != 1), ("--sbatch-arg", a.sbatch_arg),
                               ("--no-wait", a.no_wait)) if v]
        if used:
            ap.error(f"{', '.join(used)} need(s) --slurm")
    return a


def inputs_of(spec, pts):
    """(flag, path) of every file the points read, and their identities for the manifest: a
    finished point is kept on a rerun only while the files it read are the same."""
    paths, seen, frames = [("the spec", spec.path)], set(), {}
    for p in pts:
        args = dict(zip(p["args"][::2], p["args"][1::2]))
        for i in range(0, len(p["args"]) - 1, 2):
            flag = p["args"][i][2:]
            if flag in spec.command.paths and p["args"][i + 1] not in seen:
                seen.add(p["args"][i + 1])
                paths.append((f"'{spec.names.get(flag, flag)}'", p["args"][i + 1]))
            if flag in spec.command.folders:     # a sequence: only the scans of the points' --frames
                m = re.fullmatch(r"(\d+):(\d+)", str(args.get("--frames", "")))
                want = (int(m.group(1)), int(m.group(2))) if m else None          # None: every frame
                key = p["args"][i + 1]
                if key not in frames:
                    frames[key] = want
                elif frames[key] is not None:
                    frames[key] = None if want is None else (min(frames[key][0], want[0]), max(frames[key][1], want[1]))
    ids = []
    for flag, path in paths[1:]:
        role = f"{flag.strip(chr(39))} {os.path.relpath(path, spec.dir)}"
        if os.path.isdir(path):
            ids += core.sequence_inputs(role, path, frames.get(path))
        else:
            ids.append(core.input_identity(role, path))
    return paths, ids


def run(a):
    tigris_at(a.tigris or default_tigris())    # a missing binary is named before the spec is read
    spec = Spec(a.spec, a.tigris or default_tigris())
    tig = spec.tig
    pts = spec.expand()
    out = os.path.abspath(a.out) if a.out else None
    plan = make_plan(spec, tig, pts)
    folder = core.OutFolder(out, "sweep", OUTPUTS, argv=a.argv) if out else None
    if out:
        paths, ids = inputs_of(spec, pts)
        folder.check_path()
        folder.check_inputs(paths)
        check_folder(out, plan)
    todo = [p for p in pts if not (out and finished(out, p, spec.command))]
    dry_check(spec, tig, todo, out or tempfile.gettempdir(), a.jobs)
    tig.headline  # noqa: B018                   # the CSV's stage columns: a binary without them fails now
    # Settings that decide every point's results; a grown or shrunk grid resumes (new points run).
    settings = {"command": plan["command"], "base_args": plan["base_args"]}
    if a.check:
        if out:                                  # would the run take DIR? (nothing made or locked)
            folder.preview(settings, ids, all_inputs_must_match=False, input_paths=paths)
        note(f"{spec.given}: {len(pts)} points, valid" + (f"; {len(pts) - len(todo)} finished in {out}" if out else ""))
        return 0
    folder.claim(settings=settings, inputs=ids, input_paths=paths, all_inputs_must_match=False)

    def work():
        os.makedirs(os.path.join(out, "points"), exist_ok=True)
        return sweep_into(a, out, spec, tig, plan, pts)
    return folder.run(work)


def sweep_into(a, out, spec, tig, plan, pts):
    job = read_json(os.path.join(out, "slurm", "job.json"))
    if job and shutil.which("squeue") and core.squeue_active(job["job"]):
        raise SpecError(f"Slurm job {job['job']} of an earlier submission is still running into {out}; "
                        f"wait for it, or scancel {job['job']}")
    todo = [p for p in pts if not finished(out, p, spec.command)]
    note(f"{len(pts)} points, {len(pts) - len(todo)} finished earlier (skipped), {len(todo)} to run; "
         f"tigris {tig.path}")
    write_json(os.path.join(out, "plan.json"), plan)
    for p in todo:                               # an earlier failed try of a point is not its result
        for f in ("point.json", spec.command.result):
            if os.path.exists(os.path.join(point_dir(out, p["id"]), f)):
                os.remove(os.path.join(point_dir(out, p["id"]), f))
    if todo:
        if a.slurm:
            if not run_slurm(a, plan, todo, out, spec.names):
                return 0
        else:
            run_local(plan, todo, out, a.jobs, spec.names)
    return collect(out)


def main(argv):
    core.handle_stop_signals()                   # a hang-up or kill stops the points like Ctrl-C
    try:
        if argv[:1] == ["_task"] and len(argv) == 3:
            return run_task(argv[1], argv[2])
        if argv[:1] == ["collect"]:
            if len(argv) != 2 or argv[1].startswith("-") or not argv[1].strip():
                die("usage: tigris_sweep.py collect DIR")
            return collect_command(os.path.abspath(argv[1]))
        return run(parse_args(argv))
    except core.Refused as e:
        die(str(e))
    except core.SlurmFailed as e:
        die(str(e), core.SBATCH_FAILED)
    except OSError as e:                         # a full disk, a folder gone: named, no traceback
        die(f"{e.filename + ': ' if isinstance(e.filename, str) else ''}{e.strerror or e}")
    except KeyboardInterrupt as e:
        code = core.exit_status(e)
        note(f"interrupted ({signal.Signals(code - 128).name}): running points stopped; "
             "finished points are kept (rerun the same command to resume)")
        return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
