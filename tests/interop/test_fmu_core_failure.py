"""The fixed-length FMU's own RK4 loop (hosedrogue.interop.fmu_core.HoseDrogueCore), called
directly: a step it cannot take ends with the status table's line, the one every loop gives, and
the core keeps the state it had (tests/interop/test_fmu_description.py checks the same failures
as fmpy logs them)."""

import math

import numpy as np
import pytest

from hosedrogue.interop.fmu_core import HoseDrogueCore, fmu_params
from hosedrogue.interop.fmu_interface import StepFailure
from hosedrogue.model import layout as LY
from hosedrogue.model.status import STATUS_TEXT
from hosedrogue.spec.params import PAPER


@pytest.fixture(scope="module")
def params():
    return fmu_params(PAPER, PAPER.flight.altitude_m, PAPER.flight.airspeed_m_s, PAPER.wake.enabled)


@pytest.mark.parametrize("force_n, code", [((1e7, 0.0), LY.YAW_LIMIT), ((math.nan, 0.0), LY.NONFINITE)])
def test_a_step_it_cannot_take_ends_with_the_status_tables_line_and_keeps_the_state(params, force_n, code):
    """10 MN sideways at the drogue swings the links past the yaw limit within the step; a NaN
    force makes the state non-finite at once."""
    core = HoseDrogueCore(params)
    core.step(0.0, 0.1, (0.0, 0.0))
    kept = core.x.copy()
    with pytest.raises(StepFailure) as err:
        core.step(0.1, 0.5, force_n)
    assert err.value.reason.startswith(STATUS_TEXT[code] + ": ")
    assert 0.1 < err.value.t_s <= 0.6 and err.value.final
    assert core.t_s == 0.1 and np.array_equal(core.x, kept)
