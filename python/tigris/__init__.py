"""Tigris TLM from Python: the golden model and the accelerator model on NumPy arrays.

    import numpy as np, tigris
    cloud = tigris.load_cloud("frame0.bin")                     # float32 (N, 3)
    nn = tigris.search(cloud, queries, mode="nn")              # the golden model, in process
    job = tigris.run(cloud, queries, mode="knn", k=8, preset="dram-2x")   # one accelerator job
    job.stats["cycles"], job.verdict, job.bound
    reg = tigris.register(source, target, preset="dp4", search="exact")
    reg.transform                                              # 4 x 4

`search` runs the golden model in this process. `run` and `register` run the `tigris` binary
in a child process of their own (SystemC elaborates once per process), with the arrays written
as KITTI .bin files to the job's folder (a temporary one, or keep=DIR: the command's --out
folder, under the rule of --out); their figures are `tigris run`'s and `tigris register`'s,
field for field. Errors are exceptions carrying the command line's messages: ValueError for bad
arrays and settings (naming the argument), IndexError for a query index out of range,
tigris.TigrisError for a refused run or folder, and tigris.MismatchError when the accelerator's
results differ from the golden model's.
docs/python.md is the tutorial.
"""
# The analysis tools are subpackages by layer, each importing only the layers before it:
#   core     the shared core: output folders, inputs, child processes, provenance (docs/architecture.md)
#   data     the binary and its sub-commands, sweep specs, sweep CSVs, DSE documents
#   reports  the paper's claims measured (report), figures, the variants' robustness matrix
#   tools    the commands: sweep, reproduce, diff, plot, pipeline-dse (`python3 -m tigris TOOL`,
#            or `tigris TOOL`)
# The NumPy names below load on first use (PEP 562): the tools need neither NumPy nor _tigris, so
# they run from a build without the extension and start without importing NumPy.

__all__ = ["load_cloud", "synthetic_pair", "search", "run", "register", "config_keys", "presets", "binary",
           "SearchResult", "RunResult", "Registration", "TigrisError", "MismatchError", "InputError"]


def __getattr__(name):
    if name not in __all__:
        raise AttributeError(f"module 'tigris' has no attribute '{name}'")
    from . import model   # the one deferred import: NumPy and the extension, when first used
    return getattr(model, name)


def __dir__():
    return sorted(list(globals()) + __all__)
