"""Tigris TLM from Python: the golden model and the accelerator model on NumPy arrays.

    import numpy as np, tigris
    cloud = tigris.load_cloud("frame0.bin")                     # float32 (N, 3)
    nn = tigris.search(cloud, queries, mode="nn")              # the golden model, in process
    job = tigris.run(cloud, queries, mode="knn", k=8, preset="dram-2x")   # one accelerator job
    job.stats["cycles"], job.verdict, job.bound
    reg = tigris.register(source, target, preset="dp4", search="exact")
    reg.transform                                              # 4 x 4

`search` runs the golden model in this process. `run` and `register` run the `tigris` binary
in a child process of their own (SystemC elaborates once per process), with the arrays written
to a temporary folder as KITTI .bin files; their figures are `tigris run`'s and `tigris
register`'s, field for field. Errors are exceptions carrying the command line's messages:
ValueError for bad arrays and settings, tigris.TigrisError for a refused run, and
tigris.MismatchError when the accelerator's results differ from the golden model's.
docs/python.md is the tutorial.
"""
import json
import os
import shutil
import subprocess
import tempfile

import numpy as np

from . import _tigris
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
    (PREFIX/lib/python3/dist-packages/tigris -> PREFIX/bin/tigris; BUILD/python/tigris ->
    BUILD/bin/tigris)."""
    if os.environ.get("TIGRIS"):
        return os.environ["TIGRIS"]
    here = os.path.dirname(os.path.abspath(__file__))
    for up in (("..", "..", "..", "..", "bin"), ("..", "..", "bin")):
        path = os.path.normpath(os.path.join(here, *up, "tigris"))
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    raise TigrisError(f"no tigris binary beside this package ({here}): set $TIGRIS")


def _call(args):
    return subprocess.run([binary()] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       stdin=subprocess.DEVNULL)


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
    return {p["name"]: p for p in _json_of(["presets", "--json"])["presets"]}


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
    return _tigris.synthetic_pair(int(seed))


def _height(h):
    if h == "full":
        return -1
    if isinstance(h, bool) or not isinstance(h, (int, np.integer)) or not 0 <= h <= 30:
        raise ValueError(f"height must be 'full' or a whole number from 0 to 30, got {h!r}")
    return int(h)


def _shaped(mode, offsets, indices, dist2):
    """NN results as (Q,), kNN as (Q, k) when every query has k (radius: flat, with offsets)."""
    counts = np.diff(offsets)
    if mode in ("nn", "knn") and len(counts) and (counts == counts[0]).all():
        shape = (len(counts),) if mode == "nn" else (len(counts), int(counts[0]))
        return indices.reshape(shape), dist2.reshape(shape)
    return indices, dist2


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
        """Query q's (indices, dist2)."""
        a, b = int(self.offsets[q]), int(self.offsets[q + 1])
        return self.indices.reshape(-1)[a:b], self.dist2.reshape(-1)[a:b]


def search(cloud, queries=None, mode="nn", k=10, radius=0.3, max_nn=0, height=10, split_axis="widest",
           approx_thd=None, leader_scope="first_leaf", leader_in_flight="wait", leader_capacity=16,
           leader_width=0):
    """The golden model's neighbours of `queries` (default: the cloud itself) in `cloud`, as
    `tigris ref` finds them with the same settings: the tree of top height `height` (0 .. 30 or
    'full'; the default 10 is clamped to a small cloud's full height, as tigris does), exact
    search or, with approx_thd (metres, or 'default': the paper's 1.2 m, 0.4 r for radius),
    approximate leader/follower search. Returns a SearchResult."""
    cloud = _cloud(cloud, "cloud")
    queries = cloud if queries is None else _cloud(queries, "queries")
    if mode not in ("nn", "knn", "radius"):
        raise ValueError(f"mode must be nn, knn or radius, got {mode!r}")
    h = _height(height)
    if height == 10 and h > _tigris.full_height(len(cloud)):
        h = _tigris.full_height(len(cloud))
    thd, approximate = 0.0, approx_thd is not None
    if approx_thd == "default":
        thd = _tigris.default_approx_thd(mode, float(radius))
    elif approximate:
        thd = float(approx_thd)
    d = _tigris.search(cloud, queries, mode, int(k), float(radius), int(max_nn), h, split_axis, approximate,
                       thd, leader_scope, leader_in_flight, int(leader_capacity), int(leader_width))
    return SearchResult(mode, d)


# ----------------------------------------------------------------------- jobs on the binary

def _write_bin(path, a):
    """A float32 (N, 3) array as a KITTI .bin (x, y, z, intensity 0), the format the binary reads
    bit for bit."""
    out = np.zeros((len(a), 4), dtype="<f4")
    out[:, :3] = a
    out.tofile(path)


def _flags(**kw):
    args = []
    for name, v in kw.items():
        if v is None or v is False:
            continue
        v = _plain(v)
        if v is False:
            continue
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


def run(cloud=None, queries=None, mode="nn", k=10, radius=0.3, max_nn=0, height=None, approx_thd=None,
        config=None, preset=None, set=None, sampling=None, keep=None, **flags):
    """One accelerator job, checked against the golden model, as `tigris run` runs it.

    cloud, queries: float32 (N, 3) arrays (neither: the built-in synthetic pair; a cloud alone is
    searched in itself). config: a dict nested by block or of dotted keys
    ({"fe.recursion_units": 32}); preset: a shipped preset's name (tigris.presets()); both:
    the preset, then the dict over it. set: {key: value} as --set. Other tigris run flags as
    keyword arguments (leader_capacity=8, split_axis="round-robin", sim_threads=1 ...).
    sampling: sim.sampling, "off" (the default), "auto" or the share of queries to simulate
    (docs/sampling.md; the result's cycles_ci95 holds the estimate's interval). keep: a
    folder to keep the run's files in (default: a temporary one, removed). Returns a RunResult;
    raises MismatchError when a query differs from the golden model, TigrisError when the run is
    refused (the CLI's message), ValueError for bad arrays."""
    cloud = _cloud(cloud, "cloud", allow_none=True)
    queries = _cloud(queries, "queries", allow_none=True)
    if queries is not None and cloud is None:
        raise ValueError("queries need a cloud (neither: the built-in synthetic pair)")
    work = keep or tempfile.mkdtemp(prefix="tigris-run-")
    try:
        os.makedirs(work, exist_ok=True)
        args = ["run", "--mode", mode, "--out", os.path.join(work, "out"),
                "--dump-results", os.path.join(work, "results.csv")]
        if cloud is not None:
            _write_bin(os.path.join(work, "cloud.bin"), cloud)
            args += ["--cloud", os.path.join(work, "cloud.bin")]
        if queries is not None:
            _write_bin(os.path.join(work, "queries.bin"), queries)
            args += ["--queries", os.path.join(work, "queries.bin")]
        if mode == "knn":
            args += ["--k", str(k)]
        if mode == "radius":
            args += ["--radius", repr(float(radius)), "--max-nn", str(max_nn)]
        if height is not None:
            args += ["--height", str(height)]
        if approx_thd is not None:
            args += ["--approx-thd", str(approx_thd)]
        args += _config_args(work, config, preset, "--config", "config.json") + _flags(**flags)
        for key, v in (set or {}).items():
            v = _plain(v)
            args += ["--set", f"{key}={json.dumps(v) if isinstance(v, bool) else v}"]
        if sampling is not None:
            args += ["--set", f"sim.sampling={_plain(sampling)}"]
        p = _call(args)
        stats_path = os.path.join(work, "out", "stats.json")
        if p.returncode == 1 and not os.path.exists(stats_path):      # a deadlock: no stats
            raise MismatchError(f"tigris run: {_verdict_text(p)}", None)
        if p.returncode not in (0, 1) or not os.path.exists(stats_path):
            raise TigrisError(f"tigris run: {_error_text(p.stderr)}")
        with open(stats_path) as f:
            result = RunResult(json.load(f), os.path.join(work, "results.csv"), mode)
        if p.returncode == 1:
            raise MismatchError(f"tigris run: {_error_text(p.stderr) if p.stderr.strip() else result.verdict}",
                                result)
        return result
    finally:
        if keep is None:
            shutil.rmtree(work, ignore_errors=True)


def _flat(d, prefix=""):
    """{"fe": {"recursion_units": 16}} as {"fe.recursion_units": 16} (comments "//..." left out)."""
    out = {}
    for k, v in d.items():
        if not isinstance(k, str) or k.startswith("//"):
            continue
        key = f"{prefix}.{k}" if prefix else k
        out.update(_flat(v, key) if isinstance(v, dict) else {key: v})
    return out


def _plain(v):
    """A NumPy scalar as the Python value JSON and the command line take."""
    return v.item() if isinstance(v, np.generic) else v


def _config_args(work, config, preset, flag, name):
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
                merged.update(_flat(json.load(f)))
        else:
            known = presets()
            if preset not in known:
                raise ValueError(f"no preset named {preset!r}; presets: {', '.join(sorted(known))}")
            merged.update(known[preset]["sets"])
    merged.update(_flat(config))
    path = os.path.join(work, name)
    with open(path, "w") as f:
        json.dump(merged, f, default=_plain)
    return [flag, path]


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
    arguments. Returns a Registration; TigrisError with the CLI's message when refused."""
    source = _cloud(source, "source", allow_none=True)
    target = _cloud(target, "target", allow_none=True)
    if (source is None) != (target is None):
        raise ValueError("source and target go together (neither: the built-in synthetic pair)")
    work = keep or tempfile.mkdtemp(prefix="tigris-register-")
    try:
        os.makedirs(work, exist_ok=True)
        args = ["register", "--preset", preset, "--search", search, "--out", os.path.join(work, "out")]
        if source is not None:
            _write_bin(os.path.join(work, "source.bin"), source)
            _write_bin(os.path.join(work, "target.bin"), target)
            args += ["--source", os.path.join(work, "source.bin"), "--target", os.path.join(work, "target.bin")]
        if config is not None:
            if not isinstance(config, dict):
                raise ValueError(f"config must be a dict, got {type(config).__name__}")
            with open(os.path.join(work, "pipeline.json"), "w") as f:
                json.dump(config, f)
            args += ["--config", os.path.join(work, "pipeline.json")]
        args += _config_args(work, accel_config, accel_preset, "--accel-config", "accel.json") + _flags(**flags)
        p = _call(args)
        doc_path = os.path.join(work, "out", "registration.json")
        if p.returncode == 1 and not os.path.exists(doc_path):        # the accelerator failed a job
            raise MismatchError(f"tigris register: {_verdict_text(p)}", None)
        if not os.path.exists(doc_path):
            raise TigrisError(f"tigris register: {_error_text(p.stderr)}")
        with open(doc_path) as f:
            reg = Registration(json.load(f))
        if p.returncode not in (0, 1):
            raise TigrisError(f"tigris register: {_error_text(p.stderr)}")
        return reg
    finally:
        if keep is None:
            shutil.rmtree(work, ignore_errors=True)
