"""Helpers every Python test of the tree shares (tests/*.py scripts and, through
python/tests/common.py, the Python package's tests): file digests, the processes below a pid,
and a part's list of checks against the binary (Checks)."""
import hashlib
import os
import signal
import subprocess
import time

TIMEOUT = 300  # seconds per command of a case; the sanitizer build is ~10x slower


def digest(path):
    """The SHA-256 of a file's bytes, in hex (a changed byte changes it)."""
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def descendants(pid):
    """Every process below pid (through /proc's parent links)."""
    parent = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parent[int(entry)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    out, todo = set(), [pid]
    while todo:
        p = todo.pop()
        for child, pp in parent.items():
            if pp == p and child not in out:
                out.add(child)
                todo.append(child)
    return out


def alive(pid):
    """Whether pid runs (a zombie has ended)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


class Checks:
    """A part's list of checks against the binary, which all run: `verify()` then fails naming
    every one that did not hold (a test of many command lines says all that broke, not the
    first). run() and check() add to it."""
    def __init__(self, tigris=None):
        self.tigris, self.failures = tigris, []

    def run(self, args, code=0, needle=None, env=None, timeout=900):
        """`tigris ARGS`: its exit code must be `code` and its output hold `needle`; the output."""
        p = subprocess.run([self.tigris] + args, capture_output=True, text=True, timeout=timeout, env=env)
        out = p.stdout + p.stderr
        if p.returncode != code or (needle and needle not in out):
            self.failures.append(f"tigris {' '.join(args)}: exit {p.returncode} (want {code})"
                                 + (f", no {needle!r}" if needle else "") + "\n    "
                                 + out.strip()[-1500:].replace("\n", "\n    "))
        return out

    def check(self, cond, what):
        if not cond:
            self.failures.append(what)

    def verify(self):
        failures, self.failures = self.failures, []
        assert not failures, f"{len(failures)} check(s) failed:\n" + "\n".join(failures)


class Cases:
    """Named cases against the binary in a working folder: each check is one case, printed as it
    ends (ok / FAIL with the detail); `failures` names the failed ones. A command that hangs past
    TIMEOUT fails its case and the next one runs."""
    def __init__(self, tigris, d):
        self.t, self.d, self.failures, self.count = tigris, d, [], 0

    def run(self, args, **kw):
        if "input" not in kw:
            kw.setdefault("stdin", subprocess.DEVNULL)
        try:
            return subprocess.run([self.t] + args, capture_output=True, text=True, errors="replace",
                                  timeout=TIMEOUT, cwd=self.d, **kw)
        except subprocess.TimeoutExpired:  # a hang: the case fails, the next one runs
            return subprocess.CompletedProcess(args, -1, "", f"(no answer within {TIMEOUT} s: killed)")

    def check(self, name, ok, detail=""):
        self.count += 1
        print(("ok   " if ok else "FAIL ") + name + ("" if ok else f"\n    {detail.strip()[:1500]}"), flush=True)
        if not ok:
            self.failures.append(name)

    def expect(self, name, args, code, needles, also=None):
        t0 = time.time()
        p = self.run(args)
        msg = p.stdout + p.stderr
        problems = [f"exit {p.returncode}, want {code}"] if p.returncode != code else []
        problems += [f"no {n!r} in the message" for n in needles if n not in msg]
        if also and not problems:
            try:
                problem = also()
            except (OSError, ValueError, KeyError, TypeError) as e:
                problem = f"its outputs could not be checked: {e!r}"
            problems += [problem] if problem else []
        self.check(f"{name} ({time.time() - t0:.1f} s)", not problems,
                   "; ".join(problems) + f"\n    tigris {' '.join(args)}\n    " + msg)
        return p

    def stop_parent(self, name, args, wait_for_children=1, sig=signal.SIGTERM):
        """Starts args, waits for its children, signals the parent alone: every child must be gone."""
        p = subprocess.Popen([self.t] + args, cwd=self.d, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             text=True, errors="replace")
        kids, t0 = set(), time.time()
        while len(kids) < wait_for_children and time.time() - t0 < TIMEOUT and p.poll() is None:
            kids = descendants(p.pid)
            time.sleep(0.05)
        if p.poll() is not None:
            self.check(name, False, f"ended (exit {p.returncode}) before it had {wait_for_children} child(ren)")
            return
        time.sleep(0.3)
        kids |= descendants(p.pid)
        os.kill(p.pid, sig)
        try:
            _, err = p.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            self.check(name, False, "the parent did not end within 30 s of the signal")
            return
        # The parent stops its children before it exits: 2 s is slack, far less than the work
        # they were doing (a pair's registration, a back-end, a replayed job).
        deadline = time.time() + 2
        while time.time() < deadline and any(alive(k) for k in kids):
            time.sleep(0.1)
        left = [k for k in kids if alive(k)]
        for k in left:
            os.kill(k, signal.SIGKILL)
        self.check(f"{name}: {len(kids)} child process(es) stopped, exit {p.returncode}",
                   p.returncode == 128 + sig and not left,
                   f"exit {p.returncode}, still running: {left}\n{err}")
