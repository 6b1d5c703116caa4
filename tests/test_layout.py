"""The package's layout: importing it changes no global state."""

import subprocess
import sys

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
    from pathlib import Path

    from importlinter.cli import lint_imports

    assert lint_imports(config_filename=str(Path(__file__).parents[1] / "pyproject.toml")) == 0
