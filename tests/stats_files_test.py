#!/usr/bin/python3
"""Whole stats.json files, timelines and waveforms of a few runs against committed ones.

The pinned tests check chosen counters; this checks everything a run writes, so a change made
for host speed (docs/performance.md) cannot move any figure unnoticed. Wall times, the commit and
the command line (paths) are removed; a timeline or VCD is compared by the SHA-256 of its body
without its header (which names the command and the commit).

    python3 -m pytest tests/stats_files_test.py --tigris build/bin/tigris
    python3 -m pytest tests/stats_files_test.py --tigris build/bin/tigris --record
        (rewrites tests/stats_files/ from this binary)

The clouds are written here, from a fixed generator: a street of ground, two walls and scattered
clutter (12,000 points), searched with 3,000 points of the same street moved 0.4 m and turned.
"""
import hashlib
import json
import math
import os
import struct
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
RECORDED = os.path.join(HERE, "stats_files")

# name -> flags of `tigris run`; "+waves": also a timeline and a VCD, compared by digest.
RUNS = {
    "nn": ["--mode", "nn", "+waves"],
    "knn51": ["--mode", "knn", "--k", "51", "+waves"],
    "radius": ["--mode", "radius", "--radius", "0.3", "+waves"],
    "knn8-paper-accounting": ["--mode", "knn", "--k", "8", "--config", "paper-accounting"],
    "nn-approx": ["--mode", "nn", "--approx-thd", "default"],
    "radius-approx": ["--mode", "radius", "--radius", "0.3", "--approx-thd", "default"],
    "knn8-mqmn-small": ["--mode", "knn", "--k", "8", "--set", "be.issue_policy=mqmn", "--set",
                        "sram.results.bytes=65536", "--set", "fe.recursion_units=8"],
}
VOLATILE = {"wall_seconds", "phase_seconds", "commit", "command_line"}


class Lcg:
    """A fixed generator (not Python's random, whose algorithm may change)."""

    def __init__(self, seed):
        self.s = seed

    def uniform(self, lo, hi):
        self.s = (self.s * 6364136223846793005 + 1442695040888963407) % 2**64
        return lo + (hi - lo) * (self.s >> 11) / 2**53


def street(n, seed, dx, yaw_deg):
    g = Lcg(seed)
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    pts = []
    for i in range(n):
        kind = i % 4
        x = g.uniform(-20, 20)
        if kind < 2:  # the road
            y, z = g.uniform(-6, 6), -1.7 + g.uniform(-0.02, 0.02)
        elif kind == 2:  # a wall on either side
            y, z = (6.0 if g.uniform(0, 1) < 0.5 else -6.0) + g.uniform(-0.03, 0.03), g.uniform(-1.7, 2.0)
        else:  # clutter
            y, z = g.uniform(-6, 6), g.uniform(-1.7, 1.0)
        x -= dx
        pts.append((c * x - s * y, s * x + c * y, z))
    return pts


def write_bin(path, pts):
    with open(path, "wb") as f:
        for x, y, z in pts:
            f.write(struct.pack("<4f", x, y, z, 0.0))


def digest_body(path, header_end):
    """SHA-256 of a file from the first line after the header (that line included)."""
    with open(path, "rb") as f:
        data = f.read()
    at = data.find(header_end)
    assert at >= 0, f"{path}: no {header_end!r} line"
    return hashlib.sha256(data[at:]).hexdigest()


def timeline_digest(path):
    with open(path) as f:
        doc = json.load(f)
    doc.get("otherData", {}).pop("run", None)  # command line and commit
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()


def strip(d):
    if isinstance(d, dict):
        if isinstance(d.get("path"), str) and os.path.isabs(d["path"]):  # a preset in this build's share/
            d = dict(d, path=os.path.basename(d["path"]))
        return {k: strip(v) for k, v in d.items() if k not in VOLATILE}
    if isinstance(d, list):
        return [strip(v) for v in d]
    return d


def first_difference(a, b, path=""):
    if type(a) is not type(b):
        return f"{path or '.'}: {json.dumps(a)[:80]} != {json.dumps(b)[:80]}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}: only in the {'recorded' if k in a else 'new'} file"
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} entries recorded, {len(b)} now"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path}: recorded {json.dumps(a)}, now {json.dumps(b)}"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """The clouds every run searches; the runs use relative paths (stats.json records them)."""
    d = str(tmp_path_factory.mktemp("stats-files"))
    write_bin(os.path.join(d, "cloud.bin"), street(12000, 1, 0.0, 0.0))
    write_bin(os.path.join(d, "queries.bin"), street(3000, 2, 0.4, 1.0))
    return d


@pytest.mark.parametrize("name", list(RUNS))
def test_stats_file(tigris, workdir, name, pytestconfig):
    """Every stats.json figure (and the timeline and waveforms) of run `name` as recorded."""
    flags = [f for f in RUNS[name] if f != "+waves"]
    waves = "+waves" in RUNS[name]
    cmd = [tigris, "run", "--cloud", "cloud.bin", "--queries", "queries.bin", "--out", name, *flags]
    if waves:
        cmd += ["--timeline", name + ".trace.json", "--vcd", name + ".vcd"]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=workdir)
    assert p.returncode == 0, f"{name}: exit {p.returncode}\n{p.stderr[-1500:]}"
    with open(os.path.join(workdir, name, "stats.json")) as f:
        now = {"stats": strip(json.load(f))}
    if waves:
        now["timeline_sha256"] = timeline_digest(os.path.join(workdir, name + ".trace.json"))
        now["vcd_sha256"] = digest_body(os.path.join(workdir, name + ".vcd"), b"$timescale")
    path = os.path.join(RECORDED, name + ".json")
    if pytestconfig.getoption("record"):
        os.makedirs(RECORDED, exist_ok=True)
        with open(path, "w") as f:
            json.dump(now, f, indent=1, sort_keys=True)
            f.write("\n")
        return
    with open(path) as f:
        recorded = json.load(f)
    diff = first_difference(recorded, now)
    assert not diff, f"{name} ({' '.join(flags)}): {diff}"


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
