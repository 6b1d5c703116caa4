"""The link chain's dynamics (numba): Kane's equations, the articulated-body solve, the statics,
the energy and the derived outputs of the fixed-length chain, and the workspace every kernel
writes into.

Everything here is a pure function of float64 arrays (notation: :mod:`hosedrogue.model.chain_loads`,
whose kinematics and loads these functions call, and ``docs/model.md``). Kane's equations give
``H(q) qdd = Q(q, qd, t, u)``. With masses lumped at joints and ``dV_i/dqd_{j}`` zero for
``j > i`` every generalized force is a dot product of a link's partial velocity with a *suffix
sum* of joint forces, so ``Q`` costs O(n). ``H`` is dense (its entry for links i, j is
``S_max(i,j) l_i l_j g_i . g_j`` with ``S_k`` the mass at and aft of joint k+1), but the time
integrators never form it: :func:`chain_forward_dynamics` solves for ``qdd`` in O(n) by an
articulated-body recursion. The dense path (:func:`accelerations_dense`) stays as the reference
the recursion is tested against. The drogue's rotational inertia is the last link's transverse
inertia (in ``J[n-1]``, docs/model.md §2).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..jit import JIT, JIT_NO_ALLOC, JIT_NO_ALLOC_INLINE
from .chain_loads import (env_at, joint_forces, joint_kinematics, kink, link_frames, rotational_terms,
                          still_level)
from .frame import frame_loads
from .layout import BENDING_MOMENT, ENV_SIZE, PS_BENDING, PS_EI, PS_G, PS_M_TOW, Layout


@njit(**JIT_NO_ALLOC_INLINE)
def generalized_forces(l, M, n, a, b, c, F, tau, xi, G, Q):
    """Q (2n): generalized active forces minus velocity-product inertia terms (dense path).

    G (n+1,3) receives the suffix sums G_k = sum_{m>=k} (F_m - M_m xi_m) over joints 1..n, with
    xi_m = sum_{i<m} c_i (xi, (n+1,3)) the velocity-product part of joint m's acceleration.
    """
    for i in range(3):
        xi[0, i] = 0.0
    for k in range(n):
        for i in range(3):
            xi[k + 1, i] = xi[k, i] + c[k, i]
    for i in range(3):
        G[n, i] = 0.0
    for k in range(n - 1, -1, -1):
        for i in range(3):
            G[k, i] = G[k + 1, i] + F[k + 1, i] - M[k] * xi[k + 1, i]
    for k in range(n):
        lk = l[k]
        Q[2 * k] = lk * (a[k, 0] * G[k, 0] + a[k, 1] * G[k, 1] + a[k, 2] * G[k, 2]) + tau[k, 0]
        Q[2 * k + 1] = lk * (b[k, 0] * G[k, 0] + b[k, 1] * G[k, 1] + b[k, 2] * G[k, 2]) + tau[k, 1]


@njit(**JIT_NO_ALLOC)
def mass_matrix(l, S, J, ps, n, a, b, cs, H):
    """H (2n,2n): S_max(i,j) l_i l_j g_i . g_j plus the links' rotational inertia (the drogue's is
    the last link's, ``J[n-1]``)."""
    for j in range(n):
        for i in range(j, n):
            s = S[i] * l[i] * l[j]
            aa = a[j, 0] * a[i, 0] + a[j, 1] * a[i, 1] + a[j, 2] * a[i, 2]
            ab = a[j, 0] * b[i, 0] + a[j, 1] * b[i, 1] + a[j, 2] * b[i, 2]
            ba = b[j, 0] * a[i, 0] + b[j, 1] * a[i, 1] + b[j, 2] * a[i, 2]
            bb = b[j, 0] * b[i, 0] + b[j, 1] * b[i, 1] + b[j, 2] * b[i, 2]
            H[2 * j, 2 * i] = s * aa
            H[2 * j, 2 * i + 1] = s * ab
            H[2 * j + 1, 2 * i] = s * ba
            H[2 * j + 1, 2 * i + 1] = s * bb
            H[2 * i, 2 * j] = s * aa
            H[2 * i + 1, 2 * j] = s * ab
            H[2 * i, 2 * j + 1] = s * ba
            H[2 * i + 1, 2 * j + 1] = s * bb
    for k in range(n):
        c2 = cs[k, 2]
        H[2 * k, 2 * k] += J[k] * c2 * c2
        H[2 * k + 1, 2 * k + 1] += J[k]


#: the rows of the workspace tuple (:func:`make_workspace`; ``ws[WS_QDD]``, ...): a tuple of scratch
#: arrays, indexed by these module-level ints, which numba freezes as the constant indices a tuple
#: of arrays of different shapes needs
WS = Layout("ws", [
    ("WS_E", 1, "e (n, 3): each link's direction, pointing aft"),
    ("WS_A", 1, "a (n, 3): de/dth1"),
    ("WS_B", 1, "b (n, 3): de/dth2"),
    ("WS_CS", 1, "cs (n, 4): [c1, s1, c2, s2] of each link"),
    ("WS_R", 1, "r (n+1, 3): joint positions [m]"),
    ("WS_V", 1, "v (n+1, 3): joint velocities [m/s]"),
    ("WS_C", 1, "c (n, 3): the links' velocity-product accelerations [m/s^2]"),
    ("WS_F", 1, "F (n+1, 3): the joints' external forces [N]"),
    ("WS_MOM", 1, "Mom (n, 3): the links' external moments [N m]"),
    ("WS_TAU", 1, "tau (n, 2): the rotational generalized forces [N m]"),
    ("WS_U", 1, "U (n, 6): the recursion's 3x2 blocks, row-major"),
    ("WS_DINV", 1, "Dinv (n, 4): the recursion's inverse 2x2 blocks, row-major"),
    ("WS_RHS", 1, "(n, 2): the right-hand sides of the joint equations"),
    ("WS_DRAG", 1, "(3,): the drogue's drag [N]"),
    ("WS_TOW", 1, "(3,): the tow-point force [N]"),
    ("WS_QDD", 1, "qdd (2n,): the angles' accelerations [rad/s^2]"),
    ("WS_ENV", 1, "(ENV_SIZE,): this evaluation's copy of env (with the gust at its time)"),
    ("WS_T0", 1, "(1,): the exit tension [N] (exit_tension)"),
])
(WS_E, WS_A, WS_B, WS_CS, WS_R, WS_V, WS_C, WS_F, WS_MOM, WS_TAU, WS_U, WS_DINV, WS_RHS, WS_DRAG, WS_TOW, WS_QDD,
 WS_ENV, WS_T0) = WS.offsets()


def make_workspace(n):
    """Scratch arrays for one chain of n links, allocated once per run (not per evaluation).

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    tuple of numpy.ndarray
        The workspace, its rows :data:`WS` (frames, joint positions [m] and velocities [m/s],
        forces [N], accelerations, ...).
    """
    return (
        np.empty((n, 3)),  # WS_E
        np.empty((n, 3)),  # WS_A
        np.empty((n, 3)),  # WS_B
        np.empty((n, 4)),  # WS_CS
        np.empty((n + 1, 3)),  # WS_R
        np.empty((n + 1, 3)),  # WS_V
        np.empty((n, 3)),  # WS_C
        np.empty((n + 1, 3)),  # WS_F
        np.empty((n, 3)),  # WS_MOM
        np.empty((n, 2)),  # WS_TAU
        np.empty((n, 6)),  # WS_U
        np.empty((n, 4)),  # WS_DINV
        np.empty((n, 2)),  # WS_RHS
        np.empty(3),  # WS_DRAG
        np.empty(3),  # WS_TOW
        np.empty(2 * n),  # WS_QDD
        np.empty(ENV_SIZE),  # WS_ENV
        np.empty(1),  # WS_T0
    )


make_workspace_jit = njit(**JIT)(make_workspace)


@njit(**JIT_NO_ALLOC)
def chain_forward_dynamics(l, M, J, n, a, b, cs, c, F, tau, U, Dinv, rv, qdd, tow_force):
    """Solve H qdd = Q in O(n) by an articulated-body recursion for this chain.

    The part of the chain aft of joint k, cut through link k, resists the acceleration A of
    joint k with the force ``IA_k A + beta_k``. Backward pass: from the drogue, fold each
    link's two joint equations into (IA, beta) of the joint ahead of it. Forward pass: from the
    tow point (A_0 = 0), solve each link's 2x2 joint equations. Returns the force the hose
    exerts on the tow point, ``F_0 - (IA_1 A_0 + beta_1)`` with A_0 = 0.
    """
    # IA (symmetric 3x3, stored full) and beta of the subsystem aft of the current joint
    IA00 = IA01 = IA02 = IA11 = IA12 = IA22 = 0.0
    be0 = be1 = be2 = 0.0
    for k in range(n - 1, -1, -1):
        # add the lumped mass and external force of joint k+1
        IA00 += M[k]
        IA11 += M[k]
        IA22 += M[k]
        be0 -= F[k + 1, 0]
        be1 -= F[k + 1, 1]
        be2 -= F[k + 1, 2]
        lk = l[k]
        g0x, g0y, g0z = lk * a[k, 0], lk * a[k, 1], lk * a[k, 2]
        g1x, g1y, g1z = lk * b[k, 0], lk * b[k, 1], lk * b[k, 2]
        # U = IA G (3x2)
        u00 = IA00 * g0x + IA01 * g0y + IA02 * g0z
        u10 = IA01 * g0x + IA11 * g0y + IA12 * g0z
        u20 = IA02 * g0x + IA12 * g0y + IA22 * g0z
        u01 = IA00 * g1x + IA01 * g1y + IA02 * g1z
        u11 = IA01 * g1x + IA11 * g1y + IA12 * g1z
        u21 = IA02 * g1x + IA12 * g1y + IA22 * g1z
        # D = G^T IA G + R (R: the link's rotational inertia; the last link's includes the drogue's)
        c2 = cs[k, 2]
        r0 = J[k] * c2 * c2
        r1 = J[k]
        d00 = g0x * u00 + g0y * u10 + g0z * u20 + r0
        d01 = g0x * u01 + g0y * u11 + g0z * u21
        d11 = g1x * u01 + g1y * u11 + g1z * u21 + r1
        det = d00 * d11 - d01 * d01
        i00 = d11 / det
        i01 = -d01 / det
        i11 = d00 / det
        # right-hand side of the joint equations without the fore joint's acceleration
        h0 = tau[k, 0] - (g0x * be0 + g0y * be1 + g0z * be2)
        h1 = tau[k, 1] - (g1x * be0 + g1y * be1 + g1z * be2)
        U[k, 0], U[k, 1], U[k, 2], U[k, 3], U[k, 4], U[k, 5] = u00, u01, u10, u11, u20, u21
        Dinv[k, 0], Dinv[k, 1], Dinv[k, 2], Dinv[k, 3] = i00, i01, i01, i11
        rv[k, 0] = h0
        rv[k, 1] = h1
        # W = U Dinv (3x2)
        w00 = u00 * i00 + u01 * i01
        w01 = u00 * i01 + u01 * i11
        w10 = u10 * i00 + u11 * i01
        w11 = u10 * i01 + u11 * i11
        w20 = u20 * i00 + u21 * i01
        w21 = u20 * i01 + u21 * i11
        # articulated inertia seen through the link: IA - U Dinv U^T
        IA00 -= w00 * u00 + w01 * u01
        IA01 -= w00 * u10 + w01 * u11
        IA02 -= w00 * u20 + w01 * u21
        IA11 -= w10 * u10 + w11 * u11
        IA12 -= w10 * u20 + w11 * u21
        IA22 -= w20 * u20 + w21 * u21
        # bias seen through the link: IA~ c + U Dinv h + beta
        cx, cy, cz = c[k, 0], c[k, 1], c[k, 2]
        be0 += IA00 * cx + IA01 * cy + IA02 * cz + w00 * h0 + w01 * h1
        be1 += IA01 * cx + IA11 * cy + IA12 * cz + w10 * h0 + w11 * h1
        be2 += IA02 * cx + IA12 * cy + IA22 * cz + w20 * h0 + w21 * h1
    tow_force[0] = F[0, 0] - be0
    tow_force[1] = F[0, 1] - be1
    tow_force[2] = F[0, 2] - be2
    Ax = Ay = Az = 0.0
    for k in range(n):
        px = Ax + c[k, 0]
        py = Ay + c[k, 1]
        pz = Az + c[k, 2]
        h0 = rv[k, 0] - (U[k, 0] * px + U[k, 2] * py + U[k, 4] * pz)
        h1 = rv[k, 1] - (U[k, 1] * px + U[k, 3] * py + U[k, 5] * pz)
        q1 = Dinv[k, 0] * h0 + Dinv[k, 1] * h1
        q2 = Dinv[k, 2] * h0 + Dinv[k, 3] * h1
        qdd[2 * k] = q1
        qdd[2 * k + 1] = q2
        lk = l[k]
        Ax = px + lk * (a[k, 0] * q1 + b[k, 0] * q2)
        Ay = py + lk * (a[k, 1] * q1 + b[k, 1] * q2)
        Az = pz + lk * (a[k, 2] * q1 + b[k, 2] * q2)


@njit(**JIT_NO_ALLOC_INLINE)
def loads(t, q, qd, u, l, M, J, ps, env, gust, ws, full=True):
    """Kinematics and loads of a state into the workspace: link frames ws[0:4], joint positions
    ws[WS_R] and velocities ws[WS_V], velocity-product accelerations ws[WS_C], joint forces
    ws[WS_F], link moments ws[WS_MOM], rotational generalized forces ws[WS_TAU], drogue drag
    ws[WS_DRAG]. ``full`` False (a constant of the compiled caller): level flight in still air
    only (:func:`hosedrogue.model.chain_loads.still_air_velocity`)."""
    link_frames(q, l.shape[0], ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS])
    loads_given_frames(t, q, qd, u, l, M, J, ps, env, gust, ws, full)


@njit(**JIT_NO_ALLOC_INLINE)
def loads_given_frames(t, q, qd, u, l, M, J, ps, env, gust, ws, full=True):
    """:func:`loads` when the link frames ws[0:4] already hold those of q."""
    n = l.shape[0]
    e, a, b, cs, r, v, c, F, Mom, tau = (ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C],
                                         ws[WS_F], ws[WS_MOM], ws[WS_TAU])
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    joint_forces(t, u, l, M, ps, env_at(t, env, gust, ws[WS_ENV], full), gust, n, e, r, v, F, Mom, ws[WS_DRAG], full)
    if full:  # nothing in level flight (frame_loads' own test)
        frame_loads(ps[PS_G], ps[PS_M_TOW], l, M, J, n, e, r, v, ws[WS_ENV], F, Mom)
    rotational_terms(qd, J, n, cs, Mom, tau)


@njit(**JIT_NO_ALLOC_INLINE)
def evaluate_ws(t, x, u, l, M, S, J, ps, env, gust, ws):
    """Accelerations (ws[WS_QDD]) and outputs in the workspace: joint positions ws[WS_R], velocities
    ws[WS_V], drogue drag ws[WS_DRAG], tow-point force ws[WS_TOW]. O(n)."""
    n = l.shape[0]
    loads(t, x[: 2 * n], x[2 * n:], u, l, M, J, ps, env, gust, ws)
    forward_dynamics_ws(l, M, J, ps, ws)


@njit(**JIT_NO_ALLOC_INLINE)
def forward_dynamics_ws(l, M, J, ps, ws):
    """qdd (ws[WS_QDD]), tow-point force (ws[WS_TOW]) and exit tension (ws[WS_T0]) from the loads
    in the workspace."""
    n = l.shape[0]
    chain_forward_dynamics(l, M, J, n, ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_C], ws[WS_F], ws[WS_TAU],
                           ws[WS_U], ws[WS_DINV], ws[WS_RHS], ws[WS_QDD], ws[WS_TOW])
    ws[WS_T0][0] = exit_tension(l, ps, ws[WS_E], ws[WS_F], ws[WS_TOW], n)
    # the mass lumped at the (fixed) tow point adds only its weight to the tow-point force
    ws[WS_TOW][2] += ps[PS_M_TOW] * ps[PS_G]


@njit(**JIT_NO_ALLOC)
def exit_tension(l, ps, e, F, pull, n):
    """The exit tension T_0 [N]: the hose's pull on the exit (the recursion's tow-point force
    ``pull``, before the tow-point mass's weight) less the exit joint's own external load ``F[0]``,
    along the exit link e_0 - the generalized force of the hose on its free length L, so the
    force a hose drum holds. With the ``moment`` bending it includes the bending energy's
    dependence on L through lbar_0 = (l_0 + l_1) / 2 (``-dU/dL``, which keeps the varying-length
    model conservative); the one definition for the fixed-length and the engagement chains."""
    T = 0.0
    for i in range(3):
        T += (pull[i] - F[0, i]) * e[0, i]
    if ps[PS_BENDING] == BENDING_MOMENT and n > 1:
        lbar = 0.5 * (l[0] + l[1])
        gamma = kink(e, 0)[4]
        T += 0.25 * ps[PS_EI] * gamma * gamma / (lbar * lbar)
    return T


@njit(**JIT_NO_ALLOC_INLINE)
def rhs_ws(t, x, u, l, M, S, J, ps, env, gust, ws, dx):
    """State derivative dx (4n) of x = [q, qd], using the workspace ws (no allocation)."""
    n = l.shape[0]
    evaluate_ws(t, x, u, l, M, S, J, ps, env, gust, ws)
    qdd = ws[WS_QDD]
    for i in range(2 * n):
        dx[i] = x[2 * n + i]
        dx[2 * n + i] = qdd[i]


def rhs(t, x, u, l, M, S, J, ps, env, gust, dx, work=None):
    """dx/dt of x = [q, qd], from Python (the linearization, the fixed-length FMU): the accelerations
    of :data:`evaluate_point`, the one compiled entry of a state evaluated from Python (a compiled
    ``rhs`` of its own compiled and linked the whole evaluation once more: 1 s of a cold start).

    Parameters
    ----------
    t, x, u : float, numpy.ndarray
        Time [s], the state (4n,) and the control force (2,) [N] (float64, contiguous).
    l, M, S, J, ps, env, gust : numpy.ndarray
        The model's arrays (:meth:`hosedrogue.model.system.HoseModel.kernel_args`).
    dx : numpy.ndarray
        Receives dx/dt (4n,).
    work : tuple, optional
        A :func:`point_work` to reuse (one per thread); made here if None.
    """
    n = l.shape[0]
    ws, xi, G, Q = point_work(n) if work is None else work
    evaluate_point(False, float(t), x, u, l, M, J, ps, env, gust, ws, xi, G, Q)
    dx[: 2 * n] = x[2 * n:]
    dx[2 * n:] = ws[WS_QDD]


@njit(**JIT)
def accelerations_dense(t, x, u, l, M, S, J, ps, env, gust):
    """qdd by forming the dense mass matrix and solving it (O(n^3)); the reference the
    recursion is tested against."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    loads(t, x[: 2 * n], x[2 * n:], u, l, M, J, ps, env, gust, ws)
    xi = np.empty((n + 1, 3))
    G = np.empty((n + 1, 3))
    Q = np.empty(2 * n)
    generalized_forces(l, M, n, ws[WS_A], ws[WS_B], ws[WS_C], ws[WS_F], ws[WS_TAU], xi, G, Q)
    H = np.empty((2 * n, 2 * n))
    mass_matrix(l, S, J, ps, n, ws[WS_A], ws[WS_B], ws[WS_CS], H)
    return np.linalg.solve(H, Q)


def _point(full):
    """:func:`evaluate_point` compiled for every case (``full``) or for level flight in still air at
    rest only (:func:`evaluate_point_still`; ``full`` as :func:`loads`'): a closure over the
    constant, whose other branches numba prunes before it types them."""

    @njit(**JIT_NO_ALLOC)
    def evaluate_point(residual, t, x, u, l, M, J, ps, env, gust, ws, xi, G, Q):
        """One state evaluated from Python, the one compiled entry of the balance position
        (docs/develop.md, "The compiled core"): the loads of x = [q, qd] into the workspace ws,
        then either (``residual``) the generalized forces into Q (2n; with qd = 0 and u = 0 the
        statics' residual, zero exactly at an equilibrium; xi and G (n+1, 3) are scratch) or, as
        :func:`evaluate_ws`, the accelerations ws[WS_QDD], the tow-point force ws[WS_TOW] and the
        exit tension ws[WS_T0] (xi, G and Q unused)."""
        n = l.shape[0]
        loads(t, x[: 2 * n], x[2 * n:], u, l, M, J, ps, env, gust, ws, full)
        if residual:
            generalized_forces(l, M, n, ws[WS_A], ws[WS_B], ws[WS_C], ws[WS_F], ws[WS_TAU], xi, G, Q)
        else:
            forward_dynamics_ws(l, M, J, ps, ws)

    return evaluate_point


#: :func:`_point`'s entry of every case, and of level flight in still air at rest (:func:`point_kernel`
#: picks): the latter compiles no tanker motion, gust record, bow wave or structural damping
evaluate_point, evaluate_point_still = _point(True), _point(False)


def point_kernel(env, x, t: float = 0.0, narrow: bool = False):
    """The compiled entry of :func:`_point` for a state: :data:`evaluate_point_still` if ``narrow``
    and the case is level flight in still air (:func:`chain_loads.still_level`) at rest (qd = 0),
    else :data:`evaluate_point` (the same numbers bit for bit). Narrow is worth it in a process
    that evaluates nothing else of the chain (``steady``); one that simulates compiles both.

    Parameters
    ----------
    env, x, t, narrow : numpy.ndarray, numpy.ndarray, float, bool
        The air's scalars, the state [q, qd] (4n,), the time [s], and whether to take the narrow entry.
    """
    at_rest = not np.any(x[x.shape[0] // 2:])
    return evaluate_point_still if narrow and at_rest and still_level(env, t) else evaluate_point


def point_work(n):
    """Every array :data:`evaluate_point` takes beside the state and the model: ``(ws, xi, G, Q)``
    (:func:`make_workspace`, :func:`static_scratch` and the residual (2n,) [N m]).

    Parameters
    ----------
    n : int
        Number of links [-].
    """
    return (make_workspace(n),) + static_scratch(n) + (np.empty(2 * n),)


def static_scratch(n):
    """Scratch of :func:`evaluate_point`'s residual for one chain.

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    tuple of numpy.ndarray
        ``(xi, G)``, each (n+1, 3): the joints' velocity-product accelerations [m/s^2] and the
        suffix sums of their loads [N] (:func:`generalized_forces`).
    """
    return np.empty((n + 1, 3)), np.empty((n + 1, 3))


@njit(**JIT)
def energy(x, l, M, J, ps):
    """(kinetic, potential) energy [J]; potential = gravity (z down) + bending-moment elastic
    energy (the ``moment`` option is the conservative one)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    q = x[: 2 * n]
    qd = x[2 * n:]
    e, a, b, cs, r, v, c = ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C]
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    T, Ug, Ub = chain_energy(n, l, M, J, ps, e, cs, r, v, qd)
    return T, Ug + Ub


@njit(**JIT_NO_ALLOC)
def chain_energy(n, l, M, J, ps, e, cs, r, v, qd):
    """(kinetic, gravity, bending) energy [J] of a chain whose frames, joint positions r and
    velocities v are given: the joint masses' translation, the links' transverse rotation
    ``J_k (c2^2 thd1^2 + thd2^2) / 2`` (the drogue's in the last link's), ``-sum M_k g z_k``
    and, for the ``moment`` bending, ``sum (E I / lbar) gamma^2 / 2``. The one energy of both
    chains (the engagement's velocities include the reel's L' e_0)."""
    g = ps[PS_G]
    T = 0.0
    Ug = 0.0
    for k in range(n):
        T += 0.5 * M[k] * (v[k + 1, 0] ** 2 + v[k + 1, 1] ** 2 + v[k + 1, 2] ** 2)
        c2 = cs[k, 2]
        T += 0.5 * J[k] * (c2 * c2 * qd[2 * k] ** 2 + qd[2 * k + 1] ** 2)
        Ug -= M[k] * g * r[k + 1, 2]
    Ub = 0.0
    if ps[PS_BENDING] == BENDING_MOMENT:
        for k in range(n - 1):
            gamma = kink(e, k)[4]
            Ub += 0.5 * ps[PS_EI] / (0.5 * (l[k] + l[k + 1])) * gamma * gamma
    return T, Ug, Ub


@njit(**JIT)
def mass_matrix_at(q, l, S, J, ps):
    """Dense H(q) for tests and linear analysis."""
    n = l.shape[0]
    e = np.empty((n, 3))
    a = np.empty((n, 3))
    b = np.empty((n, 3))
    cs = np.empty((n, 4))
    H = np.empty((2 * n, 2 * n))
    link_frames(q, n, e, a, b, cs)
    mass_matrix(l, S, J, ps, n, a, b, cs, H)
    return H


@njit(**JIT_NO_ALLOC)
def copy_vector(dst, src):
    """``dst[:] = src`` for two vectors of one length, element by element: numba's array
    assignment compiles, beside the copy, the text of its shape-mismatch error (numba's string
    formatting, about 1.5 s of a cold start per pair of shapes; docs/develop.md, "The compiled
    core")."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]


@njit(**JIT_NO_ALLOC)
def copy_matrix(dst, src):
    """:func:`copy_vector` of two matrices of one shape."""
    for i in range(dst.shape[0]):
        for j in range(dst.shape[1]):
            dst[i, j] = src[i, j]


@njit(**JIT)
def outputs_series(ts, xs, us, l, M, S, J, ps, env, gust, joints, drogue_vel, drogue_drag, tow, tension):
    """Derived outputs at every saved state: joints (N, n+1, 3), drogue velocity, drogue drag
    and tow-point force (N, 3), exit tension (N,)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    for i in range(ts.shape[0]):
        evaluate_ws(ts[i], xs[i], us[i], l, M, S, J, ps, env, gust, ws)
        copy_matrix(joints[i], ws[WS_R])
        copy_vector(drogue_vel[i], ws[WS_V][n])
        copy_vector(drogue_drag[i], ws[WS_DRAG])
        copy_vector(tow[i], ws[WS_TOW])
        tension[i] = ws[WS_T0][0]
