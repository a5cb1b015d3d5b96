"""pytest's configuration for the project's Python tests (docs/testing.md).

The binary under test is an option and a fixture: `--tigris PATH` (default $TIGRIS, else
build/bin/tigris of this tree). `--keep` keeps the tests' temporary folders, `--record` rewrites
the recordings a test compares against. A run whose every test was skipped (no Slurm cluster,
say) exits 77, which ctest reports as skipped.
"""
import importlib.util
import os
import subprocess
import sys
import time

import pytest

ROOT = os.path.dirname(os.path.abspath(__file__))
LOCAL_SLURM = os.path.join(ROOT, "scripts", "local_slurm.sh")
SKIPPED_ALL = 77  # ctest's SKIP_RETURN_CODE for these tests


def pytest_addoption(parser):
    parser.addoption("--tigris", default=os.environ.get("TIGRIS") or os.path.join(ROOT, "build", "bin", "tigris"),
                     help="the tigris binary under test (default: $TIGRIS, else build/bin/tigris)")
    parser.addoption("--keep", action="store_true", help="keep the tests' temporary folders")
    parser.addoption("--record", action="store_true",
                     help="rewrite the recordings a test compares against (tests/stats_files/) from this binary")


@pytest.fixture(scope="session")
def tigris(pytestconfig):
    """The tigris binary under test, an absolute path."""
    path = os.path.abspath(pytestconfig.getoption("tigris"))
    if not os.access(path, os.X_OK):
        pytest.exit(f"no tigris binary at {path} (give --tigris)", returncode=2)
    return path


@pytest.fixture(scope="module")
def slurm_cluster(tmp_path_factory):
    """(environment with SLURM_CONF, folder) of a one-node Slurm cluster (scripts/local_slurm.sh),
    stopped by PID at the end. Its tests skip with the reason when it cannot start (no root or
    sudo, no packages), unless TIGRIS_REQUIRE_SLURM=1."""
    d = str(tmp_path_factory.mktemp("slurm"))
    cluster = os.path.join(d, "cluster")
    t0 = time.monotonic()
    p = subprocess.run([LOCAL_SLURM, "start", cluster], capture_output=True, text=True, timeout=600)
    if p.returncode != 0 or not p.stdout.startswith("export SLURM_CONF="):
        reason = (p.stderr.strip().splitlines() or ["no message"])[-1]
        msg = f"local Slurm cluster did not start (exit {p.returncode}): {reason}"
        subprocess.run([LOCAL_SLURM, "stop", cluster], capture_output=True, text=True)
        if os.environ.get("TIGRIS_REQUIRE_SLURM") == "1":
            pytest.fail(f"{msg}\n{p.stderr}")
        print(p.stderr[-3000:])
        pytest.skip(msg)
    print(f"cluster up in {time.monotonic() - t0:.1f} s", flush=True)
    try:
        yield dict(os.environ, SLURM_CONF=p.stdout.strip().split("=", 1)[1]), d
    finally:
        s = subprocess.run([LOCAL_SLURM, "stop", cluster], capture_output=True, text=True, timeout=120)
        print(s.stderr.strip())
        assert s.returncode == 0 and not os.path.exists(os.path.join(cluster, "pids")), s.stderr


def pytest_configure(config):
    # The package tigris the tests import: the one on PYTHONPATH (an install under test), else
    # the build tree's of the binary under test (it has the extension), else the source's (the
    # tools need none).
    binary = os.path.abspath(config.getoption("tigris"))
    built = os.path.join(os.path.dirname(os.path.dirname(binary)), "python")
    if importlib.util.find_spec("tigris") is None:
        sys.path.insert(0, built if os.path.isfile(os.path.join(built, "tigris", "__main__.py"))
                        else os.path.join(ROOT, "python"))
    # The Python tests' helpers (python/tests/common.py) read the options from here.
    os.environ["TIGRIS_TEST_BINARY"] = binary
    if config.getoption("keep"):
        os.environ["TIGRIS_TEST_KEEP"] = "1"


def pytest_sessionfinish(session, exitstatus):
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is None or exitstatus != 0:
        return
    skipped, passed = reporter.stats.get("skipped", []), reporter.stats.get("passed", [])
    if skipped and not passed:
        session.exitstatus = SKIPPED_ALL
