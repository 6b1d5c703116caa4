"""The O(n) articulated-body recursion against the dense mass-matrix solve."""

import numpy as np
import pytest

from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER


@pytest.mark.parametrize("n", [1, 2, 5, 20, 200])
@pytest.mark.parametrize("bending", ["paper", "moment"])
def test_recursion_matches_dense_solve(n, bending, rng):
    """Same accelerations to 1e-10 relative (the brief's bound). Both are exact solutions of
    H qdd = Q; they differ only by round-off, which grows with H's condition number (~1e4 at
    n = 200 here), so 1e-10 leaves ample margin yet catches any wrong term (order 1e-3 or more)."""
    p = PAPER.replace(hose={"links": n, "bending": bending}, turbulence={"enabled": True, "start_s": 0.0})
    m = HoseModel(p, duration_s=15.0)  # gusts over the 15 s the times below are drawn from
    for _ in range(4):
        q = np.empty(2 * n)
        q[0::2] = rng.uniform(-0.3, 1.2, n)
        q[1::2] = rng.uniform(-0.8, 0.8, n)
        qd = rng.uniform(-1.5, 1.5, 2 * n)
        u = rng.uniform(-200, 200, 2)
        t = rng.uniform(0.0, 15.0)
        fast = m.accelerations(q, qd, t, u)
        dense = m.accelerations_dense(q, qd, t, u)
        assert np.linalg.norm(fast - dense) <= 1e-10 * np.linalg.norm(dense)


@pytest.mark.parametrize("lumping", ["aft", "split"])
def test_tow_force_is_momentum_balance(lumping, rng):
    """Without air the only external loads are the joint weights, so the force on the tow point
    must equal sum(M g z) - sum(M A), with the joint accelerations A taken here by central
    differences of the joint velocities along the motion (a different route from the
    recursion's). 1e-6 relative is the difference quotient's truncation error (h = 1e-6 s)."""
    from hosedrogue.constants import G0

    n = 9
    m = HoseModel(PAPER.replace(hose={"links": n, "bending": "moment", "mass_lumping": lumping},
                                flight={"density_scale": 0.0}))
    q = np.empty(2 * n)
    q[0::2] = rng.uniform(0.8, 2.0, n)
    q[1::2] = rng.uniform(-0.5, 0.5, n)
    x = np.concatenate([q, rng.uniform(-1, 1, 2 * n)])
    h = 1e-6
    dx = m.derivative(0.0, x)
    acc = (m.outputs(x + h * dx).joint_velocities_m_s - m.outputs(x - h * dx).joint_velocities_m_s) / (2 * h)
    # the whole hose's weight, the half link lumped at the (fixed) tow point included for "split"
    hose_and_drogue = m.params.hose.mass_per_length_kg_m * m.params.hose.length_m + m.params.drogue.mass_kg
    assert m.M.sum() + m.M_tow == pytest.approx(hose_and_drogue, rel=1e-14)
    expected = hose_and_drogue * np.array([0.0, 0.0, G0]) - (m.M[:, None] * acc[1:]).sum(axis=0)
    got = m.outputs(x).tow_force_n
    assert np.linalg.norm(got - expected) <= 1e-6 * np.linalg.norm(expected)
