"""The one table of why a compiled run stopped (hosedrogue.model.status): every failing code the
kernels return has its line, and the fixed-length loops (simulate and the stepper) say the same."""

from hosedrogue.model import layout as LY
from hosedrogue.model.status import STATUS_TEXT, status_text
from hosedrogue.spec.params import PAPER


def test_every_failing_code_has_one_line():
    failing = {LY.NONFINITE, LY.YAW_LIMIT, LY.STEP_LIMIT, LY.STAGE_LIMIT, LY.REEL_END}
    assert set(STATUS_TEXT) == failing
    assert all(text and "\n" not in text for text in STATUS_TEXT.values())


def test_the_paper_hoses_yaw_limit_names_the_cure_and_no_other_code_does():
    assert "converged" in status_text(LY.YAW_LIMIT, PAPER)
    assert status_text(LY.YAW_LIMIT) == STATUS_TEXT[LY.YAW_LIMIT]
    assert status_text(LY.NONFINITE, PAPER) == STATUS_TEXT[LY.NONFINITE]
    converged = PAPER.replace(hose={"bending": "moment"})
    assert status_text(LY.YAW_LIMIT, converged) == STATUS_TEXT[LY.YAW_LIMIT]


def test_simulate_and_the_stepper_stop_at_the_yaw_limit_with_the_same_message():
    """The same start past the limit at once, run by simulate and by the fixed-length stepper."""
    from hosedrogue.analysis.equilibrium import solve_equilibrium
    from hosedrogue.simulation import simulate
    from hosedrogue.simulation.stepper import FixedLengthStepper

    p = PAPER.replace(numerics={"max_yaw_deg": 1.0})
    eq = solve_equilibrium(p)
    n = p.hose.links
    x0 = eq.state.copy()
    x0[2 * n + 1:: 2] = 1.0  # yaw rates [rad/s] carry the links past 1 deg within the first steps
    res = simulate(p, 1.0, x0=x0, equilibrium=eq)
    st = FixedLengthStepper(p, 1.0, control_step_s=p.numerics.step_s, x0=x0, equilibrium=eq)
    while not st.done:
        st.step()
    other = st.result()
    assert not res.completed and not other.completed
    assert "yaw passed the limit" in res.message and "converged" in res.message
    assert res.message == other.message
    assert res.t_s[-1] == other.t_s[-1]  # the same last state kept: both save on the same output grid
