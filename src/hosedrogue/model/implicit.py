"""The stiff integrator of the elastic chains (numba): two-stage L-stable SDIRK, each stage solved
by one linearly implicit correction inside the O(n) recursion (docs/model.md §11, "Time integration").

Alexander's two-stage, second-order, L-stable, stiffly accurate SDIRK (Alexander 1977, SIAM J.
Numer. Anal. 14, 1006; Hairer & Wanner, Solving ODEs II, IV.6), g = 1 - 1/sqrt(2)::

    Y1 = y_n + h g f(t_n + g h, Y1)
    Y2 = y_n + h (1 - g) f(t_n + g h, Y1) + h g f(t_n + h, Y2),    y_n+1 = Y2.

A stage ``Y = Yhat + h g f(Y)`` of the chain's second-order structure (positions p, velocities
w, ``p' = w``, ``w' = a``) is ``w = what + h g a``, ``p = phat + h g w``: one unknown per
velocity, the acceleration a. It is found by one correction from a guess a0 (the previous
stage's slope): the state of the guess is evaluated with the axial spring-damper of every link
taken implicitly - its Jacobian ``h g c_a / l + (h g)^2 EA / l`` added to the recursion's joint
blocks and ``aug a0`` to the joint forces (:func:`hosedrogue.model.elastic.stiff_terms`) - which
is exact for the linear spring-damper and leaves an O(h^2) error in a from the rest, so the step
keeps its second order (local error O(h^3)). Everything else (the first-order states: reel work,
controller, ...) takes the guess's slope. :func:`stage_point` forms a stage's state from Yhat and
a slope guess.
"""

from __future__ import annotations

import math

from numba import njit

from ..jit import JIT_NO_ALLOC

#: The SDIRK's diagonal coefficient g = 1 - 1/sqrt(2) [-] (L-stable, second order).
SDIRK2_GAMMA = 1.0 - 1.0 / math.sqrt(2.0)


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
def after_stage1(z, h, K1, zhat):
    """The second stage's explicit part ``zhat = z + h (1 - g) K1``."""
    c = h * (1.0 - SDIRK2_GAMMA)
    for i in range(z.shape[0]):
        zhat[i] = z[i] + c * K1[i]
