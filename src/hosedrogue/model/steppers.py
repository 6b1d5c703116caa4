"""The time steps of the compiled core, each written once: the classical RK4 and the stiff SDIRK.

Each chain (the fixed-length and the engagement, rigid or elastic links) gives its derivative,
``deriv(t, z, model, hg, guess, dz)``: dz/dt [units of z per s] of the state z at time t [s]
into dz, ``model`` the chain's arrays in one tuple (what the derivative unpacks: numba passes a
tuple as its members), ``hg`` and ``guess`` an implicit stage's (:mod:`hosedrogue.model.implicit`:
h g [s] and the stage's slope guess; for the true derivative 0 and an array of len(z) whose
values it does not read). :func:`rk4` and :func:`sdirk2` make each scheme's step for one derivative, as a
compiled closure over it: the scheme is written here once and compiled once per chain, its
derivative inlined (a derivative passed as an argument would make numba's cache of every caller
unusable: a compiled function cannot be cached when it passes a function value).

The steps are compiled with ``inline="always"`` (:data:`hosedrogue.jit.JIT_INLINE`): numba puts
their code into the loop that calls them instead of compiling each as a function of its own,
which would optimize and generate the machine code of the whole derivative once more for each
(docs/develop.md, "Compile time").
"""

from __future__ import annotations

import math

from numba import njit

from ..jit import JIT_INLINE, JIT_NO_ALLOC
from .implicit import (SDIRK2_GAMMA, SDIRK_MAX_CORRECTIONS, SDIRK_MAX_SUBSTEPS, SDIRK_TOLERANCE_M_S, after_stage1,
                       correction_size, stage_point)
from .layout import OK, STAGE_LIMIT


@njit(**JIT_NO_ALLOC)
def rk4_stage(z, c, k, out):
    """A classical RK4 stage's trial state ``out = z + c k`` (c = h/2 or h [s], k a slope)."""
    for i in range(z.shape[0]):
        out[i] = z[i] + c * k[i]


@njit(**JIT_NO_ALLOC)
def rk4_combine(z, h, k1, k2, k3, k4):
    """The classical RK4 update of z in place: ``z += h/6 (k1 + 2 k2 + 2 k3 + k4)`` (h [s])."""
    for i in range(z.shape[0]):
        z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


def rk4(deriv, compiled=True):
    """The classical RK4 step of ``deriv``: ``(step, step_given_k1)``.

    Parameters
    ----------
    deriv : numba dispatcher or callable
        ``deriv(t, z, model, hg, guess, dz)`` (module docstring), called here with hg = 0.
    compiled : bool, optional
        True (the default): the steps are compiled closures, inlined into the compiled loop that
        calls them. False: the same steps as plain Python functions, for a ``deriv`` that runs
        Python code (a user's control function, :func:`hosedrogue.simulate`): the one RK4 step
        of the package either way, its stages and update the compiled :func:`rk4_stage` and
        :func:`rk4_combine`.

    Returns
    -------
    step : numba dispatcher or function
        ``step(t, z, h, model, work)``: one step of size h [s] from (t, z), in place; ``work``
        (at least 5 rows of len(z)): the slopes k1..k4 in rows 0-3, the trial state in row 4 (the
        explicit evaluations' guess, which they do not read, is the state evaluated).
    step_given_k1 : numba dispatcher or function
        ``step_given_k1(t, z, h, model, work)``: the same step when ``work[0]`` holds k1 = dz/dt
        at (t, z) already (a saved state's evaluation serves both).
    """
    wrap = njit(**JIT_INLINE) if compiled else (lambda f: f)

    @wrap
    def step_given_k1(t, z, h, model, work):
        # the stages k2, k3, k4 in one loop: the derivative's code is put into the step once, not
        # once per stage (the same arithmetic in the same order)
        tmp = work[4]
        for s in range(1, 4):
            c = 0.5 * h if s < 3 else h
            rk4_stage(z, c, work[s - 1], tmp)
            deriv(t + c, tmp, model, 0.0, tmp, work[s])
        rk4_combine(z, h, work[0], work[1], work[2], work[3])

    @wrap
    def step(t, z, h, model, work):
        deriv(t, z, model, 0.0, z, work[0])
        step_given_k1(t, z, h, model, work)

    return step, step_given_k1


def sdirk2(deriv):
    """The SDIRK step of ``deriv`` (:mod:`hosedrogue.model.implicit`), with its substeps.

    Parameters
    ----------
    deriv : numba dispatcher
        ``deriv(t, z, model, hg, guess, dz)`` (module docstring).

    Returns
    -------
    numba dispatcher
        ``step(t, z, h, model, n, iters, frames, pairs, work)``: one step of size h [s] from
        (t, z), in place, for a hose of n links; ``iters`` the least corrections per stage;
        ``frames`` the array into which each evaluation writes the link frames (the correction's
        size reads their yaw cosines); ``pairs`` the second-order pairs of the state
        (:func:`~hosedrogue.model.implicit.stage_point`); ``work`` (8, len(z)): the stages in rows
        1-3, the step's start in rows 4-5, the first stage's slope guess in row 7 (the last stage
        slope of the previous step, or dz/dt at z), which receives the next one. Where a stage's
        corrections do not converge, the step is redone as 2, 4, 8 and 16 substeps. Returns OK,
        or STAGE_LIMIT if they did not converge even then (z back at the step's start).
    """

    @njit(**JIT_INLINE)
    def stage(t, zbase, model, n, iters, frames, pairs, hg, Kg, K, Y):
        # corrections until the last moves no stage velocity by more than SDIRK_TOLERANCE_M_S
        # (at least iters, at most SDIRK_MAX_CORRECTIONS); the stage's slope into K. Kg (the
        # guess, overwritten) and K trade places after each correction instead of copying the
        # slope into the guess: the same numbers, one copy at the end if the slope is in Kg
        nz = zbase.shape[0]
        g, s = Kg, K
        for it in range(max(SDIRK_MAX_CORRECTIONS, iters)):
            stage_point(zbase, g, hg, pairs, Y)
            deriv(t, Y, model, hg, g, s)
            d = correction_size(n, hg, g, s, Y, frames)
            g, s = s, g
            if not math.isfinite(d):
                return False
            if it + 1 >= iters and d <= SDIRK_TOLERANCE_M_S:
                if it % 2 == 1:  # an even number of corrections: the slope is in Kg
                    for i in range(nz):
                        K[i] = Kg[i]
                return True
        return False

    @njit(**JIT_INLINE)
    def one_step(t, z, h, model, n, iters, frames, pairs, work):
        # one step; False (z then undefined, the guess row 7 overwritten) if a stage's corrections
        # did not converge. The first stage starts from the guess in row 7 and the second from the
        # first's slope, each in place (a stage overwrites its guess). The two stages in one loop:
        # the stage's code (and the derivative's call) is put into the step once, not twice
        hg = h * SDIRK2_GAMMA
        K1, zhat, Y, K2 = work[1], work[2], work[3], work[7]
        for s in range(2):
            if s == 0:
                ts, base, guess, slope = t + hg, z, K2, K1
            else:
                ts, base, guess, slope = t + h, zhat, K1, K2
            if not stage(ts, base, model, n, iters, frames, pairs, hg, guess, slope, Y):
                return False
            if s == 0:
                stage_point(z, K1, hg, pairs, Y)
                after_stage1(z, h, K1, zhat)
        stage_point(zhat, K2, hg, pairs, z)  # the new state, into z
        return True

    @njit(**JIT_INLINE)
    def step(t, z, h, model, n, iters, frames, pairs, work):
        z0, g0 = work[4], work[5]
        nz = z.shape[0]
        for i in range(nz):
            z0[i] = z[i]
            g0[i] = work[7][i]
        m = 1
        while m <= SDIRK_MAX_SUBSTEPS:
            hs = h / m
            ok = True
            for j in range(m):
                if not one_step(t + j * hs, z, hs, model, n, iters, frames, pairs, work):
                    ok = False
                    break
            if ok:
                return OK
            for i in range(nz):
                z[i] = z0[i]
                work[7][i] = g0[i]
            m *= 2
        return STAGE_LIMIT

    return step


def event_loop(advance, save):
    """The fixed-length hose's event loop for one kind of link, written once: steps on the global
    grid of size h [s], a saved state where the grid says, a stop at the first status that is not
    OK. The kinds give their own two parts, each a compiled inline function:

    * ``advance(j, last, z, h, model, scratch, at_save) -> (status, k)``: the steps number j + 1
      to ``last`` (step i from t = (i - 1) h to i h), z in place; ``at_save`` says whether the state
      at j was just saved (its evaluation may serve the first step). Returns OK and ``last``, or the
      status that stopped it and the last step whose state z holds (the failing step's own, or the
      one before it for a step that leaves z at its start);
    * ``save(i, t, z, model, rec, scratch)``: row i of the record ``rec`` from the state at t.

    Parameters
    ----------
    advance, save : numba dispatchers
        See above.

    Returns
    -------
    numba dispatcher
        ``interval(z, step0, nsteps, h, every, record, close, saved, model, rec, scratch) ->
        (status, saved count, steps done)``: ``nsteps`` steps from global step ``step0``, in
        place; with ``record`` the state at every global step j in [step0, step0 + nsteps) that
        is a multiple of ``every`` is saved at row ``saved`` on, and with ``close`` too the state
        after the last step if it is on that grid (a whole run's end). Compiled inline into the
        caller (each kind's run, control step and sampled-data loop), whose cache keeps it.
    """

    @njit(**JIT_INLINE)
    def interval(z, step0, nsteps, h, every, record, close, saved, model, rec, scratch):
        s = 0
        while s < nsteps:
            j = step0 + s
            at_save = record and j % every == 0
            if at_save:
                save(saved, j * h, z, model, rec, scratch)
                saved += 1
            last = min(nsteps, s + every - j % every) if record else nsteps  # to the next saved state
            status, k = advance(j, step0 + last, z, h, model, scratch, at_save)
            if status != OK:
                return status, saved, k - step0
            s = last
        if close and record and (step0 + nsteps) % every == 0:
            save(saved, (step0 + nsteps) * h, z, model, rec, scratch)
            saved += 1
        return OK, saved, nsteps

    return interval
