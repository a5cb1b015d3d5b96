#!/usr/bin/python3
"""tigris sweep: runs a sweep spec of `tigris run`, `ref`, `register` or `odometry` points
locally or as one Slurm job array, and collects one CSV (docs/sweeps.md).

  python3 -m tigris sweep SPEC.json --out DIR [--jobs N] [--tigris PATH] [--check]
                  [--slurm [--partition P] [--time T] [--mem M] [--chunk K]
                           [--sbatch-arg ARG ...] [--no-wait]]
  python3 -m tigris sweep collect DIR      re-collect DIR/sweep.csv and DIR/sweep.json

Python 3 standard library only, with the package's core (folders, inputs, child processes);
Slurm tasks run this same module as `_task TASKFILE INDEX`. The folder is held for the run and
recorded in DIR/manifest.json (docs/architecture.md, "The shared core").
Exit codes: 0 every point ok, 1 some point mismatched or failed (the CSV is still written),
2 bad spec, arguments or sweep folder, 3 Slurm submission failed, 128 + the signal when
interrupted (130 SIGINT, 129 SIGHUP, 143 SIGTERM; finished points kept).
"""
import argparse, csv, datetime, io, json, os, re, shlex
import shutil, signal, socket, subprocess, sys, tempfile, time

from .. import core
from ..data.binary import COMMANDS, SpecError, Tigris, default_tigris, tigris_at  # noqa: F401
from ..data.spec import NOT_SWEEPABLE, Spec, cli_value, csv_value, inputs_of  # noqa: F401

PROG = "tigris sweep"

WALL = "wall_seconds"
# The sweep folder's own entries (its manifest's outputs); `tigris plot DIR` writes DIR/plots.
OUTPUTS = ["plan.json", "points/", "sweep.csv", "sweep.json", "slurm/", "plots/"]
# The sweep's files in a point's folder, which the point's tigris (the folder's owner) leaves alone.
POINT_FILES = ["point.json", "stdout.txt", "stderr.txt"]



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


# ----------------------------------------------------------------------------------------------
# One point: `tigris run ARGS --out DIR/points/<id>`, recorded in point.json (child processes:
# core.pool and core.spawn, in their own process groups, stopped with the driver)

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


def flatten(stats):
    """Scalar leaves of stats.json as (dotted path, value); lists and `config` left out."""
    return [(k, v) for k, v in core.dotted(stats).items()
            if not isinstance(v, (dict, list)) and k != "config" and not k.startswith("config.")]


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
    # python3 -m tigris sweep on the node, the package found by its absolute folder.
    task, env = core.python_module_command("sweep", ["_task", tasks])
    write_text(script, "#!/bin/sh\n# One task of a tigris sweep job array: runs its chunk of points.\n"
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
    cmd, env = core.python_module_command("sweep", ["collect", out])
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

    def body():
        if argv[:1] == ["_task"] and len(argv) == 3:
            return run_task(argv[1], argv[2])
        if argv[:1] == ["collect"]:
            if len(argv) != 2 or argv[1].startswith("-") or not argv[1].strip():
                die("usage: tigris sweep collect DIR")
            return collect_command(os.path.abspath(argv[1]))
        return run(parse_args(argv))
    return core.run_command(body, lambda m: say(f"{PROG}: {m}"), "running points stopped; finished points are "
                            "kept (rerun the same command to resume)")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
