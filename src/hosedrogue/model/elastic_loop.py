"""The fixed-length elastic chain's closed loop (numba): RK4 or the stiff SDIRK (docs/model.md §11).

The state is ``z = [x, xc, (ua)]`` with the elastic hose state ``x = [q, qd, lam, lamd]`` (6n:
angles [rad], their rates [rad/s], the links' actual lengths [m] and their rates [m/s]), then the
controller's and the rate-limited actuator's states as in :mod:`hosedrogue.model.integrate`,
whose control, actuator and controller laws it uses. ``scheme`` 0 is the classical RK4, 1 the
SDIRK of :mod:`hosedrogue.model.implicit`, both the steps of :mod:`hosedrogue.model.steppers`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from .elastic import elastic_drogue_yz, elastic_evaluate_ws, hose_rates, make_elastic_workspace_jit
from .integrate import actuator_rates, applied_force_at, controller_rates, is_open_loop, step_status
from .chain_dynamics import (WS_CS, WS_DRAG, WS_R, WS_T0, WS_TOW, WS_V, copy_matrix, copy_vector,
                             make_workspace_jit)
from .layout import OK, SCHEME_RK4, STAGE_LIMIT
from .steppers import event_loop, rk4, sdirk2


@njit(**JIT_NO_ALLOC)
def elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, hg,
                       guess, dz, u):
    """dz/dt of z = [x, xc, (ua)] (x the 6n elastic hose state); u receives the force applied to
    the drogue. ``hg``, ``guess``: an implicit stage's (:func:`hosedrogue.model.elastic.stiff_terms`);
    0 and anything for the true derivative. Returns the axial dissipation [W]."""
    n = l.shape[0]
    nx = 6 * n
    if is_open_loop(z, nx, Cc, Dc):
        u[0] = 0.0
        u[1] = 0.0
        m0 = m1 = c0 = c1 = 0.0
    else:
        y, zz = elastic_drogue_yz(z[: 2 * n], z[4 * n: 5 * n], n, ws)
        m0, m1, c0, c1 = applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    p = elastic_evaluate_ws(t, z[:nx], u, l, M, J, ps, env, gust, ws, ews, hg, guess)
    hose_rates(z, n, ws, ews, dz)
    actuator_rates(c0, c1, z, nx + Ac.shape[0], act, dz)
    controller_rates(m0, m1, z, nx, Ac, Bc, dz)
    return p


@njit(**JIT_INLINE)
def elastic_rate(t, z, model, hg, guess, dz):
    """:func:`elastic_loop_deriv` as the steppers' derivative (:mod:`hosedrogue.model.steppers`):
    ``model`` is ``(l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews,
    u)``."""
    l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, u = model
    elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, hg, guess,
                       dz, u)


_rk4_step, _ = rk4(elastic_rate)
_sdirk2_step = sdirk2(elastic_rate)


@njit(**JIT_NO_ALLOC)
def elastic_step(t, z, h, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
                 ews, pairs, work, u):
    """One step of size h [s] from (t, z), in place: RK4 or the SDIRK (``scheme``; ``iters`` the
    SDIRK's least corrections per stage) of :mod:`hosedrogue.model.steppers`. ``work`` (8,
    len(z)): the stages; ``work[7]`` must hold the slope guess of the SDIRK's first stage (the
    previous step's last stage slope, or dz/dt at z) and receives the next one. Returns OK, or
    STAGE_LIMIT if the SDIRK's stages did not converge even on 16 substeps (z then back at the
    step's start). A function of its own without numba's runtime (as ``rk4_steps``): the steps
    inlined into it then take no reference counts of the arrays they unpack from ``model``, which
    they would inlined into :func:`elastic_run` (it allocates)."""
    model = (l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, u)
    if scheme == SCHEME_RK4:
        _rk4_step(t, z, h, model, work)
        return OK
    return _sdirk2_step(t, z, h, model, l.shape[0], iters, ws[WS_CS], pairs, work)  # ws[WS_CS]: the frames


def hose_pairs(n):
    """The second-order pairs (position row, velocity row, count) of the elastic hose state.

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    numpy.ndarray (2, 3) of int64
        ``(0, 2n, 2n)`` for the angles and ``(4n, 5n, n)`` for the lengths.
    """
    return np.array([[0, 2 * n, 2 * n], [4 * n, 5 * n, n]], dtype=np.int64)


hose_pairs_jit = njit(**JIT)(hose_pairs)


@njit(**JIT)
def elastic_run(z0, h, nsteps, save_every, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                noise_dt, max_yaw, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension):
    """Integrate ``nsteps`` steps of size h [s] from (0, z0) with ``scheme`` (RK4 or SDIRK with
    ``iters`` corrections per stage) through the fixed-length hose's event loop
    (:func:`~.steppers.event_loop`, as :func:`~hosedrogue.model.integrate.rk4_run`); keep every
    ``save_every``-th state (the last one included) in ts, zs, us and its outputs (joints [m],
    drogue velocity [m/s], drogue drag [N], tow-point force [N], exit tension [N]). Returns
    (status, saved count, stop time): a step whose SDIRK stages do not converge stops with
    STAGE_LIMIT at its start (the state of that time kept; the run's last saved row may be
    older), a non-finite state or a yaw beyond ``max_yaw`` [rad] after its step. The run starts at
    t = 0 (the event loop's steps are counted from it)."""
    n = l.shape[0]
    z = z0.copy()
    work = np.zeros((8, z.shape[0]))
    u = np.empty(2)
    ws = make_workspace_jit(n)
    ews = make_elastic_workspace_jit(n)
    model = (scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, max_yaw)
    rec = (ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension)
    scratch = (ws, ews, hose_pairs_jit(n), work, u)
    # the SDIRK's first slope guess: dz/dt at the start (then each step's last stage slope)
    elastic_loop_deriv(0.0, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, 0.0,
                       work[7], work[7], u)
    status, saved, done = _elastic_interval(z, 0, nsteps, h, save_every, True, True, 0, model, rec, scratch)
    return status, saved, done * h


@njit(**JIT_INLINE)
def _elastic_advance(j, last, z, h, model, scratch, at_save):
    # steps j + 1 .. last one by one (the SDIRK's guess carried in work[7]); a step whose stages
    # do not converge leaves z at its start: the last step done is the one before it
    scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, max_yaw = model
    ws, ews, pairs, work, u = scratch
    n = l.shape[0]
    for k in range(j + 1, last + 1):
        if elastic_step((k - 1) * h, z, h, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                        noise_dt, ws, ews, pairs, work, u) != OK:
            return STAGE_LIMIT, k - 1
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, k
    return OK, last


@njit(**JIT_INLINE)
def _elastic_save(i, t, z, model, rec, scratch):
    # row i: the true derivative at the saved state gives its outputs (into work[6], unused by the steps)
    _, _, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, _ = model
    ws, ews, _, work, u = scratch
    ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension = rec
    n = l.shape[0]
    elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, 0.0,
                       work[6], work[6], u)
    ts[i] = t
    copy_vector(zs[i], z)  # element by element: no array assignment (docs/develop.md)
    us[i, 0] = u[0]
    us[i, 1] = u[1]
    copy_matrix(joints[i], ws[WS_R])
    copy_vector(drogue_vel[i], ws[WS_V][n])
    copy_vector(drogue_drag[i], ws[WS_DRAG])
    copy_vector(tow[i], ws[WS_TOW])
    tension[i] = ws[WS_T0][0]


#: The event loop of elastic links (:func:`elastic_run`).
_elastic_interval = event_loop(_elastic_advance, _elastic_save)
