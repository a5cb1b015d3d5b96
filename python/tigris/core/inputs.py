"""Inputs: one opener for every file a tool reads (the C++ twin: core/input_file.*): links
resolved, regular files only, a size bound, errors naming the file and line."""
import errno, hashlib, json, os, re, stat
from .base import MAX_INPUT_BYTES, MAX_JSON_DEPTH, MAX_SETTINGS_BYTES, Refused, size_text


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
