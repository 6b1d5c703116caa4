"""The reel's set point at rest by the raw measurement's kernel (what a sampled-data stepper
compiles; docs/develop.md, "The compiled core", fifth round) is the output kernel's, bit for bit,
for rigid and elastic links, compiled with the drogue controller's code and without it; and the stepper asks
for it."""

import numpy as np
import pytest

from hosedrogue.engagement import driver
from hosedrogue.engagement.loop import no_loop
from hosedrogue.engagement.result import segment_outputs
from hosedrogue.model import layout as LY
from hosedrogue.model.engagement import outputs as EO
from hosedrogue.scenarios import load_scenario


@pytest.fixture(scope="module", params=["approach-moderate", "engage-response"])
def start(request):
    """A rigid (approach-moderate) and an elastic (engage-response, the SDIRK) engagement's start."""
    sc = load_scenario(request.param)
    e = sc.engagement
    return driver.prepare(sc.params, 0.1, reel=e.reel, probe=e.probe, bow_wave=e.bow_wave)


@pytest.mark.parametrize("controlled", [False, True])
def test_the_set_point_at_rest_by_the_measurement_is_the_outputs_one(start, controlled):
    """T_0 of the balance position, in the steady air and with the reel held as
    ``exit_tension_at_rest`` sets them up, by ``measured_exit_tension`` and by the output kernel:
    the same evaluation of the same state, so the same 64 bits (and a tension: positive)."""
    st = start
    chain, model = st.chain, st.model
    e = st.ep.copy()
    e[LY.EP_LAW] = LY.LAW_LOCKED
    e[LY.EP_PROBE] = 0.0
    e[LY.EP_BW] = LY.BW_OFF
    by_outputs = segment_outputs(np.zeros(1), st.z[None, :], chain, _Steady(model), e, controlled=controlled)[2][0, LY.O_T0]
    by_raw = EO.measured_exit_tension(st.z, chain.n, chain.l, chain.M, chain.J, model.ps, model.steady_env,
                                      model.gust_values, e, chain.chart, no_loop(), controlled)
    assert by_outputs > 0.0
    assert np.float64(by_raw).tobytes() == np.float64(by_outputs).tobytes()


def test_the_driver_gives_the_same_set_point_either_way(start):
    """``exit_tension_at_rest(..., measured=True)`` (the stepper's) and the default (the driver's)."""
    st = start
    a = driver.exit_tension_at_rest(st.params, st.chain, st.z, st.ep, st.model)
    b = driver.exit_tension_at_rest(st.params, st.chain, st.z, st.ep, st.model, measured=True)
    assert a > 0.0 and np.float64(a).tobytes() == np.float64(b).tobytes()
    assert np.float64(st.t_set).tobytes() == np.float64(a).tobytes()  # prepare's default: the output kernel


class _Steady:
    """The model's arrays in steady air (``exit_tension_at_rest``'s)."""

    def __init__(self, model):
        self.ps, self.env, self.gust_values = model.ps, model.steady_env, model.gust_values
