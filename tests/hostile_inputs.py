#!/usr/bin/env python3
"""Hostile-input matrix (issues 11 and 18): bad files, paths, flags and keys through `tigris ref`,
`tigris run` and `tigris register`. Each case must end in bounded time with its expected exit
code (2 for bad input) and a short message that names the input (file, flag or key), or with a
correct result; never a crash, a hang, a sanitizer report, an overwritten input or a message
that echoes a megabyte or raw control bytes. `cases()` lists the plain exit-2 cases; `checked()`
the ones with another exit code or a check of what was (not) written.

Run: python3 -m pytest tests/hostile_inputs.py --tigris PATH (two tests, the plain exit-2 cases
and the checked ones; each names every case that failed). Other tests import the scenes made
here (make_register_files, room_points).
"""
import json
import math
import os
import random
import struct
import subprocess
import sys
import time

import pytest

from support import digest

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


def room_points(rng):
    """A box room 16 m wide with three pillars and a floor: a scene registration converges on."""
    room = []
    for _ in range(6000):
        u, v = rng.uniform(-8, 8), rng.uniform(0, 3)
        room += [(u, -8, v), (u, 8, v), (-8, u, v), (8, u, v)][rng.randrange(4):][:1]
    for cx, cy in ((2, 3), (-3, 1), (4, -4)):
        for _ in range(800):
            a, h = rng.uniform(0, 2 * math.pi), rng.uniform(0, 3)
            room.append((cx + 0.4 * math.cos(a), cy + 0.4 * math.sin(a), h))
    room += [(rng.uniform(-8, 8), rng.uniform(-8, 8), 0.0) for _ in range(3000)]
    return room


def ply(path, pts):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
                 "property float y\nproperty float z\nend_header\n" % len(pts)).encode())
        for p in pts:
            f.write(struct.pack("<3f", *p))


def read_json(path):
    with open(path) as fh:
        return json.load(fh)


def make_register_files(d, f):
    """Small clouds for `register`: a flat plane, the plane moved, random points."""
    rng = random.Random(18)
    plane = [(rng.uniform(-10, 10), rng.uniform(-10, 10), 0.0) for _ in range(6000)]
    ply(os.path.join(d, "plane.ply"), plane)
    ply(os.path.join(d, "plane_b.ply"), [(x + 0.3, y + 0.1, z) for x, y, z in plane])
    ply(os.path.join(d, "rand2k.ply"), [(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(0, 3))
                                        for _ in range(2000)])
    ply(os.path.join(d, "rand2k_b.ply"), [(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(0, 3))
                                          for _ in range(2000)])
    # A scene with structure (a box room with pillars), for runs that must converge.
    room = room_points(rng)
    ply(os.path.join(d, "room.ply"), room)
    ply(os.path.join(d, "room_b.ply"), [(x - 0.2, y - 0.1, z) for x, y, z in room])
    for name in ("plane.ply", "plane_b.ply", "rand2k.ply", "rand2k_b.ply", "room.ply", "room_b.ply"):
        f[name] = os.path.join(d, name)
    def put(name, data):
        f[name] = os.path.join(d, name)
        with open(f[name], "wb") as fh:
            fh.write(data)
    put("gt_huge.txt", b"1 0 0 1e308\n0 1 0 0\n0 0 1 0\n")
    put("gt_identity.txt", b"1 0 0 0\n0 1 0 0\n0 0 1 0\n")
    put("gt_binary.txt", b"1 0 0 \x00\x01\x02\n0 1 0 0\n0 0 1 0\n")
    put("cfg_1e400.json", b'{"normals": {"radius": 1e400}}')
    put("cfg_object.json", b'{"normals": {"radius": {"value": 0.3}}}')
    put("cfg_float_int.json", b'{"icp": {"max_iterations": 10.0}}')
    put("cfg_nul_key.json", b'{"normals": {"rad\\u0000ius": 0.3}}')
    put("cfg_dup.json", b'{"icp": {"max_iterations": 5}, "icp": {"reciprocal": true}}')
    put("cfg_dup_key.json", b'{"icp": {"max_iterations": 5, "max_iterations": 7}}')
    put("run_dup.json", b'{"fe": {"recursion_units": 4}, "fe": {"recursion_units": 8}}')
    os.mkdir(os.path.join(d, "cfg_dir.json"))
    f["cfg_dir.json"] = os.path.join(d, "cfg_dir.json")


def checked(f, d):
    """Cases with their own expectations: (name, args, exit code, needles, check). `check(out,
    text)` returns a problem or None; `out` is the case's --out folder."""
    ok = ["--cloud", f["ok.bin"], "--queries", f["q.bin"]]
    same = os.path.join(d, "same_out.csv")
    link = os.path.join(d, "link_to_cloud.csv")
    os.symlink(f["ok.bin"], link)
    cloud_digest = digest(f["ok.bin"])

    def cloud_intact(out, text):
        return None if digest(f["ok.bin"]) == cloud_digest else "the input cloud was overwritten"

    def searched_itself(out, text):
        w = read_json(os.path.join(out, "stats.json"))["workload"]
        if "(the cloud itself)" not in w["queries"] or w["cloud"] != f["ok.bin"]:
            return f"workload {w}"
        return None

    out = []
    for cmd in ("ref", "run"):
        out += [
            (f"{cmd}: cloud alone searches itself", [cmd, "--cloud", f["ok.bin"]], 0, ["the cloud itself"],
             searched_itself),
            (f"{cmd}: queries alone", [cmd, "--queries", f["q.bin"]], 2, ["--queries", "--cloud"], None),
            (f"{cmd}: dump-results onto the cloud", [cmd] + ok + ["--dump-results", f["ok.bin"]], 2,
             ["--dump-results", "would overwrite the input --cloud"], cloud_intact),
            (f"{cmd}: dump-results through a symlink to the cloud", [cmd] + ok + ["--dump-results", link], 2,
             ["would overwrite the input --cloud"], cloud_intact),
            (f"{cmd}: dump-results and dump-schedule one file",
             [cmd] + ok + ["--dump-results", same, "--dump-schedule", same], 2, ["same file"], None),
            (f"{cmd}: dump-results onto stats.json",
             [cmd] + ok + ["--out", os.path.join(d, "o1"), "--dump-results", os.path.join(d, "o1", "..", "o1", "stats.json")],
             2, ["same file", "stats.json"], None),
            (f"{cmd}: radius 1e-300", [cmd] + ok + ["--mode", "radius", "--radius", "1e-300"], 2, ["--radius", "1e-300"],
             lambda o, t: "printed as 0.000000" if "0.000000" in t else None),
            (f"{cmd}: max-work nan", [cmd] + ok + ["--max-work", "nan"], 2, ["--max-work"], None),
            (f"{cmd}: max-results nan", [cmd] + ok + ["--max-results", "nan"], 2, ["--max-results"], None),
            (f"{cmd}: max-work inf", [cmd] + ok + ["--max-work", "inf"], 2, ["--max-work"], None),
        ]
        for flag in ("--cloud", "--queries", "--approx-thd", "--dump-results", "--dump-schedule", "--height",
                     "--mode", "--out"):
            args = ([] if flag == "--cloud" else ["--cloud", f["ok.bin"]]) if flag in ("--cloud", "--queries") else ok
            out.append((f"{cmd}: {flag} ''", [cmd] + args + [flag, ""], 2, [flag, "empty value"], None))
        out.append((f"{cmd}: --out=", [cmd] + ok + ["--out="], 2, ["--out", "empty value"], None))
    out += [
        ("ref: --schedule ''", ["ref"] + ok + ["--schedule", ""], 2, ["--schedule", "empty value"], None),
        ("ref: schedule and dump-results one file", ["ref"] + ok + ["--schedule", f["wrong_schedule.csv"],
         "--dump-results", f["wrong_schedule.csv"]], 2, ["would overwrite the input --schedule"], None),
        ("run: --timeline ''", ["run"] + ok + ["--timeline", ""], 2, ["--timeline", "empty value"], None),
        ("run: --vcd ''", ["run"] + ok + ["--vcd", ""], 2, ["--vcd", "empty value"], None),
        ("run: --config ''", ["run"] + ok + ["--config", ""], 2, ["--config", "empty value"], None),
        ("run: vcd and timeline one file", ["run"] + ok + ["--vcd", same, "--timeline", same], 2, ["same file"], None),
        ("run: timeline onto the vcd's save file", ["run"] + ok + ["--vcd", os.path.join(d, "w.vcd"), "--timeline",
         os.path.join(d, "w.gtkw")], 2, ["same file", "GTKWave"], None),
        ("run: energy exponent 1000", ["run"] + ok + ["--set", "energy.sram_size_exponent=1000"], 2,
         ["energy.sram_size_exponent", "out of range"], None),
        ("run: subnormal key value is a number", ["run"] + ok + ["--set", "energy.distance_pj=1e-320"], 0, ["MATCH"],
         lambda o, t: "rejected as not a number" if "must be a number" in t else None),
        ("run: timeline-queries -1", ["run"] + ok + ["--timeline", os.path.join(d, "t.json"), "--timeline-queries",
         "-1"], 2, ["--timeline-queries", "4294967295"], lambda o, t: "a 300-digit bound" if "1797693" in t else None),
        ("run: duplicate config section", ["run"] + ok + ["--config", f["run_dup.json"]], 2,
         [f["run_dup.json"], "'fe' appears twice"], None),
        ("run: k far beyond the cloud is refused", ["run", "--cloud", f["rand2k.ply"], "--mode", "knn", "--k",
         "100000"], 2, ["--max-work", "k-wide result slots"], None),
        ("run: k beyond a tiny cloud still runs", ["run", "--cloud", f["q.bin"], "--mode", "knn", "--k", "100000"],
         0, ["MATCH"], None),
    ]
    return out + register_checked(f, d)


def register_checked(f, d):
    room = ["--source", f["room_b.ply"], "--target", f["room.ply"]]
    plane = ["--source", f["plane_b.ply"], "--target", f["plane.ply"]]
    jpath = lambda o: os.path.join(o, "registration.json")

    def degenerate(out, text):
        raw = open(jpath(out)).read()
        j = json.loads(raw)
        if j["status"] != "degenerate" or j["transform"] is not None:
            return f"status {j['status']}, transform {j['transform']}"
        return "NaN in registration.json" if "NaN" in raw or "nan" in raw.lower().replace("nan_", "") else None

    def not_converged(out, text):
        j = read_json(jpath(out))
        return None if j["status"] in ("not_converged", "degenerate") else f"status {j['status']}"

    def per_m_null(out, text):
        e = read_json(jpath(out))["error"]
        return None if e["translation_m_per_m"] is None and e["translation_m"] > 0 else f"error {e}"

    cfg_out = os.path.join(d, "cfgdir", "registration.json")
    os.makedirs(os.path.dirname(cfg_out))
    with open(cfg_out, "w") as fh:
        fh.write('{"icp": {"max_iterations": 5}}\n')
    symlinked = os.path.join(d, "symlinked")
    os.makedirs(symlinked)
    victim = os.path.join(d, "victim.txt")
    with open(victim, "w") as fh:
        fh.write("keep me\n")
    os.symlink(victim, os.path.join(symlinked, "registration.json"))

    def not_through_link(out, text):  # the folder is the user's: refused, the link's target intact
        return None if open(victim).read() == "keep me\n" else "wrote through the registration.json symlink"

    out = [
        ("register: seed -1", ["register", "--seed", "-1"], 2, ["--seed"], None),
        ("register: source ''", ["register", "--source", "", "--target", f["room.ply"]], 2, ["--source", "empty value"], None),
        ("register: out ''", ["register", "--out", ""], 2, ["--out", "empty value"], None),
        ("register: kitti-frames without kitti-poses", ["register"] + room + ["--kitti-frames", "3,2"], 2,
         ["--kitti-frames", "--kitti-poses"], None),
        ("register: out onto the config", ["register", "--config", cfg_out, "--out", os.path.dirname(cfg_out)], 2,
         ["would overwrite the input --config"], None),
        ("register: ground truth 1e308", ["register"] + room + ["--ground-truth", f["gt_huge.txt"]], 2,
         [f["gt_huge.txt"], "1e6 m"], None),
        ("register: ground truth with NUL bytes", ["register"] + room + ["--ground-truth", f["gt_binary.txt"]], 2,
         [f["gt_binary.txt"], "\\x00\\x01\\x02"], None),
        ("register: identity ground truth", ["register"] + room + ["--ground-truth", f["gt_identity.txt"]], 0,
         ["per metre: n/a"], per_m_null),
        ("register: config 1e400", ["register", "--config", f["cfg_1e400.json"], "--list-config"], 2,
         [f["cfg_1e400.json"], "number overflow"], None),
        ("register: config is a folder", ["register", "--config", f["cfg_dir.json"], "--list-config"], 2,
         [f["cfg_dir.json"], "is a folder"], None),
        ("register: config object for a number", ["register", "--config", f["cfg_object.json"], "--list-config"], 2,
         ["'normals.radius' must be a number, got an object"], None),
        ("register: config 10.0 for an integer", ["register", "--config", f["cfg_float_int.json"], "--list-config"], 2,
         ["'icp.max_iterations' must be an integer, got 10.0"], None),
        ("register: config NUL in a key", ["register", "--config", f["cfg_nul_key.json"], "--list-config"], 2,
         ["normals.rad\\x00ius"], None),
        ("register: config duplicate section", ["register", "--config", f["cfg_dup.json"], "--list-config"], 2,
         [f["cfg_dup.json"], "'icp' appears twice"], None),
        ("register: config duplicate key", ["register", "--config", f["cfg_dup_key.json"], "--list-config"], 2,
         [f["cfg_dup_key.json"], "'max_iterations' appears twice"], None),
        ("register: subnormal --set", ["register", "--set", "icp.transformation_epsilon=1e-320", "--list-config"], 0,
         ["icp.transformation_epsilon"], lambda o, t: "rejected" if "must be a number" in t else None),
        ("register: inject-shell beyond its key's range", ["register", "--inject-shell", "0,1e30", "--list-config"], 2,
         ["--inject-shell", "inject.normals_shell_outer", "out of range"], None),
        ("register: approx-thd beyond its key's range", ["register", "--approx-thd", "1e9", "--list-config"], 2,
         ["--approx-thd", "search.nn_thd", "out of range"], None),
        ("register: inject-kth 100000 is bounded", ["register"] + room + ["--inject-kth", "100000", "--max-work", "2e7"],
         2, ["--max-work", "icp"], None),
        ("register: inject-shell 0,100 is bounded", ["register"] + room + ["--inject-shell", "0,100", "--max-work", "2e7"],
         2, ["--max-work", "normals"], None),
        ("register: max-work nan", ["register", "--max-work", "nan"], 2, ["--max-work"], None),
        ("register: does not write through a registration.json symlink", ["register"] + room + ["--out", symlinked],
         2, ["did not write (registration.json)"], not_through_link),
        ("register: unrelated clouds", ["register", "--source", f["rand2k_b.ply"], "--target", f["rand2k.ply"]], 1,
         ["warning"], not_converged),
        # The accelerator in the loop: its configuration is checked before any work.
        ("register: accel-config missing", ["register"] + room + ["--search", "accel", "--accel-config",
                                                                   os.path.join(d, "no_such_accel.json")], 2,
         ["no_such_accel.json"], None),
        ("register: accel-config 1e400", ["register"] + room + ["--search", "accel", "--accel-config",
                                                                 f["cfg_1e400.json"]], 2, [f["cfg_1e400.json"]], None),
        ("register: accel-set clock nan", ["register"] + room + ["--search", "accel", "--accel-set", "clock_mhz=nan"], 2,
         ["clock_mhz"], None),
        ("register: compare with record-trace", ["register", "--compare", "--record-trace", os.path.join(d, "c.trace")],
         2, ["--record-trace does not go with --compare"], None),
        ("register: accel with injected K-th neighbour", ["register"] + room + ["--search", "accel", "--inject-kth", "3"],
         0, ["accelerator"], lambda o, t: None if read_json(jpath(o))["injection"]["rpce_kth"] == 3 else "no injection"),
    ]
    for search in ("exact", "approx", "flann", "accel"):
        out.append((f"register: flat plane, {search}", ["register"] + plane + ["--search", search], 1,
                    ["warning", "degenerate"], degenerate))
    out.append(("register: plane onto itself", ["register", "--source", f["plane.ply"], "--target", f["plane.ply"]], 1,
                ["warning", "degenerate"], degenerate))
    return out


def run_case(tigris, name, args, code, needles, check, out_dir):
    """Runs one case; returns a list of problems (empty: it held)."""
    if "--out" not in args and "--list-config" not in args:
        args = args + ["--out", out_dir]
    out = args[args.index("--out") + 1] if "--out" in args else out_dir
    try:
        p = subprocess.run([tigris] + args, capture_output=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return [f"no answer within {TIMEOUT} s"], args, ""
    err = (p.stdout + p.stderr).decode("utf-8", "replace")
    problems = []
    if p.returncode != code:
        problems.append(f"exit {p.returncode}, want {code}")
    for needle in needles:
        if needle not in err:
            problems.append(f"the message does not name {needle!r}")
    if code == 2 and len(p.stderr) > 4000:
        problems.append(f"{len(p.stderr)} bytes of message")
    if any(m in err for m in SANITIZER_MARKS):
        problems.append("a crash or sanitizer report")
    if "\x1b" in err:
        problems.append("raw escape bytes echoed")
    if check and not problems:
        try:
            problem = check(out, err)
        except (OSError, ValueError, KeyError, TypeError) as e:
            problem = f"check failed: {e!r}"
        if problem:
            problems.append(problem)
    return problems, args, err


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """(folder, {name: path}) of the hostile files and the register scenes."""
    d = str(tmp_path_factory.mktemp("hostile"))
    f = make_files(d)
    make_register_files(d, f)
    return d, f


def run_all(tigris, d, todo, tag):
    """Runs every case; fails naming each that did not hold."""
    failed = []
    for i, (name, args, code, needles, check) in enumerate(todo):
        t0 = time.time()
        problems, args, err = run_case(tigris, name, args, code, needles, check, os.path.join(d, f"{tag}{i}"))
        if problems:
            failed.append(name)
            print(f"FAIL {name}: {'; '.join(problems)}\n    tigris {' '.join(args)}\n    " +
                  err.strip().replace("\n", "\n    ")[:1500])
        else:
            print(f"ok   {name} ({time.time() - t0:.1f} s)", flush=True)
    assert not failed, f"{len(failed)} of {len(todo)} hostile inputs not handled: " + "; ".join(failed)


def test_exit_2(tigris, files):
    d, f = files
    run_all(tigris, d, [(n, args, 2, [needle], None) for n, args, needle in cases(f, d)], "plain")


def test_checked(tigris, files):
    d, f = files
    run_all(tigris, d, checked(f, d), "checked")


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
