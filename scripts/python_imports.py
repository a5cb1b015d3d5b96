#!/usr/bin/env python3
"""The package tigris's imports (issue 56): its layers in order (core, data, reports, tools: each
imports only itself and the layers before it, and none the NumPy module `model`), no import cycle,
and no import of one of its modules inside a function (the way a cycle hides), except of the
modules that load matplotlib (plots, figure_truth), which the tools take only when they draw, and
of `model`, which `import tigris` loads on first use.

    scripts/python_imports.py        exit 1 naming each problem
"""
import ast
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PYTHON = os.path.join(ROOT, "python")
PACKAGE = "tigris"
LAYERS = ["core", "data", "reports", "tools"]
# matplotlib: imported when a figure is drawn; NumPy and the extension: when a name needs them
LAZY = {"tigris.reports.plots", "tigris.reports.figure_truth", "tigris.model"}


def modules():
    """{dotted name: path} of the package's modules (its tests aside)."""
    out = {}
    for root, dirs, files in os.walk(os.path.join(PYTHON, PACKAGE)):
        dirs[:] = [d for d in dirs if d not in ("tests", "__pycache__")]
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(root, f), PYTHON)[:-3].replace(os.sep, ".")
                out[rel[:-len(".__init__")] if rel.endswith(".__init__") else rel] = os.path.join(root, f)
    return out


def layer_of(name):
    """The index of the layer `name` is in (LAYERS), None for the package's own modules."""
    parts = name.split(".")
    return LAYERS.index(parts[1]) if len(parts) > 1 and parts[1] in LAYERS else None


def targets(node, package, known):
    """The package's modules an import statement names."""
    names = []
    if isinstance(node, ast.ImportFrom):
        base = node.module or ""
        if node.level:
            base = package
            for _ in range(node.level - 1):
                base = base.rsplit(".", 1)[0]
            base = f"{base}.{node.module}" if node.module else base
        # `from P import m` names the module P.m when there is one, else P itself
        names = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
    elif isinstance(node, ast.Import):
        names = [a.name for a in node.names]
    return [n for n in names if n in known]


def main():
    known = modules()
    graph, problems = {}, []
    for name, path in sorted(known.items()):
        tree = ast.parse(open(path).read(), path)
        package = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
        graph[name] = {t for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))
                       for t in targets(node, package, known)}
        for fn in ast.walk(tree):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in ast.walk(fn):
                    if isinstance(node, (ast.Import, ast.ImportFrom)):
                        for t in set(targets(node, package, known)) - LAZY:
                            problems.append(f"{os.path.relpath(path, ROOT)}:{node.lineno}: {fn.name}() imports {t} "
                                            "inside a function (import it at the top)")
    for name, deps in sorted(graph.items()):
        layer = layer_of(name)
        for d in sorted(deps):
            if layer is not None and (d == "tigris.model" or layer_of(d) is None and d != PACKAGE
                                      or (layer_of(d) or 0) > layer):
                problems.append(f"{name} ({LAYERS[layer]}) imports {d}, "
                                f"{'the NumPy module' if d == 'tigris.model' else 'a later layer'}")
    state = {}

    def visit(n, trail):
        state[n] = "open"
        for d in sorted(graph.get(n, ())):
            if state.get(d) == "open":
                problems.append("import cycle: " + " -> ".join(trail + [n, d]))
            elif d not in state:
                visit(d, trail + [n])
        state[n] = "done"

    for n in sorted(graph):
        if n not in state:
            visit(n, [])
    for p in problems:
        print(p)
    print(f"{len(known)} modules, {sum(len(v) for v in graph.values())} imports, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
