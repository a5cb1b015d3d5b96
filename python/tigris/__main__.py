"""python3 -m tigris TOOL ARGS: the analysis tools, as `tigris TOOL ARGS` runs them.

The binary runs this same dispatcher (with $TIGRIS set to itself and $TIGRIS_COMMIT to its
commit); run directly, the tools use the binary of the prefix or build tree the package sits in
(tigris.data.binary.find_binary) or $TIGRIS.
"""
import importlib
import os
import sys

# A partial copy of the package (TIGRIS_PYTHONPATH at one without its layers) is said in one
# line, not a traceback.
_HERE = os.path.dirname(os.path.abspath(__file__))
_MISSING = [f"{d}/" for d in ("core", "data", "reports", "tools") if not os.path.isfile(os.path.join(_HERE, d, "__init__.py"))]
if _MISSING:
    _env = os.environ.get("TIGRIS_PYTHONPATH")
    print(f"tigris: error: {f'TIGRIS_PYTHONPATH={_env}: ' if _env else ''}{_HERE} has no {', '.join(_MISSING)} (the "
          "package's layers): a partial copy of the package tigris; " +
          ("point TIGRIS_PYTHONPATH at the folder that holds a whole one, or unset it" if _env else "reinstall tigris"),
          file=sys.stderr)
    sys.exit(2)

from .data.binary import commit_of_binary  # noqa: E402

# tool -> (module, summary); the first five are also commands of the binary (tigris --help).
TOOLS = {
    "sweep": ("tools.sweep", "a design-space sweep from a JSON spec, locally or on Slurm (docs/sweeps.md)"),
    "reproduce": ("tools.reproduce", "the paper's section 6 experiments, figures and REPORT.md"),
    "diff": ("tools.diff", "compare runs: configurations, headline figures, every other differing leaf"),
    "plot": ("tools.plot", "figures of a sweep folder or CSV"),
    "pipeline-dse": ("tools.pipeline_dse", "the paper's section 3: the registration pipeline's design space"),
    "report": ("reports.report", "REPORT.md (the paper's claims measured) from sweep CSVs"),
    "figures": ("reports.plots", "the paper's figures from sweep CSVs"),
    "odometry-plots": ("reports.odometry_plots", "an odometry folder's figures (tigris odometry draws them)"),
}


def usage(out):
    print("usage: python3 -m tigris TOOL [ARGS...]   (TOOL --help explains each)\n\ntools:", file=out)
    for name, (_, summary) in TOOLS.items():
        print(f"  {name:16}{summary}", file=out)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        usage(sys.stdout if argv else sys.stderr)
        return 0 if argv else 2
    if argv[0] not in TOOLS:
        print(f"python3 -m tigris: error: no tool '{argv[0]}'", file=sys.stderr)
        usage(sys.stderr)
        return 2
    module, _ = TOOLS[argv[0]]
    if not os.environ.get("TIGRIS_COMMIT"):
        os.environ["TIGRIS_COMMIT"] = commit_of_binary()
    tool = importlib.import_module(f"{__package__}.{module}")
    sys.argv = [f"tigris {argv[0]}"] + argv[1:]
    return tool.main(argv[1:])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
