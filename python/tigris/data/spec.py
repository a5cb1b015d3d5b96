"""A sweep spec (docs/sweeps.md): {"command", "base", "grid", "points"} read and checked against
the binary (`Spec`), each key canonical and each value typed as the binary takes it; the points it
expands to and the files they read."""
import difflib, hashlib, itertools, json, math, os, re
from decimal import Decimal
from typing import Any

from .. import core
from .binary import COMMANDS, SpecError, is_preset_name, tigris_at


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


# Flags that tigris applies over a configuration key: a spec giving both would run the flag's
# value while the CSV shows the key's, so one spelling only.
PIPELINE_FLAG_KEYS = {"height": "search.top_height", "approx-thd": "search.nn_thd", "inject-kth": "inject.rpce_kth"}
FLAG_KEYS = {"run": {"height": "tree.top_height", "split-axis": "tree.split_axis",
                     "leader-capacity": "leader.capacity_per_leaf"},
             "ref": {}, "register": PIPELINE_FLAG_KEYS, "odometry": PIPELINE_FLAG_KEYS}
MAX_POINTS = 100_000                                 # a spec's points, counted before expanding
MAX_SPEC_BYTES = 16 << 20


def cli_value(v: Any) -> str:
    """A spec value as tigris reads it: booleans true/false, numbers in plain decimal."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        r = repr(v)
        return format(Decimal(r), "f") if "e" in r or "E" in r else r
    return str(v)


def csv_value(v: Any) -> str:
    return "" if v is None else cli_value(v)


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

    def _at(self, loc: str, msg: str) -> str:
        loc = loc if len(loc) <= 200 else loc[:200] + "..."
        return f"{self.given}: {loc}: {msg}"

    def _key(self, key: str, loc: str) -> str:
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

    def _value(self, canon: str, v: Any, loc: str) -> Any:
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

    def _settings(self, obj: Any, loc: str) -> dict[str, Any]:
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


def _id_value(key: str, v: Any, preset_flag: "str | None" = None) -> str:
    """A point's name for a value: a path's file name; for the preset flag, a preset's name and a
    file's relative path as written (./top-6: ._top-6), so the two never read alike."""
    if key == preset_flag and not os.path.isabs(v):
        s = v
    else:
        s = os.path.basename(v) if any(key in c.paths for c in COMMANDS.values()) else cli_value(v)
    return re.sub(r"[^A-Za-z0-9._+-]", "_", s) or "_"



def inputs_of(spec: Spec, pts: list[dict[str, Any]]) -> tuple[list[tuple[str, str]], list[dict[str, Any]]]:
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
