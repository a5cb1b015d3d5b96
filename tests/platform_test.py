#!/usr/bin/env python3
"""Tigris as a platform other programs use (docs/install.md): the install, relocated; a PCL
program outside the tree built against the installed CMake package; the Python module from the
relocated prefix; the Debian package's contents. A test per part, in this order:

  install   `cmake --install BUILD --prefix A`, A copied to B and removed: B/bin/tigris runs
            `run` (with a preset), `presets`, `sweep` (a spec naming a preset), `plot` and every
            other command (small); no source path in the binary; the installed headers and
            package files are there
  example   examples/pcl_search built with find_package(TigrisTLM) from B (CMAKE_PREFIX_PATH
            only): registers the built-in pair on the golden model, in the loop with a preset
            (the same transform, every job checked, none falling back), and records a trace that
            `tigris run --trace` replays bit-exact
  python    with PYTHONPATH=B/lib/python3/dist-packages: `import tigris` gives the module and the
            tools, `python3 -m tigris sweep` runs a sweep as `tigris sweep` does, and
            python/tests/test_tigris.py passes (the installed package finds B/bin/tigris beside it)
  deb       `cpack -G DEB`: the package's Depends, and its files unpacked (dpkg-deb -x) run
            `tigris run --config paper` from there

Run: python3 -m pytest tests/platform_test.py --tigris BUILD/bin/tigris [-k PART] (the build
folder is the binary's: BUILD/bin/tigris).
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 1200


# A sanitizer build's ctest preloads the sanitizer runtimes for python3 (its module is
# instrumented); the other programs run without them (cpack hangs under a preloaded ASan).
PLAIN_ENV = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}


def sh(cmd, cwd=None, env=None, ok=(0,)):
    p = subprocess.run(cmd, cwd=cwd, env=PLAIN_ENV if env is None else env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=TIMEOUT, stdin=subprocess.DEVNULL)
    if p.returncode not in ok:
        raise AssertionError(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stdout[-4000:]}")
    return p.stdout


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def check_no_tree_paths(binary_path, trees):
    """No path into the source or build tree in the binary: it reads nothing from them. A
    sanitizer build keeps each source file's name for its diagnostics (GCC's instrumentation
    takes the compiler's input path as given); those, and only those, are allowed there."""
    with open(binary_path, "rb") as f:
        binary = f.read()
    sanitized = b"__asan_init" in binary or b"__ubsan_handle" in binary
    for tree in trees:
        for m in re.finditer(re.escape(tree.encode()) + rb"[^\0]*", binary):
            text = m.group().decode(errors="replace")
            check(sanitized, f"the installed binary holds {text!r}, a path into {tree}")
            check(re.fullmatch(re.escape(tree) + r"/[\w/.+-]+\.(cpp|hpp|h)", text),
                  f"the sanitizer build's binary holds {text!r}, a path into {tree} that is no source file's name")


def installed(build, tmp):
    """The install, copied elsewhere and the original removed: the prefix that must work."""
    first, moved = os.path.join(tmp, "first"), os.path.join(tmp, "moved", "prefix")
    sh(["cmake", "--install", build, "--prefix", first])
    shutil.copytree(first, moved, symlinks=True)
    shutil.rmtree(first)
    return moved


def part_install(build, prefix, tmp):
    tig = os.path.join(prefix, "bin", "tigris")
    for f in ("include/tigris/sw_ref/kdtree.hpp", "include/tigris/registration/search_plugin.hpp",
              "lib/cmake/TigrisTLM/TigrisTLMConfig.cmake", "share/tigris/presets/paper.json",
              "lib/python3/dist-packages/tigris/__main__.py", "lib/python3/dist-packages/tigris/tools/sweep.py",
              "lib/python3/dist-packages/tigris/core/folders.py"):
        check(os.path.isfile(os.path.join(prefix, f)), f"the install has no {f}")
    check(not glob.glob(os.path.join(prefix, "lib/python3/dist-packages/tigris/**/test*"), recursive=True) and
          not os.path.exists(os.path.join(prefix, "share/tigris/sweep")), "the install carries tests or the old sweep/")
    check_no_tree_paths(tig, [SRC, os.path.abspath(build)])
    work = os.path.join(tmp, "work")
    os.makedirs(work)
    out = sh([tig, "run", "--config", "dram-8x", "--out", "r"], cwd=work)
    check("MATCH" in out, f"tigris run from the relocated prefix did not match:\n{out}")
    stats = json.load(open(os.path.join(work, "r", "stats.json")))
    check(stats["config"]["dram"]["bytes_per_cycle"] == 409.6, "--config dram-8x did not set the DRAM bandwidth")
    check(any(i.get("path", "").startswith(prefix) for i in stats["inputs"] if i.get("role") == "config"),
          "stats.json's inputs do not name the preset's file in the prefix")
    presets = json.loads(sh([tig, "presets", "--json"]))
    check(presets["dir"] == os.path.join(prefix, "share", "tigris", "presets"), f"presets read from {presets['dir']}")
    check({"paper", "top-6", "top-10", "dram-2x", "dram-8x", "pb-banks-64", "pb-banks-256", "nc-32k",
           "nc-512k", "paper-accounting"} <= {p["name"] for p in presets["presets"]}, "a preset is missing")
    with open(os.path.join(work, "spec.json"), "w") as f:
        json.dump({"command": "run", "base": {"config": "top-6", "sim-threads": 1},
                   "grid": {"fe.recursion_units": [32, 64]}}, f)
    out = sh([tig, "sweep", "spec.json", "--out", "sw", "--jobs", "2"], cwd=work)
    check("2 ok" in out, f"the relocated sweep:\n{out}")
    rows = open(os.path.join(work, "sw", "sweep.csv")).read()
    check("top-6.json" in rows, "the sweep's CSV does not name the preset's file")
    out = sh([tig, "plot", "sw"], cwd=work)
    check(glob.glob(os.path.join(work, "sw", "plots", "*.png")), f"tigris plot drew nothing:\n{out}")
    # Every other command, small, from the same prefix.
    sh([tig, "ref", "--mode", "knn", "--k", "4", "--out", "ref"], cwd=work)
    out = sh([tig, "diff", "r", os.path.join("sw", "points", "fe.recursion_units=64")], cwd=work, ok=(0, 1))
    check("dram.bytes_per_cycle" in out, f"tigris diff from the relocated prefix:\n{out}")
    reg = sh([tig, "register", "--search", "exact", "--out", "reg"], cwd=work)
    check(json.load(open(os.path.join(work, "reg", "registration.json")))["status"] == "converged", reg)
    sh([tig, "synth", "--frames", "3", "--out", "seq"], cwd=work)
    sh([tig, "odometry", "--sequence", "seq", "--search", "exact", "--out", "odo"], cwd=work)
    check(os.path.isfile(os.path.join(work, "odo", "metrics.json")), "tigris odometry wrote no metrics.json")
    sh([tig, "reproduce", "--quick", "--specs-only", "--out", "rp"], cwd=work)
    check(glob.glob(os.path.join(work, "rp", "specs", "*.json")), "tigris reproduce --specs-only wrote no spec")
    sh([tig, "pipeline-dse", "--help"], cwd=work)
    bad = sh([tig, "run", "--config", "dram2x"], cwd=work, ok=(2,))
    check("no preset named 'dram2x' (did you mean 'dram-2x'?)" in bad, f"an unknown preset's message:\n{bad}")
    print("install: the relocated prefix runs run, presets, sweep, plot, ref, diff, register, synth, odometry, "
          "reproduce and pipeline-dse; no source path in the binary")


def part_example(build, prefix, tmp):
    ex = os.path.join(tmp, "example")
    shutil.copytree(os.path.join(SRC, "examples", "pcl_search"), os.path.join(ex, "src"))
    env = dict(PLAIN_ENV, CMAKE_PREFIX_PATH=prefix)
    sh(["cmake", "-S", os.path.join(ex, "src"), "-B", os.path.join(ex, "build")], env=env)
    sh(["cmake", "--build", os.path.join(ex, "build"), "-j2"], env=env)
    prog = os.path.join(ex, "build", "register_pair")
    golden = sh([prog, "--builtin"])
    accel = sh([prog, "--builtin", "--accel", "--config", "nc-32k"])

    def transform(out):
        m = re.search(r"transform:\n((?:\s+.*\n){4})", out)
        check(m, f"no transform printed:\n{out}")
        return m.group(1)
    check(transform(golden) == transform(accel), "the accelerator in the loop changed ICP's transform")
    m = re.search(r"accelerator: (\d+) jobs, (\d+) queries, (\d+) cycles.*; (\d+) searches fell back", accel)
    check(m and int(m.group(1)) > 1 and int(m.group(3)) > 0, f"no accelerator jobs:\n{accel}")
    check(int(m.group(4)) == 0, f"searches fell back to the CPU:\n{accel}")
    m2 = re.search(r"searches (\d+),", accel)
    check(m2 and int(m2.group(1)) == int(m.group(2)), "the jobs' queries are not every search")
    trace = os.path.join(ex, "icp.trace")
    sh([prog, "--builtin", "--record-trace", trace])
    replay = sh([os.path.join(prefix, "bin", "tigris"), "run", "--trace", trace, "--out", os.path.join(ex, "replay"),
                 "--jobs", "2"])
    check("MATCH (every query of every job bit-exact)" in replay, f"the example's trace did not replay:\n{replay}")
    bad = sh([prog, os.path.join(ex, "nope.pcd"), os.path.join(ex, "nope.pcd")], ok=(2,))
    check("nope.pcd" in bad, f"a missing cloud's message:\n{bad}")
    print("example: built against the installed package; golden and in-the-loop transforms equal, trace replays")


def part_python(build, prefix, tmp):
    site = os.path.join(prefix, "lib", "python3", "dist-packages")
    check(glob.glob(os.path.join(site, "tigris", "_tigris*.so")), "the install has no Python module")
    env = dict(os.environ, PYTHONPATH=site)               # the preloads, if any, stay for python3
    env.pop("TIGRIS", None)
    out = sh([sys.executable, "-c", "import tigris, tigris.tools.sweep, tigris.reports.report; print(tigris.binary()); "
              "print(tigris.tools.sweep.__file__)"], env=env, cwd=tmp)
    check(out.split() == [os.path.join(prefix, "bin", "tigris"), os.path.join(site, "tigris", "tools", "sweep.py")],
          f"the installed package runs and holds:\n{out}")
    # python3 -m tigris sweep, as `tigris sweep` runs it: the same points, the same CSV.
    work = os.path.join(tmp, "pysweep")
    os.makedirs(work)
    with open(os.path.join(work, "spec.json"), "w") as f:
        json.dump({"base": {"mode": "nn"}, "grid": {"height": [4, 6]}}, f)
    out = sh([sys.executable, "-m", "tigris", "sweep", "spec.json", "--out", "py", "--jobs", "2"], env=env, cwd=work)
    check("2 ok" in out, f"python3 -m tigris sweep:\n{out}")
    sh([os.path.join(prefix, "bin", "tigris"), "sweep", "spec.json", "--out", "bin", "--jobs", "2"], cwd=work)
    rows = [[r.split(",")[:3] for r in open(os.path.join(work, d, "sweep.csv")).read().splitlines()] for d in ("py", "bin")]
    check(rows[0] == rows[1] and len(rows[0]) == 3, f"python3 -m tigris sweep and tigris sweep differ: {rows}")
    sh([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", os.path.join(SRC, "python", "tests", "test_tigris.py"),
        "--tigris", os.path.join(prefix, "bin", "tigris")], env=env, cwd=tmp)
    print("python: the relocated package gives the module and the tools; python3 -m tigris sweep is tigris sweep; "
          "python/tests/test_tigris.py passes")


def part_deb(build, prefix, tmp):
    out = sh(["cpack", "-G", "DEB", "-B", os.path.join(tmp, "deb")], cwd=build)
    debs = glob.glob(os.path.join(tmp, "deb", "tigris-tlm_*.deb"))
    check(len(debs) == 1, f"cpack made {debs}:\n{out}")
    depends = sh(["dpkg-deb", "-f", debs[0], "Depends"])
    for pkg in ("libsystemc-dev", "libpcl-dev", "python3-numpy"):
        check(pkg in depends, f"the package does not depend on {pkg}: {depends}")
    root = os.path.join(tmp, "deb-root")
    sh(["dpkg-deb", "-x", debs[0], root])
    run = sh([os.path.join(root, "usr", "bin", "tigris"), "run", "--config", "paper", "--out", "r"], cwd=tmp)
    check("MATCH" in run, f"the packaged binary:\n{run}")
    # The package's Python tools are the binary's: found in usr/lib/python3/dist-packages beside it.
    usage = sh([os.path.join(root, "usr", "bin", "tigris"), "diff", "--help"], cwd=tmp)
    check("usage: tigris diff" in usage, f"the packaged tigris diff:\n{usage}")
    site = os.path.join(root, "usr", "lib", "python3", "dist-packages")
    out = sh([sys.executable, "-c", "import tigris, tigris.tools.sweep; print(tigris.binary()); "
              "print(tigris.search(*tigris.synthetic_pair()).indices.shape)"],
             env=dict({k: v for k, v in PLAIN_ENV.items() if k != "TIGRIS"}, PYTHONPATH=site), cwd=tmp)
    check(out.split()[0] == os.path.join(root, "usr", "bin", "tigris") and "(" in out,
          f"import tigris from the package's files:\n{out}")
    print(f"deb: {os.path.basename(debs[0])} depends on {depends.strip()}; its binary runs unpacked")


PARTS = {"install": part_install, "example": part_example, "python": part_python, "deb": part_deb}


@pytest.fixture(scope="module")
def platform(tigris, tmp_path_factory):
    """(the build folder, the relocated install prefix, a scratch folder)."""
    build = os.path.dirname(os.path.dirname(tigris))
    tmp = str(tmp_path_factory.mktemp("platform"))
    return build, installed(build, tmp), tmp


@pytest.mark.parametrize("part", list(PARTS))
def test_part(platform, part):
    PARTS[part](*platform)


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, *sys.argv[1:]]))
