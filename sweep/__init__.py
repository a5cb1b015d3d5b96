"""The analysis side of Tigris TLM, one Python package: the design-space sweep (tigris_sweep),
the comparison of runs (tigris_diff), the figures (tigris_plot, plots, odometry_plots), the
paper's evaluation reproduced (reproduce, report, evaldata), its design variants (variants) and
the registration pipeline's design-space exploration (pipeline_dse); `core` is the shared core
they all use for output folders, inputs, child processes, --list-flags and provenance. The tools
run as modules with the folder that holds this package on PYTHONPATH (`python3 -m
sweep.tigris_sweep ARGS`, as the tigris binary runs them: `tigris sweep ARGS`)."""
