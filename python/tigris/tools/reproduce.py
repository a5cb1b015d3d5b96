#!/usr/bin/python3
"""Reproduces the paper's evaluation (section 6) as sweeps, then the figures and REPORT.md.

    python3 -m tigris reproduce [--out DIR] [--cloud FILE [--queries FILE]] [--quick] [--jobs N]
                               [--tigris PATH] [--only EXP ...] [--specs-only | --report-only]
                               [--variants [NAME ...]] [--variants-file FILE]
                               [--slurm [--partition P] [--time T] [--mem M] [--chunk K]
                                        [--sbatch-arg ARG ...] [--no-wait]]

Writes one sweep spec per experiment to DIR/specs/<exp>.json, runs each with the sweep driver
beside this module (python3 -m tigris sweep SPEC --out DIR/sweeps/<exp>), locally (--jobs)
or as Slurm job arrays (--slurm and its options are passed through), then plots.py's figures into
DIR/figures and report.py's DIR/REPORT.md. Finished points are skipped on a rerun, so an
interrupted or --no-wait run is completed by running the same command again (or --report-only
once the Slurm jobs are done). Every experiment the accelerator's accounting can change also runs
under the preset paper-accounting (docs/model.md, "Two accountings"; --quick leaves out its RU x SU x
PE grids) into DIR/variants/paper-accounting/, REPORT.md's second column of every claim.
--variants also runs the experiments under design variants
(the shipped presets marked as variants, `tigris presets`: details the paper leaves open) into
DIR/variants/<name>/, and REPORT.md gets
the robustness matrix of the claims and DIR/figures/variants.png. Default workload: the built-in synthetic frame pair; a cloud
without --queries is searched in itself. DIR/workload.json records the workload of DIR's
results: a rerun without --cloud reuses it, one with another workload is refused. DIR holds
manifest.json (docs/architecture.md): it must be new, empty or an earlier reproduce's folder, and a
rerun whose cloud or queries file changed content is refused, saying what changed.
Exit codes: 0 REPORT.md written, 1 every point failed (REPORT.md lists them) or no sweep.csv,
2 bad arguments, workload or DIR (or the driver's exit 2), 3 sbatch failed, 128 + the signal
when interrupted (the running sweep is stopped the same way, its finished points kept).
"""
import argparse
import csv
import glob
import io
import json
import os
import shlex
import signal
import sys

from .. import core
from ..data import binary, dse_data
from ..data.spec import FLAG_KEYS
from ..reports import report
from ..reports import variants as vt

HERE = os.path.dirname(os.path.realpath(__file__))
DRIVER = os.path.join(HERE, "sweep.py")   # the sweep driver, run as python3 -m tigris sweep
NC_DEFAULT = 131072
RADIUS = 0.30
WORKLOAD = "workload.json"
# Experiments whose CSV is not of `tigris run` points: the report reads each on its own.
OWN_CSV = ("redundancy", "registrations", "odometry-approx")
# The paper authors' leaf sizes and leader list (PointCloud-pipeline, bin/config.txt, kdtree.h):
# the accuracy claims' second convention (docs/model.md, fidelity targets).
AUTHORS_ACCURACY = {"search.normals_leaf_size": 64, "search.rpce_leaf_size": 32, "search.leader_capacity": 1 << 20}
OUTPUTS = ["specs/", "sweeps/", "variants/", "figures/", "REPORT.md", WORKLOAD]
# The paper's accounting (a shipped preset whose "//preset" has "accounting"): every claim is
# measured under it beside the default machine. --quick leaves its RU x SU x PE grids out (the
# knee claims read not measured in its column), keeping a quick run quick.
ACCOUNTING = "paper-accounting"
QUICK_WITHOUT_ACCOUNTING = ("units-su", "units-pe")


class Refused(core.Refused):
    """Bad arguments, workload or output folder: printed, exit 2."""


def note(msg):
    try:
        print(f"reproduce: {msg}", file=sys.stderr, flush=True)
    except OSError:                              # a hung-up terminal
        pass


def experiments(quick=False):
    """name -> (what it measures, spec without the workload). The full set is the paper's
    grids (64-point RU x SU x PE, top heights 4..15); --quick keeps each figure's and each
    claim's points with fewer heights, thresholds and unit counts."""
    units = [16, 32, 64, 128]
    heights = ["full", 6, 8, 10, 11, 12, 14] if quick else ["full"] + list(range(4, 16))
    heights_r = ["full", 8, 10, 11, 12] if quick else ["full"] + list(range(4, 16))
    nn_thd = [0.3, 1.2, 2.4] if quick else [0.15, 0.3, 0.6, 1.2, 2.4]
    r_thd = [0.06, 0.12] if quick else [0.03, 0.06, 0.12, 0.24]
    radius = {"mode": "radius", "radius": RADIUS}
    exps = {
        "heights-nn": ("redundancy, top height vs time and energy, Acc-KD vs Acc-2SKD (NN)",
                       {"base": {"mode": "nn"}, "grid": {"height": heights}}),
        "heights-radius": ("redundancy, top height vs time and energy, Acc-KD vs Acc-2SKD "
                           f"(radius {RADIUS} m)",
                           {"base": dict(radius), "grid": {"height": heights_r}}),
    }
    if quick:
        exps["units-su"] = ("RU x SU at 32 PE per SU (Fig. 13, knee)",
                            {"base": {"mode": "nn", "set": {"be.pes_per_su": 32}},
                             "grid": {"fe.recursion_units": units, "be.search_units": units}})
        exps["units-pe"] = ("RU x PE at 32 SU (Fig. 13, knee)",
                            {"base": {"mode": "nn", "set": {"be.search_units": 32}},
                             "grid": {"fe.recursion_units": units, "be.pes_per_su": units}})
    else:
        exps["units"] = ("RU x SU x PE, 16..128 each (Fig. 13, knee)",
                         {"base": {"mode": "nn"},
                          "grid": {"fe.recursion_units": units, "be.search_units": units,
                                   "be.pes_per_su": units}})
    opt = lambda b, f, p: {"fe.bypassing": b, "fe.forwarding": f, "be.issue_policy": p}  # noqa: E731
    exps["optimizations"] = ("No-Opt / Bypass / +Forward / MQMN (Fig. 11)",
                             {"base": {"mode": "nn"},
                              "points": [opt(False, False, "mqsn"), opt(True, False, "mqsn"),
                                         opt(True, True, "mqsn"), opt(True, True, "mqmn")]})
    exps["node-cache"] = ("memory traffic and energy with and without the Node Cache (Fig. 12)",
                          {"base": {"mode": "nn"},
                           "grid": {"node_cache.bytes": [NC_DEFAULT, 0], "height": [10, "full"]}})
    # The golden model counts the redundancy under both conventions (docs/model.md, fidelity
    # targets): leaf sets around 32 lie between heights 11 and 12 of a KITTI-sized cloud.
    exps["redundancy"] = ("two-stage redundancy under the model's and the authors' conventions "
                          "(tigris ref --redundancy; self: the cloud searched in itself)",
                          {"command": "ref", "base": {"redundancy": True},
                           "points": [dict(search, height=h) for search in ({"mode": "nn"}, radius)
                                      for h in (11, 12)]})
    # The headline claims (docs/model.md, fidelity targets): whole registrations with the
    # accelerator in the loop against the CPU-only system (PCL's FLANN), exact and approximate,
    # and the approximate search's accuracy cost over a synthetic drive.
    presets = ["dp4"] if quick else ["dp4", "dp7"]
    exps["registrations"] = ("registrations on the CPU (FLANN, golden model) and with the accelerator in the loop "
                             "(exact, approximate): end to end and KD-tree time",
                             {"command": "register",
                              "grid": {"preset": presets, "search": ["flann", "exact", "accel", "accel-approx"]}})
    # The accuracy cost also in the authors' convention (their pipeline's bin/config.txt): leaves of
    # 64 points for normals and 32 for ICP, and a leader list bounded by nothing.
    exps["odometry-approx"] = ("odometry over a synthetic drive, exact against approximate search: the accuracy cost "
                               "(and approximate in the authors' convention: leaves of 64 / 32 points, unbounded "
                               "leaders)",
                               {"command": "odometry", "base": {"synthetic": 4 if quick else 12, "seed": 1},
                                "grid": {"preset": presets, "search": ["exact", "approx"]},
                                "points": [dict(AUTHORS_ACCURACY, preset=p, search="approx") for p in presets]})
    exps["approx-nn"] = ("approximation threshold vs visits, cycles, accuracy (NN); {} = exact",
                         {"base": {"mode": "nn"}, "grid": {"approx-thd": nn_thd}, "points": [{}]})
    exps["approx-radius"] = (f"approximation threshold vs visits, cycles, recall (radius {RADIUS} m)",
                             {"base": dict(radius), "grid": {"approx-thd": r_thd}, "points": [{}]})
    return exps


def with_workload(spec, cloud, queries):
    spec = json.loads(json.dumps(spec))
    base = spec.setdefault("base", {})
    if spec.get("command") == "odometry":  # its own synthetic drive
        return spec
    if spec.get("command") == "register":  # the later frame registered into the earlier one
        if cloud and queries:
            base["source"], base["target"] = os.path.abspath(queries), os.path.abspath(cloud)
        return spec
    if cloud:
        base["cloud"] = os.path.abspath(cloud)
    if queries:
        base["queries"] = os.path.abspath(queries)
    return spec


def show(w):
    return (f"cloud {w['cloud'] or 'synthetic frame 0'}, queries "
            f"{w['queries'] or ('the cloud itself' if w['cloud'] else 'synthetic frame 1')}")


def workload(out, cloud, queries):
    """The workload to run or report on. The results in DIR are of one workload, recorded in
    DIR/workload.json (or, for a DIR made before that file, in its specs): a rerun without
    --cloud reuses it; another one is refused, so specs and results never mix."""
    given = {"cloud": os.path.abspath(cloud) if cloud else None,
             "queries": os.path.abspath(queries) if queries else None}
    path = os.path.join(out, WORKLOAD)
    results = glob.glob(os.path.join(glob.escape(out), "sweeps", "*", "plan.json"))
    rec = None
    if os.path.lexists(path):
        try:
            rec = core.read_json_input(path, WORKLOAD)
            if not (isinstance(rec, dict) and all(isinstance(rec.get(k), (str, type(None))) for k in given)):
                raise core.Refused("not {\"cloud\": path or null, \"queries\": path or null}")
        except core.Refused as e:
            raise Refused(f"{path}: unreadable ({e}); it records the workload of {out}'s results: "
                          "repair or delete it, or use another --out")
        rec = {k: rec.get(k) for k in given}
    if rec is None or not results:
        return given
    if cloud is None and queries is None:
        if rec != given:
            note(f"{out} holds results of {show(rec)} ({path}): reusing that workload")
        return rec
    if rec != given:
        raise Refused(f"{out} holds results of {show(rec)} ({path}); this run asks for {show(given)}: "
                      "the results would mix. Rerun without --cloud/--queries to use the recorded "
                      "workload, or use another --out")
    return rec


write_json = core.write_json


def write_specs(out, names, quick, cloud, queries):
    """Writes DIR/specs/<exp>.json and DIR/workload.json; returns [(name, spec path, sweep folder)]."""
    exps = experiments(quick)
    made = []
    try:
        os.makedirs(os.path.join(out, "specs"), exist_ok=True)
        write_json(os.path.join(out, WORKLOAD), {"cloud": cloud, "queries": queries})
        for name in names:
            what, spec = exps[name]
            if name == "registrations" and cloud and not queries:
                note("registrations: a cloud alone has no second frame to register; left out")
                continue
            spec = with_workload(spec, cloud, queries)
            if name == "redundancy" and cloud and queries:  # also the cloud searched in itself
                spec["points"] += [dict(p, queries=os.path.abspath(cloud)) for p in spec["points"]]
            spec["comment"] = f"tigris/tools/reproduce.py{' --quick' if quick else ''}: {what}"
            path = os.path.join(out, "specs", name + ".json")
            write_json(path, spec)
            made.append((name, path, os.path.join(out, "sweeps", name)))
    except OSError as e:
        raise Refused(f"cannot write {e.filename or out}: {e.strerror or e}")
    return made


def variant_plan(out, plan, chosen, defaults, quick, cloud, queries, omit=()):
    """[(variant, [(exp, spec path or None, sweep folder)])]: each variant's specs in
    DIR/variants/<name>/specs/; an experiment the variant cannot change has no spec and is read
    from the default's sweep folder; one in `omit` has no entry (its claims are not measured
    under the variant). DIR/variants/<name>/variant.json records the definition its results
    belong to: a rerun with another definition under that name is refused."""
    exps = experiments(quick)
    made = []
    for v in chosen:
        vdir = os.path.join(out, "variants", v.name)
        rec_path = os.path.join(vdir, vt.VARIANT_FILE)
        if glob.glob(os.path.join(glob.escape(vdir), "sweeps", "*", "plan.json")) and os.path.exists(rec_path):
            try:
                rec = core.read_json_input(rec_path, vt.VARIANT_FILE)
            except core.Refused as e:
                raise Refused(f"{rec_path}: unreadable ({e}); it records the variant of {vdir}'s "
                              "results: repair or delete it")
            if rec != v.as_json():
                raise Refused(f"{vdir} holds results of variant {v.name!r} defined as {json.dumps(rec)}; "
                              f"it is now {json.dumps(v.as_json())}: the results would mix. Give the "
                              "variant another name, or delete that folder")
        entries = []
        try:
            os.makedirs(os.path.join(vdir, "specs"), exist_ok=True)
            write_json(rec_path, v.as_json())
            for name, _spec, folder in plan:
                if name in omit:
                    continue
                what, spec = exps[name]
                if not vt.affects(v, name, spec):
                    entries.append((name, None, folder))
                    continue
                spec = with_workload(vt.apply(spec, v, defaults), cloud, queries)
                spec["comment"] = (f"tigris/tools/reproduce.py{' --quick' if quick else ''}: {what}; "
                                   f"variant {v.name}: {v.describe()}")
                path = os.path.join(vdir, "specs", name + ".json")
                write_json(path, spec)
                entries.append((name, path, os.path.join(vdir, "sweeps", name)))
        except OSError as e:
            raise Refused(f"cannot write {e.filename or vdir}: {e.strerror or e}")
        made.append((v, entries))
    return made


def accounting_plan(out, plan, defaults, quick, cloud, queries):
    """The paper's accounting's (variant, entries) of variant_plan: its keys are no experiment's
    axis, so it needs no model defaults to apply (`defaults` may be empty)."""
    try:
        v = vt.accounting(ACCOUNTING)
    except vt.VariantError as e:
        raise Refused(f"the paper's accounting: {e}")
    return variant_plan(out, plan, [v], defaults, quick, cloud, queries,
                        omit=QUICK_WITHOUT_ACCOUNTING if quick else ())[0]


def driver_argv(a, args):
    """(argv, env) of the sweep driver with `args`: the package's tigris sweep as a module
    (env: PYTHONPATH finds the package), or another script --driver names (env: this one's)."""
    if os.path.realpath(a.driver) == os.path.realpath(DRIVER):
        return core.python_module_command("sweep", args)
    return [sys.executable, a.driver] + list(args), None


def driver_command(spec, folder, a):
    """(argv, env) that run the driver on spec into folder."""
    cmd = [spec, "--out", folder]
    if a.tigris:
        cmd += ["--tigris", a.tigris]
    if a.slurm:
        cmd.append("--slurm")
        for opt in ("partition", "time", "mem", "chunk"):
            if getattr(a, opt) is not None:
                cmd += [f"--{opt}", str(getattr(a, opt))]
        for s in a.sbatch_arg or []:
            cmd.append(f"--sbatch-arg={s}")
        if a.no_wait:
            cmd.append("--no-wait")
    else:
        cmd += ["--jobs", str(a.jobs)]
    return driver_argv(a, cmd)


def parse_args(argv):
    argv = list(sys.argv[1:] if argv is None else argv)
    fixed = []  # `--sbatch-arg --qos=x` as well as `--sbatch-arg=--qos=x`, as the driver takes it
    while argv:
        a = argv.pop(0)
        fixed.append(f"--sbatch-arg={argv.pop(0)}" if a == "--sbatch-arg" and argv else a)
    argv = fixed
    names = list(experiments(False)) + [n for n in experiments(True) if n not in experiments(False)]
    ap = argparse.ArgumentParser(prog="reproduce", description=__doc__.split("\n\n")[0],
                                 epilog="experiments: " + ", ".join(names))
    core.role(ap.add_argument("--out", default="reproduce-out", help="output folder (default reproduce-out)"),
              "out_folder")
    core.role(ap.add_argument("--cloud", help="tree cloud (KITTI .bin, .pcd, .ply); default: synthetic frame 0, "
                              "or the one OUT/workload.json records"), "input")
    core.role(ap.add_argument("--queries", help="query points (needs --cloud); default: the cloud itself, "
                              "synthetic frame 1 without --cloud"), "input")
    ap.add_argument("--quick", action="store_true", help="small grids (a few minutes on 2 cores)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="local points at once")
    core.role(ap.add_argument("--tigris", help="tigris binary (passed to the driver)"), "input")
    core.role(ap.add_argument("--driver", default=DRIVER, help="the sweep driver (default: tigris/tools/sweep.py, "
                              "run as python3 -m tigris sweep)"), "input")
    core.role(ap.add_argument("--dse", metavar="DIR", help="a `tigris pipeline-dse` folder: the report adds "
                              "the paper's section-3 claims measured there"), "input")
    ap.add_argument("--only", nargs="+", metavar="EXP", choices=names, help="only these experiments")
    try:
        shipped = ", ".join(vt.by_name())
    except vt.VariantError as e:
        shipped = f"none readable ({e})"
    ap.add_argument("--variants", nargs="*", metavar="NAME", help="also run the experiments under "
                    "design variants (all of them, or the NAMEs): " + shipped +
                    "; REPORT.md gets the robustness matrix (the shipped presets marked as variants: "
                    "`tigris presets` says what each changes and why). The paper's accounting ("
                    f"{ACCOUNTING}) is no variant: every run measures it")
    core.role(ap.add_argument("--variants-file", metavar="FILE", help="your own variants (JSON, see "
                              "docs/sweeps.md), added to the built-in list; implies --variants"), "input")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--specs-only", action="store_true", help="write the specs, run nothing")
    g.add_argument("--report-only", action="store_true",
                   help="no runs: re-collect the sweep folders, then the figures and the report")
    s = ap.add_argument_group("Slurm (passed to tigris/tools/sweep.py)")
    s.add_argument("--slurm", action="store_true", help="run every sweep as a Slurm job array")
    s.add_argument("--partition")
    s.add_argument("--time")
    s.add_argument("--mem")
    s.add_argument("--chunk", type=int)
    s.add_argument("--sbatch-arg", action="append", metavar="ARG")
    s.add_argument("--no-wait", action="store_true", help="return after submitting; rerun with "
                   "--report-only when the jobs are done")
    ap.add_argument("--list-flags", action="store_true", help="Print this command's flags as JSON (flag, type, "
                    "default, meaning) for tools, and exit")
    core.list_flags(ap, "reproduce", argv)
    a = ap.parse_args(argv)
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    if not a.slurm and (a.partition or a.time or a.mem or a.chunk or a.sbatch_arg or a.no_wait):
        ap.error("--partition, --time, --mem, --chunk, --sbatch-arg and --no-wait need --slurm")
    if not a.out.strip():
        ap.error("--out is empty: give the output folder (an empty path would be the current folder)")
    for flag, f in (("--cloud", a.cloud), ("--queries", a.queries)):
        if f is not None:
            try:
                core.check_input(f, flag)
            except core.Refused as e:
                ap.error(str(e))
    if a.queries and not a.cloud:
        ap.error("--queries needs --cloud (the cloud its points are searched in; a cloud alone is "
                 "searched in itself)")
    exps = experiments(a.quick)
    a.names = [n for n in (a.only or list(exps)) if n in exps]
    bad = [n for n in (a.only or []) if n not in exps]
    if bad:
        ap.error(f"{', '.join(bad)}: not an experiment of the {'quick' if a.quick else 'full'} set "
                 f"({', '.join(exps)})")
    return a


def call_driver(cmd, env=None):
    """Runs the driver; a signal here stops it the way the driver stops its points (it kills
    them and keeps the finished ones): SIGTERM to its group, SIGKILL only after its own children's
    grace, and they stop with it anyway (PR_SET_PDEATHSIG)."""
    return core.run_child(cmd, grace=2 * core.KILL_AFTER, env=env)


def main(argv=None):
    core.handle_stop_signals()
    argv = list(sys.argv[1:] if argv is None else argv)
    a = parse_args(argv)
    a.command_line = "tigris reproduce " + shlex.join(argv)
    if a.tigris:  # the report's model defaults come from the binary that ran
        os.environ["TIGRIS"] = os.path.abspath(a.tigris)
    out = os.path.abspath(a.out)
    folder = core.OutFolder(out, "reproduce", OUTPUTS, argv=argv)
    try:
        folder.check_path()
        if a.dse:                                # a typo found now, not after every sweep
            try:
                dse_data.read_dse(a.dse)
            except ValueError as e:
                raise Refused(f"--dse: {e}")
        w = workload(out, a.cloud, a.queries)
        chosen, defaults = choose_variants(a)
        paths = [(f, p) for f, p in (("--cloud", w["cloud"]), ("--queries", w["queries"]),
                                     ("--variants-file", a.variants_file)) if p]
        ids = [core.input_identity(f[2:], p) for f, p in paths[:2] if f != "--variants-file"]
        folder.claim(settings={"cloud": w["cloud"], "queries": w["queries"]}, inputs=ids, input_paths=paths)
    except core.Refused as e:
        print(f"reproduce: error: {e}", file=sys.stderr)
        return 2
    rc = 2
    try:
        plan = write_specs(out, a.names, a.quick, w["cloud"], w["queries"])
        aplan = accounting_plan(out, plan, defaults, a.quick, w["cloud"], w["queries"])
        vplan = variant_plan(out, plan, chosen, defaults, a.quick, w["cloud"], w["queries"]) if chosen else []
        rc = run(a, out, plan, vplan, aplan)
        return rc
    except core.Refused as e:
        print(f"reproduce: error: {e}", file=sys.stderr)
        return 2
    except core.SlurmFailed as e:
        print(f"reproduce: error: {e}", file=sys.stderr)
        rc = core.SBATCH_FAILED
        return rc
    except KeyboardInterrupt as e:
        rc = core.exit_status(e)
        note(f"interrupted ({signal.Signals(rc - 128).name}); finished points are kept")
        return rc
    finally:
        folder.finish(rc)


def choose_variants(a):
    """The variants to run ([] without --variants) and the model's defaults they replace."""
    if a.variants is None and not a.variants_file:
        return [], {}
    try:
        tig = binary.tigris_at(a.tigris or binary.default_tigris(), "run")
    except binary.SpecError as e:
        raise Refused(f"--variants: the model's keys and defaults come from the tigris binary: {e}")
    defaults = dict(tig.config, **{"leader-width": tig.flags.get("leader-width")})
    try:
        user = vt.load(a.variants_file, list(experiments(a.quick)), tig.key_info,
                       set(FLAG_KEYS["run"].values())) if a.variants_file else []
        chosen = vt.choose(a.variants or [], user, a.variants_file)
        known = set(experiments(a.quick))
        for v in chosen:                          # a shipped preset naming no experiment of ours
            bad = [e for e in v.experiments or [] if e not in known]
            if bad:
                raise vt.VariantError(f"variant {v.name!r}: \"experiments\": not an experiment: {', '.join(bad)} "
                                      f"({', '.join(sorted(known))})")
        return chosen, defaults
    except vt.VariantError as e:
        raise Refused(str(e))


def run_sweeps(a, entries, failed, pending, prefix=""):
    """Runs (or with --report-only collects) each (name, spec, folder); entries without a spec
    are another configuration's folders. Returns the driver's fatal exit code, or 0."""
    for name, spec, folder in entries:
        if spec is None:
            continue
        label = prefix + name
        if a.report_only:
            if not os.path.isfile(os.path.join(folder, "plan.json")):
                print(f"reproduce: {label}: no sweep in {folder} (not run)", file=sys.stderr)
                continue
            cmd, env = driver_argv(a, ["collect", folder])
        else:
            cmd, env = driver_command(spec, folder, a)
        note(f"{label}: {' '.join(cmd)}")
        rc = call_driver(cmd, env)
        if rc == 2 or rc == 3 or rc >= 128:
            print(f"reproduce: {label}: the driver failed (exit {rc})", file=sys.stderr)
            return rc
        if rc == 1:
            failed.append(label)
        if a.slurm and a.no_wait and not a.report_only:
            pending.append(label)
    return 0


def sweep_csvs(entries, own=False):
    """The sweep.csv of each entry that has one: of `tigris run` sweeps, or (own) of the others."""
    return [os.path.join(f, "sweep.csv") for n, _, f in entries
            if os.path.isfile(os.path.join(f, "sweep.csv")) and (n in OWN_CSV) == own]


def run(a, out, plan, vplan=(), aplan=None):
    note(f"{len(plan)} sweep specs in {os.path.join(out, 'specs')}"
         + (f"; the paper's accounting: {sum(1 for e in aplan[1] if e[1])} sweeps in "
            f"{os.path.join(out, 'variants', aplan[0].name)}" if aplan else "")
         + (f"; {len(vplan)} variant(s) in {os.path.join(out, 'variants')}: "
            + ", ".join(f"{v.name} ({sum(1 for e in ent if e[1])} sweeps)" for v, ent in vplan) if vplan else ""))
    if a.specs_only:
        return 0
    if not os.path.isfile(a.driver):
        print(f"reproduce: the sweep driver {a.driver} is missing", file=sys.stderr)
        return 2
    failed, pending = [], []
    rc = run_sweeps(a, plan, failed, pending)
    configs = ([aplan] if aplan else []) + list(vplan)
    for v, entries in configs:
        rc = rc or run_sweeps(a, entries, failed, pending, prefix=f"{v.name}/")
    if rc:
        return rc
    if pending:
        print(f"reproduce: submitted {len(pending)} Slurm sweep(s); when they are done, run the "
              f"same command with --report-only instead of --no-wait", file=sys.stderr)
        return 0
    # `tigris run` sweeps feed the claim groups; the others (ref, register, odometry) their own.
    found = {n: os.path.join(f, "sweep.csv") for n, _, f in plan if os.path.isfile(os.path.join(f, "sweep.csv"))}
    csvs = [c for n, c in found.items() if n not in OWN_CSV]
    red = [found["redundancy"]] if "redundancy" in found else []
    if not csvs:
        print("reproduce: no sweep.csv to report on", file=sys.stderr)
        return 1
    try:
        import matplotlib  # noqa: F401
        draw = True
    except ImportError:
        print("reproduce: matplotlib is missing (Debian: apt-get install python3-matplotlib; run "
              "with /usr/bin/python3): REPORT.md without figures", file=sys.stderr)
        draw = False
    title = "Tigris TLM: the paper's evaluation, reproduced" + (" (--quick)" if a.quick else "")
    vcsvs = [(v.name, v, sweep_csvs(entries)) for v, entries in vplan]
    accounting = None
    if aplan:  # its registrations: the accelerator points it ran (the CPU's are the default's)
        reg = sweep_csvs([e for e in aplan[1] if e[0] == "registrations" and e[1]], own=True)
        accounting = (aplan[0], sweep_csvs(aplan[1]), reg[0] if reg else None)
    try:
        path, claims = report.write_report(csvs, out, os.path.join(out, "figures"), draw, title,
                                           dse_dir=a.dse, variants=vcsvs, command=a.command_line,
                                           redundancy=red[0] if red else None,
                                           headline=(found.get("registrations"), found.get("odometry-approx")),
                                           accounting=accounting)
    except (OSError, ValueError) as e:
        print(f"reproduce: error: the report: {e}", file=sys.stderr)
        return 2
    measured = [c for c in claims if c.measured != "not measured"]
    print(f"reproduce: {path}: {len(measured)} of {len(claims)} claims measured; on the default machine "
          f"{report.counts(claims)} (its summary gives the paper's accounting's too)"
          + (f"; sweeps with failed points: {', '.join(failed)}" if failed else ""), file=sys.stderr)
    statuses = csv_statuses(csvs)
    if "ok" not in statuses:
        print(f"reproduce: every point failed ({len(statuses)} points in {len(csvs)} sweep{'s' if len(csvs) > 1 else ''}): no claim "
              f"could be measured; the errors are in {path}, section \"Rows not ok\"", file=sys.stderr)
        return 1
    # A configuration not run at all (--report-only on an earlier folder) is not measured, not dead.
    ran = [(v, csv_statuses(os.path.join(f, "sweep.csv") for _, spec, f in entries if spec)) for v, entries in configs]
    dead = [v.name for v, statuses in ran if statuses and "ok" not in statuses]
    if dead:  # its column would hold the default's shared rows only: a robustness that was not measured
        print(f"reproduce: every run of variant(s) {', '.join(dead)} failed (their sweep.csv under "
              f"{os.path.join(out, 'variants')} say why): their columns are not measured", file=sys.stderr)
        return 1
    return 0


def csv_statuses(paths):
    statuses = []
    for p in paths:
        if os.path.isfile(p):
            statuses += [r.get("status") for r in csv.DictReader(io.StringIO(core.read_text_input(p), newline=""))]
    return statuses


if __name__ == "__main__":
    sys.exit(main())
