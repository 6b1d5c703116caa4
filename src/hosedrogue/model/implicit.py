"""The stiff integrator of the elastic chains (numba): two-stage L-stable SDIRK, each stage solved
by linearly implicit corrections inside the O(n) recursion (docs/model.md §11, "Time integration").

Alexander's two-stage, second-order, L-stable, stiffly accurate SDIRK (Alexander 1977, SIAM J.
Numer. Anal. 14, 1006; Hairer & Wanner, Solving ODEs II, IV.6), g = 1 - 1/sqrt(2)::

    Y1 = y_n + h g f(t_n + g h, Y1)
    Y2 = y_n + h (1 - g) f(t_n + g h, Y1) + h g f(t_n + h, Y2),    y_n+1 = Y2.

A stage ``Y = Yhat + h g f(Y)`` of the chain's second-order structure (positions p, velocities
w, ``p' = w``, ``w' = a``) is ``w = what + h g a``, ``p = phat + h g w``: one unknown per
velocity, the acceleration a. It is found by corrections from a guess a0 (the previous stage's
slope): each evaluates the state of the guess with a diagonal approximation of the stiff forces'
Jacobian added to the recursion's joint blocks, ``aug (a - a0)`` (a simplified Newton iteration
whose fixed point is the implicit stage):

* the axial spring-damper of every link, ``h g c_a / l + (h g)^2 EA / l`` on its length
  (:func:`hosedrogue.model.elastic.stiff_terms`): exact, it is linear in the length;
* bending and the string stiffness of the tension on the angles, ``(h g)^2 (2 K_bend + T lam)``
  (:func:`hosedrogue.model.elastic.angle_stiff_terms`): the bending's diagonal doubled bounds its
  tridiagonal stiffness (Gershgorin), so the iteration contracts on every bending mode, and
  ``T lam`` is the exact transverse stiffness of a straight string in absolute angles.

The corrections go on until the last one moves no stage velocity by more than
:data:`SDIRK_TOLERANCE_M_S` (:func:`correction_size`; at least ``numerics.sdirk_corrections``, at
most :data:`SDIRK_MAX_CORRECTIONS`); a step whose stage does not converge is redone as 2, 4, 8,
16 substeps, and beyond that the run stops (STAGE_LIMIT). Everything else (drag, the first-order
states: reel work, controller, ...) takes the guess's slope. :func:`stage_point` forms a stage's
state from Yhat and a slope guess.
"""

from __future__ import annotations

import math

from numba import njit

from ..jit import JIT_NO_ALLOC

#: The SDIRK's diagonal coefficient g = 1 - 1/sqrt(2) [-] (L-stable, second order).
SDIRK2_GAMMA = 1.0 - 1.0 / math.sqrt(2.0)

#: A stage's corrections have converged when the last one moved no stage velocity of the hose (a
#: length's rate, or an angle's rate times its link's length) by more than this [m/s]: 1 mm/s,
#: a thousandth of the probe's closure speed; over a 5 ms step it moves a joint by 5 um.
SDIRK_TOLERANCE_M_S = 1e-3
#: At most this many corrections per stage [-] (at least ``numerics.sdirk_corrections``); a stage
#: that has not converged by then is redone on halved steps.
SDIRK_MAX_CORRECTIONS = 6
#: A step is split into at most this many equal substeps [-] (halving four times); a stage that
#: does not converge on them stops the run (status STAGE_LIMIT).
SDIRK_MAX_SUBSTEPS = 16


@njit(**JIT_NO_ALLOC)
def stage_point(zhat, K, hg, pairs, Y):
    """A stage's state ``Y = zhat + hg K`` (hg = h g [s]) for the slope guess K, with the rows of
    each second-order pair made consistent: for ``pairs[i] = (p, w, count)``, positions
    ``z[p:p+count]`` and velocities ``z[w:w+count]``, ``K[p+j] = zhat[w+j] + hg K[w+j]`` (the
    position's slope is the stage velocity). K is updated in place."""
    for i in range(zhat.shape[0]):
        Y[i] = zhat[i] + hg * K[i]
    for r in range(pairs.shape[0]):
        p, w, cnt = pairs[r, 0], pairs[r, 1], pairs[r, 2]
        for j in range(cnt):
            K[p + j] = Y[w + j]
            Y[p + j] = zhat[p + j] + hg * K[p + j]


@njit(**JIT_NO_ALLOC)
def correction_size(n, hg, Kg, K, Y, cs):
    """How far the last correction moved the stage [m/s]: the largest change ``hg |K - Kg|`` of a
    stage velocity of the hose state ``[q, qd, lam, lamd, ...]`` (n links; Y the stage's state), the
    angles' rates as the speeds they give the link's end (the pitch's times the link's length and
    the cosine of its yaw, ``cs[k, 2]``; the yaw's times the length); compared with
    :data:`SDIRK_TOLERANCE_M_S`.

    The pitches', the yaws' and the lengths' largest changes are three running maxima, combined at
    the end: a maximum is exact in any order (a NaN is passed over either way), so the result is
    the single running maximum's to the bit, and the three chains of comparisons overlap instead of
    waiting on each other (0.72 -> 0.24 us at 160 links, about 4 % of a step)."""
    dp = dy = dl = 0.0
    for k in range(n):
        lk = Y[4 * n + k]
        v = abs(K[2 * n + 2 * k] - Kg[2 * n + 2 * k]) * lk * abs(cs[k, 2])
        if v > dp:
            dp = v
        v = abs(K[2 * n + 2 * k + 1] - Kg[2 * n + 2 * k + 1]) * lk
        if v > dy:
            dy = v
        v = abs(K[5 * n + k] - Kg[5 * n + k])
        if v > dl:
            dl = v
    d = dp
    if dy > d:
        d = dy
    if dl > d:
        d = dl
    return hg * d


@njit(**JIT_NO_ALLOC)
def after_stage1(z, h, K1, zhat):
    """The second stage's explicit part ``zhat = z + h (1 - g) K1``."""
    c = h * (1.0 - SDIRK2_GAMMA)
    for i in range(z.shape[0]):
        zhat[i] = z[i] + c * K1[i]
