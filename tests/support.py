"""Helpers every Python test of the tree shares (tests/*.py scripts and, through
sweep/tests/common.py, the sweep tools' tests): file digests and the processes below a pid."""
import hashlib
import os


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
