"""The engagement's compiled variants (docs/develop.md, "The compiled core", fourth round): the steps
and outputs compiled without the loops' code (no controller, pilot or receiver) give the bits of
the ones compiled with it, and each run is given the variant of its kind of link, integrator and
loops."""

import dataclasses

import numpy as np
import pytest

from hosedrogue.model import layout as LY
from hosedrogue.model.engagement import evaluation as EV, outputs as EO, steps as ES


def test_a_run_without_loops_is_the_same_by_the_steps_compiled_without_them(monkeypatch, tmp_path):
    """The responsive reel's engagement (no controller, pilot or receiver) through the capture and
    the take-up's remeshes: its states, outputs and per-step loads by the steps and outputs
    compiled without the loops' code are those of the ones compiled with it, to the bit (the
    pruned code is code that such a run never enters)."""
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run

    scenario = dataclasses.replace(load_scenario("engage-response"), duration_s=4.0)
    bare = run(scenario)
    monkeypatch.setattr(ES, "has_loops", lambda ep: True)
    monkeypatch.setattr(EO, "has_loops", lambda ep: True)
    full = run(scenario)
    assert bare.outcome["result"] == "captured" and bare.outcome["remesh_events"] > 0
    assert np.array_equal(bare.step_loads, full.step_loads)
    assert np.array_equal(bare.drogue_tension_n, full.drogue_tension_n)
    bare.to_csv(tmp_path / "bare.csv")
    full.to_csv(tmp_path / "full.csv")
    assert (tmp_path / "bare.csv").read_bytes() == (tmp_path / "full.csv").read_bytes()


@pytest.mark.parametrize("slot", ["EP_CTRL", "EP_PIL", "EP_RCV"])
def test_each_loop_selects_the_steps_compiled_with_the_loops(slot):
    """A controller, a pilot or a receiver each select the steps and outputs compiled with the
    loops; none of them the ones without; the kind of link and the integrator select theirs."""
    ep = np.zeros(LY.EP_SIZE)
    assert not EV.has_loops(ep)
    kinds = {(0.0, LY.SCHEME_RK4): 0, (1.0, LY.SCHEME_RK4): 1, (1.0, LY.SCHEME_SDIRK2): 2,
             (0.0, LY.SCHEME_SDIRK2): 0}  # rigid links: RK4 whatever the scheme slot holds
    bare = (ES.eng_steps_rigid_bare, ES.eng_steps_elastic_rk4_bare, ES.eng_steps_elastic_sdirk2_bare)
    looped = (ES.eng_steps_rigid, ES.eng_steps_elastic_rk4, ES.eng_steps_elastic_sdirk2)
    for (elastic, scheme), kind in kinds.items():
        ep[LY.EP_ELASTIC], ep[LY.EP_SCHEME] = elastic, scheme
        ep[getattr(LY, slot)] = 0.0
        assert ES.link_kind(ep) == kind and ES.steps_kernel(ep) is bare[kind]
        ep[getattr(LY, slot)] = 1.0
        assert EV.has_loops(ep) and ES.steps_kernel(ep) is looped[kind]


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
