"""The tigris binary as the tools see it: where it is, its sub-commands (what a sweep point
runs and where its result is), and its flags and configuration keys as it lists them for tools
(`Tigris`), so no tool carries a copy of them."""
import difflib, json, os, re, subprocess
from typing import Any, Callable

from .. import core


class SpecError(core.Refused):
    """A bad spec, argument or sweep folder: printed, exit 2."""


class Command:
    """What a sweep point runs: a tigris sub-command, the file its result is in, and how that
    result reads (ok / mismatch / not_converged)."""
    def __init__(self, name: str, result: str, files: tuple[str, ...], folders: tuple[str, ...],
                 fixed: tuple[str, ...], required: str, config_from: "str | None", headline: list[str],
                 stage_columns: "tuple[str, tuple[str, ...]] | None" = None) -> None:
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

    def headline_of(self, stages: list[dict[str, Any]]) -> list[str]:
        """The headline with the columns of `stages` (core.pipeline_stages), in their order."""
        if not self.stage_columns:
            return list(self.headline)
        prefix, fields = self.stage_columns
        return list(self.headline) + [f"{prefix.format(key=s['key'])}.{f}" for s in stages for f in fields]

    def status(self, rc: int, result: Any) -> "tuple[str, str] | None":
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

def typed(text: str) -> Any:
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


def find_binary() -> "str | None":
    """The tigris binary: $TIGRIS (the binary that started this tool), else the one of the prefix
    or build tree this package sits in (PREFIX/lib/python3/dist-packages/tigris -> PREFIX/bin;
    BUILD/python/tigris -> BUILD/bin), else the source tree's build/bin (python/tigris ->
    build/bin); None when there is none."""
    if os.environ.get("TIGRIS"):
        return os.environ["TIGRIS"]
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    source = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
    for path in (os.path.join(package, "..", "..", "..", "..", "bin", "tigris"),
                 os.path.join(package, "..", "..", "bin", "tigris"),
                 os.path.join(source, "..", "..", "build", "bin", "tigris")):
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return os.path.normpath(path)
    return None


def commit_of_binary() -> str:
    """The commit of find_binary()'s binary (`tigris --version`: "tigris V (commit C)"), for a
    tool run without the binary; "unknown" when there is none or it does not say."""
    path = find_binary()
    try:
        text = core.capture([path, "--version"], timeout=30).stdout if path else ""
    except (OSError, subprocess.TimeoutExpired):
        text = ""
    m = re.search(r"\(commit ([^)]+)\)", text)
    return m.group(1) if m else "unknown"


def default_tigris() -> str:
    """find_binary(), else the source tree's build/bin/tigris (which the error then names)."""
    source = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
    return find_binary() or os.path.normpath(os.path.join(source, "..", "..", "build", "bin", "tigris"))


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

    @property
    def presets_dir(self) -> str:
        """The folder of the binary's shipped presets (`tigris presets --json`'s "dir")."""
        self._list_presets()
        return self._presets_dir

    def _list_presets(self) -> None:
        if not hasattr(self, "_presets"):
            listed = self._ask_json("presets", "--json")
            self._presets = {p["name"]: p["file"] for p in listed.get("presets", [])}
            self._presets_dir = listed.get("dir") or ""

    def preset_file(self, name: str, error: Callable[[str], Exception]) -> str:
        """The file of the binary's preset `name` (`tigris presets --json`); error(msg) when
        there is none."""
        self._list_presets()
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
