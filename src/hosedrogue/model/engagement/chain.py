"""The engagement's chain of varying length (numba): where the state's tail starts, the exit
link's length and the masses that follow it from L, the angle charts, and the kinematics with
the reel's terms (the model: :mod:`hosedrogue.model.engagement`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ...jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from ..chain_dynamics import WS_A, WS_B, WS_C, WS_CS, WS_E, WS_R, WS_V
from ..chain_loads import joint_kinematics, link_frames
from ..elastic import add_axial_rates
from ..layout import (
    EP_ELASTIC, EP_JD, EP_JLINK, EP_MD, EP_MU, EP_SPLIT, PIL_VY, PIL_Y, RCV_VX, RCV_X, Z_L, Z_LD, Z_TAIL,
)


@njit(**JIT)
def tail_start(n, ep):
    """Index of the state's tail (L, L', the work states, ...): after the 4n hose entries
    ``[q, qd]``, or the 6n ``[q, qd, lam, lamd]`` of elastic links."""
    return 6 * n if ep[EP_ELASTIC] != 0.0 else 4 * n


@njit(**JIT)
def apply_charts(n, chart, e, a, b):
    """Links in the alternative chart have e = R e_std(theta), R the rotation by +90 deg about x
    ((x, y, z) -> (x, -z, y)): its singular directions are +-z instead of +-y, so a link whose yaw
    nears +-90 deg in one chart is far from singular in the other (docs/engagement.md). Returns
    whether any link is in the alternative chart (else an evaluation need not :func:`rotate_rows`)."""
    charted = False
    for k in range(n):
        if chart[k] != 0.0:
            charted = True
            for arr in (e, a, b):
                y = arr[k, 1]
                arr[k, 1] = -arr[k, 2]
                arr[k, 2] = y
    return charted


@njit(**JIT_INLINE)
def rotate_rows(n, chart, c, inverse):
    """Rotate rows of c (n,3) of the alternative-chart links by R (or R^T if inverse)."""
    for k in range(n):
        if chart[k] != 0.0:
            y = c[k, 1]
            if inverse:
                c[k, 1] = c[k, 2]
                c[k, 2] = -y
            else:
                c[k, 1] = -c[k, 2]
                c[k, 2] = y


@njit(**JIT_NO_ALLOC)
def set_variable_link(L, n, l, M, J, ep):
    """Length of the exit link from L, and the masses and inertia that depend on it.

    ``split`` lumping: half of each link's mass at each end joint (the exit's half is carried by
    the tanker); ``aft``: each link's mass at its aft joint. Joint k+1's mass is M[k]; the drogue's
    mass is in M[n-1]. ``ep[EP_JLINK] < 0`` selects the rod inertia m l^2 / 12 for link 0 (the
    other links' J are set once); else every link has the fixed ``ep[EP_JLINK]``.
    """
    fixed = 0.0
    for k in range(1, n):
        fixed += l[k]
    l[0] = L - fixed
    mu = ep[EP_MU]
    if ep[EP_SPLIT] != 0.0:
        if n == 1:
            M[0] = 0.5 * mu * l[0] + ep[EP_MD]
        else:
            M[0] = 0.5 * mu * (l[0] + l[1])
    else:
        M[0] = mu * l[0] + (ep[EP_MD] if n == 1 else 0.0)
    if ep[EP_JLINK] < 0.0:
        J[0] = mu * l[0] ** 3 / 12.0 + (ep[EP_JD] if n == 1 else 0.0)


@njit(**JIT_NO_ALLOC)
def patch_kinematics(Ld, n, e, a, b, qd, v, c):
    """Add the variable exit link's terms: L' e_0 to every joint's velocity (joint 0: the hose
    material at the exit) and 2 L' de_0/dt to link 0's velocity-product acceleration."""
    ex, ey, ez = e[0, 0], e[0, 1], e[0, 2]
    for k in range(n + 1):
        v[k, 0] += Ld * ex
        v[k, 1] += Ld * ey
        v[k, 2] += Ld * ez
    d1 = qd[0]
    d2 = qd[1]
    for i in range(3):
        c[0, i] += 2.0 * Ld * (a[0, i] * d1 + b[0, i] * d2)


@njit(**JIT_NO_ALLOC)
def chain_kinematics(z, n, l, M, J, ep, chart, ws):
    """Set the exit link's length from L and write the frames (ws[0:4]), joint positions (ws[WS_R]),
    velocities (ws[WS_V]) and velocity-product accelerations (ws[WS_C]) of state z, the reel's L' terms
    included (the accelerations in the standard chart: no ``rotate_rows``). Elastic links: with
    their actual lengths and stretching rates, the exit's hose material at ``L' lam_0 / l_0``."""
    nh = tail_start(n, ep)
    set_variable_link(z[nh + Z_L], n, l, M, J, ep)
    q = z[: 2 * n]
    qd = z[2 * n: 4 * n]
    e, a, b, cs, r, v, c = ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C]
    link_frames(q, n, e, a, b, cs)
    apply_charts(n, chart, e, a, b)
    if ep[EP_ELASTIC] != 0.0:
        lam = z[4 * n: 5 * n]
        joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
        add_axial_rates(n, e, a, b, qd, z[5 * n: 6 * n], v, c)
        exit_material_velocity(z[nh + Z_LD], lam, l, e, v)
        return
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    patch_kinematics(z[4 * n + Z_LD], n, e, a, b, qd, v, c)


@njit(**JIT)
def exit_material_velocity(Ld, lam, l, e, v):
    """Elastic links: the hose material at the exit (joint 0's row of v) moves along the exit
    link at ``L' lam_0 / l_0`` (material paid out at L' is stretched as the exit link is)."""
    s0 = Ld * lam[0] / l[0]
    v[0, 0] = s0 * e[0, 0]
    v[0, 1] = s0 * e[0, 1]
    v[0, 2] = s0 * e[0, 2]


@njit(**JIT_NO_ALLOC)
def drogue_motion(z, n, l, M, J, ep, chart, ws):
    """Drogue (joint n) y, z [m] and y', z' [m/s] of state z (kinematics only, into ws)."""
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    r, v = ws[WS_R], ws[WS_V]
    return r[n, 1], r[n, 2], v[n, 1], v[n, 2]


def elastic_pairs(n, pilot, receiver):
    """The second-order pairs (position row, velocity row, count) of the elastic engagement state:
    angles, lengths, the free length L and, if flown, the pilot's or the receiver's probe position.

    Parameters
    ----------
    n : int
        Number of links [-].
    pilot, receiver : bool
        The pilot (``EP_PIL``) or the receiver (``EP_RCV``) flies the probe.

    Returns
    -------
    numpy.ndarray (3 or 4, 3) of int64
    """
    b = 6 * n
    rows = [[0, 2 * n, 2 * n], [4 * n, 5 * n, n], [b + Z_L, b + Z_LD, 1]]
    if pilot:
        rows.append([b + Z_TAIL + PIL_Y, b + Z_TAIL + PIL_VY, 2])
    elif receiver:
        rows.append([b + Z_TAIL + RCV_X, b + Z_TAIL + RCV_VX, 3])
    return np.array(rows, dtype=np.int64)


elastic_pairs_jit = njit(**JIT)(elastic_pairs)
