"""Output folders: the one way a tool owns its --out (the C++ twin: core/out_folder.*):
manifest, lock, ownership, resume or fresh, atomic writes."""
import fcntl, fnmatch, json, os, shlex, shutil, signal, sys, time
from .base import (MANIFEST, PARENT_ENV, SBATCH_FAILED, TMP_PREFIX, Interrupted, Refused, SlurmFailed, dotted,
                   now_utc, tigris_commit)
from .inputs import read_json_input


def replace_file(path, write):
    """Calls write(tmp) for .tigris-tmp-<name>-<pid> beside path, then renames it over path: a
    killed run leaves the old file or none, never half a file, and a symbolic link at path is
    replaced, never written through. Refused naming path when it cannot."""
    d, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(d, f"{TMP_PREFIX}{name}-{os.getpid()}")
    try:
        write(tmp)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise Refused(f"cannot write {path}: {e.strerror or e}")


def atomic_write(path, data):
    """Writes data (str or bytes) to path through replace_file."""
    if isinstance(data, str):
        data = data.encode("utf-8", "backslashreplace")

    def write(tmp):
        with open(tmp, "wb") as f:
            f.write(data)
    replace_file(path, write)


def write_json(path, obj):
    atomic_write(path, json.dumps(obj, indent=1) + "\n")


def save_figure(fig, path, **kw):
    """A matplotlib figure written through replace_file (format from path's extension)."""
    fmt = os.path.splitext(path)[1][1:] or "png"
    replace_file(path, lambda tmp: fig.savefig(tmp, format=fmt, **kw))


def parent_outputs():
    """The names a parent keeps in this command's folder (TIGRIS_PARENT_OUTPUTS)."""
    return os.environ.get(PARENT_ENV, "").split()


def _alive(pid):
    try:
        os.kill(pid, 0)
    except PermissionError:  # someone else's
        return True
    except (ProcessLookupError, OverflowError, ValueError):
        return False
    return True


def _matches(name, is_dir, patterns):
    for p in patterns:
        if p.endswith("/"):
            if is_dir and fnmatch.fnmatchcase(name, p[:-1]):
                return p
        elif fnmatch.fnmatchcase(name, p):
            return p
    return None


def _show(v):
    text = json.dumps(v, separators=(", ", ": "))
    return text if len(text) <= 80 else text[:77] + "..."


class OutFolder:
    """The folder a command writes, held for its whole run (docs/architecture.md): claim() checks
    and locks it and writes manifest.json (status running); finish() records the end."""

    def __init__(self, path, command, outputs, flag="--out", argv=None):
        self.given, self.path = path, os.path.abspath(path)
        self.command, self.outputs, self.flag = command, list(outputs), flag
        # As the C++ commands record it: the tigris binary (it sets $TIGRIS for its Python tools).
        self.argv = [os.environ.get("TIGRIS") or "tigris", command] + list(sys.argv[1:] if argv is None else argv)
        self.fd, self.made, self.manifest, self.old = None, False, None, None

    # -- checks before anything is made
    def check_path(self):
        """The folder is one, or can be made: named before any work."""
        p = self.path
        if os.path.exists(p) and not os.path.isdir(p):
            raise Refused(f"{self.flag} {self.given}: exists and is not a folder")
        up = p
        while not os.path.lexists(up):
            up = os.path.dirname(up)
        if not os.path.isdir(up):
            raise Refused(f"{self.flag} {self.given}: cannot be made, {up} is not a folder")
        if not os.access(up, os.W_OK | os.X_OK):
            raise Refused(f"{self.flag} {self.given}: {up} is not writable")

    def _own_patterns(self, old):
        pats = [MANIFEST, TMP_PREFIX + "*"]
        if old is not None:
            pats += [p for p in old.get("outputs", []) if isinstance(p, str)] + self.outputs
        return pats

    def check_inputs(self, inputs, old=None):
        """An input that lies in the folder under a name the command writes is refused, naming its flag."""
        root = os.path.realpath(self.path)
        pats = self.outputs + ([p for p in old.get("outputs", []) if isinstance(p, str)] if old else []) + [MANIFEST]
        for flag, path in inputs:
            real = os.path.realpath(path)
            if not real.startswith(root + os.sep):
                continue
            first = os.path.relpath(real, root).split(os.sep)[0]
            nested = os.path.relpath(real, root) != first
            hit = _matches(first, nested or os.path.isdir(real), pats)
            if hit:
                raise Refused(f"{flag} {path}: lies inside {self.flag} {self.given} under a name tigris "
                              f"{self.command} writes ({hit}): it would be overwritten; move it or use "
                              f"another {self.flag}")

    # -- the claim
    def claim(self, settings=None, inputs=(), resume=True, all_inputs_must_match=True, input_paths=(),
              only_same=False):
        """Creates or checks the folder, locks it, compares or clears an earlier run, writes the
        manifest. inputs: identities (input_identity) compared on resume; input_paths: (flag,
        path) of every input, none of which may be an output; only_same (with resume False): an
        earlier run is cleared only when its settings and inputs were these (a default folder is
        never another input's run lost without a word). Raises Refused (exit 2)."""
        self.check_path()
        self.check_inputs(input_paths)
        try:
            if not os.path.isdir(self.path):
                os.makedirs(os.path.dirname(self.path), exist_ok=True)
                try:
                    os.mkdir(self.path)
                    self.made = True
                except FileExistsError:          # another run made it first: the lock decides
                    pass
            self.fd = os.open(self.path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        except OSError as e:
            raise Refused(f"{self.flag} {self.given}: cannot make or open it: {e.strerror or e}")
        try:
            self._lock()
            old = self._read_old()
            self.check_inputs(input_paths, old)
            self._check_entries(old)
            settings = settings or {}
            inputs = list(inputs)
            if old is not None:
                if resume:
                    changed = self._changes(old, settings, inputs, all_inputs_must_match)
                    if changed:
                        raise Refused(f"{self.given} holds a run of tigris {self.command} with other settings or "
                                      "inputs, which would mix with this one's:\n  " + "\n  ".join(changed)
                                      + f"\nrerun as before, or use another {self.flag} (or remove {self.given} "
                                      "to start afresh)")
                else:
                    changed = self._changes(old, settings, inputs, all_inputs_must_match) if only_same else []
                    if changed:
                        raise Refused(f"{self.given} holds the output of another run of tigris {self.command}, "
                                      "which is kept:\n  " + "\n  ".join(changed) + f"\ngive {self.flag} for "
                                      f"this one, or remove {self.given} to replace it")
                    self._remove_outputs(old)
            self._remove_temporaries()
            self.old = old
            self.manifest = {"tigris_manifest": 1, "command": self.command, "argv": self.argv, "cwd": os.getcwd(),
                             "commit": tigris_commit(), "settings": settings, "inputs": inputs, "outputs": self.outputs,
                             "status": "running", "pid": os.getpid(), "started": now_utc(), "finished": None}
            write_json(os.path.join(self.path, MANIFEST), self.manifest)
        except BaseException:
            if self.made:
                self._abandon()                  # refused in a folder it made: none left
            self.release()
            raise
        return old

    def preview(self, settings=None, inputs=(), all_inputs_must_match=True, input_paths=()):
        """What claim() would refuse, found without making, locking or writing anything (--check)."""
        self.check_path()
        self.check_inputs(input_paths)
        if not os.path.isdir(self.path):
            return None
        fd = os.open(self.path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        try:
            self.fd = fd
            self._lock()
            old = self._read_old()
            self.check_inputs(input_paths, old)
            self._check_entries(old)
            changed = self._changes(old, settings or {}, list(inputs), all_inputs_must_match) if old else []
            if changed:
                raise Refused(f"{self.given} holds a run of tigris {self.command} with other settings or inputs: "
                              + "; ".join(changed))
            return old
        finally:
            self.release()

    def attach(self, legacy=None):
        """Locks a folder of an earlier run of this command without a new run (sweep's collect);
        legacy: a file that marks the command's folder written before manifests."""
        if not os.path.isdir(self.path):
            raise Refused(f"{self.given}: no such folder")
        try:
            self.fd = os.open(self.path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        except OSError as e:
            raise Refused(f"{self.given}: cannot open it: {e.strerror or e}")
        try:
            self._lock()
            self.old = self._read_old()
            if self.old is None and not (legacy and os.path.isfile(os.path.join(self.path, legacy))):
                raise Refused(f"{self.given} holds no {MANIFEST}: not a folder of tigris {self.command}")
        except BaseException:
            self.release()
            raise
        return self.old

    def _lock(self):
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            m = self._holder()
            who = f"pid {m.get('pid')}, tigris {m.get('command')}" if isinstance(m, dict) else "another process"
            raise Refused(f"{self.given} is locked by a run still writing into it ({who}): wait until it has "
                          f"finished, or use another {self.flag}")

    def _holder(self):
        """The manifest of the run holding the lock. It writes its manifest (its pid) just after
        locking, so a run that finds the lock taken waits a moment for a live holder's."""
        deadline = time.monotonic() + 2.0
        while True:
            m = self._peek()
            pid = m.get("pid") if isinstance(m, dict) else None
            if (isinstance(pid, int) and _alive(pid)) or time.monotonic() > deadline:
                return m
            time.sleep(0.05)

    def _peek(self):
        try:
            return read_json_input(os.path.join(self.path, MANIFEST), MANIFEST)
        except Refused:
            return None

    def _read_old(self):
        path = os.path.join(self.path, MANIFEST)
        if not os.path.lexists(path):
            return None
        try:
            m = read_json_input(path, "the folder's manifest")
        except Refused as e:
            raise Refused(f"{e}; it records what wrote {self.given}: delete that folder or use another {self.flag}")
        if not (isinstance(m, dict) and m.get("tigris_manifest") == 1 and isinstance(m.get("command"), str)
                and isinstance(m.get("outputs", []), list)):
            raise Refused(f"{path}: not a manifest of tigris (tigris_manifest, command, outputs): use another "
                          f"{self.flag}")
        if m["command"] != self.command:
            raise Refused(f"{self.given} holds the results of tigris {m['command']} ({MANIFEST}), not of tigris "
                          f"{self.command}: use another {self.flag}")
        return m

    def _check_entries(self, old):
        pats, theirs = self._own_patterns(old), parent_outputs()
        clash = [n for n in theirs if _matches(n, False, self.outputs + [MANIFEST])]
        if clash:
            raise Refused(f"{PARENT_ENV} names {clash[0]}, which tigris {self.command} writes itself")
        foreign = []
        for e in sorted(os.listdir(self.path)):
            full = os.path.join(self.path, e)
            if e in theirs or _matches(e, os.path.isdir(full) and not os.path.islink(full), pats):
                continue
            foreign.append(e)
        if foreign:
            more = f" and {len(foreign) - 5} more" if len(foreign) > 5 else ""
            raise Refused(f"{self.flag} {self.given} holds files tigris {self.command} did not write "
                          f"({', '.join(foreign[:5])}{more}): it writes only into a new or empty folder or one "
                          f"of its own earlier runs ({MANIFEST}); use another {self.flag}, or move them")

    def _changes(self, old, settings, inputs, strict):
        out = []
        a, b = dotted(old.get("settings") or {}), dotted(settings)
        for k in sorted(set(a) | set(b)):
            if a.get(k, "(unset)") != b.get(k, "(unset)"):
                out.append(f"settings.{k}: {_show(a.get(k, '(unset)'))} -> {_show(b.get(k, '(unset)'))}")
        was = {i.get("role"): i for i in old.get("inputs") or [] if isinstance(i, dict)}
        now = {i["role"]: i for i in inputs}
        for role in list(was) + [r for r in now if r not in was]:
            o, n = was.get(role), now.get(role)
            if o is None or n is None:
                if strict:
                    out.append(f"input {role} ({(o or n).get('path')}): " + ("new" if o is None else "no longer read"))
            elif o.get("path") != n["path"]:
                out.append(f"input {role}: {o.get('path')} -> {n['path']}")
            elif o.get("bytes") != n["bytes"] or o.get("sha256") != n["sha256"]:
                out.append(f"input {role} ({n['path']}): content changed ({o.get('bytes')} -> {n['bytes']} bytes)")
        return out

    def _remove_outputs(self, old):
        pats, theirs = [p for p in old.get("outputs", []) if isinstance(p, str)], parent_outputs()
        for e in os.listdir(self.path):
            full = os.path.join(self.path, e)
            isdir = os.path.isdir(full) and not os.path.islink(full)
            if e == MANIFEST or e in theirs or not _matches(e, isdir, pats):
                continue
            try:
                shutil.rmtree(full) if isdir else os.remove(full)
            except OSError as err:
                raise Refused(f"cannot remove the earlier run's {full}: {err.strerror or err}")

    def _remove_temporaries(self):
        for e in os.listdir(self.path):
            if e.startswith(TMP_PREFIX):
                try:
                    os.remove(os.path.join(self.path, e))
                except OSError:
                    pass

    # -- writing and the end
    def file(self, name):
        """The path of one of the command's files (a parent's file is never written)."""
        if name.split("/")[0] in parent_outputs():
            raise Refused(f"{os.path.join(self.given, name)} is the parent's ({PARENT_ENV}): not written")
        return os.path.join(self.path, name)

    def write(self, name, data):
        atomic_write(self.file(name), data)

    def write_json(self, name, obj):
        write_json(self.file(name), obj)

    def run(self, work):
        """Runs work() in the claimed folder and records its end: its exit code, or the one its
        exception stands for (core.exit_status)."""
        rc = 2
        try:
            rc = work()
            return rc
        except BaseException as e:
            rc = exit_status(e)
            raise
        finally:
            self.finish(rc)

    def finish(self, code):
        """Records the end (exit code: 0 done, 128+ interrupted, else failed) and releases the lock."""
        if self.manifest is not None and self.fd is not None and code != 0 and self.made and self._abandon():
            self.release()                       # failed before writing anything: no folder left
            return
        if self.manifest is not None and self.fd is not None:
            status = "done" if code == 0 else "interrupted" if code >= 128 else "failed"
            self.manifest.update(status=status, finished=now_utc())
            try:
                write_json(os.path.join(self.path, MANIFEST), self.manifest)
            except Refused:
                pass
        self.release()

    def _abandon(self):
        """Removes the folder this run made when it holds nothing but the manifest and empty folders."""
        def empty(d):
            for e in os.listdir(d):
                full = os.path.join(d, e)
                if not (os.path.isdir(full) and not os.path.islink(full) and empty(full)):
                    if not (d == self.path and (e == MANIFEST or e.startswith(TMP_PREFIX))):
                        return False
            return True
        try:
            if not empty(self.path):
                return False
            for root, dirs, files in os.walk(self.path, topdown=False):
                for f in files:
                    os.remove(os.path.join(root, f))
                for d in dirs:
                    os.rmdir(os.path.join(root, d))
            os.rmdir(self.path)
        except OSError:
            return False
        return True

    def release(self):
        if self.fd is not None:
            os.close(self.fd)                    # the lock goes with the descriptor
            self.fd = None


def refuse_if_written(path, name, enclosing=False):
    """An input (a file or folder) whose folder a run still writes into is refused, naming that
    run: its files are half made or stale (a sweep writes sweep.csv as it ends). enclosing: the
    folders above it too (a sweep's point before its run has started). A run writes: its
    manifest says running with a live pid, and its lock is held (else the pid is another's)."""
    d = path if os.path.isdir(path) else os.path.dirname(os.path.abspath(path))
    folders = [os.path.abspath(d)]
    while enclosing and os.path.dirname(folders[-1]) != folders[-1]:
        folders.append(os.path.dirname(folders[-1]))
    for d in folders:
        try:
            m = read_json_input(os.path.join(d, MANIFEST), MANIFEST)
        except Refused:
            continue
        pid = m.get("pid") if isinstance(m, dict) and m.get("status") == "running" else None
        if not (isinstance(pid, int) and _alive(pid)):
            continue
        try:
            fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            argv = m.get("argv")
            cmd = shlex.join([os.path.basename(argv[0])] + argv[1:]) if isinstance(argv, list) and argv and \
                all(isinstance(x, str) for x in argv) else f"tigris {m.get('command')}"
            cmd = cmd if len(cmd) <= 200 else cmd[:197] + "..."
            who = "" if os.path.isdir(path) and os.path.samefile(path, d) else f": {d}"
            raise Refused(f"{name} {path}{who} is still being written by pid {pid} ({cmd}): its files are "
                          "not final; wait until that run has finished")
        finally:
            os.close(fd)


def run_command(body, say, stopped, also=()):
    """A command's main around body() -> exit code, the same exit codes for every tool: a refused
    input or folder, an OSError (a full disk, a folder gone) or one of `also` said through
    say("error: ...") and 2; a failed Slurm submission SBATCH_FAILED; a stop signal said as
    "interrupted (SIGNAME): " + `stopped` and 128 + the signal. Never a traceback for these."""
    try:
        return body()
    except Refused as e:
        say(f"error: {e}")
        return 2
    except SlurmFailed as e:
        say(f"error: {e}")
        return SBATCH_FAILED
    except (OSError, *also) as e:
        name = getattr(e, "filename", None)
        say(f"error: {name + ': ' if isinstance(name, str) else ''}{getattr(e, 'strerror', None) or e}")
        return 2
    except KeyboardInterrupt as e:
        code = exit_status(e)
        say(f"interrupted ({signal.Signals(code - 128).name}): {stopped}")
        return code


def exit_status(exc):
    """The exit code of an exception leaving a command's main (for OutFolder.finish)."""
    if isinstance(exc, Interrupted):
        return 128 + exc.signum
    if isinstance(exc, KeyboardInterrupt):
        return 130
    if isinstance(exc, SystemExit):
        return exc.code if isinstance(exc.code, int) else 1
    return 2
