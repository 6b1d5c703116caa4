"""A run that designs nothing imports no design or plotting library: python-control (with the
scipy.signal and matplotlib.pyplot it imports) costs about 0.8 s of CPU per process, paid by every
campaign worker, subprocess and CLI command that only runs a scenario."""

import json
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.subprocess

# what only a controller's design (python-control) or a figure window (pyplot) needs
DESIGN_MODULES = ("control", "scipy.signal", "matplotlib.pyplot")

SCRIPT = """
import json, sys
import hosedrogue as hd
from hosedrogue.studies import campaign  # what a campaign's worker imports
r = hd.run(hd.load_scenario(sys.argv[1]).with_overrides(duration_s=float(sys.argv[2])))
print(json.dumps({"completed": bool(r.completed), "loaded": [m for m in sys.argv[3:] if m in sys.modules]}))
"""


def _loaded_after_run(scenario: str, duration_s: float) -> dict:
    out = subprocess.run([sys.executable, "-c", SCRIPT, scenario, str(duration_s), *DESIGN_MODULES],
                         capture_output=True, text=True, timeout=300, env=os.environ)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_an_approach_without_a_controller_imports_no_design_library():
    done = _loaded_after_run("approach-moderate", 1.0)
    assert done["completed"]
    assert done["loaded"] == []


def test_a_fixed_length_run_without_a_controller_imports_no_design_library():
    done = _loaded_after_run("paper-turbulence", 1.0)
    assert done["completed"]
    assert done["loaded"] == []


def test_the_gymnasium_environments_import_no_design_library():
    code = ("import json, sys, gymnasium, hosedrogue.envs\n"
            "env = gymnasium.make('hosedrogue/Docking-v1')\n"
            "env.reset(seed=0)\n"
            "env.step(env.action_space.sample())\n"
            "print(json.dumps([m for m in sys.argv[1:] if m in sys.modules]))\n")
    out = subprocess.run([sys.executable, "-c", code, *DESIGN_MODULES], capture_output=True, text=True, timeout=300,
                         env=os.environ)
    assert out.returncode == 0, out.stderr[-2000:]
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []
