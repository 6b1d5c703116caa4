"""The balance position's entry compiled for level flight in still air at rest
(``evaluate_point_still``) against the entry of every case (``evaluate_point``): the narrow one is
the same code with the tanker's motion, the gust record, the bow wave and the structural damping
(zero at rest) pruned, so wherever :func:`point_kernel` lets it run, both must give the same bits
(a difference would mean a pruned branch was live, or that the selection let the narrow entry see
a case it does not model); and the selection must refuse every case the narrow entry leaves out."""

import numpy as np
import pytest

from hosedrogue.analysis.equilibrium import solve_equilibrium, towed_cable_guess
from hosedrogue.analysis.steady_flight import steady_params
from hosedrogue.model import chain_dynamics as CD, layout as LY
from hosedrogue.model.chain_loads import still_level
from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER


def _evaluate(kernel, model, x, residual, env):
    ws, xi, G, Q = CD.point_work(model.n)
    kernel(residual, 0.0, x, np.zeros(2), model.l, model.M, model.J, model.ps, env, model.gust_values, ws, xi, G, Q)
    if residual:
        return Q.copy()
    return np.concatenate([ws[CD.WS_QDD], ws[CD.WS_R].ravel(), ws[CD.WS_DRAG], ws[CD.WS_TOW], ws[CD.WS_T0]])


@pytest.mark.parametrize("hose", [{}, {"bending": "paper", "drag_quadrature": "gauss2", "bending_damping_n_m2_s": 5.0},
                                  {"bending": "off", "links": 7}])
def test_still_entry_gives_the_full_entrys_bits(hose):
    model = HoseModel(PAPER.replace(hose=hose))
    env = model.steady_env
    assert still_level(env)
    q = towed_cable_guess(model)
    rest = np.concatenate([q, np.zeros_like(q)])
    assert CD.point_kernel(env, rest, narrow=True) is CD.evaluate_point_still
    for residual in (True, False):
        a = _evaluate(CD.evaluate_point, model, rest, residual, env)
        b = _evaluate(CD.evaluate_point_still, model, rest, residual, env)
        assert a.tobytes() == b.tobytes()


def test_narrow_balance_position_is_the_same():
    wide = solve_equilibrium(PAPER)
    narrow = solve_equilibrium(PAPER, narrow=True)
    for name in ("q", "joints_m", "drogue_drag_n", "tow_force_n"):
        assert getattr(wide, name).tobytes() == getattr(narrow, name).tobytes()
    assert wide.exit_tension_n == narrow.exit_tension_n and wide.residual == narrow.residual


def test_selection_refuses_the_air_the_still_entry_leaves_out():
    model = HoseModel(PAPER)
    env = model.steady_env
    rest = np.zeros(4 * model.n)
    assert CD.point_kernel(env, rest, narrow=False) is CD.evaluate_point
    assert CD.point_kernel(env, rest, narrow=True) is CD.evaluate_point_still
    moving = rest.copy()
    moving[-1] = 1e-3  # one link's yaw rate: the damping and the drag of a moving link
    assert CD.point_kernel(env, moving, narrow=True) is CD.evaluate_point
    for slot, value in ((LY.ENV_M_ON, 1.0), (LY.ENV_BW, 1.0), (LY.ENV_FROZEN, 1.0)):
        other = env.copy()
        other[slot] = value
        assert not still_level(other) and CD.point_kernel(other, rest, narrow=True) is CD.evaluate_point
    gusty = env.copy()  # a gust window open at t (the covariance's record holds one at all times)
    gusty[LY.ENV_T_ON], gusty[LY.ENV_T_OFF] = -1e300, 1e300
    assert not still_level(gusty, 0.0)
    gusty[LY.ENV_T_ON], gusty[LY.ENV_T_OFF] = 5.0, 10.0
    assert still_level(gusty, 4.0) and not still_level(gusty, 5.0) and still_level(gusty, 10.0)
    turn = HoseModel(steady_params(PAPER, 20.0, 0.0))  # a steady turn: the frame's apparent forces
    assert turn.steady_env[LY.ENV_M_ON] == 1.0 and not still_level(turn.steady_env)
