"""The shared core of the Python tools (docs/architecture.md, "The shared core"): output folders
(OutFolder, atomic_write), inputs (read_input, read_text_input, read_json_input,
input_identity) and child processes (spawn, stop_groups, pool, run_child, the Slurm helpers).
The C++ commands do the same in testbench/out_folder.*, sw_ref/io/input_file.* and
testbench/children.*; both write one manifest format. Python 3 standard library only."""
import argparse, ctypes, datetime, errno, fcntl, fnmatch, hashlib, json, os, re, shutil, signal, stat
import subprocess, sys, time

MAX_INPUT_BYTES = 4 << 30           # clouds, traces
MAX_SETTINGS_BYTES = 64 << 20       # JSON, CSV and text settings
MAX_JSON_DEPTH = 512
MANIFEST = "manifest.json"
TMP_PREFIX = ".tigris-tmp-"
PARENT_ENV = "TIGRIS_PARENT_OUTPUTS"
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
KILL_AFTER = 5.0                    # SIGTERM to a child's group, then SIGKILL after this long
SBATCH_FAILED = 3                   # the exit code of a failed Slurm submission, in every command


class Refused(Exception):
    """A bad argument, input or output folder: the command prints it and exits 2."""


class SlurmFailed(Exception):
    """sbatch missing or refusing: the command prints it and exits 3."""


class Interrupted(KeyboardInterrupt):
    """SIGINT, SIGTERM or SIGHUP to the parent: exit 128 + signum after stopping every child."""
    def __init__(self, signum=signal.SIGINT):
        super().__init__(signum)
        self.signum = signum


def now_utc():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def size_text(b):
    return f"{b >> 30} GiB" if b >= 1 << 30 else f"{b >> 20} MiB" if b >= 1 << 20 else f"{b} bytes"


# ----------------------------------------------------------------------------------------------
# Inputs: one opener for every file a tool reads

def _fail(path, what, why):
    raise Refused(f"{path}: {'cannot read ' + what + ': ' if what else ''}{why}")


def _kind(mode):
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def _broken_link(path):
    """The first component of path that is a symbolic link to nothing, with its target."""
    parts, cur = os.path.normpath(path).split(os.sep), ""
    for i, part in enumerate(parts):
        cur = part if i == 0 else os.path.join(cur or os.sep, part)
        if cur and os.path.islink(cur) and not os.path.exists(cur):
            try:
                return cur, os.readlink(cur)
            except OSError:
                return cur, "?"
    return None


def _stat_input(path, what):
    if not path:
        _fail("(empty path)", what, "no such file (an empty path names none)")
    try:
        return os.stat(path)
    except OSError as e:
        if e.errno == errno.ELOOP:
            _fail(path, what, "a loop of symbolic links")
        if e.errno == errno.ENOENT:
            link = _broken_link(path)
            if link:
                inner = link[0] != os.path.normpath(path)      # a link on the way to the file
                _fail(path, what, f"a broken symbolic link ({link[0]} -> {link[1]})" if inner
                      else f"a broken symbolic link (to {link[1]})")
            _fail(path, what, "no such file")
        if e.errno == errno.ENOTDIR:
            _fail(path, what, "a part of the path is not a folder")
        _fail(path, what, e.strerror or str(e))


def _check_stat(st, path, what, max_bytes, hint):
    if not stat.S_ISREG(st.st_mode):
        _fail(path, what, f"is {_kind(st.st_mode)}, not a regular file")
    if st.st_size > max_bytes:
        _fail(path, what, f"is {size_text(st.st_size)}, more than the {size_text(max_bytes)} such an input may be "
                          f"({hint or 'is it the right file?'})")


def _open_input(path, what, max_bytes, hint=None):
    """An fd of a checked regular file; a FIFO is refused before it is opened (O_NONBLOCK:
    one swapped in after the check opens without waiting, and fstat refuses it)."""
    _check_stat(_stat_input(path, what), path, what, max_bytes, hint)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC | os.O_NONBLOCK | os.O_NOCTTY)
    except OSError as e:
        _fail(path, what, e.strerror or str(e))
    try:
        st = os.fstat(fd)
        _check_stat(st, path, what, max_bytes, hint)
    except BaseException:
        os.close(fd)
        raise
    return fd, st.st_size


def check_input(path, what="", max_bytes=MAX_INPUT_BYTES, hint=None):
    """Refused unless path names (through any links) a regular file of at most max_bytes."""
    st = _stat_input(path, what)
    _check_stat(st, path, what, max_bytes, hint)
    return st.st_size


def read_input(path, what="", max_bytes=MAX_INPUT_BYTES, hint=None):
    """The whole file as bytes: symlinks resolved (broken or looping: an error naming the link),
    a regular file only (a folder, FIFO or device: an error naming its kind), at most max_bytes."""
    fd, size = _open_input(path, what, max_bytes, hint)
    try:
        chunks, got = [], 0
        while got < size:
            try:
                b = os.read(fd, min(size - got, 1 << 24))
            except OSError as e:
                _fail(path, what, f"read error: {e.strerror}")
            if not b:
                _fail(path, what, "read error (the file shrank while it was read)")
            chunks.append(b)
            got += len(b)
        if os.read(fd, 1):
            _fail(path, what, "read error (the file grew while it was read)")
        return b"".join(chunks)
    finally:
        os.close(fd)


def read_text_input(path, what="", max_bytes=MAX_SETTINGS_BYTES, hint=None):
    """read_input as UTF-8 text; a bad byte is an error naming the line."""
    data = read_input(path, what, max_bytes, hint)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        _fail(f"{path}:{line}", what,
              f"not UTF-8 text (byte {e.start})")


_STRINGS = re.compile(r'"(?:[^"\\\n]|\\.)*"')
_BRACKETS = re.compile(r"[\[\]{}]")


def json_depth_error(text, limit=MAX_JSON_DEPTH):
    """(line, depth) where text nests deeper than limit, else None; strings are skipped."""
    bare = _STRINGS.sub('""', text)
    depth = 0
    for m in _BRACKETS.finditer(bare):
        depth += 1 if m.group() in "[{" else -1
        if depth > limit:
            return bare.count("\n", 0, m.start()) + 1, depth
    return None


class _Duplicate(ValueError):
    def __init__(self, key):
        super().__init__(key)
        self.key = key


def _no_duplicates(pairs):
    seen = {}
    for k, v in pairs:
        if k in seen:
            raise _Duplicate(k)
        seen[k] = v
    return seen


def _no_constant(name):
    raise ValueError(f"{name} is not a JSON number")


def parse_json(text, where):
    """JSON text as read_json_input parses it; `where` names it in errors (the file)."""
    deep = json_depth_error(text)
    if deep:
        raise Refused(f"{where}:{deep[0]}: not accepted: nested too deeply (more than {MAX_JSON_DEPTH} levels)")
    try:
        return json.loads(text, object_pairs_hook=_no_duplicates, parse_constant=_no_constant)
    except json.JSONDecodeError as e:
        raise Refused(f"{where}:{e.lineno}:{e.colno}: not valid JSON: {e.msg}")
    except _Duplicate as e:
        key = json.dumps(e.key)
        hits = [m.start() for m in re.finditer(re.escape(key) + r"\s*:", text)]
        line = text.count("\n", 0, hits[1]) + 1 if len(hits) > 1 else "?"
        raise Refused(f"{where}:{line}: duplicate key {key}")
    except RecursionError:
        raise Refused(f"{where}: not accepted: nested too deeply")
    except ValueError as e:                      # an integer of more than 4300 digits, NaN
        raise Refused(f"{where}: not valid JSON: {'a number with too many digits' if 'digits' in str(e) else e}")


def read_json_input(path, what="", max_bytes=MAX_SETTINGS_BYTES, hint=None):
    """A JSON document from a file: read_text_input, duplicate keys and nesting deeper than 512
    refused, every error naming the file and line."""
    return parse_json(read_text_input(path, what, max_bytes, hint), path)


def input_identity(role, path, what="", max_bytes=MAX_INPUT_BYTES):
    """{"role", "path", "bytes", "sha256"} of an input for a manifest (streamed, not kept)."""
    fd, size = _open_input(path, what or role, max_bytes)
    h = hashlib.sha256()
    try:
        while True:
            b = os.read(fd, 1 << 20)
            if not b:
                break
            h.update(b)
    finally:
        os.close(fd)
    return {"role": role, "path": os.path.realpath(path), "bytes": size, "sha256": h.hexdigest()}


def sequence_inputs(role, folder, frames=None):
    """Identities of a KITTI-layout sequence's files (poses.txt, calib.txt, times.txt and the
    scans velodyne/NNNNNN.bin, or NNNNNN.bin in the folder itself); frames: (first, last) or None."""
    ids = []
    for name in ("poses.txt", "calib.txt", "times.txt"):
        if os.path.lexists(os.path.join(folder, name)):
            ids.append(input_identity(f"{role}/{name}", os.path.join(folder, name), name, MAX_SETTINGS_BYTES))
    velo = os.path.join(folder, "velodyne")
    scans = velo if os.path.isdir(velo) else folder
    for name in sorted(os.listdir(scans)):
        m = re.fullmatch(r"(\d+)\.bin", name)
        if m and (frames is None or frames[0] <= int(m.group(1)) <= frames[1]):
            ids.append(input_identity(f"{role}/{os.path.relpath(os.path.join(scans, name), folder)}",
                                      os.path.join(scans, name)))
    return ids


# ----------------------------------------------------------------------------------------------
# Output folders

def atomic_write(path, data):
    """Writes data (str or bytes) beside path as .tigris-tmp-<name>-<pid>, then renames it over
    path: a killed run leaves the old file or none, never half a file."""
    d, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(d, f"{TMP_PREFIX}{name}-{os.getpid()}")
    if isinstance(data, str):
        data = data.encode("utf-8", "backslashreplace")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise Refused(f"cannot write {path}: {e.strerror or e}")


def write_json(path, obj):
    atomic_write(path, json.dumps(obj, indent=1) + "\n")


def save_figure(fig, path, **kw):
    """A matplotlib figure written like atomic_write (format from path's extension)."""
    d, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(d, f"{TMP_PREFIX}{name}-{os.getpid()}")
    try:
        fig.savefig(tmp, format=os.path.splitext(name)[1][1:] or "png", **kw)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise Refused(f"cannot write {path}: {e.strerror or e}")


def parent_outputs():
    """The names a parent keeps in this command's folder (TIGRIS_PARENT_OUTPUTS)."""
    return os.environ.get(PARENT_ENV, "").split()


def _matches(name, is_dir, patterns):
    for p in patterns:
        if p.endswith("/"):
            if is_dir and fnmatch.fnmatchcase(name, p[:-1]):
                return p
        elif fnmatch.fnmatchcase(name, p):
            return p
    return None


def _flat(obj, prefix=""):
    if isinstance(obj, dict) and obj:
        out = {}
        for k, v in obj.items():
            out.update(_flat(v, f"{prefix}.{k}" if prefix else str(k)))
        return out
    return {prefix: obj}


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
    def claim(self, settings=None, inputs=(), resume=True, all_inputs_must_match=True, input_paths=()):
        """Creates or checks the folder, locks it, compares or clears an earlier run, writes the
        manifest. inputs: identities (input_identity) compared on resume; input_paths: (flag,
        path) of every input, none of which may be an output. Raises Refused (exit 2)."""
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
                    self._remove_outputs(old)
            self._remove_temporaries()
            self.old = old
            self.manifest = {"tigris_manifest": 1, "command": self.command, "argv": self.argv, "cwd": os.getcwd(),
                             "settings": settings, "inputs": inputs, "outputs": self.outputs,
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
            m = self._peek()
            who = f"pid {m.get('pid')}, tigris {m.get('command')}" if isinstance(m, dict) else "another process"
            raise Refused(f"{self.given} is locked by a run still writing into it ({who}): wait until it has "
                          f"finished, or use another {self.flag}")

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
        a, b = _flat(old.get("settings") or {}), _flat(settings)
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


def exit_status(exc):
    """The exit code of an exception leaving a command's main (for OutFolder.finish)."""
    if isinstance(exc, Interrupted):
        return 128 + exc.signum
    if isinstance(exc, KeyboardInterrupt):
        return 130
    if isinstance(exc, SystemExit):
        return exc.code if isinstance(exc.code, int) else 1
    return 2


# ----------------------------------------------------------------------------------------------
# Child processes

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


# ----------------------------------------------------------------------------------------------
# --list-flags, as the C++ commands print it (testbench/options.cpp flags_json)

def flags_json(parser, command):
    flags = []
    for act in parser._actions:
        longs = [o for o in act.option_strings if o.startswith("--")]
        if not longs:
            continue
        takes = act.nargs != 0
        kind = {int: "INT", float: "FLOAT"}.get(act.type, "TEXT") if takes else ""
        default = act.default if takes and act.default not in (None, argparse.SUPPRESS) else ""
        doc = (act.help or "").replace("%(default)s", str(act.default)).replace("%%", "%")
        flags.append({"flag": longs[0][2:], "takes_value": takes, "type": kind,
                      "default": "" if isinstance(default, list) else str(default), "doc": doc})
    return {"command": command, "flags": flags}


def list_flags(parser, command, argv):
    """`tigris COMMAND --list-flags` (alone): prints the flags as JSON and exits 0."""
    if list(argv) == ["--list-flags"]:
        print(json.dumps(flags_json(parser, command), indent=2))
        sys.exit(0)


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
