"""The engagement's compiled variants (docs/develop.md, "The compiled core", fourth round): the steps
and outputs compiled without the loops' code (no controller, pilot or receiver), or with a pilot's
or receiver's only, give the bits of the ones compiled with every loop, and each run is given the
variant of its kind of link, integrator and loops."""

import dataclasses

import numpy as np
import pytest

from hosedrogue.engagement import driver as DR
from hosedrogue.model import layout as LY
from hosedrogue.model.engagement import evaluation as EV, outputs as EO, steps as ES


@pytest.mark.parametrize("name, duration_s, kind", [("engage-response", 4.0, EV.NO_LOOPS),
                                                     ("approach-moderate-pilot", 3.0, EV.STEERED)])
def test_a_run_is_the_same_by_the_steps_compiled_for_its_loops_only(monkeypatch, tmp_path, name, duration_s, kind):
    """The responsive reel's engagement (no controller, pilot or receiver) through the capture and
    the take-up's remeshes, and the pilot flying the probe in turbulence: their states, outputs
    and per-step loads by the steps and outputs compiled for their loops only are those of the
    ones compiled with every loop, to the bit (the pruned code is code that such a run never
    enters)."""
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run

    scenario = dataclasses.replace(load_scenario(name), duration_s=duration_s)
    own = run(scenario)
    for module in (ES, EO, DR):
        monkeypatch.setattr(module, "loop_kind", lambda ep: EV.CONTROLLED)
    full = run(scenario)
    if kind == EV.NO_LOOPS:
        assert own.outcome["result"] == "captured" and own.outcome["remesh_events"] > 0
    else:
        assert own.probe_position_m.shape[0] > 100 and np.ptp(own.probe_position_m[:, 1]) > 0.0  # the pilot flew
    assert (own.step_loads is None) == (kind == EV.STEERED)  # rigid links keep no per-step loads
    if own.step_loads is not None:
        assert np.array_equal(own.step_loads, full.step_loads)
    assert np.array_equal(own.drogue_tension_n, full.drogue_tension_n)
    own.to_csv(tmp_path / "own.csv")
    full.to_csv(tmp_path / "full.csv")
    assert (tmp_path / "own.csv").read_bytes() == (tmp_path / "full.csv").read_bytes()


@pytest.mark.parametrize("slots, kind", [((), EV.NO_LOOPS), (("EP_PIL",), EV.STEERED), (("EP_RCV",), EV.STEERED),
                                         (("EP_CTRL",), EV.CONTROLLED), (("EP_CTRL", "EP_PIL"), EV.CONTROLLED),
                                         (("EP_CTRL", "EP_RCV"), EV.CONTROLLED)])
def test_each_loop_selects_the_steps_compiled_for_it(slots, kind):
    """A controller (with or without a pilot or receiver) selects the steps and outputs compiled
    with every loop; a pilot or a receiver alone the steered ones; none of them the ones without;
    the kind of link and the integrator select theirs."""
    ep = np.zeros(LY.EP_SIZE)
    for slot in slots:
        ep[getattr(LY, slot)] = 1.0
    assert EV.loop_kind(ep) == kind
    kinds = {(0.0, LY.SCHEME_RK4): 0, (1.0, LY.SCHEME_RK4): 1, (1.0, LY.SCHEME_SDIRK2): 2,
             (0.0, LY.SCHEME_SDIRK2): 0}  # rigid links: RK4 whatever the scheme slot holds
    chosen = set()
    for (elastic, scheme), link in kinds.items():
        ep[LY.EP_ELASTIC], ep[LY.EP_SCHEME] = elastic, scheme
        assert ES.link_kind(ep) == link and ES.steps_kernel(ep) is ES.STEPS[kind, link]
        chosen.add(ES.steps_kernel(ep))
        # the raw measurement (and the outputs) exist with the drogue controller and without it only
        raw = {(True, 1.0): EO.eng_raw_elastic, (True, 0.0): EO.eng_raw_rigid,
               (False, 1.0): EO.eng_raw_elastic_bare, (False, 0.0): EO.eng_raw_rigid_bare}
        assert EO.raw_kernel(ep) is raw[kind == EV.CONTROLLED, elastic]
    assert len(chosen) == 3 and len(set(ES.STEPS.values())) == 9  # nine distinct compiled steps


def test_the_loop_arrays_without_a_controller_are_the_numba_type_of_those_with_one():
    """``no_loop()`` (the read-only arrays of ``LinearController.static_zero()``) and a user's
    controller give the kernels one numba type, so that nothing is compiled twice for the loop
    (an engagement FMU compiled its evaluation for both)."""
    from types import SimpleNamespace

    from numba import typeof

    from hosedrogue.engagement.loop import no_loop
    from hosedrogue.model.integrate import loop_arrays
    from hosedrogue.spec.params import Actuator

    ctrl = SimpleNamespace(A=np.zeros((1, 1)), B=np.zeros((1, 2)), C=np.zeros((2, 1)), D=np.zeros((2, 2)), n_states=1)
    user = loop_arrays(ctrl, np.zeros(2), Actuator(), np.zeros((1, 2)), 1.0)
    assert typeof(no_loop()) == typeof(user)
    assert all(a.flags.writeable for a in no_loop() if isinstance(a, np.ndarray))
