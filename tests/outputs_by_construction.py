#!/usr/bin/env python3
"""Every written path is claimed by the output core, tested by construction (issue 54).

The output flags come from the commands themselves (`tigris COMMAND --list-flags`, "role":
"output"), the Python module's path arguments from its signatures (`keep`): a new flag or
argument is covered without editing this file. Each output is tried against the folder's
record (manifest.json), each name the command writes itself (the manifest's "outputs"), an
input, another output, a file nobody wrote and a named pipe nobody reads: each must be refused
(exit 2, a message naming the path) with every byte of every file unchanged; then written
(a new path) and written again by a rerun into the same folder (the command's own file).

Only BASE is written by hand: the cheapest invocation of each command that has an output flag.
A command with an output flag and no BASE entry fails the test.

Run: python3 -m pytest tests/outputs_by_construction.py --tigris PATH (three tests: the commands'
output flags, the issue's reproductions, the Python module's keep=); each names every case that
failed.
"""
import hashlib
import inspect
import json
import os
import subprocess
import sys
import signal
import threading
import time

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import support  # noqa: E402
from support import TIMEOUT  # noqa: E402


def base_args(command, d):
    """The cheapest invocation of `command` whose output flags are tried (files in d)."""
    cloud, other = os.path.join(d, "cloud.bin"), os.path.join(d, "other.bin")
    return {
        "ref": ["--cloud", cloud, "--queries", other],
        "run": ["--cloud", cloud, "--queries", other],
        "register": ["--source", other, "--target", cloud, "--search", "exact"],
    }.get(command)


def snapshot(d):
    """Every entry under d: a file by its digest, a folder as such (a refused run may leave none)."""
    out = {}
    for root, dirs, files in os.walk(d):
        for f in dirs:
            out[os.path.join(root, f)] = "folder"
        for f in files:
            p = os.path.join(root, f)
            if os.path.islink(p) or not os.path.isfile(p):
                out[p] = "special"
                continue
            with open(p, "rb") as fh:
                out[p] = hashlib.sha256(fh.read()).hexdigest()
    return out


class Cases(support.Cases):
    def refused(self, name, args, needle):
        """args must exit 2 naming `needle`, and change no file under the work folder."""
        before = snapshot(self.d)
        p = self.run(args)
        after = snapshot(self.d)
        changed = sorted(set(before.items()) ^ set(after.items()))
        msg = p.stdout + p.stderr
        problems = [f"exit {p.returncode}, want 2"] if p.returncode != 2 else []
        needles = needle if isinstance(needle, tuple) else (needle,)
        problems += [f"none of {needles} in the message"] if not any(n in msg for n in needles) else []
        problems += [f"files changed: {changed[:4]}"] if changed else []
        self.check(name, not problems, "; ".join(problems) + "\n    tigris " + " ".join(args) + "\n    " + msg)


def output_flags(tigris):
    """{command: [output flags]} over every subcommand `tigris --help` lists."""
    text = subprocess.run([tigris, "--help"], capture_output=True, text=True).stdout
    commands = [line.split()[0] for line in text.split("Subcommands:")[1].splitlines() if line.strip()]
    out = {}
    for c in commands:
        p = subprocess.run([tigris, c, "--list-flags"], capture_output=True, text=True)
        if p.returncode != 0:
            continue  # a command without --list-flags: test_hostile's test_list_flags covers them
        flags = json.loads(p.stdout)["flags"]
        outs = [f["flag"] for f in flags if f.get("role") == "output"]
        if outs:
            out[c] = outs
    return out


def write_cloud(path, shift):
    """A corner of a room (floor and two walls, 0.25 m apart, a little noise): small, and with
    the surfaces a registration needs."""
    g = np.arange(0, 8, 0.25)
    u, v = [a.ravel() for a in np.meshgrid(g, g)]
    z = np.zeros_like(u)
    pts = np.concatenate([np.stack(s, 1) for s in ((u, v, z), (u, z, v / 2), (z, u, v / 2))])
    pts += np.random.default_rng(7).normal(0, 0.01, pts.shape) + [shift, 0, 0]
    out = np.zeros((len(pts), 4), "<f4")
    out[:, :3] = pts
    out.tofile(path)


def cli_cases(c, d, command, flags):
    base = base_args(command, d)
    if base is None:
        c.check(f"{command}: a base invocation for its output flags {flags}", False,
                "add the command to base_args() in tests/outputs_by_construction.py")
        return
    out = os.path.join(d, f"{command}-out")
    # The command's own names, from the record of a run with no output flag.
    p = c.run([command] + base + ["--out", out])
    if p.returncode != 0:
        c.check(f"{command}: a plain run", False, p.stderr)
        return
    with open(os.path.join(out, "manifest.json")) as f:
        own = [o.rstrip("/") for o in json.load(f)["outputs"]]
    inputs = [base[i + 1] for i, a in enumerate(base) if a in ("--cloud", "--queries", "--source", "--target")]
    fifo = os.path.join(d, "nobody-reads")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    foreign = os.path.join(d, "somebodys.txt")
    with open(foreign, "w") as f:
        f.write("not tigris's\n")
    for flag in flags:
        opt = "--" + flag
        tries = [("the folder's record", os.path.join(out, "manifest.json"), "writes itself"),
                 ("an input", inputs[0], "would overwrite the input"),
                 ("a file nobody wrote", foreign, "was not written"),
                 ("a named pipe nobody reads", fifo, "named pipe that no process reads")]
        tries += [(f"the command's own {n}", os.path.join(out, n), ("writes itself", "are the same file"))
                  for n in own]
        for what, path, needle in tries:
            c.refused(f"{command} {opt} at {what}", [command] + base + ["--out", out, opt, path], needle)
        for other in flags:
            if other != flag:
                path = os.path.join(d, "both.out")
                c.refused(f"{command} {opt} and --{other} on one path",
                          [command] + base + ["--out", out, opt, path, "--" + other, path], "same file")
        # A new path is written; a rerun into the same folder replaces its own file.
        path = os.path.join(d, f"{command}-{flag}.out")
        stamp = None
        for attempt in ("written", "rewritten by a rerun"):
            p = c.run([command] + base + ["--out", out, opt, path])
            st = os.stat(path) if os.path.exists(path) else None
            with open(os.path.join(out, "manifest.json")) as f:
                recorded = [w["path"] for w in json.load(f).get("written", [])]
            ok = (p.returncode == 0 and st is not None and st.st_size > 0 and st.st_mtime_ns != stamp
                  and os.path.realpath(path) in recorded)
            c.check(f"{command} {opt}: {attempt}, recorded in the manifest", ok,
                    f"exit {p.returncode}, {st}, written {recorded}\n{p.stderr}")
            stamp = st.st_mtime_ns if st else None
        # ... but not by a run into another folder (it is not that run's file).
        c.refused(f"{command} {opt}: another folder's file", [command] + base + ["--out", out + "-2", opt, path],
                  "was not written")


def reproductions(c, d):
    """The issue's reproductions that are not one flag against one path."""
    base = base_args("run", d)
    # 6: the GTKWave save file beside --vcd is the user's when no run into the folder wrote it:
    # kept, with a note, and the run goes on.
    gtkw = os.path.join(d, "mine.gtkw")
    with open(gtkw, "w") as f:
        f.write("[*] the user's view\n")
    p = c.run(["run"] + base + ["--out", os.path.join(d, "gtkw-out"), "--vcd", os.path.join(d, "mine.vcd")])
    with open(gtkw) as f:
        kept = f.read() == "[*] the user's view\n"
    c.check("run --vcd beside the user's .gtkw: kept, with a note", p.returncode == 0 and kept and "is kept" in p.stderr,
            f"exit {p.returncode}, kept {kept}\n{p.stderr}")
    # 14: a named pipe with a reader is written as a stream (the reader sees it whole). The read
    # end is open before tigris starts (else tigris may find no reader yet, which it refuses).
    fifo = os.path.join(d, "read-pipe")
    os.mkfifo(fifo)
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    os.set_blocking(fd, True)
    chunks = []
    proc = subprocess.Popen([c.t, "ref"] + base + ["--out", os.path.join(d, "fifo-out"), "--dump-results", fifo],
                            cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def drain():  # a read finds no writer (0 bytes) until tigris opens its end: read until it ends
        while True:
            b = os.read(fd, 1 << 16)
            if b:
                chunks.append(b)
            elif proc.poll() is not None:
                return
            else:
                time.sleep(0.01)

    reader = threading.Thread(target=drain)
    reader.start()
    out_, err_ = proc.communicate(timeout=TIMEOUT)
    reader.join(timeout=TIMEOUT)
    os.close(fd)
    p = subprocess.CompletedProcess(proc.args, proc.returncode, out_, err_)
    got = b"".join(chunks).decode().splitlines()
    c.check("ref --dump-results into a named pipe with a reader", p.returncode == 0 and got[:1] == ["query,rank,index,dist2"]
            and len(got) > 1000, f"exit {p.returncode}, {len(got)} lines\n{p.stderr}")
    # A stream the caller set up: stdout redirected to a file holds the CSV alone (the summary
    # goes to stderr once stdout is an output); /dev/null discards, also twice, and a VCD into it.
    with open(os.path.join(d, "stdout.csv"), "w") as f:
        p = subprocess.run([c.t, "ref"] + base + ["--out", os.path.join(d, "stdout-out"), "--dump-results",
                                                 "/dev/stdout"], cwd=d, stdout=f, stderr=subprocess.PIPE, text=True)
    with open(os.path.join(d, "stdout.csv")) as f:
        lines = f.read().splitlines()
    c.check("ref --dump-results /dev/stdout > file: the CSV alone", p.returncode == 0 and lines[:1] ==
            ["query,rank,index,dist2"] and all(line[:1].isdigit() for line in lines[1:]) and "tigris ref" in p.stderr,
            f"exit {p.returncode}, {len(lines)} lines, last {lines[-2:]}\n{p.stderr}")
    p = c.run(["run"] + base + ["--out", os.path.join(d, "null-out"), "--vcd", "/dev/null", "--dump-results",
                                "/dev/null", "--dump-schedule", "/dev/null"])
    c.check("run --vcd, --dump-results and --dump-schedule into /dev/null", p.returncode == 0, p.stderr)
    # A run stopped by Ctrl-C keeps the record of what the folder's earlier run wrote: the same
    # command again replaces its own file (it was refused as somebody's).
    res = os.path.join(d, "stopped.csv")
    stop_out = os.path.join(d, "stop-out")
    args = [c.t, "run", "--mode", "knn", "--k", "51", "--out", stop_out, "--dump-results", res]  # seconds long
    first = c.run(args[1:])
    proc = subprocess.Popen(args, cwd=d, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while time.time() - t0 < TIMEOUT and proc.poll() is None:  # stopped once it holds the folder
        try:
            with open(os.path.join(stop_out, "manifest.json")) as f:
                m = json.load(f)
            if m.get("pid") == proc.pid and m.get("status") == "running":
                break
        except (OSError, ValueError):
            pass
        time.sleep(0.02)
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=TIMEOUT)
    again = c.run(args[1:])
    c.check("run --dump-results after a Ctrl-C: the rerun replaces its own file",
            first.returncode == 0 and proc.returncode == 130 and again.returncode == 0,
            f"exit {first.returncode}, stopped {proc.returncode}, rerun {again.returncode}\n{again.stderr}")
    # 1: --compare --check-flags checks the flags and writes or removes nothing in a folder that
    # holds a comparison.
    cmp = os.path.join(d, "cmp")
    os.makedirs(os.path.join(cmp, "exact"))
    with open(os.path.join(cmp, "manifest.json"), "w") as f:
        json.dump({"tigris_manifest": 1, "command": "register", "outputs": ["comparison.json", "exact/"],
                   "status": "done"}, f)
    for n in ("comparison.json", "exact/registration.json"):
        with open(os.path.join(cmp, n), "w") as f:
            f.write("{}\n")
    before = snapshot(cmp)
    p = c.run(["register", "--compare", "--repeat", "1", "--out", cmp, "--check-flags"])
    c.check("register --compare --check-flags leaves the folder as it was", p.returncode == 0 and snapshot(cmp) == before,
            f"exit {p.returncode}\n{p.stderr}")


def python_cases(c, d, tigris):
    """Every function of the module taking `keep` (a folder it writes) against a folder of the
    user's files, a regular file, and another function's folder."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(tigris)), "..", "python"))
    os.environ.setdefault("TIGRIS", tigris)
    import tigris as T
    cloud = np.fromfile(os.path.join(d, "cloud.bin"), "<f4").reshape(-1, 4)[:, :3].copy()
    funcs = [(n, f) for n, f in ((n, getattr(T, n)) for n in T.__all__)   # the module's names load lazily
             if inspect.isfunction(f) and not n.startswith("_") and "keep" in inspect.signature(f).parameters]
    c.check("the module has functions with keep=", len(funcs) >= 2, str([n for n, _ in funcs]))
    # The positive control: a new folder is taken, and taken again.
    fresh = os.path.join(d, "py-run-fresh")
    try:
        T.run(keep=fresh, cloud=cloud, queries=cloud[:200])
        T.run(keep=fresh, cloud=cloud, queries=cloud[:200])
        c.check("python run(keep=) at a new folder, twice", os.path.exists(os.path.join(fresh, "manifest.json")))
    except (T.TigrisError, ValueError) as e:
        c.check("python run(keep=) at a new folder, twice", False, str(e))
    args = {"run": dict(cloud=cloud, queries=cloud[:200]), "register": dict(source=cloud, target=cloud)}
    for name, f in funcs:
        kw = args.get(name)
        if kw is None:
            c.check(f"python {name}: arguments for its keep= cases", False, "add them to python_cases()")
            continue
        users = os.path.join(d, f"py-{name}-users")
        os.makedirs(users, exist_ok=True)
        for n in ("cloud.bin", "queries.bin", "source.bin", "results.csv", "config.json"):
            with open(os.path.join(users, n), "w") as fh:
                fh.write("the user's\n")
        plain = os.path.join(d, f"py-{name}-file")
        with open(plain, "w") as fh:
            fh.write("a file\n")
        for what, path in (("a folder of the user's files", users), ("a regular file", plain)):
            before = snapshot(d)
            try:
                f(keep=path, **kw)
                ok, detail = False, "accepted"
            except (T.TigrisError, ValueError) as e:
                ok, detail = os.path.basename(path) in str(e), str(e)  # the message names the path
            changed = sorted(set(before.items()) ^ set(snapshot(d).items()))
            c.check(f"python {name}(keep=) at {what}: refused, nothing changed", ok and not changed,
                    f"{detail}; changed: {changed[:4]}")


@pytest.fixture(scope="module")
def work(tigris, tmp_path_factory):
    """A folder with two small clouds, the cases' working folder."""
    d = str(tmp_path_factory.mktemp("outputs"))
    write_cloud(os.path.join(d, "cloud.bin"), 0.0)
    write_cloud(os.path.join(d, "other.bin"), 0.3)
    return d


def verify(c):
    assert not c.failures, f"{len(c.failures)} of {c.count} cases failed: " + "; ".join(c.failures)


def test_output_flags(tigris, work):
    flags = output_flags(tigris)
    c = Cases(tigris, work)
    c.check("some commands have output flags", len(flags) >= 3, json.dumps(flags))
    for command, fl in sorted(flags.items()):
        cli_cases(c, work, command, fl)
    verify(c)


def test_reproductions(tigris, work):
    c = Cases(tigris, work)
    reproductions(c, work)
    verify(c)


def test_python_keep(tigris, work):
    c = Cases(tigris, work)
    python_cases(c, work, tigris)
    verify(c)


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
