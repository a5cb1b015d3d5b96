#!/usr/bin/env python3
"""The shared core against a hostile user (docs/architecture.md, "The shared core"): output
folders, inputs and child processes of the C++ commands (ref, run, register, odometry, synth).
Each case is a reproduction of the hardening round that found each command doing these on its
own; it must end with its exit code and a message naming what is wrong, and nothing that was
not the command's may change. The Python commands' cases are in python/tests/test_hostile.py.

Run: python3 -m pytest tests/hostile_core.py --tigris PATH [-k GROUP] (a test per group of
cases; each names every case that failed).
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from support import TIMEOUT, Cases, digest


@pytest.fixture(scope="module")
def work(tigris, tmp_path_factory):
    """The cases' working folder, with a small synthetic sequence (`small`) to copy."""
    d = str(tmp_path_factory.mktemp("core"))
    p = Cases(tigris, d).run(["synth", "--frames", "3", "--out", "small"])
    assert p.returncode == 0, p.stderr
    return d


def copy_sequence(d, name):
    dst = os.path.join(d, name)
    shutil.rmtree(dst, ignore_errors=True)
    shutil.copytree(os.path.join(d, "small"), dst, symlinks=True)
    if os.path.exists(os.path.join(dst, "manifest.json")):
        os.remove(os.path.join(dst, "manifest.json"))  # a user's copy: not tigris synth's folder
    return dst


def folders(c, d):
    """Data lost or overwritten (reproductions 1, 4, 6): a folder with files the command did not write."""
    seq = copy_sequence(d, "kitti")
    before = digest(os.path.join(seq, "poses.txt"))
    c.expect("odometry --synthetic into a KITTI sequence is refused", ["odometry", "--synthetic", "2", "--out", seq],
             2, ["did not write", "poses.txt"])
    c.expect("odometry --sequence S --out S: its poses.txt is an input", ["odometry", "--sequence", seq, "--out", seq],
             2, ["poses.txt", "--out"])
    c.check("  ... the ground truth is intact", digest(os.path.join(seq, "poses.txt")) == before)
    os.makedirs(os.path.join(d, "F"))
    with open(os.path.join(d, "F", "calib.txt"), "w") as f:
        f.write("P0: mine\n")
    c.expect("synth into a folder with a user's calib.txt", ["synth", "--frames", "2", "--out", "F"], 2,
             ["did not write (calib.txt)"], lambda: None if open(os.path.join(d, "F", "calib.txt")).read() ==
             "P0: mine\n" else "calib.txt changed")
    c.expect("ref --out a synth folder (another command's)", ["ref", "--out", "small"], 2,
             ["holds the output of tigris synth"])
    # A replay: a trace recorded, replayed; its own job file as the next replay's trace is refused.
    c.expect("register --record-trace into its own --out", ["register", "--record-trace", "R/t.bin", "--out", "R"],
             0, ["registration.json"])
    c.expect("run --trace, --jobs 2", ["run", "--trace", "R/t.bin", "--trace-stages", "icp", "--jobs", "2",
                                       "--out", "D"], 0, ["MATCH"])
    jobs = sorted(os.listdir(os.path.join(d, "D", "jobs")))
    shutil.copy(os.path.join(d, "R", "t.bin"), os.path.join(d, "D", "jobs", jobs[0]))
    before = digest(os.path.join(d, "D", "jobs", jobs[0]))
    c.expect("run --trace D/jobs/FILE --out D: the input is an output", ["run", "--trace", f"D/jobs/{jobs[0]}",
             "--out", "D"], 2, ["lies in --out D", "jobs"],
             lambda: None if digest(os.path.join(d, "D", "jobs", jobs[0])) == before else "the trace was overwritten")
    with open(os.path.join(d, "D", "jobs", "job_99999.json"), "w") as f:
        f.write("{}")
    c.expect("a fresh replay clears the earlier replay's job files", ["run", "--trace", "R/t.bin", "--trace-stages",
             "icp", "--out", "D"], 0, ["MATCH"],
             lambda: "job_99999.json is still there" if os.path.exists(os.path.join(d, "D", "jobs", "job_99999.json"))
             else None)
    c.expect("run --trace X --out FILE: refused before any job runs", ["run", "--trace", "R/t.bin", "--out", "R/t.bin"],
             2, ["exists and is not a folder"])
    # An output flag naming the folder's manifest (hardening round 4, reproduction 2).
    for name, args in [("run --timeline OUT/manifest.json", ["run", "--timeline", "M1/manifest.json", "--out", "M1"]),
                       ("ref --dump-results OUT/manifest.json", ["ref", "--dump-results", "M2/manifest.json",
                                                                 "--out", "M2"])]:
        c.expect(f"{name} is refused before any work", args, 2, ["manifest.json", "another name"],
                 lambda a=args: None if not os.path.exists(os.path.join(d, a[-1], "stats.json")) else "it ran")
    with open(os.path.join(d, "D", "note.txt"), "w") as f:
        f.write("mine")
    c.expect("run --out a folder holding a user's file", ["run", "--out", "D"], 2, ["did not write (note.txt)"])


def odometry(c, d):
    """Resume with changed inputs (7), concurrent runs (5), damaged pair reports (17), flags first (21)."""
    seq = copy_sequence(d, "seq")
    c.expect("odometry, 1 pair", ["odometry", "--sequence", seq, "--frames", "0:1", "--out", "O"], 0, ["ATE"])
    c.expect("odometry rerun resumes", ["odometry", "--sequence", seq, "--frames", "0:1", "--out", "O"], 0,
             ["1 already in O"])
    with open(os.path.join(seq, "poses.txt"), "a") as f:
        f.write("\n")
    c.expect("odometry rerun after poses.txt changed is refused", ["odometry", "--sequence", seq, "--frames", "0:1",
             "--out", "O"], 2, ["input poses.txt", "content changed"])
    os.truncate(os.path.join(seq, "poses.txt"), os.path.getsize(os.path.join(seq, "poses.txt")) - 1)
    scan = os.path.join(seq, "velodyne", "000001.bin")
    data = open(scan, "rb").read()
    with open(scan, "wb") as f:
        f.write(data[:-16])
    c.expect("odometry rerun after a scan changed is refused", ["odometry", "--sequence", seq, "--frames", "0:1",
             "--out", "O"], 2, ["input scan 000001", "content changed"])
    with open(scan, "wb") as f:
        f.write(data)
    c.expect("odometry rerun with other frames is refused", ["odometry", "--sequence", seq, "--frames", "0:2",
             "--out", "O"], 2, ["settings.frames"])
    reg = os.path.join(d, "O", "pairs", "000000", "registration.json")
    good = open(reg).read()
    with open(reg, "w") as f:
        f.write(good[:len(good) // 2])
    c.expect("a truncated pair report is named", ["odometry", "--sequence", seq, "--frames", "0:1", "--out", "O"], 2,
             [reg.replace(d + "/", ""), "JSON"])
    j = json.loads(good)
    del j["stages"]
    with open(reg, "w") as f:
        json.dump(j, f)
    c.expect("a pair report without stages is named", ["odometry", "--sequence", seq, "--frames", "0:1", "--out", "O"],
             2, ["registration.json", "no 'stages'"])
    j = json.loads(good)
    j["stages"][next(iter(j["stages"]))]["seconds"] = "fast"
    with open(reg, "w") as f:
        json.dump(j, f)
    c.expect("a pair report with a text for seconds is named", ["odometry", "--sequence", seq, "--frames", "0:1",
             "--out", "O"], 2, ["registration.json", "'seconds'"])
    with open(reg, "w") as f:
        f.write(good)
    # Two runs into one folder started together: exactly one runs, the other is refused.
    procs = [subprocess.Popen([c.t, "odometry", "--sequence", seq, "--frames", "0:1", "--set",
                               f"icp.max_iterations={n}", "--out", "P"], cwd=d, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True) for n in (20, 30)]
    outs = [(p.wait(timeout=TIMEOUT), p.stderr.read()) for p in procs]
    codes = sorted(code for code, _ in outs)
    c.check(f"two odometry runs into one folder: exits {codes}", codes == [0, 2] and any(
        "another run is writing into this folder" in e for _, e in outs), str(outs))
    for flag in (["--approx-thd", "abc"], ["--set", "icp.bogus=1"], ["--search", "accel", "--accel-set", "fe.bogus=1"]):
        c.expect(f"odometry {' '.join(flag)}: refused before its folder exists",
                 ["odometry", "--sequence", seq, "--out", "Q"] + flag, 2, [flag[-2]],
                 lambda: "Q was created" if os.path.exists(os.path.join(d, "Q")) else None)
    t0 = time.time()
    c.expect("register --compare --accel-set fe.bogus=1: refused before any back-end runs",
             ["register", "--compare", "--accel-set", "fe.bogus=1", "--out", "C"], 2, ["--accel-set", "fe.bogus"],
             lambda: "C was created" if os.path.exists(os.path.join(d, "C")) else
             (f"took {time.time() - t0:.0f} s" if time.time() - t0 > 60 else None))


def inputs(c, d):
    """Devices, FIFOs, links (18, 11, 23) and values no file should hold (9, 14, 23)."""
    os.mkfifo(os.path.join(d, "fifo.json"))
    for args, path, needle in ((["run", "--trace", "/dev/zero"], "/dev/zero", "character device"),
                               (["run", "--config", "/dev/zero"], "/dev/zero", "character device"),
                               (["run", "--config", "fifo.json"], "fifo.json", "FIFO"),
                               (["run", "--cloud", "/dev/zero"], "/dev/zero", "character device"),
                               (["register", "--ground-truth", "/dev/zero"], "/dev/zero", "character device"),
                               (["register", "--kitti-poses", "/dev/zero"], "/dev/zero", "character device"),
                               (["register", "--config", "/dev/zero"], "/dev/zero", "character device"),
                               (["register", "--search", "accel", "--accel-config", "/dev/zero"], "/dev/zero",
                                "character device")):
        c.expect(" ".join(args), args + ["--out", "I"], 2, [path, needle])
    for name, target, needle in (("poses.txt", "/dev/zero", "character device"),
                                 ("calib.txt", "/dev/zero", "character device"),
                                 ("calib.txt", "nowhere", "broken symbolic link"),
                                 ("poses.txt", "fifo.json", "FIFO")):
        seq = copy_sequence(d, "dev")
        os.remove(os.path.join(seq, name))
        os.symlink(target if target.startswith("/") else os.path.join(d, target), os.path.join(seq, name))
        c.expect(f"odometry with {name} -> {target}", ["odometry", "--sequence", seq, "--out", "I2"], 2,
                 [name, needle])
    seq = copy_sequence(d, "dir")
    os.remove(os.path.join(seq, "poses.txt"))
    os.mkdir(os.path.join(seq, "poses.txt"))
    c.expect("odometry with poses.txt a folder", ["odometry", "--sequence", seq, "--out", "I3"], 2,
             ["poses.txt", "is a folder"])
    seq = copy_sequence(d, "loop")
    scan = os.path.join(seq, "velodyne", "000002.bin")
    os.remove(scan)
    os.symlink("000002.bin", scan)
    c.expect("odometry with a scan that links to itself", ["odometry", "--sequence", seq, "--out", "I4"], 2,
             ["000002.bin", "loop of symbolic links"])
    seq = copy_sequence(d, "tr")
    with open(os.path.join(seq, "calib.txt")) as f:
        lines = f.read().splitlines()
    lines = [(" ".join(ln.split()[:4] + ["1e300"] + ln.split()[5:]) if ln.startswith("Tr:") else ln) for ln in lines]
    with open(os.path.join(seq, "calib.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    c.expect("odometry with Tr's translation 1e300", ["odometry", "--sequence", seq, "--out", "I5"], 2,
             ["calib.txt:", "beyond 100 m"])
    scans = [os.path.join(d, "small", "velodyne", f"00000{i}.bin") for i in (0, 1)]
    poses = os.path.join(d, "small", "poses.txt")
    c.expect("register --kitti-frames 1,1: a standstill has no per-metre error",
             ["register", "--source", scans[1], "--target", scans[1], "--kitti-poses", poses, "--kitti-frames", "1,1",
              "--out", "I6"], 0, ["per metre: n/a"],
             lambda: None if json.load(open(os.path.join(d, "I6", "registration.json")))["error"].get(
                 "translation_m_per_m") is None else "translation_m_per_m is a number")
    with open(os.path.join(d, "gt.txt"), "w") as f:
        f.write("1 0 0 1e-320\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
    c.expect("a ground truth holding 1e-320 (a subnormal) is finite", ["register", "--ground-truth", "gt.txt",
             "--out", "I7"], 0, ["error vs ground truth"])


def recorded_trace(c, d):
    """A registration's trace to replay: the folders group's (R/t.bin) when it ran, else one
    recorded now (a registration is the slowest step here, under the sanitizers most of all)."""
    if os.path.exists(os.path.join(d, "R", "t.bin")):
        return "R/t.bin"
    c.expect("register --record-trace for the replay", ["register", "--record-trace", "K6t.bin", "--out", "K6r"], 0, [])
    return "K6t.bin"


def children(c, d):
    """SIGTERM to the parent alone stops every child (19, 20)."""
    seq = copy_sequence(d, "kids")
    c.stop_parent("odometry --jobs 2, SIGTERM to the parent", ["odometry", "--sequence", seq, "--jobs", "2",
                                                               "--out", "K1"], 2)
    try:
        status = json.load(open(os.path.join(d, "K1", "manifest.json")))["status"]
    except (OSError, ValueError, KeyError) as e:
        status = repr(e)
    c.check("  ... its manifest says interrupted", status == "interrupted", status)
    c.stop_parent("odometry, SIGINT to the parent", ["odometry", "--sequence", seq, "--out", "K2"], 1, signal.SIGINT)
    c.stop_parent("odometry, SIGHUP to the parent", ["odometry", "--sequence", seq, "--out", "K3"], 1, signal.SIGHUP)
    c.stop_parent("register --compare, SIGTERM to the parent", ["register", "--compare", "--out", "K4"], 1)
    c.stop_parent("register --search accel (model server), SIGTERM", ["register", "--search", "accel",
                                                                       "--out", "K5"], 2)
    c.stop_parent("run --trace --jobs 2, SIGTERM to the parent", ["run", "--trace", recorded_trace(c, d), "--jobs", "2",
                                                                  "--out", "K6"], 2)
    c.expect("odometry reruns into the interrupted folder and resumes", ["odometry", "--sequence", seq, "--jobs", "2",
             "--out", "K1"], 0, ["ATE"])


def presets(c, d):
    """A prefix whose presets folder is a broken link, then one with a corrupt preset file beside
    good ones (issue 54: "none installed", and one bad file broke every preset)."""
    pfx = os.path.join(d, "pfx")
    os.makedirs(os.path.join(pfx, "bin"))
    os.makedirs(os.path.join(pfx, "share", "tigris"))
    shutil.copy(c.t, os.path.join(pfx, "bin", "tigris"))
    link = os.path.join(pfx, "share", "tigris", "presets")
    os.symlink(os.path.join(d, "no-such-presets"), link)
    t = c.t
    c.t = os.path.join(pfx, "bin", "tigris")
    try:
        c.expect("presets: a broken link is named", ["presets"], 1, ["is a link to", "which does not exist"])
        os.remove(link)
        shipped = os.path.join(os.path.dirname(os.path.dirname(t)), "share", "tigris", "presets")
        shutil.copytree(shipped, link)
        with open(os.path.join(link, "zz-broken.json"), "w") as f:
            f.write('{"fe": {"recursion_units": ')
        c.expect("presets: a corrupt file is named, the others listed", ["presets"], 1,
                 ["zz-broken is left out", "every-leaf-w4"])
        c.expect("run --config of a good preset beside a corrupt one", ["run", "--config", "top-6", "--max-work", "1",
                                                                          "--out", "pre"], 2, ["--max-work 1"])
    finally:
        c.t = t


GROUPS = [("folders", folders), ("odometry", odometry), ("inputs", inputs), ("children", children),
          ("presets", presets)]

@pytest.mark.parametrize("group", [g for _, g in GROUPS], ids=[n for n, _ in GROUPS])
def test_group(tigris, work, group):
    c = Cases(tigris, work)
    group(c, work)
    assert not c.failures, f"{len(c.failures)} of {c.count} cases failed: " + "; ".join(c.failures)


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
