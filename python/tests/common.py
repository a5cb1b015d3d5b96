"""Shared helpers of the Python package's tests, which pytest runs (conftest.py at the top of the
tree gives --tigris and --keep and puts the package on sys.path; each file also runs standalone:
python3 python/tests/test_X.py --tigris build/bin/tigris [--keep]). The tests import the package
as a user does (`from tigris.reports import report`, `from tigris.core import folders`); the
tools run as `python3 -m tigris TOOL` (tool_command)."""
import argparse, csv, json, os, random, shutil, struct, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))     # the source tree
PACKAGE = os.path.join(REPO, "python", "tigris")  # the package's source
if os.path.join(REPO, "python") not in sys.path and not any(
        os.path.isfile(os.path.join(p, "tigris", "__main__.py")) for p in sys.path):
    sys.path.insert(0, os.path.join(REPO, "python"))   # standalone, before conftest.py has run
from tigris.core import paper_stages, parse_stages, python_module_command  # noqa: E402
sys.path.insert(0, os.path.join(REPO, "tests"))  # the tree's shared test helpers
from support import alive, descendants, digest  # noqa: E402,F401

SKIP = 77                                        # ctest SKIP_RETURN_CODE

# What `tigris register --list-stages` prints (registration/pipeline.hpp's stage_list): the one
# copy the tests hold, for synthetic stage data; test_pipeline_dse.test_list_stages checks that
# the binary under test prints these stages. The tools themselves ask the binary.
LIST_STAGES_OUTPUT = """[
  {"key": "outlier_removal", "title": "outlier removal"},
  {"key": "normals", "title": "normal estimation"},
  {"key": "keypoints", "title": "key-point detection"},
  {"key": "descriptors", "title": "descriptor calculation"},
  {"key": "kpce", "title": "KPCE"},
  {"key": "rejection", "title": "rejection"},
  {"key": "icp", "title": "ICP", "parts": [{"title": "RPCE", "time": "kdtree_search"},
                                          {"title": "transformation estimation", "time": "rest"}]}
]"""
LIST_STAGES = parse_stages(LIST_STAGES_OUTPUT, "LIST_STAGES_OUTPUT")
PAPER_STAGES = paper_stages(LIST_STAGES)         # [(title, key, time)]: outlier removal .. rejection, RPCE, ...
PAPER_TITLES = tuple(title for title, _, _ in PAPER_STAGES)


def tool_command(tool, *args, env=None, python=None):
    """(argv, env) that run the package's tool ("sweep", "reproduce", ...) as `python3 -m tigris
    TOOL ARGS` with the package's folder first on PYTHONPATH; env: the environment to start
    from (default os.environ)."""
    return python_module_command(tool, [str(x) for x in args], env=env, python=python)


def run_tool(tool, *args, env=None, python=None, **kw):
    """subprocess.run of `python3 -m tigris TOOL ARGS` (tool_command), stdout and stderr
    captured as text; kw: more of subprocess.run's (cwd, timeout)."""
    cmd, env = tool_command(tool, *args, env=env, python=python)
    return subprocess.run(cmd, capture_output=True, text=True, env=env, **kw)


def package_env(env=None):
    """env (default os.environ) with the repository first on PYTHONPATH: a child `python3 -c`
    that imports the package."""
    return tool_command("sweep", env=env)[1]


def options():
    """The run's options (conftest.py: pytest's --tigris and --keep; standalone, the environment):
    a.tigris, the binary under test; a.keep, keep the temporary folders."""
    tigris = os.path.abspath(os.environ.get("TIGRIS_TEST_BINARY") or os.environ.get("TIGRIS") or
                             os.path.join(HERE, "..", "..", "build", "bin", "tigris"))
    if not os.access(tigris, os.X_OK):
        sys.exit(f"no tigris binary at {tigris} (give --tigris)")
    return argparse.Namespace(tigris=tigris, keep=os.environ.get("TIGRIS_TEST_KEEP") == "1")


def main(path):
    """A test file run standalone (python3 python/tests/test_X.py [--tigris PATH] [--keep] [-k NAME]):
    pytest on that file."""
    import pytest
    sys.exit(pytest.main([path, *sys.argv[1:]]))


class Workdir:
    """A temporary folder, removed at the end unless --keep or the test failed."""
    def __init__(self, a, name):
        self.path = tempfile.mkdtemp(prefix=f"tigris-{name}-")
        self.keep = a.keep

    def __enter__(self):
        return self.path

    def __exit__(self, exc_type, exc, tb):
        if self.keep or exc_type not in (None, SystemExit) or exc_type is SystemExit and exc.code not in (0, SKIP):
            print(f"(files kept in {self.path})", file=sys.stderr)
        else:
            shutil.rmtree(self.path, ignore_errors=True)


def write_cloud(path, n, seed):
    """A small KITTI .bin (x, y, z, intensity float32): random points in a 40 x 40 x 4 m box."""
    r = random.Random(seed)
    with open(path, "wb") as f:
        for _ in range(n):
            f.write(struct.pack("<4f", r.uniform(-20, 20), r.uniform(-20, 20), r.uniform(-2, 2), 0.0))


def small_workload(folder, n_cloud=3000, n_queries=800):
    write_cloud(os.path.join(folder, "cloud.bin"), n_cloud, 1)
    write_cloud(os.path.join(folder, "queries.bin"), n_queries, 2)


def write_spec(folder, spec, name="spec.json"):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(spec, f, indent=1)
    return path


def sweep(a, *args, check=None, timeout=300, env=None, **kw):
    """Runs the driver (python3 -m tigris sweep ARGS); returns the CompletedProcess
    (stdout, stderr as text). env: the environment to start from (default os.environ); kw:
    more of subprocess.run's (cwd, preexec_fn)."""
    cmd, env = tool_command("sweep", *args, env=env)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, **kw)
    if check is not None and p.returncode != check:
        raise AssertionError(f"exit {p.returncode}, expected {check}: {' '.join(args)}\n"
                             f"stdout: {p.stdout}\nstderr: {p.stderr}")
    return p


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def footer_clear(fig, gid="tigris-footer"):
    """The text of fig's footer (core.add_footer), checked to lie inside the figure and below
    every axes with its labels and ticks: neither cut off nor overlapping."""
    fig.canvas.draw()
    text = next((t for t in fig.texts if t.get_gid() == gid), None)
    assert text is not None, "no footer"
    box = text.get_window_extent()
    assert box.x0 >= 0 and box.y0 >= 0 and box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height, box
    for ax in fig.axes:
        assert ax.get_tightbbox().y0 > box.y1, (ax.get_tightbbox(), box)
    return text.get_text()
