#!/usr/bin/env python3
"""The Python tools' imports (issue 56): no import cycle among the sweep package's modules, and
no import of one of them inside a function (the way a cycle hides), except of the modules that
load matplotlib (plots, figure_truth), which the tools take only when they draw.

    scripts/python_imports.py        exit 1 naming each cycle and each import inside a function
"""
import ast
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = "sweep"
LAZY = {"sweep.plots", "sweep.figure_truth"}  # matplotlib: imported when a figure is drawn


def modules():
    """{dotted name: path} of the package's modules (its tests aside)."""
    out = {}
    for root, dirs, files in os.walk(os.path.join(ROOT, PACKAGE)):
        dirs[:] = [d for d in dirs if d not in ("tests", "__pycache__")]
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(root, f), ROOT)[:-3].replace(os.sep, ".")
                out[rel[:-len(".__init__")] if rel.endswith(".__init__") else rel] = os.path.join(root, f)
    return out


def targets(node, package, known):
    """The package's modules an import statement names."""
    names = []
    if isinstance(node, ast.ImportFrom) and node.level:
        base = package
        for _ in range(node.level - 1):
            base = base.rsplit(".", 1)[0]
        names = [f"{base}.{node.module}"] if node.module else [f"{base}.{a.name}" for a in node.names]
    elif isinstance(node, ast.ImportFrom) and node.module:
        names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
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
