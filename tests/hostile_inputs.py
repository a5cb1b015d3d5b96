#!/usr/bin/env python3
"""Hostile-input matrix (issue 11): bad files, paths, flags and keys through `tigris ref` and
`tigris run`. Each case must end in bounded time with exit 2 and a short message that names
the input (file, flag or key), or with a correct result; never a crash, a hang, a sanitizer
report or a message that echoes a megabyte or raw control bytes.

Usage: hostile_inputs.py --tigris PATH [-k SUBSTRING]   (exit 0 when every case holds)
"""
import argparse
import os
import struct
import subprocess
import sys
import tempfile
import time

TIMEOUT = 120  # seconds per case; a sanitizer build is ~10x slower than Release
SANITIZER_MARKS = ("AddressSanitizer", "LeakSanitizer", "runtime error:", "Segmentation fault",
                   "terminate called", "Aborted", "core dumped")


def points(path, pts, w=0.0):
    with open(path, "wb") as f:
        for p in pts:
            f.write(struct.pack("<4f", *p, w))


def make_files(d):
    f = {}
    def put(name, data):
        path = os.path.join(d, name)
        with open(path, "wb") as fh:
            fh.write(data)
        f[name] = path
        return path
    grid = [(x * 0.5, y * 0.5, (x * y) % 3 * 0.1) for x in range(20) for y in range(20)]
    points(os.path.join(d, "ok.bin"), grid)
    f["ok.bin"] = os.path.join(d, "ok.bin")
    points(os.path.join(d, "q.bin"), grid[::37])
    f["q.bin"] = os.path.join(d, "q.bin")
    put("empty.bin", b"")
    put("trunc.bin", open(f["ok.bin"], "rb").read()[:20])
    put("nan.bin", struct.pack("<4f", 1, 2, 3, 0) + struct.pack("<4f", float("nan"), 0, 0, 0))
    put("inf.bin", struct.pack("<4f", 1, 2, 3, 0) + struct.pack("<4f", 0, float("inf"), 0, 0))
    put("huge.bin", struct.pack("<4f", 1, 2, 3, 0) + struct.pack("<4f", 2e19, 0, 0, 0))
    put("same.bin", struct.pack("<4f", 1, 2, 3, 0) * 3000)
    os.mkdir(os.path.join(d, "adir.bin"))
    f["adir.bin"] = os.path.join(d, "adir.bin")
    ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    put("noend.ply", (ply_head + "0 0 0\n1 1 1\n2 2 2\n").encode())
    put("short.ply", (ply_head + "end_header\n0 0 0\n1 1 1\n").encode())
    put("badnum.ply", (ply_head + "end_header\n0 0 0\n1 x 1\n2 2 2\n").encode())
    put("nox.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\nend_header\n1 2\n")
    put("binshort.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        b"property float y\nproperty float z\nend_header\n" + struct.pack("<7f", *range(7)))
    put("garbage.ply", b"ply\n\x00\xff\xfe garbage")
    pcd_head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n"
    put("short.pcd", (pcd_head + "DATA ascii\n0 0 0\n1 1 1\n").encode())
    put("nofields.pcd", b"VERSION 0.7\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n")
    put("binshort.pcd", (pcd_head + "DATA binary\n").encode() + struct.pack("<5f", *range(5)))
    put("lies.pcd", pcd_head.replace("POINTS 3", "POINTS 7").encode() + b"DATA ascii\n0 0 0\n1 1 1\n2 2 2\n")
    put("bad.json", b'{"fe": {"recursion_units": 4,}')
    put("types.json", b'{"fe": {"recursion_units": "many"}}')
    put("unknown.json", b'{"fe": {"recursion_unitz": 4}}')
    put("bad_schedule.csv", b"seq,query,leaf\n0,zero,1\n")
    put("long_schedule.csv", b"seq,query,leaf\n" + b"7" * (1 << 20) + b"\n")
    put("wrong_schedule.csv", b"seq,query,leaf\n0,99999,0\n")
    return f


def cases(f, d):
    ok = ["--cloud", f["ok.bin"], "--queries", f["q.bin"]]
    both = []  # (name, args after the subcommand, needle); run through ref and run
    for name in ("empty.bin", "trunc.bin", "nan.bin", "inf.bin", "huge.bin", "adir.bin", "noend.ply",
                 "short.ply", "badnum.ply", "nox.ply", "binshort.ply", "garbage.ply", "short.pcd",
                 "nofields.pcd", "binshort.pcd", "lies.pcd"):
        both.append(("cloud " + name, ["--cloud", f[name], "--queries", f["q.bin"]], f[name]))
        both.append(("queries " + name, ["--cloud", f["ok.bin"], "--queries", f[name]], f[name]))
    missing = os.path.join(d, "missing.bin")
    both += [
        ("missing cloud", ["--cloud", missing, "--queries", f["q.bin"]], missing),
        ("out empty", ok + ["--out", ""], "--out"),
        ("out unwritable", ok + ["--out", "/proc/tigris/out"], "/proc/tigris/out"),
        ("out is a file", ok + ["--out", f["ok.bin"]], f["ok.bin"]),
        ("dump-results full disk", ok + ["--dump-results", "/dev/full"], "/dev/full"),
        ("dump-schedule unwritable", ok + ["--dump-schedule", "/proc/x/s.csv"], "/proc/x/s.csv"),
        ("k zero", ok + ["--mode", "knn", "--k", "0"], "k"),
        ("k negative", ok + ["--mode", "knn", "--k", "-3"], "k"),
        ("k for nn", ok + ["--k", "3"], "--k"),
        ("radius negative", ok + ["--mode", "radius", "--radius", "-1"], "radius"),
        ("radius nan", ok + ["--mode", "radius", "--radius", "nan"], "radius"),
        ("radius inf", ok + ["--mode", "radius", "--radius", "inf"], "radius"),
        ("height too big", ok + ["--height", "99"], "height"),
        ("height negative", ok + ["--height", "-2"], "height"),
        ("height words", ok + ["--height", "tall"], "height"),
        ("seed negative", ok + ["--seed", "-1"], "--seed"),
        ("seed 1e23", ok + ["--seed", "1e23"], "--seed"),
        ("max-nn negative", ok + ["--mode", "radius", "--max-nn", "-1"], "--max-nn"),
        ("mode unknown", ok + ["--mode", "fast"], "--mode"),
        ("approx-thd negative", ok + ["--approx-thd", "-1"], "approx"),
        ("leader-capacity negative", ok + ["--approx-thd", "default", "--leader-capacity", "-1"], "leader"),
        ("control bytes in a path", ["--cloud", os.path.join(d, "a\x1b[31mb.bin"), "--queries", f["q.bin"]], "\\x1b[31mb.bin"),
        ("schedule missing", ok + ["--schedule", missing], missing),
        ("schedule garbage", ok + ["--schedule", f["bad_schedule.csv"]], f["bad_schedule.csv"]),
        ("schedule 1 MB line", ok + ["--schedule", f["long_schedule.csv"]], f["long_schedule.csv"]),
        ("schedule wrong query", ok + ["--schedule", f["wrong_schedule.csv"]], f["wrong_schedule.csv"]),
        ("work guard", ["--cloud", f["same.bin"], "--queries", f["same.bin"], "--max-work", "1e5"], "--max-work"),
        ("result guard", ["--cloud", f["same.bin"], "--queries", f["q.bin"], "--mode", "radius",
                          "--radius", "100", "--max-results", "100"], "--max-results"),
    ]
    out = []
    for cmd in ("ref", "run"):
        for name, args, needle in both:
            if cmd == "run" and name.startswith("schedule"):
                continue  # run takes no --schedule
            out.append((f"{cmd}: {name}", [cmd] + args, needle))
    run_only = [
        ("vcd full disk", ok + ["--vcd", "/dev/full"], "/dev/full"),
        ("timeline unwritable", ok + ["--timeline", "/proc/x/t.json"], "/proc/x/t.json"),
        ("config missing", ok + ["--config", missing], missing),
        ("config bad json", ok + ["--config", f["bad.json"]], f["bad.json"]),
        ("config wrong type", ok + ["--config", f["types.json"]], "fe.recursion_units"),
        ("config unknown key", ok + ["--config", f["unknown.json"]], "fe.recursion_unitz"),
        ("set unknown key", ok + ["--set", "fe.recursion_unitz=4"], "fe.recursion_unitz"),
        ("set no value", ok + ["--set", "fe.recursion_units"], "fe.recursion_units"),
        ("set clock 0", ok + ["--set", "clock_mhz=0"], "clock_mhz"),
        ("set clock 1e-10", ok + ["--set", "clock_mhz=1e-10"], "clock_mhz"),
        ("set clock hex", ok + ["--set", "clock_mhz=0x10"], "clock_mhz"),
        ("set dram 1e-15", ok + ["--set", "dram.bytes_per_cycle=1e-15"], "dram.bytes_per_cycle"),
        ("set energy 1e308", ok + ["--set", "energy.distance_pj=1e308"], "energy.distance_pj"),
        ("set stall rate 2", ok + ["--set", "stall.rate=2"], "stall.rate"),
        ("set zero RUs", ok + ["--set", "fe.recursion_units=0"], "fe.recursion_units"),
        ("set 1e8 SUs", ok + ["--set", "be.search_units=100000000"], "be.search_units"),
        ("set tiny Point Buffer", ok + ["--set", "sram.points.bytes=1"], "sram.points.bytes"),
        ("set policy unknown", ok + ["--set", "be.issue_policy=best"], "be.issue_policy"),
        ("k beyond the Result Buffer", ok + ["--mode", "knn", "--k", "100000000"], "Result Buffer"),
        ("timeline-queries negative", ok + ["--timeline", os.path.join(d, "t.json"), "--timeline-queries", "-1"],
         "--timeline-queries"),
    ]
    out += [(f"run: {n}", ["run"] + a, needle) for n, a, needle in run_only]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tigris", required=True)
    ap.add_argument("-k", default="", help="only cases whose name holds this")
    a = ap.parse_args()
    failures = 0
    with tempfile.TemporaryDirectory(prefix="tigris_hostile_") as d:
        f = make_files(d)
        todo = [c for c in cases(f, d) if a.k in c[0]]
        for name, args, needle in todo:
            if "--out" not in args:
                args += ["--out", os.path.join(d, "out")]
            t0 = time.time()
            try:
                p = subprocess.run([a.tigris] + args, capture_output=True, timeout=TIMEOUT)
            except subprocess.TimeoutExpired:
                print(f"FAIL {name}: no answer within {TIMEOUT} s")
                failures += 1
                continue
            err = (p.stdout + p.stderr).decode("utf-8", "replace")
            problems = []
            if p.returncode != 2:
                problems.append(f"exit {p.returncode}, want 2")
            if needle not in err:
                problems.append(f"the message does not name {needle!r}")
            if len(p.stderr) > 4000:
                problems.append(f"{len(p.stderr)} bytes of message")
            if any(m in err for m in SANITIZER_MARKS):
                problems.append("a crash or sanitizer report")
            if "\x1b" in err:
                problems.append("raw escape bytes echoed")
            if problems:
                failures += 1
                print(f"FAIL {name}: {'; '.join(problems)}\n    tigris {' '.join(args)}\n    " +
                      err.strip().replace("\n", "\n    ")[:1500])
            else:
                print(f"ok   {name} ({time.time() - t0:.1f} s)")
    print(f"{len(todo) - failures} of {len(todo)} hostile inputs handled")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
