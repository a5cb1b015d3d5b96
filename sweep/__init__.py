"""The analysis side of Tigris TLM, one Python package: the design-space sweep (tigris_sweep),
the comparison of runs (tigris_diff), the figures (tigris_plot, plots, odometry_plots), the
paper's evaluation reproduced (reproduce, report, evaldata), its design variants (variants) and
the registration pipeline's design-space exploration (pipeline_dse); `core` is the shared core
they all use for output folders, inputs, child processes, --list-flags and provenance. The tools
run as modules with the folder that holds this package on PYTHONPATH (`python3 -m
sweep.tigris_sweep ARGS`, as the tigris binary runs them: `tigris sweep ARGS`)."""
import os as _os
import sys as _sys

# Every tool imports the shared core first: a copy of this folder without core/ (TIGRIS_SWEEP_DIR
# at a partial copy) is said in one line, not a traceback.
_here = _os.path.dirname(_os.path.abspath(__file__))
if not _os.path.isfile(_os.path.join(_here, "core", "__init__.py")):
    _env = _os.environ.get("TIGRIS_SWEEP_DIR")
    print(f"tigris: error: {f'TIGRIS_SWEEP_DIR={_env}: ' if _env else ''}{_here} has no core/ (the tools' shared "
          "core): a partial copy of sweep/; " + ("point TIGRIS_SWEEP_DIR at a whole one, or unset it" if _env
                                                 else "reinstall tigris"), file=_sys.stderr)
    _sys.exit(2)
