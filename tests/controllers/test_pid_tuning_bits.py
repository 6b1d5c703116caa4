"""The tuned gains are the same bits in every process: the tuning (this model's linearization at
the paper's case, its 2nd-order channels, the search) run in two fresh processes with a different
hash seed and different BLAS and OpenMP thread counts."""

import os
import subprocess
import sys

import pytest

_SCRIPT = """
from hosedrogue.analysis.linearize import linearize
from hosedrogue.controllers.design import paper_step_targets, reduced_channels
from hosedrogue.controllers.pid_tuning import tune_pid_to_step
from hosedrogue.spec.params import PAPER

ch = reduced_channels(linearize(PAPER), 2)
for name, g in (("lateral", ch.lateral), ("vertical", ch.vertical)):
    t = tune_pid_to_step(g, paper_step_targets()[name])
    print(name, *(float(v).hex() for v in (t.gains.kp, t.gains.ki, t.gains.kd, t.gains.n_filter)))
"""


def _run(extra: dict) -> str:
    env = {**os.environ, **extra}
    out = subprocess.run([sys.executable, "-c", _SCRIPT], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return out.stdout


@pytest.mark.subprocess
def test_tuned_gains_are_bit_identical_across_processes():
    a = _run({"PYTHONHASHSEED": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"})
    b = _run({"PYTHONHASHSEED": "12345", "OMP_NUM_THREADS": "2", "OPENBLAS_NUM_THREADS": "2"})
    assert a.count("\n") == 2 and a == b
