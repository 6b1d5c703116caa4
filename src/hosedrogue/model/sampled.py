"""Compiled core of the sampled-data loops (numba): the measurement a sampled-data controller
reads, and the fixed-length hose integrated between samples with the commands held.

A sampled-data controller (docs/controllers.md) is called every control step; between calls the
compiled loop runs with its command held. The drogue's command (its force, or the deflections of
its control surfaces) is held as the state of a "hold" controller of the closed loop
(:func:`held_command`: ``xc' = 0``, ``u = xc`` through the actuator's limits or to the
surfaces), so the loops of :mod:`.integrate` and
:mod:`hosedrogue.model.engagement` run unchanged between samples and the command survives remeshes.

The measurement
---------------
At each sample the kernels write the *raw* quantities of the state (``R_*``, :mod:`hosedrogue.model.layout`: drogue
position and velocity, probe tip position and velocity, free hose length and reel speed, exit
tension, coupled flag, an actuated drogue's dynamic pressure) into a ring of ``D + 1`` rows, D the sensor delay in samples;
:func:`deliver` turns the row of D samples ago (of sample 0 before then) into the measurement
buffer (``M_*`` layout, read by :class:`hosedrogue.controllers.sampled.Measurement`): the drogue
position gets the sensor noise of that instant (zero-order held, ``noise_dt``), the relative
position and velocity are drogue minus probe tip. Vectors in the tanker frame S_p.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..jit import JIT, JIT_NO_ALLOC
from . import drogue_actuator as DA
from .integrate import closed_loop_deriv, fl_interval, save_state
from .layout import OK
from .chain_dynamics import WS_R, WS_T0, WS_V, make_workspace_jit

from .layout import (  # the raw measurement of a state (one ring row, R_*), the measurement buffer (M_*)
    # and the counters of a stepped run (C_*), declared and documented there
    C_ORIGIN, C_SAMPLE, C_SAVED, C_SIZE, C_SPC, C_STATUS, C_STEP, C_TARGET, C_TOTAL, M_BALANCE, M_COUPLED,
    M_DROGUE, M_DROGUE_V, M_L, M_PROBE, M_PROBE_V, M_Q, M_REEL_V, M_REL, M_REL_V, M_SIZE, M_T, M_T0, R_COUPLED,
    R_DROGUE, R_DROGUE_V, R_L, R_PROBE, R_PROBE_V, R_Q, R_REEL_V, R_T0, RAW_SIZE,
)


@njit(**JIT_NO_ALLOC)
def noise3_at(t, noise, noise_dt):
    """Zero-order-held sensor noise (3 axes) [m] at time t [s] from samples (k, 3)."""
    i = int(t / noise_dt)
    if i >= noise.shape[0]:
        i = noise.shape[0] - 1
    if i < 0:
        i = 0
    return noise[i, 0], noise[i, 1], noise[i, 2]


@njit(**JIT_NO_ALLOC)
def deliver(ring, k, delay, sample_h, noise, noise_dt, balance, mbuf):
    """The measurement of sample k into ``mbuf``: the ring row of sample ``k - delay`` (sample 0
    before then), at its time ``j sample_h`` [s], the drogue position with the sensor noise of
    that instant; relative position and velocity drogue minus probe tip."""
    j = k - delay
    if j < 0:
        j = 0
    row = ring[j % ring.shape[0]]
    t = j * sample_h
    nx, ny, nz = noise3_at(t, noise, noise_dt)
    mbuf[M_T] = t
    mbuf[M_DROGUE] = row[R_DROGUE] + nx
    mbuf[M_DROGUE + 1] = row[R_DROGUE + 1] + ny
    mbuf[M_DROGUE + 2] = row[R_DROGUE + 2] + nz
    for i in range(3):
        mbuf[M_DROGUE_V + i] = row[R_DROGUE_V + i]
        mbuf[M_PROBE + i] = row[R_PROBE + i]
        mbuf[M_PROBE_V + i] = row[R_PROBE_V + i]
        mbuf[M_REL + i] = mbuf[M_DROGUE + i] - row[R_PROBE + i]
        mbuf[M_REL_V + i] = row[R_DROGUE_V + i] - row[R_PROBE_V + i]
        mbuf[M_BALANCE + i] = balance[i]
    mbuf[M_L] = row[R_L]
    mbuf[M_REEL_V] = row[R_REEL_V]
    mbuf[M_T0] = row[R_T0]
    mbuf[M_COUPLED] = row[R_COUPLED]
    mbuf[M_Q] = row[R_Q]


# --- the fixed-length hose between samples: fl_interval (.integrate) -------------------------------------
@njit(**JIT)
def fl_raw(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, work, u, raw):
    """The raw measurement (``R_*``) of the fixed-length state z at time t [s]: drogue position
    and velocity, exit tension of the evaluation with the loop as it is, the hose length, the
    dynamic pressure at an actuated drogue (u[2] of the evaluation when ``u`` has room, else
    NaN); no probe (NaN), reel speed 0, not coupled."""
    n = l.shape[0]
    closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, work[4], u)
    r, v = ws[WS_R], ws[WS_V]
    length = 0.0
    for k in range(n):
        length += l[k]
    for i in range(3):
        raw[R_DROGUE + i] = r[n, i]
        raw[R_DROGUE_V + i] = v[n, i]
        raw[R_PROBE + i] = math.nan
        raw[R_PROBE_V + i] = math.nan
    raw[R_L] = length
    raw[R_REEL_V] = 0.0
    raw[R_T0] = ws[WS_T0][0]
    raw[R_COUPLED] = 0.0
    raw[R_Q] = u[2] if u.shape[0] > 2 else math.nan



@njit(**JIT)
def fl_advance(ctr, z, h, every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, max_yaw,
               record, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension, ws, work, u, ring, delay,
               sample_h, noise3, noise3_dt, balance, mbuf):
    """One control step of the fixed-length hose: :func:`fl_interval` of ``min(spc, total -
    step)`` steps from the counters ``ctr`` (``C_*``: global step, saved rows, sample index,
    total steps, steps per control step; updated in place, ``C_STATUS`` the kernels' status),
    then, if the state is fine, the raw measurement of the next sample into the ring and its
    measurement (delayed by ``delay`` samples) into ``mbuf`` (:func:`deliver`). Every argument
    but the counters is the same from one call to the next, so the caller passes one tuple."""
    step0 = ctr[C_STEP]
    count = min(ctr[C_SPC], ctr[C_TOTAL] - step0)
    status, saved, done = fl_interval(z, step0, count, h, every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref,
                                      act, noise, noise_dt, max_yaw, record, ts, zs, us, joints, drogue_vel,
                                      drogue_drag, tow, tension, ctr[C_SAVED], ws, work, u)
    ctr[C_STEP] = step0 + done
    ctr[C_SAVED] = saved
    ctr[C_SAMPLE] += 1
    ctr[C_STATUS] = status
    if status == OK:
        k = ctr[C_SAMPLE]
        fl_raw((step0 + count) * h, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt,
               ws, work, u, ring[k % ring.shape[0]])
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
    return status


@njit(**JIT)
def fl_linear_sampled_run(z, nsteps, spc, h, every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act,
                          noise, noise_dt, max_yaw, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension,
                          ring, delay, noise3, noise3_dt, balance, Ad, Bd, Cd, Dd, Bw, nx):
    """A built-in linear drogue controller in sampled-data mode, compiled end to end: every
    ``spc`` RK4 steps it reads the measured drogue offset ``y = (drogue y, z + noise) - balance``
    [m] of the measurement (:func:`deliver`, the sensor delay included) and sets the held force
    ``u = Cd xd + Dd y`` [N] (the hold controller's state ``z[nx:nx+2]``), then ``xd <- Ad xd +
    Bd y + Bw e`` (the zero-order-hold discretization); the loop arrays are the hold controller's.
    e is the anti-windup error of a drogue with control surfaces in force mode, the force its
    clipped mixing makes at the measured q minus u (:func:`~.drogue_actuator.mixing_error`), else 0.
    Saves every ``every``-th step from 0 to ``nsteps`` into the record. Returns (status, saved
    count, steps done)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    work = np.empty((5, z.shape[0]))
    u = np.empty(us.shape[1])  # room for an actuated drogue's q and servo rates (the saved outputs)
    mbuf = np.empty(M_SIZE)
    nd = Ad.shape[0]
    xd = np.zeros(nd)
    xn = np.empty(nd)
    sample_h = spc * h
    fl_raw(0.0, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, work, u, ring[0])
    saved = 0
    step = 0
    k = 0
    while step < nsteps:
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
        y0 = mbuf[M_DROGUE + 1] - mbuf[M_BALANCE + 1]
        y1 = mbuf[M_DROGUE + 2] - mbuf[M_BALANCE + 2]
        for i in range(2):
            acc = Dd[i, 0] * y0 + Dd[i, 1] * y1
            for j in range(nd):
                acc += Cd[i, j] * xd[j]
            z[nx + i] = acc
        e0 = e1 = 0.0
        if DA.is_actuated(act) and act[DA.DA_MODE] == DA.MODE_FORCE:
            e0, e1 = DA.mixing_error(z[nx], z[nx + 1], mbuf[M_Q], act)
        for i in range(nd):
            acc = Bd[i, 0] * y0 + Bd[i, 1] * y1 + Bw[i, 0] * e0 + Bw[i, 1] * e1
            for j in range(nd):
                acc += Ad[i, j] * xd[j]
            xn[i] = acc
        for i in range(nd):
            xd[i] = xn[i]
        count = min(spc, nsteps - step)
        status, saved, done = fl_interval(z, step, count, h, every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc,
                                          y_ref, act, noise, noise_dt, max_yaw, True, ts, zs, us, joints,
                                          drogue_vel, drogue_drag, tow, tension, saved, ws, work, u)
        step += done
        if status != OK:
            return status, saved, step
        k += 1
        if step < nsteps:
            fl_raw(step * h, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, work, u,
                   ring[k % ring.shape[0]])
    if nsteps % every == 0:
        save_state(saved, nsteps * h, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
                   work, u, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension)
        saved += 1
    return OK, saved, nsteps


class HeldCommand(NamedTuple):
    """The "hold" controller of a held command of ``n_states`` numbers (:func:`held_command`),
    in the form :func:`~hosedrogue.model.integrate.loop_arrays` takes a controller."""

    A: np.ndarray  #: (n, n) zeros [1/s]
    B: np.ndarray  #: (n, 2) zeros
    C: np.ndarray  #: (n, n) identity: the outputs are the states
    D: np.ndarray  #: (n, 2) zeros
    n_states: int  #: n [-]
    anti_windup: None = None  #: none: the held command stays as it was given


def held_command(drogue_actuator=None) -> HeldCommand:
    """The hold controller of the drogue's command: the force (u_y, u_z) [N] (2 states; through
    the ``[actuator]`` or mixed to the control surfaces), or with ``drogue_actuator.command =
    "deflection"`` one deflection command per surface [rad] (n_s states).

    Parameters
    ----------
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (their ``command`` and ``surfaces``).

    Returns
    -------
    HeldCommand
    """
    n = 2 if drogue_actuator is None else drogue_actuator.command_size
    return HeldCommand(np.zeros((n, n)), np.zeros((n, 2)), np.eye(n), np.zeros((n, 2)), n)
