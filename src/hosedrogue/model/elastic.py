"""The elastic link chain (numba): each link's length is a coordinate, with an axial spring-damper.

Shared by the fixed-length chain (:mod:`hosedrogue.model.elastic_loop`) and the engagement's
chain of varying length (:mod:`hosedrogue.model.engagement`); docs/model.md §11.

Link k (0-based) has its pitch and yaw ``q[2k], q[2k+1]`` as in :mod:`hosedrogue.model.chain_loads`
and its actual length ``lam[k]`` [m]; its material (unstretched) length is ``l[k]``. Joint
positions ``r_k+1 = r_k + lam_k e_k``, velocities ``V_k+1 = V_k + lam_k de_k/dt + lamd_k e_k``.
The link is a Kelvin-Voigt spring-damper along itself: strain ``eps = lam / l - 1``, tension
``T = EA eps + c_a deps/dt`` (``ps[PS_EA]``, ``ps[PS_CA]``), elastic energy ``EA l eps^2 / 2``,
dissipation ``c_a l (deps/dt)^2``. Masses are lumped from the material lengths, and the drag and
bending act per material length (:func:`~hosedrogue.model.chain_loads.joint_forces_stretched`), so at
rest the tension along the material coordinate is that of the inextensible hose.

Every joint is then a three-degree-of-freedom joint (two angles and the length): the
articulated-body recursion of :func:`~hosedrogue.model.chain_dynamics.chain_forward_dynamics` with 3x3
joint blocks, :func:`elastic_forward_dynamics`, still O(n). Its argument ``aug`` adds a
diagonal term to each link's length block: an implicit integrator's stiffness ``h g c_a / l +
(h g)^2 EA / l`` (docs/model.md §11, "Time integration"), which makes the axial spring-damper
implicit inside the O(n) solve at no extra cost.

Elastic workspace ``ews`` (:func:`make_elastic_workspace`), its rows :data:`EWS`: U (n, 9), D^-1
(n, 6), joint right-hand sides (n, 3), tensions T [N] (n,), strain rates [1/s] (n,), the length
blocks' augmentation (n,), generalized forces on the lengths [N] (n,), length accelerations
[m/s^2] (n,), the angles' augmentation (n, 2).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from .frame import frame_loads
from .layout import BENDING_MOMENT, PS_BENDING, PS_CA, PS_EA, PS_EI, PS_G, PS_M_TOW, Layout
from .chain_dynamics import (
    WS_A, WS_B, WS_C, WS_CS, WS_DRAG, WS_E, WS_ENV, WS_F, WS_MOM, WS_QDD, WS_R, WS_T0, WS_TAU, WS_TOW, WS_V,
    chain_energy, copy_matrix, copy_vector, make_workspace_jit,
)
from .chain_loads import (
    drogue_from_frames, env_at, joint_forces_stretched, joint_kinematics, kink, link_frames, rotational_terms,
)


def is_elastic(ps) -> bool:
    """Whether the ``ps`` array describes an elastic hose (finite axial stiffness).

    Parameters
    ----------
    ps : array (PS_SIZE,)
        Model scalars (:class:`~hosedrogue.model.system.HoseModel`'s ``ps``).

    Returns
    -------
    bool
    """
    return bool(math.isfinite(ps[PS_EA]))


#: the rows of the elastic workspace tuple (:func:`make_elastic_workspace`; ``ews[EWS_T]``, ...)
EWS = Layout("ews", [
    ("EWS_U", 1, "U (n, 9): the recursion's 3x3 blocks"),
    ("EWS_DINV", 1, "D^-1 (n, 6): the recursion's inverse blocks"),
    ("EWS_RHS", 1, "(n, 3): the joints' right-hand sides"),
    ("EWS_T", 1, "T (n,): the links' tensions [N]"),
    ("EWS_EPSD", 1, "(n,): the strain rates [1/s]"),
    ("EWS_AUG", 1, "aug (n,): the length blocks' augmentation [kg]"),
    ("EWS_TAUL", 1, "(n,): the generalized forces on the lengths [N]"),
    ("EWS_LAMDD", 1, "(n,): the length accelerations [m/s^2]"),
    ("EWS_ANG_AUG", 1, "(n, 2): the angles' augmentation [kg m^2]"),
])
EWS_U, EWS_DINV, EWS_RHS, EWS_T, EWS_EPSD, EWS_AUG, EWS_TAUL, EWS_LAMDD, EWS_ANG_AUG = EWS.offsets()


def make_elastic_workspace(n):
    """Scratch arrays of the elastic chain of n links (its rows: :data:`EWS`).

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    tuple of numpy.ndarray
        U (n, 9), D^-1 (n, 6), right-hand sides (n, 3), tensions [N], strain rates [1/s],
        augmentation [kg], length forces [N], length accelerations [m/s^2] (n,) each, the angles'
        augmentation (n, 2) [kg m^2].
    """
    return (np.empty((n, 9)), np.empty((n, 6)), np.empty((n, 3)), np.empty(n), np.empty(n), np.zeros(n),
            np.empty(n), np.empty(n), np.zeros((n, 2)))


make_elastic_workspace_jit = njit(**JIT)(make_elastic_workspace)


def without_accelerations(ews):
    """The elastic workspace ``ews`` (:func:`make_elastic_workspace`) with no room for the length
    accelerations (``ews[EWS_LAMDD]`` of length 0): :func:`elastic_forward_dynamics` then makes its
    backward sweep only (the tow-point force; ``qdd`` untouched), for output kernels, which read
    no accelerations (the forward pass is a quarter of the solve). Compiled code calls
    :data:`without_accelerations_jit`.

    Parameters
    ----------
    ews : tuple of numpy.ndarray
        An elastic workspace.
    """
    return (ews[EWS_U], ews[EWS_DINV], ews[EWS_RHS], ews[EWS_T], ews[EWS_EPSD], ews[EWS_AUG], ews[EWS_TAUL],
            np.empty(0), ews[EWS_ANG_AUG])


without_accelerations_jit = njit(**JIT_INLINE)(without_accelerations)


@njit(**JIT_NO_ALLOC)
def add_axial_rates(n, e, a, b, qd, lamd, v, c):
    """Add the links' stretching rates to the joint velocities v (n+1, 3) (``v_k+1 += sum_{j<=k}
    lamd_j e_j``) and to the velocity-product accelerations c (n, 3) (``c_k += 2 lamd_k de_k/dt``),
    after :func:`~hosedrogue.model.chain_loads.joint_kinematics` ran with the actual lengths."""
    sx = sy = sz = 0.0
    for k in range(n):
        ld = lamd[k]
        sx += ld * e[k, 0]
        sy += ld * e[k, 1]
        sz += ld * e[k, 2]
        v[k + 1, 0] += sx
        v[k + 1, 1] += sy
        v[k + 1, 2] += sz
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        for i in range(3):
            c[k, i] += 2.0 * ld * (a[k, i] * d1 + b[k, i] * d2)


@njit(**JIT_NO_ALLOC)
def axial_tensions(n, l, lam, lamd, l0_rate, ps, T, epsd):
    """Tension T [N] and strain rate epsd [1/s] of every link: ``eps = lam / l - 1``,
    ``deps/dt = lamd / l`` (link 0 minus ``lam_0 l0_rate / l_0^2``: material joining the exit
    link at ``l0_rate`` [m/s] relaxes it), ``T = EA eps + c_a deps/dt``. Returns the dissipated
    power ``sum c_a l (deps/dt)^2`` [W]."""
    EA = ps[PS_EA]
    ca = ps[PS_CA]
    # link 0 first, then the others in a loop of their own with no sum in it: its divisions go
    # into vector instructions (the same quotients, two or four at a time); the dissipation's sum,
    # a chain of additions in link order, after (the same terms in the same order)
    if n > 0:
        lk = l[0]
        ed = lamd[0] / lk
        ed -= lam[0] * l0_rate / (lk * lk)
        epsd[0] = ed
        T[0] = EA * (lam[0] / lk - 1.0) + ca * ed
    for k in range(1, n):
        lk = l[k]
        ed = lamd[k] / lk
        epsd[k] = ed
        T[k] = EA * (lam[k] / lk - 1.0) + ca * ed
    p = 0.0
    for k in range(n):
        ed = epsd[k]
        p += ca * l[k] * ed * ed
    return p


@njit(**JIT_NO_ALLOC)
def strain_energy(n, l, lam, ps):
    """Elastic energy of the links' stretch ``sum EA l eps^2 / 2`` [J]."""
    EA = ps[PS_EA]
    U = 0.0
    for k in range(n):
        eps = lam[k] / l[k] - 1.0
        U += 0.5 * EA * l[k] * eps * eps
    return U


@njit(**JIT_NO_ALLOC)
def elastic_exit_tension(n, l, lam, ps, e, epsd):
    """The force of the hose on its free length L [N]: the generalized force ``-dU/dL - dR/dL'``
    of the strain energy, the Rayleigh function ``sum c_a l (deps/dt)^2 / 2`` and (``moment``
    bending) the bending energy through lbar_0, with the exit link's material length l_0 = L -
    sum of the others: ``EA eps_0 (1 + eps_0 / 2) + c_a deps_0/dt (1 + eps_0) + E I gamma_0^2 /
    (4 lbar_0^2)``. It differs from the exit link's tension by O(eps) (docs/model.md §11); the
    one definition of the exit tension of both elastic chains."""
    eps = lam[0] / l[0] - 1.0
    T = ps[PS_EA] * eps * (1.0 + 0.5 * eps) + ps[PS_CA] * epsd[0] * (1.0 + eps)
    if ps[PS_BENDING] == BENDING_MOMENT and n > 1:
        lbar = 0.5 * (l[0] + l[1])
        gamma = kink(e, 0)[4]
        T += 0.25 * ps[PS_EI] * gamma * gamma / (lbar * lbar)
    return T


@njit(**JIT_NO_ALLOC)
def stiff_terms(n, l, hg, ps, guess, T, aug, taul):
    """The length blocks' augmentation ``aug_k = h g c_a / l_k + (h g)^2 EA / l_k`` [kg] of an
    implicit stage (hg = h g [s]; 0 for an explicit evaluation) and the generalized forces on the
    lengths ``-T_k + aug_k guess_k`` [N], guess the stage's length accelerations before the solve
    [m/s^2]: the recursion then solves ``(M + diag(aug)) a = Q + aug guess``, whose solution is
    the stage's with the axial spring-damper taken at the new accelerations (docs/model.md §11)."""
    EA = ps[PS_EA]
    ca = ps[PS_CA]
    for k in range(n):
        if hg != 0.0:
            aug[k] = (hg * ca + hg * hg * EA) / l[k]
            taul[k] = -T[k] + aug[k] * guess[k]
        else:
            aug[k] = 0.0
            taul[k] = -T[k]


@njit(**JIT_NO_ALLOC)
def angle_stiff_terms(n, l, lam, hg, ps, cs, T, guess, tau, augq):
    """The angle blocks' augmentation ``augq`` (n, 2) [kg m^2] of an implicit stage (hg = h g [s];
    0 for an explicit evaluation: zeros) and ``augq guess`` added to the angles' generalized
    forces ``tau`` (n, 2) [N m], guess the stage's angle accelerations (2n,) [rad/s^2]
    (:mod:`hosedrogue.model.implicit`): ``(h g)^2 (2 K_bend + T lam)`` per angle, the pitch's
    times cos^2 of the yaw (the angle's rotation of the link).

    ``K_bend = E I / lbar`` of the joints at either end of the link (``moment`` bending; the other
    bending laws stay explicit) is the diagonal of the bending's tridiagonal stiffness in the
    absolute angles; doubled, it bounds that stiffness (Gershgorin), which makes the corrections
    contract on every bending mode. ``T lam`` (the link's tension, if pulling, times its length)
    is the transverse stiffness of a straight string in absolute angles, whose inverse mass
    matrix makes the string's fast waves ``2 sqrt(T / mu) / l``."""
    if hg == 0.0:
        for k in range(n):
            augq[k, 0] = 0.0
            augq[k, 1] = 0.0
        return
    EI = ps[PS_EI]
    moment = ps[PS_BENDING] == BENDING_MOMENT
    kj = 0.0  # the joint's E I / lbar between link k-1 and link k, computed once for both links
    for k in range(n):
        kb = 0.0
        if moment:
            if k > 0:
                kb += kj
            if k < n - 1:
                kj = EI / (0.5 * (l[k] + l[k + 1]))
                kb += kj
        ks = T[k] * lam[k] if T[k] > 0.0 else 0.0
        kk = hg * hg * (2.0 * kb + ks)
        c2 = cs[k, 2]
        augq[k, 0] = kk * c2 * c2
        augq[k, 1] = kk
        tau[k, 0] += augq[k, 0] * guess[2 * k]
        tau[k, 1] += augq[k, 1] * guess[2 * k + 1]


@njit(**JIT_NO_ALLOC)
def elastic_forward_dynamics(lam, M, J, n, a, b, e, cs, c, F, tau, taul, aug, U, Dinv, rv, qdd, lamdd, tow_force,
                             augq):
    """Solve ``(H + diag(aug)) [qdd, lamdd] = Q`` in O(n) for the elastic chain.

    The articulated-body recursion of :func:`~hosedrogue.model.chain_dynamics.chain_forward_dynamics`
    with three joint coordinates per link (pitch, yaw, length): the joint's motion matrix is
    ``G = [lam a, lam b, e]`` and its block ``D = G^T IA G + diag(J c2^2 + augq_0, J + augq_1, aug)``
    (``augq`` (n, 2): :func:`angle_stiff_terms`). ``tau`` (n, 2)
    are the angles' generalized forces (:func:`~hosedrogue.model.chain_loads.rotational_terms`),
    ``taul`` (n,) the lengths' (minus the tension, :func:`stiff_terms`). Returns the force of the
    hose on the tow point (exit) into ``tow_force`` (the backward sweep's), and the accelerations
    into ``qdd`` and ``lamdd`` (the forward pass's) unless ``lamdd`` has length 0
    (:func:`without_accelerations`: the forward pass is skipped).
    """
    IA00 = IA01 = IA02 = IA11 = IA12 = IA22 = 0.0
    be0 = be1 = be2 = 0.0
    for k in range(n - 1, -1, -1):
        IA00 += M[k]
        IA11 += M[k]
        IA22 += M[k]
        be0 -= F[k + 1, 0]
        be1 -= F[k + 1, 1]
        be2 -= F[k + 1, 2]
        lk = lam[k]
        g0x, g0y, g0z = lk * a[k, 0], lk * a[k, 1], lk * a[k, 2]
        g1x, g1y, g1z = lk * b[k, 0], lk * b[k, 1], lk * b[k, 2]
        g2x, g2y, g2z = e[k, 0], e[k, 1], e[k, 2]
        # U = IA G (3x3), column j = IA g_j
        u00 = IA00 * g0x + IA01 * g0y + IA02 * g0z
        u10 = IA01 * g0x + IA11 * g0y + IA12 * g0z
        u20 = IA02 * g0x + IA12 * g0y + IA22 * g0z
        u01 = IA00 * g1x + IA01 * g1y + IA02 * g1z
        u11 = IA01 * g1x + IA11 * g1y + IA12 * g1z
        u21 = IA02 * g1x + IA12 * g1y + IA22 * g1z
        u02 = IA00 * g2x + IA01 * g2y + IA02 * g2z
        u12 = IA01 * g2x + IA11 * g2y + IA12 * g2z
        u22 = IA02 * g2x + IA12 * g2y + IA22 * g2z
        c2 = cs[k, 2]
        d00 = g0x * u00 + g0y * u10 + g0z * u20 + J[k] * c2 * c2 + augq[k, 0]
        d01 = g0x * u01 + g0y * u11 + g0z * u21
        d02 = g0x * u02 + g0y * u12 + g0z * u22
        d11 = g1x * u01 + g1y * u11 + g1z * u21 + J[k] + augq[k, 1]
        d12 = g1x * u02 + g1y * u12 + g1z * u22
        d22 = g2x * u02 + g2y * u12 + g2z * u22 + aug[k]
        # D^-1 by cofactors (D symmetric positive definite)
        c00 = d11 * d22 - d12 * d12
        c01 = d02 * d12 - d01 * d22
        c02 = d01 * d12 - d02 * d11
        c11 = d00 * d22 - d02 * d02
        c12 = d01 * d02 - d00 * d12
        c22 = d00 * d11 - d01 * d01
        det = d00 * c00 + d01 * c01 + d02 * c02
        i00, i01, i02, i11, i12, i22 = c00 / det, c01 / det, c02 / det, c11 / det, c12 / det, c22 / det
        h0 = tau[k, 0] - (g0x * be0 + g0y * be1 + g0z * be2)
        h1 = tau[k, 1] - (g1x * be0 + g1y * be1 + g1z * be2)
        h2 = taul[k] - (g2x * be0 + g2y * be1 + g2z * be2)
        U[k, 0], U[k, 1], U[k, 2] = u00, u01, u02
        U[k, 3], U[k, 4], U[k, 5] = u10, u11, u12
        U[k, 6], U[k, 7], U[k, 8] = u20, u21, u22
        Dinv[k, 0], Dinv[k, 1], Dinv[k, 2], Dinv[k, 3], Dinv[k, 4], Dinv[k, 5] = i00, i01, i02, i11, i12, i22
        rv[k, 0] = h0
        rv[k, 1] = h1
        rv[k, 2] = h2
        # W = U D^-1 (3x3)
        w00 = u00 * i00 + u01 * i01 + u02 * i02
        w01 = u00 * i01 + u01 * i11 + u02 * i12
        w02 = u00 * i02 + u01 * i12 + u02 * i22
        w10 = u10 * i00 + u11 * i01 + u12 * i02
        w11 = u10 * i01 + u11 * i11 + u12 * i12
        w12 = u10 * i02 + u11 * i12 + u12 * i22
        w20 = u20 * i00 + u21 * i01 + u22 * i02
        w21 = u20 * i01 + u21 * i11 + u22 * i12
        w22 = u20 * i02 + u21 * i12 + u22 * i22
        # articulated inertia seen through the joint: IA - U D^-1 U^T
        IA00 -= w00 * u00 + w01 * u01 + w02 * u02
        IA01 -= w00 * u10 + w01 * u11 + w02 * u12
        IA02 -= w00 * u20 + w01 * u21 + w02 * u22
        IA11 -= w10 * u10 + w11 * u11 + w12 * u12
        IA12 -= w10 * u20 + w11 * u21 + w12 * u22
        IA22 -= w20 * u20 + w21 * u21 + w22 * u22
        cx, cy, cz = c[k, 0], c[k, 1], c[k, 2]
        be0 += IA00 * cx + IA01 * cy + IA02 * cz + w00 * h0 + w01 * h1 + w02 * h2
        be1 += IA01 * cx + IA11 * cy + IA12 * cz + w10 * h0 + w11 * h1 + w12 * h2
        be2 += IA02 * cx + IA12 * cy + IA22 * cz + w20 * h0 + w21 * h1 + w22 * h2
    tow_force[0] = F[0, 0] - be0
    tow_force[1] = F[0, 1] - be1
    tow_force[2] = F[0, 2] - be2
    if lamdd.shape[0] == 0:  # no room for the accelerations (without_accelerations): the tow force only
        return
    Ax = Ay = Az = 0.0
    for k in range(n):
        px = Ax + c[k, 0]
        py = Ay + c[k, 1]
        pz = Az + c[k, 2]
        h0 = rv[k, 0] - (U[k, 0] * px + U[k, 3] * py + U[k, 6] * pz)
        h1 = rv[k, 1] - (U[k, 1] * px + U[k, 4] * py + U[k, 7] * pz)
        h2 = rv[k, 2] - (U[k, 2] * px + U[k, 5] * py + U[k, 8] * pz)
        i00, i01, i02, i11, i12, i22 = Dinv[k, 0], Dinv[k, 1], Dinv[k, 2], Dinv[k, 3], Dinv[k, 4], Dinv[k, 5]
        q1 = i00 * h0 + i01 * h1 + i02 * h2
        q2 = i01 * h0 + i11 * h1 + i12 * h2
        q3 = i02 * h0 + i12 * h1 + i22 * h2
        qdd[2 * k] = q1
        qdd[2 * k + 1] = q2
        lamdd[k] = q3
        lk = lam[k]
        Ax = px + lk * (a[k, 0] * q1 + b[k, 0] * q2) + e[k, 0] * q3
        Ay = py + lk * (a[k, 1] * q1 + b[k, 1] * q2) + e[k, 1] * q3
        Az = pz + lk * (a[k, 2] * q1 + b[k, 2] * q2) + e[k, 2] * q3


@njit(**JIT_NO_ALLOC)
def elastic_loads(t, q, qd, lam, lamd, u, l, M, J, ps, env, gust, ws):
    """Kinematics and loads of the fixed-length elastic chain into the workspace (the slots of
    :func:`~hosedrogue.model.chain_dynamics.loads`): frames, joint positions and velocities with the
    actual lengths and their rates, forces, moments, the angles' generalized forces."""
    n = l.shape[0]
    e, a, b, cs, r, v, c, F, Mom, tau = (ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C],
                                         ws[WS_F], ws[WS_MOM], ws[WS_TAU])
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
    add_axial_rates(n, e, a, b, qd, lamd, v, c)
    joint_forces_stretched(t, u, l, lam, M, ps, env_at(t, env, gust, ws[WS_ENV]), gust, n, e, r, v, F, Mom, ws[WS_DRAG])
    # the tanker's motion (nothing in level flight); the links' rates from their actual lengths
    frame_loads(ps[PS_G], ps[PS_M_TOW], lam, M, J, n, e, r, v, ws[WS_ENV], F, Mom)
    rotational_terms(qd, J, n, cs, Mom, tau)


@njit(**JIT_NO_ALLOC)
def elastic_evaluate_ws(t, x, u, l, M, J, ps, env, gust, ws, ews, hg, guess):
    """Accelerations of the fixed-length elastic chain at x = [q, qd, lam, lamd] (6n): qdd into
    ws[WS_QDD], the length accelerations into ews[EWS_LAMDD]; the outputs of
    :func:`~hosedrogue.model.chain_dynamics.evaluate_ws` (joints ws[WS_R], velocities ws[WS_V],
    drogue drag ws[WS_DRAG], tow-point force ws[WS_TOW], exit tension ws[WS_T0]) and the tensions
    ews[EWS_T]. ``hg`` and ``guess`` (the stage's slope guess, the rates of the state's 6n entries
    first): an implicit stage's (:func:`stiff_terms`, :func:`angle_stiff_terms`; hg = 0 explicit,
    guess unused).
    Returns the axial dissipation [W]."""
    n = l.shape[0]
    q = x[: 2 * n]
    qd = x[2 * n: 4 * n]
    lam = x[4 * n: 5 * n]
    lamd = x[5 * n: 6 * n]
    elastic_loads(t, q, qd, lam, lamd, u, l, M, J, ps, env, gust, ws)
    T, epsd, aug, taul = ews[EWS_T], ews[EWS_EPSD], ews[EWS_AUG], ews[EWS_TAUL]
    p_axial = axial_tensions(n, l, lam, lamd, 0.0, ps, T, epsd)
    stiff_terms(n, l, hg, ps, guess[5 * n: 6 * n], T, aug, taul)
    angle_stiff_terms(n, l, lam, hg, ps, ws[WS_CS], T, guess[2 * n: 4 * n], ws[WS_TAU], ews[EWS_ANG_AUG])
    elastic_forward_dynamics(lam, M, J, n, ws[WS_A], ws[WS_B], ws[WS_E], ws[WS_CS], ws[WS_C], ws[WS_F], ws[WS_TAU],
                             taul, aug, ews[EWS_U], ews[EWS_DINV], ews[EWS_RHS], ws[WS_QDD], ews[EWS_LAMDD],
                             ws[WS_TOW], ews[EWS_ANG_AUG])
    ws[WS_T0][0] = elastic_exit_tension(n, l, lam, ps, ws[WS_E], epsd)
    ws[WS_TOW][2] += ps[PS_M_TOW] * ps[PS_G]
    return p_axial


@njit(**JIT)
def elastic_energy(x, l, M, J, ps):
    """(kinetic, potential) energy [J] of the fixed-length elastic chain at x = [q, qd, lam,
    lamd]; potential = gravity + bending (``moment``) + the links' strain energy."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    q = x[: 2 * n]
    qd = x[2 * n: 4 * n]
    lam = x[4 * n: 5 * n]
    lamd = x[5 * n: 6 * n]
    e, a, b, cs, r, v, c = ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C]
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
    add_axial_rates(n, e, a, b, qd, lamd, v, c)
    T, Ug, Ub = chain_energy(n, l, M, J, ps, e, cs, r, v, qd)
    return T, Ug + Ub + strain_energy(n, l, lam, ps)


@njit(**JIT)
def elastic_static_residual(y, l, M, J, ps, env, gust, t, Q):
    """Generalized forces at rest of y = [q (2n), lam (n)] into Q (3n) [N m], zero exactly at the
    elastic chain's balance position.

    The angles' entries are :func:`~hosedrogue.model.chain_dynamics.static_residual`'s; link k's length
    entry is the load aft of the link along ``e_k`` minus its tension ``T_k``, times ``l_k`` (so
    every entry is a virtual work per unit of its coordinate's natural scale, N m)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    ews = make_elastic_workspace_jit(n)
    x = np.zeros(6 * n)
    for k in range(n):  # element by element (copy_vector's reason)
        x[2 * k] = y[2 * k]
        x[2 * k + 1] = y[2 * k + 1]
        x[4 * n + k] = y[2 * n + k]
    elastic_evaluate_ws(t, x, np.zeros(2), l, M, J, ps, env, gust, ws, ews, 0.0, x)
    static_forces(n, l, y[2 * n: 3 * n], ws, ews, Q)


@njit(**JIT_NO_ALLOC)
def static_forces(n, l, lam, ws, ews, Q):
    """:func:`elastic_static_residual`'s Q (3n) [N m] after an evaluation at rest (loads and frames
    in ``ws``, tensions in ``ews``) of material lengths ``l``, actual ``lam``: both chains' statics."""
    # at rest the joint equations are H a = Q: the residual is Q itself, i.e. H a
    F, a, b, e = ws[WS_F], ws[WS_A], ws[WS_B], ws[WS_E]
    T = ews[EWS_T]
    Gx = Gy = Gz = 0.0
    for k in range(n - 1, -1, -1):
        Gx += F[k + 1, 0]
        Gy += F[k + 1, 1]
        Gz += F[k + 1, 2]
        lk = lam[k]
        Q[2 * k] = lk * (a[k, 0] * Gx + a[k, 1] * Gy + a[k, 2] * Gz) + ws[WS_TAU][k, 0]
        Q[2 * k + 1] = lk * (b[k, 0] * Gx + b[k, 1] * Gy + b[k, 2] * Gz) + ws[WS_TAU][k, 1]
        Q[2 * n + k] = l[k] * (e[k, 0] * Gx + e[k, 1] * Gy + e[k, 2] * Gz - T[k])


@njit(**JIT)
def elastic_outputs_series(ts, xs, us, l, M, J, ps, env, gust, joints, drogue_vel, drogue_drag, tow, tension):
    """Derived outputs at saved states of the fixed-length elastic chain (as
    :func:`~hosedrogue.model.chain_dynamics.outputs_series`)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    ews = without_accelerations_jit(make_elastic_workspace_jit(n))  # the outputs need no accelerations
    for i in range(ts.shape[0]):
        elastic_evaluate_ws(ts[i], xs[i], us[i], l, M, J, ps, env, gust, ws, ews, 0.0, xs[i])
        copy_matrix(joints[i], ws[WS_R])
        copy_vector(drogue_vel[i], ws[WS_V][n])
        copy_vector(drogue_drag[i], ws[WS_DRAG])
        copy_vector(tow[i], ws[WS_TOW])
        tension[i] = ws[WS_T0][0]


@njit(**JIT_NO_ALLOC)
def elastic_drogue_yz(q, lam, n, ws):
    """Drogue lateral and vertical position [m] of the elastic chain with angles q and actual
    lengths lam (the link frames go to ws[0:4])."""
    link_frames(q, n, ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS])
    return drogue_from_frames(lam, ws[WS_E])


@njit(**JIT_INLINE)
def hose_rates(z, n, ws, ews, dz):
    """The elastic hose's rates ``dz[:6n]`` of the state ``z = [q, qd, lam, lamd, ...]`` (n links)
    after an evaluation: the angles' and the lengths' rates from z, their accelerations from the
    evaluation (``ws[WS_QDD]`` [rad/s^2], ``ews[EWS_LAMDD]`` [m/s^2]); both elastic chains' derivative."""
    qdd = ws[WS_QDD]
    lamdd = ews[EWS_LAMDD]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    for k in range(n):
        dz[4 * n + k] = z[5 * n + k]
        dz[5 * n + k] = lamdd[k]
