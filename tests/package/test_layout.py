"""The package's layout: importing it changes no global state, dependencies point one way, and
modules and functions stay small enough to read (docs/develop.md, "Layers")."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import hosedrogue

IMPORT_ALL = """
import importlib, pkgutil, sys
import matplotlib
before = dict(matplotlib.rcParams)
import hosedrogue
for m in pkgutil.walk_packages(hosedrogue.__path__, "hosedrogue."):
    if m.name.endswith("__main__"):
        continue
    importlib.import_module(m.name)
changed = sorted(k for k, v in matplotlib.rcParams.items() if k != "backend" and before.get(k) != v)
print(matplotlib.get_backend(), changed)
"""


@pytest.mark.subprocess
def test_importing_every_module_keeps_the_users_matplotlib_backend():
    # a user who chose a backend (here the non-default 'svg', which needs no display) keeps it,
    # and no other matplotlib setting is changed (python-control loads pyplot, which is harmless)
    env = {"MPLBACKEND": "svg", "PATH": "/usr/bin:/bin"}
    r = subprocess.run([sys.executable, "-c", IMPORT_ALL], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "svg []"


def test_one_dependency_direction():
    # the import-linter layers contract in pyproject.toml (docs/develop.md, "Layers"): a module may
    # import only from layers below its own, function-level imports included
    from importlinter.cli import lint_imports

    assert lint_imports(config_filename=str(Path(__file__).parents[2] / "pyproject.toml")) == 0


MAX_MODULE_LINES = 500  # docs/develop.md, "Layers": a module a reader can hold in view, the compiled core's too
MAX_FUNCTION_LINES = 80  # code lines, docstring excluded; compiled kernels aside


def _is_compiled(node) -> bool:
    for d in node.decorator_list:
        target = d.func if isinstance(d, ast.Call) else d
        if getattr(target, "id", None) == "njit" or getattr(target, "attr", None) == "njit":
            return True
    return False


def _code_lines(node) -> int:
    lines = node.end_lineno - node.lineno + 1
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(getattr(body[0], "value", None), ast.Constant) \
            and isinstance(body[0].value.value, str):
        lines -= body[0].end_lineno - body[0].lineno + 1
    for inner in body:  # a compiled kernel defined in a factory (a closure over a constant) is aside too
        if isinstance(inner, (ast.FunctionDef, ast.AsyncFunctionDef)) and _is_compiled(inner):
            lines -= inner.end_lineno - inner.decorator_list[0].lineno + 1
    return lines


def test_modules_and_functions_stay_small():
    root = Path(hosedrogue.__file__).parent
    too_long = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix()
        text = path.read_text()
        if len(text.splitlines()) > MAX_MODULE_LINES:
            too_long.append(f"{rel}: {len(text.splitlines())} lines")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not _is_compiled(node):
                if _code_lines(node) > MAX_FUNCTION_LINES:
                    too_long.append(f"{rel}::{node.name}: {_code_lines(node)} code lines")
    assert not too_long, "; ".join(too_long)


def test_no_import_cycles():
    """No module imports itself back, directly or through others, inside a package or between
    packages (function-level imports and imports for annotations under TYPE_CHECKING count too):
    the strongly connected components of the import graph (Tarjan) are single modules."""
    import grimp

    graph = grimp.build_graph("hosedrogue", cache_dir=None)
    index, low, stack, on_stack, cycles = {}, {}, [], set(), []

    def visit(module):
        index[module] = low[module] = len(index)
        stack.append(module)
        on_stack.add(module)
        for imported in sorted(graph.find_modules_directly_imported_by(module)):
            if imported not in index:
                visit(imported)
                low[module] = min(low[module], low[imported])
            elif imported in on_stack:
                low[module] = min(low[module], index[imported])
        if low[module] == index[module]:
            component = []
            while not component or component[-1] != module:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1:
                cycles.append(" <-> ".join(sorted(component)))

    for module in sorted(graph.modules):
        if module not in index:
            visit(module)
    assert not cycles, "; ".join(cycles)
