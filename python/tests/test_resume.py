#!/usr/bin/python3
"""Sweep driver, resume: Ctrl-C stops the running points (no tigris left), finished points are
kept; a rerun runs only the missing points; a grown grid runs only the new points; another base
into the same folder is refused."""
import json, os, signal, subprocess, time
from common import main, Workdir, options, read_csv, small_workload, sweep, tool_command, write_spec

a = options()


def tigris_children(folder):
    """PIDs of processes whose command line names `folder` (the points' --out)."""
    found = []
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                with open(f"/proc/{pid}/cmdline", "rb") as f:
                    cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                continue
            if folder in cmd and "tigris run" in cmd.replace(a.tigris, "tigris"):
                found.append(int(pid))
    return found


def ended(out, pid):
    return json.load(open(os.path.join(out, "points", pid, "point.json")))["ended_at"]


def test_interrupt_and_resume():
    with Workdir(a, "resume") as d:
        small_workload(d, 120000, 40000)         # ~0.5 s a point, so the interrupt lands mid-sweep
        spec = write_spec(d, {"base": {"cloud": "cloud.bin", "queries": "queries.bin"},
                              "grid": {"fe.recursion_units": [16, 32, 64, 128]}})
        out = os.path.join(d, "out")
        cmd, env = tool_command("sweep", spec, "--out", out, "--jobs", "1", "--tigris", a.tigris)
        drv = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, env=env)
        first = os.path.join(out, "points", "fe.recursion_units=16", "point.json")
        t0 = time.monotonic()
        while not os.path.exists(first):
            assert drv.poll() is None and time.monotonic() - t0 < 120, "the first point never finished"
            time.sleep(0.01)
        time.sleep(0.1)                          # the second point is running now
        drv.send_signal(signal.SIGINT)
        err = drv.communicate(timeout=60)[1]
        assert drv.returncode == 130, f"exit {drv.returncode}\n{err}"
        assert "interrupted" in err, err
        assert tigris_children(out) == [], "a tigris run outlived the driver"
        done = [p for p in os.listdir(os.path.join(out, "points"))
                if os.path.exists(os.path.join(out, "points", p, "point.json"))]
        assert 1 <= len(done) < 4, f"interrupt came too late to test anything: {done}"
        assert not os.path.exists(os.path.join(out, "sweep.csv"))
        kept = {p: ended(out, p) for p in done}

        p = sweep(a, spec, "--out", out, "--jobs", "2", "--tigris", a.tigris, check=0)
        assert f"{len(done)} finished earlier (skipped), {4 - len(done)} to run" in p.stderr, p.stderr
        assert f"[{4 - len(done)}/{4 - len(done)}]" in p.stderr and f"[{5 - len(done)}/" not in p.stderr
        for q, t in kept.items():
            assert ended(out, q) == t, f"{q} ran again"
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["status"] for r in rows] == ["ok"] * 4, rows

        # nothing left: a rerun runs nothing and collects the same CSV
        before = open(os.path.join(out, "sweep.csv")).read()
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        assert "4 finished earlier (skipped), 0 to run" in p.stderr and "[1/" not in p.stderr, p.stderr
        assert open(os.path.join(out, "sweep.csv")).read() == before


def test_grown_and_changed_spec():
    with Workdir(a, "resume") as d:
        small_workload(d)
        base = {"cloud": "cloud.bin", "queries": "queries.bin"}
        spec = write_spec(d, {"base": base, "grid": {"height": [6, 8]}})
        out = os.path.join(d, "out")
        sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        t6 = ended(out, "height=6")
        # more grid values and a point: only those run; the CSV has every point of the new spec
        spec = write_spec(d, {"base": base, "grid": {"height": [6, 8, 10]}, "points": [{"k": 4, "mode": "knn"}]})
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        assert "2 finished earlier (skipped), 2 to run" in p.stderr, p.stderr
        assert ended(out, "height=6") == t6
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["point"] for r in rows] == ["height=6", "height=8", "height=10", "k=4,mode=knn"], rows
        assert rows[3]["mode"] == "knn" and rows[0]["mode"] == "nn"
        # fewer values: the left-out point stays on disk but not in the CSV
        spec = write_spec(d, {"base": base, "grid": {"height": [8]}})
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=0)
        assert "not in this one" in p.stderr, p.stderr
        _, rows = read_csv(os.path.join(out, "sweep.csv"))
        assert [r["point"] for r in rows] == ["height=8"]
        # another base would mix results: refused, nothing runs, the folder is unchanged
        spec = write_spec(d, {"base": dict(base, set={"fe.forwarding": False}), "grid": {"height": [8]}})
        p = sweep(a, spec, "--out", out, "--tigris", a.tigris, check=2)
        assert "another base" in p.stderr and "fe.forwarding=false" in p.stderr, p.stderr
        _, rows2 = read_csv(os.path.join(out, "sweep.csv"))
        assert rows2 == rows


if __name__ == "__main__":
    main(__file__)
