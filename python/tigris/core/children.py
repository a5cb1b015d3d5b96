"""Child processes: one pool for local children and the Slurm helpers (the C++ twin:
core/children.*, core/slurm_array.*): process groups, the death signal, stop signals."""
import ctypes, os, shutil, signal, subprocess, time
from .base import KILL_AFTER, PARENT_ENV, STOP_SIGNALS, Interrupted, SlurmFailed


_LIBC = None
_PR_SET_PDEATHSIG = 1
_live = []                                       # Popen of every running child


def _libc():
    global _LIBC
    if _LIBC is None:
        try:
            _LIBC = ctypes.CDLL(None, use_errno=True)
        except OSError:
            _LIBC = False
    return _LIBC


def _child_setup(parent):
    libc = _libc()                               # loaded before the fork

    def setup():
        for s in STOP_SIGNALS:                   # the parent's SIG_IGN during its clean-up is not inherited
            signal.signal(s, signal.SIG_DFL)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
        if libc:
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0)
        if os.getppid() != parent:               # the parent died before the prctl
            os._exit(128 + signal.SIGTERM)
    return setup


def spawn(cmd, parent_files=None, **kw):
    """Popen of a child in its own process group and session, stopped by the kernel when this
    process dies (PR_SET_PDEATHSIG). parent_files: names this process keeps in the child's
    folder, passed as TIGRIS_PARENT_OUTPUTS (otherwise the variable is not passed on)."""
    env = dict(kw.pop("env", None) or os.environ)
    env.pop(PARENT_ENV, None)
    if parent_files:
        env[PARENT_ENV] = " ".join(parent_files)
    # A stop signal is held until the child is recorded, so no child escapes the clean-up.
    old = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    try:
        p = subprocess.Popen(cmd, start_new_session=True, preexec_fn=_child_setup(os.getpid()), env=env, **kw)
        _live.append(p)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
    return p


def _forget(p):
    if p in _live:
        _live.remove(p)


def stop_groups(procs, grace=KILL_AFTER):
    """SIGTERM to every child's process group at once, SIGKILL to those left after `grace` s."""
    procs = list(procs)
    for p in procs:
        try:
            os.killpg(p.pid, signal.SIGTERM)
        except (ProcessLookupError, PermissionError):
            pass
    end = time.monotonic() + grace
    for p in procs:
        try:
            p.wait(timeout=max(0.0, end - time.monotonic()))
        except subprocess.TimeoutExpired:
            pass
    for p in procs:
        try:
            os.killpg(p.pid, signal.SIGKILL)     # the leader's own children too
        except (ProcessLookupError, PermissionError):
            pass
        try:
            p.wait(timeout=5)
        except subprocess.TimeoutExpired:
            pass
        _forget(p)


def stop_all(grace=KILL_AFTER):
    stop_groups([p for p in _live], grace)


def wait(p):
    rc = p.wait()
    _forget(p)
    return rc


def pool(tasks, jobs, launch, done):
    """Runs launch(task) -> Popen (of spawn) for every task, at most `jobs` at once, calling
    done(task, proc, rc) as each ends; a signal or an error stops every running child."""
    queue, running, ok = list(tasks), [], False
    try:
        while queue or running:
            while queue and len(running) < jobs:
                t = queue.pop(0)
                running.append((t, launch(t)))
            still = []
            for t, p in running:
                rc = p.poll()
                if rc is None:
                    still.append((t, p))
                else:
                    _forget(p)
                    done(t, p, rc)
            running = still
            if running:
                time.sleep(0.02)
        ok = True
    finally:
        if not ok:                               # also a child started as the signal came
            stop_groups(set(p for _, p in running) | set(_live))


def run_child(cmd, grace=KILL_AFTER, **kw):
    """One child to its end (its exit code; -N for a signal); a signal to this process stops it."""
    p = spawn(cmd, **kw)
    try:
        return wait(p)
    except BaseException:
        stop_groups([p], grace)
        raise


def _on_signal(signum, frame):
    for s in STOP_SIGNALS:                       # the clean-up that follows is not interrupted
        signal.signal(s, signal.SIG_IGN)
    raise Interrupted(signum)


def handle_stop_signals():
    """SIGINT, SIGTERM and SIGHUP raise Interrupted (nohup's SIG_IGN is kept)."""
    for s in STOP_SIGNALS:
        if signal.getsignal(s) != signal.SIG_IGN:
            signal.signal(s, _on_signal)


# ----------------------------------------------------------------------------------------------
# Slurm

FINAL_STATES = {"CD", "CA", "F", "TO", "NF", "PR", "OOM", "BF", "DL"}   # squeue's compact states


def sbatch(cmd):
    """Submits (cmd starts with sbatch --parsable); the job id, or SlurmFailed (exit 3)."""
    import shlex
    if not shutil.which(cmd[0]):
        raise SlurmFailed(f"--slurm: {cmd[0]} not found on PATH (is Slurm installed and SLURM_CONF set?)")
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise SlurmFailed(f"sbatch did not run: {e}\n  command: {shlex.join(cmd)}")
    if p.returncode != 0:
        raise SlurmFailed(f"sbatch failed (exit {p.returncode}): {p.stderr.strip() or p.stdout.strip()}\n"
                          f"  command: {shlex.join(cmd)}")
    return p.stdout.strip().split(";")[0]


def squeue_active(job):
    """Task ids of `job` not finished yet; None when squeue cannot tell."""
    try:
        p = subprocess.run(["squeue", "-h", "-j", str(job), "-t", "all", "-o", "%i %t"],
                           capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    if p.returncode != 0:
        return [] if "Invalid job id" in p.stderr else None
    rows = [line.split() for line in p.stdout.splitlines() if line.strip()]
    return [r[0] for r in rows if len(r) == 2 and r[1] not in FINAL_STATES]


def scancel(job):
    try:
        subprocess.run(["scancel", str(job)], capture_output=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        pass



def capture(cmd, timeout=None, **kw):
    """A short child's CompletedProcess (stdout and stderr as text), through spawn: a signal
    or the timeout (subprocess.TimeoutExpired) stops it."""
    p = spawn(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True, **kw)
    try:
        out, err = p.communicate(timeout=timeout)
    except BaseException:
        stop_groups([p])
        raise
    _forget(p)
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)
