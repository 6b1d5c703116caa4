"""Packaging: the wheel built by ``python -m build`` carries every module, the shipped scenarios
and presets (package data) and the ``hosedrogue`` command.

Installing that wheel into a clean virtual environment and running ``hosedrogue steady`` and
``hosedrogue simulate swing-release`` there is ``make wheel-check``: it downloads or unpacks the
whole dependency stack (~700 MB) and compiles the numba kernels afresh, about two minutes, too
much for every test run; this test checks the wheel's contents in seconds.
"""

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import hosedrogue

pytestmark = pytest.mark.packaging

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "hosedrogue"
#: Files that are build or run by-products, never package content.
NOT_SHIPPED = {"__pycache__", ".pyc", ".nbi", ".nbc"}

pytest.importorskip("build")
if Path(hosedrogue.__file__).resolve().parent != PACKAGE:  # pragma: no cover - installed elsewhere
    pytest.skip("needs the source tree of the imported package", allow_module_level=True)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    # built from a copy of the project's build inputs: setuptools writes build/ and the egg-info into
    # the tree it builds, so two builds of one tree (this module's tests on two xdist workers) raced
    # there ("error: [Errno 2] No such file or directory" while copying modules, seen in a fresh clone)
    tree = tmp_path_factory.mktemp("tree")
    shutil.copytree(ROOT / "src", tree / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc", "*.egg-info"))
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, tree / name)
    # isolated build (setuptools from pip's cache or the index), as a user or CI would build it
    done = subprocess.run([sys.executable, "-m", "build", "--wheel", "--outdir", str(out), str(tree)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    (path,) = out.glob("hosedrogue-*.whl")
    with zipfile.ZipFile(path) as zf:
        return {"names": set(zf.namelist()),
                "entry_points": next(zf.read(n).decode() for n in zf.namelist() if n.endswith("entry_points.txt")),
                "metadata": next(zf.read(n).decode() for n in zf.namelist() if n.endswith("METADATA"))}


def source_files() -> list[str]:
    """Every file of the package source tree, as a path inside the wheel."""
    return sorted(str(Path("hosedrogue") / p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*")
                  if p.is_file() and not (set(p.parts) | {p.suffix}) & NOT_SHIPPED)


def test_wheel_holds_every_module_and_data_file(wheel):
    missing = [name for name in source_files() if name not in wheel["names"]]
    assert not missing, f"not in the wheel: {missing}"


def test_wheel_holds_the_shipped_scenarios_and_presets(wheel):
    from hosedrogue.scenarios import shipped_scenarios

    scenarios = {f"hosedrogue/scenarios/{name}.toml" for name in shipped_scenarios()}
    assert "hosedrogue/scenarios/swing-release.toml" in scenarios
    presets = {str(Path("hosedrogue") / p.relative_to(PACKAGE)) for p in PACKAGE.glob("spec/presets/*.toml")}
    assert "hosedrogue/spec/presets/converged.toml" in presets
    assert scenarios | presets <= wheel["names"]


def test_wheel_declares_the_command_and_extras(wheel):
    """The wheel's metadata: the console script and the optional extras (installing the wheel and
    running it is ``make wheel-check``; see the module docstring)."""
    assert "hosedrogue = hosedrogue.cli:main" in wheel["entry_points"]
    for extra in ("test", "fmu", "docs"):
        assert f"Provides-Extra: {extra}" in wheel["metadata"]
