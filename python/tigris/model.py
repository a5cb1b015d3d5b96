"""The NumPy module: the golden model in this process (_tigris) and the accelerator model
through the tigris binary; `import tigris` exposes its names (see the package's docstring)."""
import fcntl
import fnmatch
import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import warnings

import numpy as np

from . import _tigris
from . import core
from .data.binary import find_binary
from ._tigris import InputError  # a bad cloud file (a ValueError), with the reader's message

__all__ = ["load_cloud", "synthetic_pair", "search", "run", "register", "config_keys", "presets", "binary",
           "SearchResult", "RunResult", "Registration", "TigrisError", "MismatchError", "InputError"]


class TigrisError(RuntimeError):
    """The tigris binary refused or failed a job; the message is its error message."""


class MismatchError(TigrisError):
    """The accelerator's results differ from the golden model's, or the simulation deadlocked:
    `.result` holds the run's RunResult (its stats name the first differing query); None after a
    deadlock or a failed job in the loop, which leave no stats (the message says what stuck)."""
    def __init__(self, message, result):
        super().__init__(message)
        self.result = result


# ------------------------------------------------------------------------------- the binary

def binary():
    """The tigris binary: $TIGRIS, else the one of the prefix or build tree this package sits in
    (tigris.data.binary.find_binary)."""
    path = find_binary()
    if path is None:
        raise TigrisError(f"no tigris binary beside this package ({os.path.dirname(__file__)}): set $TIGRIS")
    return path


def _call(args, parent_files=()):
    """The binary on `args`; `parent_files`: the names this module keeps in the command's --out
    folder, passed as TIGRIS_PARENT_OUTPUTS (the output core neither counts them foreign nor
    removes them; docs/architecture.md)."""
    env = dict(os.environ)
    env.pop("TIGRIS_PARENT_OUTPUTS", None)
    if parent_files:
        env["TIGRIS_PARENT_OUTPUTS"] = " ".join(parent_files)
    return subprocess.run([binary()] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          stdin=subprocess.DEVNULL, env=env)


def _error_text(stderr):
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    errors = [ln for ln in lines if "error:" in ln]
    return (errors[-1] if errors else lines[-1] if lines else "no message").split("error: ", 1)[-1]


def _verdict_text(p):
    """The line of a failed run that says what failed (MISMATCH, DEADLOCK), else its last line."""
    lines = [ln for ln in (p.stdout + "\n" + p.stderr).splitlines() if ln.strip()]
    said = [ln for ln in lines if "MISMATCH" in ln or "DEADLOCK" in ln or "mismatch" in ln or "deadlock" in ln]
    return (said or lines or ["exit 1, no message"])[0].strip()


def _json_of(args):
    p = _call(args)
    if p.returncode != 0:
        raise TigrisError(f"tigris {' '.join(args)}: {_error_text(p.stderr)}")
    return json.loads(p.stdout)


def config_keys():
    """Every accelerator configuration key: [{key, type, unit, default, doc, min/max or values}]
    (`tigris run --list-config --json`)."""
    return _json_of(["run", "--list-config", "--json"])["keys"]


def presets():
    """The shipped accelerator presets by name: {name: {file, why, sets, changes[, variant]}}
    (`tigris presets --json`)."""
    p = _call(["presets", "--json"])
    try:
        listed = json.loads(p.stdout)["presets"]
    except (ValueError, KeyError, TypeError):
        raise TigrisError(f"tigris presets --json: {_error_text(p.stderr)}")
    # A broken preset file is left out (named in a warning), the others stay usable.
    for bad in (q for q in listed if "error" in q):
        warnings.warn(f"tigris preset {bad['name']} is left out: {bad['error']}", stacklevel=2)
    return {q["name"]: q for q in listed if "error" not in q}


# ------------------------------------------------------------------------------- the arrays

def _cloud(a, what, allow_none=False):
    """`a` as the float32 (N, 3) C-contiguous array the model reads, without a copy when it is
    one already; ValueError naming `what` otherwise."""
    if a is None and allow_none:
        return None
    if not isinstance(a, np.ndarray):
        raise ValueError(f"{what} must be a NumPy array of float32, shape (N, 3); got {type(a).__name__}")
    if a.dtype != np.float32:
        raise ValueError(f"{what} must be float32 (the model's arithmetic is float32), got {a.dtype}: "
                         f"pass {what}.astype(np.float32)")
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what} must have shape (N, 3), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{what} is empty: a search needs at least one point")
    bad = ~np.isfinite(a).all(axis=1) | (np.abs(a) > 1e18).any(axis=1)
    if bad.any():
        raise ValueError(f"{what} row {int(np.argmax(bad))} is not a finite coordinate within 1e18 metres "
                         f"({int(bad.sum())} such rows)")
    return np.ascontiguousarray(a)


def load_cloud(path):
    """A KITTI .bin, .pcd or .ply file's points as a float32 (N, 3) array. ValueError (the
    reader's message, naming the file) for a missing, malformed or truncated file."""
    return _tigris.load_cloud(os.fspath(path))


def synthetic_pair(seed=1):
    """The built-in workload as arrays (cloud, queries): synthetic frames 0 and 1 of `seed`, two
    HDL-64E-like scans of one street, the second 1 m further on and turned 1 degree (what
    `tigris run` searches without --cloud)."""
    return _tigris.synthetic_pair(_whole("seed", seed))


def _height(h):
    if isinstance(h, str) and h == "full":
        return -1
    if isinstance(h, bool) or not isinstance(h, (int, np.integer)) or not 0 <= h <= 30:
        raise ValueError(f"height must be 'full' or a whole number from 0 to 30, got {h!r}")
    return int(h)


INT_MAX, UINT32_MAX, UINT64_MAX = 2**31 - 1, 2**32 - 1, 2**64 - 1

# The whole-number arguments and flags, with the range the model takes (the C++ types: k, the
# leader capacity and width are int, max_nn uint32; seeds uint64; the command line checks the
# rest). Out of range or not a whole number: a ValueError naming the argument, before any work.
_WHOLE = {"k": (1, INT_MAX), "max_nn": (0, UINT32_MAX), "leader_capacity": (0, INT_MAX),
          "leader_width": (0, INT_MAX), "seed": (0, UINT64_MAX), "timeline_queries": (0, UINT32_MAX),
          "sim_threads": (1, INT_MAX), "jobs": (1, INT_MAX), "repeat": (1, INT_MAX)}


def _whole(name, v):
    """`v` as an int within _WHOLE[name]'s range; ValueError naming `name` for a float (2.5 or
    2.0: never truncated), a bool, a string or a number out of range."""
    lo, hi = _WHOLE[name]
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= int(v) <= hi:
        raise ValueError(f"{name} must be a whole number from {lo} to {hi}, got {v!r}")
    return int(v)


def _shaped(mode, offsets, indices, dist2):
    """NN results as (Q,), kNN as (Q, k) when every query has k (radius: flat, with offsets)."""
    counts = np.diff(offsets)
    if mode in ("nn", "knn") and len(counts) and (counts == counts[0]).all():
        shape = (len(counts),) if mode == "nn" else (len(counts), int(counts[0]))
        return indices.reshape(shape), dist2.reshape(shape)
    return indices, dist2


def _neighbors(r, q):
    nq = len(r.offsets) - 1
    if isinstance(q, bool) or not isinstance(q, (int, np.integer)):
        raise TypeError(f"neighbors: the query index must be a whole number, got {q!r}")
    if not 0 <= q < nq:
        raise IndexError(f"neighbors: query {q} is out of range: the result holds {nq} queries, "
                         f"0 .. {nq - 1}" if nq else f"neighbors: query {q} is out of range: the result holds no query")
    a, b = int(r.offsets[q]), int(r.offsets[q + 1])
    return r.indices.reshape(-1)[a:b], r.dist2.reshape(-1)[a:b]


class SearchResult:
    """The golden model's answer. indices and dist2: for nn (Q,), for knn (Q, k) (k clamped to
    the cloud's size), for radius flat arrays with offsets (query q's are
    [offsets[q], offsets[q+1])); each query's neighbours in canonical order (distance, then
    index). visits: totals as `tigris ref` counts them; visits_top and visits_leaf_points per
    query; leaders: approximate search's leaders and followers."""
    def __init__(self, mode, d):
        self.mode = mode
        self.offsets = d["offsets"]
        self.indices, self.dist2 = _shaped(mode, self.offsets, d["indices"], d["dist2"])
        self.visits, self.leaders = d["visits"], d["leaders"]
        self.visits_top, self.visits_leaf_points = d["visits_top"], d["visits_leaf_points"]
        self.tree = {"top_height": d["top_height"], "full_height": d["full_height"], "leaves": d["leaves"]}

    def neighbors(self, q):
        """Query q's (indices, dist2), q from 0 to the number of queries less one (no negative
        index: IndexError naming the range)."""
        return _neighbors(self, q)


def search(cloud, queries=None, mode="nn", k=10, radius=0.3, max_nn=0, height=10, split_axis="widest",
           approx_thd=None, leader_scope="first_leaf", leader_in_flight="wait", leader_capacity=16,
           leader_width=0, max_work=2e9, max_results=2e8):
    """The golden model's neighbours of `queries` (default: the cloud itself) in `cloud`, as
    `tigris ref` finds them with the same settings: the tree of top height `height` (0 .. 30 or
    'full'; the default 10 is clamped to a small cloud's full height, as tigris does), exact
    search or, with approx_thd (metres, or 'default': the paper's 1.2 m, 0.4 r for radius),
    approximate leader/follower search. k (1 .. 2**31-1), max_nn (0 .. 2**32-1; 0: all),
    leader_capacity and leader_width (0 .. 2**31-1) are whole numbers (ints, never truncated):
    else a ValueError naming the argument and its range. max_work, max_results: the work bound
    of `tigris ref --max-work/--max-results` (0: none); a job estimated above it is refused with
    a ValueError before it starts, and Ctrl-C stops a running search (KeyboardInterrupt).
    Returns a SearchResult."""
    cloud = _cloud(cloud, "cloud")
    queries = cloud if queries is None else _cloud(queries, "queries")
    if mode not in ("nn", "knn", "radius"):
        raise ValueError(f"mode must be nn, knn or radius, got {mode!r}")
    h = _height(height)
    k, max_nn = _whole("k", k), _whole("max_nn", max_nn)
    leader_capacity, leader_width = _whole("leader_capacity", leader_capacity), _whole("leader_width", leader_width)
    if h == 10 and h > _tigris.full_height(len(cloud)):
        h = _tigris.full_height(len(cloud))
    thd, approximate = 0.0, approx_thd is not None
    if isinstance(approx_thd, str) and approx_thd == "default":
        thd = _tigris.default_approx_thd(mode, float(radius))
    elif approximate:
        thd = float(approx_thd)
    for name, v in (("max_work", max_work), ("max_results", max_results)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not 0 <= v < float("inf"):
            raise ValueError(f"{name} must be a number >= 0 (0: no bound), got {v!r}")
    d = _tigris.search(cloud, queries, mode, k, float(radius), max_nn, h, split_axis, approximate,
                       thd, leader_scope, leader_in_flight, leader_capacity, leader_width,
                       float(max_work), float(max_results))
    return SearchResult(mode, d)


# ----------------------------------------------------------------------- jobs on the binary

def _bin(a):
    """A float32 (N, 3) array as a KITTI .bin's content (x, y, z, intensity 0), the format the
    binary reads bit for bit: a (N, 4) little-endian float32 array, written as it is."""
    out = np.zeros((len(a), 4), dtype="<f4")
    out[:, :3] = a
    return out


# Refused keyword arguments: flags that make the command do something else than the job (a
# listing, a comparison), or that name what the module sets itself.
_NOT_FLAGS = {
    "run": {
        "list_config": "it makes `tigris run` list the configuration keys and run nothing; "
                       "tigris.config_keys() returns them",
        "json": "it applies to --list-config; tigris.config_keys() returns the keys",
        "stats_schema": "it makes `tigris run` print the schema of stats.json and run nothing "
                        "(run `tigris run --stats-schema`)",
        "list_flags": "it makes `tigris run` list its flags and run nothing (run `tigris run --list-flags`)",
        "help": "see help(tigris.run), or run `tigris run --help`",
        "out": "tigris.run chooses the output folder: keep=DIR keeps the job's files in DIR",
        "dump_results": "tigris.run dumps the results itself (the result's indices and dist2; "
                        "results.csv in keep=DIR)",
    },
    "register": {
        "list_config": "it makes `tigris register` list the pipeline's keys and run nothing "
                       "(run `tigris register --list-config`; tigris.config_keys() lists the accelerator's)",
        "list_stages": "it makes `tigris register` list its stages and run nothing "
                       "(run `tigris register --list-stages`)",
        "json": "it applies to --list-config (run `tigris register --list-config --json`)",
        "check_flags": "it makes `tigris register` check its flags and run nothing",
        "list_flags": "it makes `tigris register` list its flags and run nothing "
                      "(run `tigris register --list-flags`)",
        "help": "see help(tigris.register), or run `tigris register --help`",
        "compare": "it runs four registrations side by side and writes no registration.json "
                   "(run `tigris register --compare`)",
        "repeat": "it applies to --compare (run `tigris register --compare`)",
        "out": "tigris.register chooses the output folder: keep=DIR keeps the registration's files in DIR",
    },
}


def _flags(function, **kw):
    args = []
    for name, v in kw.items():
        if v is None or v is False:
            continue
        if name in _NOT_FLAGS[function]:
            raise ValueError(f"{name} is not an option of tigris.{function}: {_NOT_FLAGS[function][name]}")
        v = _plain(v)
        if v is False:
            continue
        if name in _WHOLE:
            v = _whole(name, v)
        flag = "--" + name.replace("_", "-")
        args += [flag] if v is True else [flag, str(v)]
    return args


class RunResult:
    """One accelerator job: stats (stats.json as a dict), verdict ("match" ...), cycles (sampled:
    the estimate), cycles_ci95 ([low, high]; [cycles, cycles] when every query was simulated),
    sampled (bool) and sampling (stats' account of it), seconds, bound (the block that bounds the
    job) and bottleneck (stats' whole verdict), and the results as SearchResult's arrays
    (indices/dist2/offsets from the run's results dump)."""
    def __init__(self, stats, results_csv, mode):
        self.stats = stats
        self.verdict = stats.get("verdict")
        self.cycles = stats.get("cycles")
        self.cycles_ci95 = stats.get("cycles_ci95")
        self.sampling = stats.get("sampling") or {}
        self.sampled = bool(self.sampling.get("sampled"))
        self.seconds = stats.get("seconds")
        self.bottleneck = stats.get("bottleneck") or {}
        self.bound = self.bottleneck.get("bound")        # "front-end", "back-end", "write-back" ...
        self.mode = mode
        self.offsets, indices, dist2 = _read_results(results_csv, stats.get("queries"))
        self.indices, self.dist2 = _shaped(mode, self.offsets, indices, dist2)


def _read_results(path, queries):
    """The results dump (query,rank,index,dist2) as offsets, indices and dist2 arrays."""
    known = isinstance(queries, int) and not isinstance(queries, bool)
    with open(path) as f:
        f.readline()                                   # the header
        empty = not f.read(1)                          # no query has a neighbour
    if empty:
        nq = int(queries) if known else 0
        return np.zeros(nq + 1, np.uint64), np.zeros(0, np.uint32), np.zeros(0, np.float32)
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=1,
                      dtype={"names": ("q", "rank", "index", "dist2"),
                             "formats": (np.int64, np.int64, np.uint32, np.float32)})
    nq = int(queries) if known else int(rows["q"].max()) + 1
    counts = np.bincount(rows["q"], minlength=nq) if len(rows) else np.zeros(nq, np.int64)
    offsets = np.zeros(nq + 1, np.uint64)
    np.cumsum(counts, out=offsets[1:])
    return offsets, rows["index"].copy(), rows["dist2"].copy()


# ---------------------------------------------------------------- the folder of a job: keep=DIR
#
# A job's folder is the command's --out folder: the command writes its files there (stats.json,
# results.csv / registration.json, manifest.json: what it wrote), and this module its inputs
# (cloud.bin, queries.bin, config.json / source.bin, target.bin, pipeline.json, accel.json) and
# their record, keep.json (each file's size and SHA-256), named to the command in
# TIGRIS_PARENT_OUTPUTS so its output core neither refuses nor removes them. keep=DIR follows
# the rule of --out (core/out_folder.cpp), checked before a byte is written: a new or empty
# folder, or one an earlier call of the same function (or the same command) wrote; any other
# file in it, or one of this module's files changed since, is a TigrisError naming them.

_MANIFEST, _RECORD, _TMP_PREFIX = core.MANIFEST, "keep.json", core.TMP_PREFIX
_INPUT_FILES = {"run": ("cloud.bin", "queries.bin", "config.json"),
                "register": ("source.bin", "target.bin", "pipeline.json", "accel.json")}


def _digest(data):
    m = memoryview(data).cast("B")
    return {"bytes": m.nbytes, "sha256": hashlib.sha256(m).hexdigest()}


def _file_digest(path):
    h, n = hashlib.sha256(), 0
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
            n += len(chunk)
    return {"bytes": n, "sha256": h.hexdigest()}


def _json_or_none(path):
    try:
        with open(path, "rb") as f:
            return json.loads(f.read(1 << 24))
    except (OSError, ValueError):
        return None


def _an_output(name, patterns):
    """The output core's match of a top-level name against a manifest's outputs ("stats.json",
    "*.vcd", "pairs/"): a leading dot only by a dot."""
    for p in patterns:
        if not isinstance(p, str) or not p.strip("/"):
            continue
        p = p.rstrip("/")
        if name.startswith(".") and not p.startswith("."):
            continue
        if fnmatch.fnmatchcase(name, p):
            return True
    return False


def _listed(names):
    return ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")


def _folder_path(keep, function):
    """keep's path as a string; ValueError when it names no folder."""
    try:
        d = os.fspath(keep)
    except TypeError:
        d = None
    if not isinstance(d, str) or not d:
        raise ValueError(f"keep must name a folder (a str or os.PathLike), got {keep!r}")
    return d


def _claim(d, shown, function, command):
    """Checks keep=`shown` (at `d`) for tigris.<function> before anything is written in it,
    creates it when missing and locks it (flock, as the output core does). Returns (the lock's
    descriptor, this module's files in it that an earlier call wrote: {name: digest}).
    TigrisError naming the folder and the files otherwise; nothing is written then."""
    where = f"tigris.{function}: keep={shown}"
    if os.path.lexists(d) and not os.path.isdir(d):
        raise TigrisError(f"{where}: {shown} exists and is not a folder; give a new or empty folder "
                          f"(tigris.{function} writes its files in it)")
    try:
        os.makedirs(d, exist_ok=True)
        fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY)
    except OSError as e:
        raise TigrisError(f"{where}: cannot create or open the folder: {e.strerror or e}") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise TigrisError(f"{where}: another run is writing into this folder; wait until it has "
                              f"finished, or give another folder") from None
        return fd, _ours(d, where, function, command)
    except BaseException:
        os.close(fd)
        raise


def _ours(d, where, function, command):
    entries = sorted(os.listdir(d))
    manifest = _json_or_none(os.path.join(d, _MANIFEST)) if _MANIFEST in entries else None
    if not (isinstance(manifest, dict) and manifest.get("tigris_manifest") == 1):
        manifest = None
    elif manifest.get("command") != command:
        raise TigrisError(f"{where}: the folder holds the output of tigris {manifest.get('command')}, not of "
                          f"tigris {command}; give a new or empty folder (nothing was written)")
    record = _json_or_none(os.path.join(d, _RECORD)) if _RECORD in entries else None
    if not (isinstance(record, dict) and record.get("tigris_keep") == 1 and record.get("function") == function
            and isinstance(record.get("files"), dict)):
        record = None
    outputs = manifest.get("outputs") if manifest and isinstance(manifest.get("outputs"), list) else []
    recorded = record["files"] if record else {}
    foreign, changed, ours = [], [], {}
    for name in entries:
        path = os.path.join(d, name)
        if (name == _MANIFEST and manifest) or (name == _RECORD and record) or name.startswith(_TMP_PREFIX):
            continue                                   # the records; a killed write's leftover
        if name in _INPUT_FILES[function] and name in recorded:
            known = recorded[name] if isinstance(recorded[name], list) else []
            now = _file_digest(path) if os.path.isfile(path) and not os.path.islink(path) else None
            if now is not None and now in known:
                ours[name] = now
            else:
                changed.append(name)
            continue
        if not _an_output(name, outputs):
            foreign.append(name)
    if foreign or changed:
        what = []
        if foreign:
            what.append(f"{'a file' if len(foreign) == 1 else 'files'} tigris.{function} did not write "
                        f"({_listed(foreign)})")
        if changed:
            what.append(f"{'a file' if len(changed) == 1 else 'files'} tigris.{function} wrote that "
                        f"{'has' if len(changed) == 1 else 'have'} changed since ({_listed(changed)})")
        raise TigrisError(f"{where}: the folder holds {' and '.join(what)}; give a new or empty folder, or one an "
                          f"earlier tigris.{function}(keep=...) wrote (nothing was written)")
    return ours


def _replace(path, data):
    """Writes `data` (bytes or an array) through the shared core's replace_file (beside `path`,
    renamed over it); a TigrisError naming `path` when it cannot."""
    def write(tmp):
        with open(tmp, "wb") as f:
            f.write(memoryview(data).cast("B"))
    try:
        core.replace_file(path, write)
    except core.Refused as e:
        raise TigrisError(str(e)) from None


class _Job:
    """The folder a run() or register() works in: keep=DIR, or a temporary one removed at the
    end. `files` ({name: bytes or array}) are the inputs this module writes in it."""
    def __init__(self, keep, function, command):
        self.function, self.command, self.files = function, command, {}
        self.temp = keep is None
        self.shown = tempfile.mkdtemp(prefix=f"tigris-{function}-") if self.temp else _folder_path(keep, function)
        self.dir = os.path.abspath(self.shown)         # as the command's --out (never taken for a flag)

    def path(self, name):
        return os.path.join(self.dir, name)

    def input(self, name, data):
        """`name`'s path, to be written with `data` (bytes or an array) by call()."""
        self.files[name] = data
        return self.path(name)

    def call(self, args, result):
        """Claims the folder, writes the inputs, runs the binary on `args`. Returns (the process,
        whether `result` (a file of the folder) is this run's)."""
        fd, ours = (None, {}) if self.temp else _claim(self.dir, self.shown, self.function, self.command)
        try:
            for name in sorted(set(ours) - set(self.files)):
                os.remove(self.path(name))             # an earlier call's input this one has not
            record = {"tigris_keep": 1, "function": self.function,
                      "about": f"the files tigris.{self.function}(keep=...) wrote in this folder (each file's "
                               f"digests: its content now, and the one it replaced); tigris {self.command} "
                               f"wrote the rest (manifest.json)",
                      "files": {}}
            for name, data in self.files.items():
                now = _digest(data)
                record["files"][name] = [now] + ([ours[name]] if name in ours and ours[name] != now else [])
            _replace(self.path(_RECORD), (json.dumps(record, indent=1) + "\n").encode())
            for name, data in self.files.items():
                _replace(self.path(name), data)
        finally:
            if fd is not None:
                os.close(fd)                           # the command locks the folder itself
        before = _stamp(self.path(result))
        p = _call(args, [_RECORD] + sorted(self.files))
        after = _stamp(self.path(result))
        return p, after is not None and after != before

    def close(self):
        if self.temp:
            shutil.rmtree(self.dir, ignore_errors=True)


def _stamp(path):
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_ino, st.st_mtime_ns, st.st_size


def run(cloud=None, queries=None, mode="nn", k=10, radius=0.3, max_nn=0, height=None, approx_thd=None,
        config=None, preset=None, set=None, sampling=None, keep=None, **flags):
    """One accelerator job, checked against the golden model, as `tigris run` runs it.

    cloud, queries: float32 (N, 3) arrays (neither: the built-in synthetic pair; a cloud alone is
    searched in itself). k (1 .. 2**31-1), max_nn (0 .. 2**32-1): whole numbers; height: 0 .. 30
    or 'full'. config: a dict nested by block or of dotted keys ({"fe.recursion_units": 32});
    preset: a shipped preset's name (tigris.presets()); both: the preset, then the dict over
    it. set: {key: value} as --set. Other tigris run flags as keyword arguments
    (leader_capacity=8, split_axis="round-robin", sim_threads=1 ...; not list_config: that is
    tigris.config_keys()). sampling: sim.sampling, "off" (the default), "auto" or the share of
    queries to simulate (docs/sampling.md; the result's cycles_ci95 holds the estimate's
    interval).

    keep: a folder to keep the job's files in (default: a temporary one, removed): the job's
    --out folder, holding stats.json, results.csv and manifest.json (tigris run's) beside
    cloud.bin, queries.bin and config.json (the inputs as this module wrote them) and keep.json
    (their record). It must be new or empty, or a folder an earlier run(keep=...) or `tigris
    run --out` wrote (its files are replaced); a folder holding any other file, or a file that
    is not a folder, is a TigrisError naming them, and nothing is written.

    Returns a RunResult; raises MismatchError when a query differs from the golden model,
    TigrisError when the run is refused (the CLI's message), ValueError for bad arrays and
    arguments (naming the argument)."""
    cloud = _cloud(cloud, "cloud", allow_none=True)
    queries = _cloud(queries, "queries", allow_none=True)
    if queries is not None and cloud is None:
        raise ValueError("queries need a cloud (neither: the built-in synthetic pair)")
    k, max_nn = _whole("k", k), _whole("max_nn", max_nn)
    h = None if height is None else _height(height)
    job = _Job(keep, "run", "run")
    try:
        args = ["run", "--mode", mode, "--out", job.dir, "--dump-results", job.path("results.csv")]
        if cloud is not None:
            args += ["--cloud", job.input("cloud.bin", _bin(cloud))]
        if queries is not None:
            args += ["--queries", job.input("queries.bin", _bin(queries))]
        if mode == "knn":
            args += ["--k", str(k)]
        if mode == "radius":
            args += ["--radius", repr(float(radius)), "--max-nn", str(max_nn)]
        if h is not None:
            args += ["--height", "full" if h < 0 else str(h)]
        if approx_thd is not None:
            args += ["--approx-thd", str(approx_thd)]
        args += _config_args(job, config, preset, "--config", "config.json") + _flags("run", **flags)
        for key, v in (set or {}).items():
            v = _plain(v)
            args += ["--set", f"{key}={json.dumps(v) if isinstance(v, bool) else v}"]
        if sampling is not None:
            args += ["--set", f"sim.sampling={_plain(sampling)}"]
        p, fresh = job.call(args, "stats.json")
        if p.returncode == 1 and not fresh:                       # a deadlock: no stats
            raise MismatchError(f"tigris run: {_verdict_text(p)}", None)
        if p.returncode not in (0, 1) or not fresh:
            raise TigrisError(f"tigris run: {_error_text(p.stderr)}")
        with open(job.path("stats.json")) as f:
            result = RunResult(json.load(f), job.path("results.csv"), mode)
        if p.returncode == 1:
            raise MismatchError(f"tigris run: {_error_text(p.stderr) if p.stderr.strip() else result.verdict}",
                                result)
        return result
    finally:
        job.close()


def _plain(v):
    """A NumPy scalar as the Python value JSON and the command line take."""
    return v.item() if isinstance(v, np.generic) else v


def _config_args(job, config, preset, flag, name):
    """--config PRESET, or a file of `config` over the preset's keys when both are given (both
    flattened to dotted keys, so a key of `config` replaces the preset's whatever its form)."""
    if config is None:
        return [flag, preset] if preset else []
    if not isinstance(config, dict):
        raise ValueError(f"config must be a dict (nested by block or dotted keys), got {type(config).__name__}")
    merged = {}
    if preset:
        if "/" in preset or preset.endswith(".json"):
            with open(preset) as f:
                merged.update(core.dotted(json.load(f)))
        else:
            known = presets()
            if preset not in known:
                raise ValueError(f"no preset named {preset!r}; presets: {', '.join(sorted(known))}")
            merged.update(known[preset]["sets"])
    merged.update(core.dotted(config))
    return [flag, job.input(name, json.dumps(merged, default=_plain).encode())]


class Registration:
    """A registration (`tigris register`): doc (registration.json as a dict), transform (4 x 4
    float64 array, None when degenerate), status, seconds, and stages: {stage key: its
    figures} (seconds, searches, kdtree ...)."""
    def __init__(self, doc):
        self.doc = doc
        self.status = doc.get("status")
        t = doc.get("transform")
        self.transform = np.array(t, dtype=np.float64) if t is not None else None
        self.seconds = doc.get("seconds")
        self.stages = doc.get("stages")
        self.error = doc.get("error")


def register(source=None, target=None, preset="dp4", search="exact", config=None, accel_config=None,
             accel_preset=None, keep=None, **flags):
    """Registers `source` onto `target` (float32 (N, 3) arrays; neither: the built-in synthetic
    pair) with the pipeline `preset` (dp4, dp7 ...) and the search back-end `search` (exact,
    approx, flann, accel, accel-approx). config: a pipeline configuration dict; accel_config /
    accel_preset: the accelerator's, with search="accel*". Other tigris register flags as keyword
    arguments. keep: a folder to keep the registration's files in (default: a temporary one,
    removed), as run()'s: the command's --out folder (registration.json, manifest.json) with
    source.bin, target.bin, pipeline.json, accel.json and keep.json; new or empty, or one an
    earlier register(keep=...) or `tigris register --out` wrote, else a TigrisError naming the
    folder's other files, with nothing written. Returns a Registration; TigrisError with the
    CLI's message when refused."""
    source = _cloud(source, "source", allow_none=True)
    target = _cloud(target, "target", allow_none=True)
    if (source is None) != (target is None):
        raise ValueError("source and target go together (neither: the built-in synthetic pair)")
    if config is not None and not isinstance(config, dict):
        raise ValueError(f"config must be a dict, got {type(config).__name__}")
    job = _Job(keep, "register", "register")
    try:
        args = ["register", "--preset", preset, "--search", search, "--out", job.dir]
        if source is not None:
            args += ["--source", job.input("source.bin", _bin(source)),
                     "--target", job.input("target.bin", _bin(target))]
        if config is not None:
            args += ["--config", job.input("pipeline.json", json.dumps(config, default=_plain).encode())]
        args += _config_args(job, accel_config, accel_preset, "--accel-config", "accel.json") + \
            _flags("register", **flags)
        p, fresh = job.call(args, "registration.json")
        if p.returncode == 1 and not fresh:                       # the accelerator failed a job
            raise MismatchError(f"tigris register: {_verdict_text(p)}", None)
        if not fresh:
            raise TigrisError(f"tigris register: {_error_text(p.stderr)}")
        with open(job.path("registration.json")) as f:
            reg = Registration(json.load(f))
        if p.returncode not in (0, 1):
            raise TigrisError(f"tigris register: {_error_text(p.stderr)}")
        return reg
    finally:
        job.close()
