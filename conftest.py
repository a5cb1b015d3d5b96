"""pytest's configuration for the project's Python tests (docs/testing.md).

The binary under test is an option and a fixture: `--tigris PATH` (default $TIGRIS, else
build/bin/tigris of this tree). `--keep` keeps the tests' temporary folders, `--record` rewrites
the recordings a test compares against. A run whose every test was skipped (no Slurm cluster,
say) exits 77, which ctest reports as skipped.
"""
import os
import types

import pytest

ROOT = os.path.dirname(os.path.abspath(__file__))
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


@pytest.fixture(scope="session")
def a(pytestconfig, tigris):
    """The run's options as the tests' helpers take them: a.tigris, a.keep."""
    return types.SimpleNamespace(tigris=tigris, keep=pytestconfig.getoption("keep"))


def pytest_configure(config):
    # The sweep tests' helpers (sweep/tests/common.py) read the options from here.
    os.environ["TIGRIS_TEST_BINARY"] = os.path.abspath(config.getoption("tigris"))
    if config.getoption("keep"):
        os.environ["TIGRIS_TEST_KEEP"] = "1"


def pytest_sessionfinish(session, exitstatus):
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is None or exitstatus != 0:
        return
    skipped, passed = reporter.stats.get("skipped", []), reporter.stats.get("passed", [])
    if skipped and not passed:
        session.exitstatus = SKIPPED_ALL
