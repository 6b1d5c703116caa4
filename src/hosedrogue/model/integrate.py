"""Time integrators (numba): fixed-step classical RK4 with an optional linear controller in the
loop, compiled end to end so a run is not dominated by Python overhead.

The closed-loop state is ``z = [x, xc, ua]``: the hose state ``x = [q, qd]`` (4n), the
controller state ``xc``, and - only when the actuator is rate-limited - the applied force ``ua``
(2). The controller reads the drogue's lateral and vertical offset from ``y_ref`` (plus sensor
noise) and commands ``u = Cc xc + Dc y`` [N], clipped to ``+-act[0:2]`` per axis. ``act`` is
``[max_hor_n, max_ver_n, max_rate_n_s, time_constant_s]`` (``ACT_*`` of
:mod:`hosedrogue.model.layout`); with a finite rate the applied force
follows the command as ``ua' = clip((u - ua) / time_constant, -rate, rate)``.

A drogue that steers itself with control surfaces (``act`` longer than the ideal actuator's
four entries, :mod:`.drogue_actuator`) has the surfaces' states in place of ``ua``; its force
comes from their deflections and the local dynamic pressure (:func:`actuated_loop_deriv`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..jit import JIT, JIT_INLINE, JIT_NO_ALLOC

from .layout import NONFINITE, OK, PS_RHO, YAW_LIMIT
from .chain_dynamics import (
    WS_A, WS_B, WS_CS, WS_DRAG, WS_E, WS_ENV, WS_F, WS_QDD, WS_R, WS_T0, WS_TOW, WS_V, copy_matrix, copy_vector,
    forward_dynamics_ws, loads_given_frames, make_workspace,
)
from .chain_loads import drogue_from_frames, env_at, link_frames
from .steppers import event_loop, rk4
from . import drogue_actuator as DA
from .layout import ACT_RATE, ACT_TAU, ACT_U_MAX


#: compilation options of the loop's functions that allocate nothing (:mod:`hosedrogue.jit`)
LOOP_JIT = JIT_NO_ALLOC


class LoopArrays(NamedTuple):
    """The controller, actuator and sensor arrays of the closed loop.

    The kernels take them after the model's arrays
    (:meth:`hosedrogue.model.system.HoseModel.kernel_args`), e.g.
    ``rk4_run(z0, h, nsteps, every, *model.kernel_args(), *loop, max_yaw, ts, zs, us, ...)``.
    """

    Ac: np.ndarray  #: controller state matrix (nc, nc) [1/s]
    Bc: np.ndarray  #: controller input matrix (nc, 2); inputs: measured drogue offset [m]
    Cc: np.ndarray  #: controller output matrix (2, nc); outputs: commanded force [N]
    Dc: np.ndarray  #: controller feedthrough (2, 2) [N/m]
    y_ref: np.ndarray  #: drogue balance position [y, z] (2,) [m]
    #: actuator [max_hor_n, max_ver_n, max_rate_n_s, time_constant_s] [N, N, N/s, s], then the drogue's
    #: control surfaces if it has them (:func:`hosedrogue.model.drogue_actuator.actuator_array`)
    act: np.ndarray
    noise: np.ndarray  #: sensor noise samples (k, 2) [m], zero-order held
    noise_dt: float  #: sensor noise sample time [s]


@njit(**LOOP_JIT)
def noise_at(t, noise, noise_dt):
    """Zero-order-held sensor noise sample [m] (2,) at time t."""
    i = int(t / noise_dt)
    if i >= noise.shape[0]:
        i = noise.shape[0] - 1
    if i < 0:
        i = 0
    return noise[i, 0], noise[i, 1]


@njit(**LOOP_JIT)
def control_law(t, z, nx, y, zz, Cc, Dc, y_ref, u_max, noise, noise_dt, u):
    """Commanded force u (2,) [N] for the drogue at lateral y, vertical zz [m] (saturated);
    returns the measured offsets."""
    ny, nz = noise_at(t, noise, noise_dt)
    m0 = y - y_ref[0] + ny
    m1 = zz - y_ref[1] + nz
    nc = Cc.shape[1]
    for i in range(2):
        acc = Dc[i, 0] * m0 + Dc[i, 1] * m1
        for j in range(nc):
            acc += Cc[i, j] * z[nx + j]
        if acc > u_max[ACT_U_MAX + i]:
            acc = u_max[ACT_U_MAX + i]
        elif acc < -u_max[ACT_U_MAX + i]:
            acc = -u_max[ACT_U_MAX + i]
        u[i] = acc
    return m0, m1


@njit(**LOOP_JIT)
def drogue_yz(z, l, ws):
    """Drogue lateral and vertical position [m] of the hose state at the start of z, through the
    link frames in the workspace ws (overwritten) and :func:`chain_loads.drogue_from_frames`."""
    n = l.shape[0]
    link_frames(z[: 2 * n], n, ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS])
    return drogue_from_frames(l, ws[WS_E])


@njit(**LOOP_JIT)
def applied_force(t, z, nx, l, Cc, Dc, y_ref, act, noise, noise_dt, ws, u):
    """Force acting on the drogue (2,) [N] into u; returns the measured offsets and the
    commanded force (which differs from u only for a rate-limited actuator). The workspace ws
    receives the link frames of z."""
    y, zz = drogue_yz(z, l, ws)
    return applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)


@njit(**LOOP_JIT)
def applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u):
    """:func:`applied_force` for a drogue at lateral y, vertical zz [m]."""
    m0, m1 = control_law(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    c0, c1 = u[0], u[1]
    na = nx + Cc.shape[1]
    if z.shape[0] > na:
        u[0] = z[na]
        u[1] = z[na + 1]
    return m0, m1, c0, c1


@njit(**LOOP_JIT)
def is_open_loop(z, nx, Cc, Dc):
    """True when the loop commands no force at all: no controller state, no feedthrough and no
    actuator state (``LinearController.static_zero()`` with an actuator without rate limit)."""
    return (Cc.shape[1] == 0 and z.shape[0] == nx and Dc[0, 0] == 0.0 and Dc[0, 1] == 0.0
            and Dc[1, 0] == 0.0 and Dc[1, 1] == 0.0)


@njit(**LOOP_JIT)
def closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act,
                      noise, noise_dt, ws, dz, u):
    """dz/dt of z = [x, xc, (ua)]; u receives the force applied to the drogue."""
    n = l.shape[0]
    nx = 4 * n
    # link frames first: the controller measures the drogue from them, the loads reuse them
    link_frames(z[: 2 * n], n, ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS])
    if DA.is_actuated(act):
        actuated_loop_deriv(t, z, nx, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, dz, u)
        return
    if is_open_loop(z, nx, Cc, Dc):
        # no controller: the force is zero whatever the measurement (skip measuring it)
        u[0] = 0.0
        u[1] = 0.0
        m0 = m1 = c0 = c1 = 0.0
    else:
        y, zz = drogue_from_frames(l, ws[WS_E])
        m0, m1, c0, c1 = applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    loads_given_frames(t, z[: 2 * n], z[2 * n: nx], u, l, M, J, ps, env, gust, ws)
    forward_dynamics_ws(l, M, J, ps, ws)
    qdd = ws[WS_QDD]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    actuator_rates(c0, c1, z, nx + Ac.shape[0], act, dz)
    controller_rates(m0, m1, z, nx, Ac, Bc, dz)


@njit(**LOOP_JIT)
def actuated_loop_deriv(t, z, nx, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, dz, u):
    """:func:`closed_loop_deriv` of a drogue steered by control surfaces (the link frames of z in
    ws): the controller's command, the surfaces' force, drag and servo rates
    (:func:`hosedrogue.model.drogue_actuator.drogue_actuator_law`), the hose, the controller with
    its anti-windup. With room in u (``u.shape[0] > 2``) also the dynamic pressure at the drogue
    [Pa] in u[2] and the surfaces' deflection rates [rad/s] in u[3:3+n_s] (the saved outputs)."""
    n = l.shape[0]
    nc = Ac.shape[0]
    na = nx + nc
    px, py, pz, vx, vy, vz = DA.drogue_motion_from_frames(l, ws[WS_E], ws[WS_A], ws[WS_B], z[2 * n: nx])
    m0, m1 = control_law(t, z, nx, py, pz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    q, e0, e1, ddx, ddy, ddz = DA.drogue_actuator_law(True, m0, m1, u[0], u[1], z, nx, na, px, py, pz, vx, vy, vz,
                                                      ps[PS_RHO], t, env_at(t, env, gust, ws[WS_ENV]), gust, Cc, Dc,
                                                      act, u, dz, na)
    loads_given_frames(t, z[: 2 * n], z[2 * n: nx], u, l, M, J, ps, env, gust, ws)
    DA.add_drogue_load(ws[WS_F], ws[WS_DRAG], n, ddx, ddy, ddz)
    forward_dynamics_ws(l, M, J, ps, ws)
    qdd = ws[WS_QDD]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    controller_rates(m0, m1, z, nx, Ac, Bc, dz)
    DA.windup_rates(e0, e1, nx, nc, act, dz)
    if u.shape[0] > 2:
        u[2] = q
        for k in range(int(act[DA.DA_NS])):
            u[3 + k] = dz[na + k]


@njit(**LOOP_JIT)
def actuator_rates(c0, c1, z, na, act, dz):
    """dz/dt of a rate-limited actuator's applied force ``ua = z[na:na+2]`` [N] (nothing if the
    state ends at ``na``): ``ua' = clip((u_cmd - ua) / time_constant, -rate, rate)`` for the
    commanded force (c0, c1) [N]. Also used by the engagement kernels."""
    if z.shape[0] > na:
        rate = act[ACT_RATE]
        for i in range(2):
            r = ((c0 if i == 0 else c1) - z[na + i]) / act[ACT_TAU]
            dz[na + i] = min(max(r, -rate), rate)


@njit(**LOOP_JIT)
def controller_rates(m0, m1, z, nx, Ac, Bc, dz):
    """dz/dt of the controller state ``xc = z[nx:nx+nc]``: ``Ac xc + Bc m`` for the measured
    offsets m = (m0, m1) [m]. Also used by the engagement kernels."""
    nc = Ac.shape[0]
    for i in range(nc):
        acc = Bc[i, 0] * m0 + Bc[i, 1] * m1
        for j in range(nc):
            acc += Ac[i, j] * z[nx + j]
        dz[nx + i] = acc


def loop_arrays(ctrl, y_ref, actuator, noise, noise_dt_s: float, drogue_actuator=None) -> LoopArrays:
    """The closed loop's controller, actuator and sensor arrays for the kernels (C-contiguous
    float64 of the shapes :class:`LoopArrays` lists), for the fixed-length and the engagement loops.

    Parameters
    ----------
    ctrl : hosedrogue.controllers.linear.LinearController
        Controller from drogue offset [m] to force [N] (its ``A, B, C, D`` and ``n_states``;
        ``LinearController.static_zero()`` for none).
    y_ref : array (2,)
        Drogue balance position [y, z] [m].
    actuator : hosedrogue.spec.params.Actuator
        Force [N] and rate [N/s] limits.
    noise : array (k, 2)
        Sensor noise samples [m] (``(1, 2)`` zeros for none; :func:`sensor_noise`).
    noise_dt_s : float
        Time each noise sample is held [s].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (the controller's force command is mixed to them; its
        ``anti_windup`` gain acts when they saturate; with ``command = "deflection"`` the
        controller's n_s outputs are the deflection commands [rad]); None: the force acts as commanded.

    Returns
    -------
    LoopArrays
    """
    def c(a, shape):
        # a writable copy: a read-only array (LinearController.static_zero()'s) is another numba type,
        # for which every kernel taking the loop would compile once more (docs/develop.md, "The compiled core")
        return np.array(a, dtype=np.float64, order="C").reshape(shape)

    nc = ctrl.n_states
    act = actuator.as_array()
    outputs = 2
    if drogue_actuator is not None:
        act = DA.actuator_array(act, drogue_actuator, getattr(ctrl, "anti_windup", None), nc, drogue_actuator.command)
        outputs = drogue_actuator.command_size
    return LoopArrays(c(ctrl.A, (nc, nc)), c(ctrl.B, (nc, 2)), c(ctrl.C, (outputs, nc)), c(ctrl.D, (outputs, 2)),
                      c(y_ref, (2,)), act, c(noise, (-1, 2)), float(noise_dt_s))


def loop_states(ctrl, actuator, drogue_actuator=None) -> np.ndarray:
    """The loop's initial states after the plant's: the controller's (zero) and, for a
    rate-limited actuator, the applied force [N] (zero), or the drogue's surfaces at rest
    (deflections [rad] and, for the second-order servo, servo rates [rad/s]: zero).

    Parameters
    ----------
    ctrl : hosedrogue.controllers.linear.LinearController
        Controller (its ``n_states``).
    actuator : hosedrogue.spec.params.Actuator
        Its ``rate_limited``.
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (their ``surfaces`` and ``servo_order``).

    Returns
    -------
    array (n_states [+ 2 or + surfaces x servo_order],)
    """
    if drogue_actuator is not None:
        return np.zeros(ctrl.n_states + drogue_actuator.surfaces * drogue_actuator.servo_order)
    return np.zeros(ctrl.n_states + (2 if actuator.rate_limited else 0))


def sensor_noise(sensor, duration_s: float, seed: int) -> np.ndarray:
    """Sensor noise samples [m] (k, 2) of a run, zero-order held for ``sensor.sample_time_s``
    (``(1, 2)`` zeros without noise); an independent stream of the turbulence seed, so the sensor
    noise does not shift the gust draws of the same seed.

    Parameters
    ----------
    sensor : hosedrogue.spec.params.Sensor
        Noise standard deviation [m] and sample time [s].
    duration_s : float
        Simulated time [s] the samples cover.
    seed : int
        The run's turbulence seed.

    Returns
    -------
    array (k, 2)
    """
    count = int(math.ceil(duration_s / sensor.sample_time_s)) + 2
    if sensor.noise_std_m == 0.0:
        return np.zeros((1, 2))
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([seed, 1])))
    return sensor.noise_std_m * rng.standard_normal((count, 2))


@njit(**JIT_INLINE)
def closed_loop_rate(t, z, model, hg, guess, dz):
    """:func:`closed_loop_deriv` as the steppers' derivative (:mod:`hosedrogue.model.steppers`):
    ``model`` is ``(l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
    u)`` (u receives the force applied to the drogue); the rigid chain has no implicit stage: hg
    and guess are not read."""
    l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, u = model
    closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, dz, u)


#: One classical RK4 step of the closed loop, ``rk4_step(t, z, h, model, work)``: from (t, z),
#: in place (``model`` :func:`closed_loop_rate`'s tuple, ``work`` (5, len(z)) scratch), and the same
#: step when ``work[0]`` already holds k1 = dz/dt at (t, z), ``rk4_step_given_k1`` (the
#: steppers' :func:`~hosedrogue.model.steppers.rk4` over :func:`closed_loop_rate`).
rk4_step, rk4_step_given_k1 = rk4(closed_loop_rate)


@njit(**LOOP_JIT)
def rk4_steps(t0, first, last, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
              noise_dt, max_yaw, ws, work, u, given_k1):
    """Steps number ``first`` to ``last`` (counted from 1 at t0) of size h [s], in place; with
    ``given_k1`` the first of them takes k1 from ``work[0]`` (:func:`rk4_step_given_k1`).

    Step ``k`` goes from ``t0 + (k - 1) h`` to ``t0 + k h``. Returns ``(status, k)``: OK and
    ``last``, or at the first step k whose state is non-finite (NONFINITE) or has a link yaw
    beyond ``max_yaw`` [rad] (YAW_LIMIT) that status and k (the state is then that after step k).
    The one integration loop: :func:`fl_interval` (the runs, the steppers, the sampled-data loop)
    and the batch call it. It is compiled without numba's runtime (:data:`LOOP_JIT`): the steps
    inlined into it then take no reference counts of the arrays they unpack from ``model``
    (inlined into a function that allocates, they would, at every evaluation).
    """
    n = l.shape[0]
    model = (l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, u)
    for step in range(first, last + 1):
        if given_k1 and step == first:
            rk4_step_given_k1(t0 + (step - 1) * h, z, h, model, work)
        else:
            rk4_step(t0 + (step - 1) * h, z, h, model, work)
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, step
    return OK, last


@njit(**LOOP_JIT)
def step_status(z, n, max_yaw):
    """OK, or why the state may not go on: non-finite, or a link yaw beyond max_yaw [rad]."""
    for i in range(z.shape[0]):
        if not math.isfinite(z[i]):
            return NONFINITE
    for k in range(n):
        if abs(z[2 * k + 1]) > max_yaw:
            return YAW_LIMIT
    return OK


def rk4_run(z0, h, nsteps, save_every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref,
            act, noise, noise_dt, max_yaw, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension):
    """A whole run of the fixed-length hose: ``nsteps`` RK4 steps of size h from (0, z0) through
    :func:`fl_interval`, keeping every ``save_every``-th state (the last one included) in ts, zs,
    us (the force applied at that state) and its derived outputs in joints (N, n+1, 3) [m],
    drogue_vel, drogue_drag, tow (N, 3) [m/s, N, N] and tension (N,) [N] (as
    :func:`~hosedrogue.model.chain_dynamics.outputs_series` gives them). Returns (status, saved
    count, stop time [s]); the run starts at t = 0 (``fl_interval``'s steps are counted from it).
    Plain Python: the loop is ``fl_interval``'s, compiled once for the run and the stepper alike
    (they pass it the same kinds of arrays).

    Stops early on a non-finite state (status NONFINITE) or a link yaw beyond ``max_yaw`` [rad]
    (status YAW_LIMIT); what was saved up to then stays valid.

    Parameters
    ----------
    z0 : numpy.ndarray
        The closed loop's state at the start (:func:`loop_states` after the hose's).
    h : float
        RK4 step [s].
    nsteps, save_every : int
        Steps, and steps from one saved state to the next [-].
    l, M, S, J, ps, env, gust : numpy.ndarray
        The model's arrays (:meth:`hosedrogue.model.system.HoseModel.kernel_args`).
    Ac, Bc, Cc, Dc, y_ref, act, noise : numpy.ndarray
        The closed loop's arrays (:class:`LoopArrays`).
    noise_dt : float
        Sensor noise sample time [s].
    max_yaw : float
        Link yaw that stops the run [rad].
    ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension : numpy.ndarray
        The record to fill, ``save_every``-th states (:func:`save_state`).

    Returns
    -------
    tuple
        (status, saved rows, stop time [s]).
    """
    z = np.array(z0, dtype=np.float64)
    work = np.empty((5, z.shape[0]))
    u = np.empty(us.shape[1])
    status, saved, done = fl_interval(z, 0, nsteps, h, save_every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc,
                                      y_ref, act, noise, noise_dt, max_yaw, True, ts, zs, us, joints, drogue_vel,
                                      drogue_drag, tow, tension, 0, make_workspace(l.shape[0]), work, u, True)
    return status, saved, done * h


@njit(**JIT)
def fl_interval(z, step0, nsteps, h, every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                noise_dt, max_yaw, record, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension, saved,
                ws, work, u, close=False):
    """The fixed-length hose's event loop for rigid links (:func:`~.steppers.event_loop`):
    ``nsteps`` RK4 steps of the closed loop from global step ``step0`` (time ``step0 h`` [s]), in
    place. With ``record`` the state at every global step j in [step0, step0 + nsteps) that is a
    multiple of ``every`` is saved at row ``saved`` on (:func:`save_state`, whose evaluation serves
    as the first stage of the step that starts there); the steps between two saved states go to
    :func:`rk4_steps` at once; with ``close`` (and ``record``) the state after the last step too,
    if it is on the grid (a whole run's end). Returns (status, saved count, steps done): a
    non-finite state or a yaw beyond ``max_yaw`` [rad] stops after its step. A whole run
    (:func:`rk4_run`), the stepper's control step (:func:`~.sampled.fl_advance`) and the built-in
    sampled-data controller (:func:`~.sampled.fl_linear_sampled_run`) all integrate through it."""
    model = (l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, max_yaw)
    return _rigid_interval(z, step0, nsteps, h, every, record, close, saved, model,
                           (ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension), (ws, work, u))


@njit(**JIT_INLINE)
def _rigid_advance(j, last, z, h, model, scratch, at_save):
    # steps j + 1 .. last by RK4; the first takes k1 from the saved state's evaluation (work[0])
    l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, max_yaw = model
    ws, work, u = scratch
    return rk4_steps(0.0, j + 1, last, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                     noise_dt, max_yaw, ws, work, u, at_save)


@njit(**JIT_INLINE)
def _rigid_save(i, t, z, model, rec, scratch):
    l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, _ = model
    ws, work, u = scratch
    ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension = rec
    save_state(i, t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, work, u, ts, zs,
               us, joints, drogue_vel, drogue_drag, tow, tension)


@njit(**JIT_INLINE)
def save_state(i, t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
               work, u, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension):
    """Row i of the saved series: time, state, applied force, and the outputs of the evaluation
    of dz/dt at (t, z), which leaves k1 in ``work[0]`` for the step that starts there. Inlined
    into its compiled callers (:data:`hosedrogue.jit.JIT_INLINE`)."""
    n = l.shape[0]
    ts[i] = t
    copy_vector(zs[i], z)  # element by element: no array assignment (docs/develop.md, "The compiled core")
    closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt,
                      ws, work[0], u)
    copy_matrix(joints[i], ws[WS_R])
    copy_vector(drogue_vel[i], ws[WS_V][n])
    copy_vector(drogue_drag[i], ws[WS_DRAG])
    copy_vector(tow[i], ws[WS_TOW])
    tension[i] = ws[WS_T0][0]
    # u is the force applied at (t, z): closed_loop_deriv measured the drogue and set it
    us[i, 0] = u[0]
    us[i, 1] = u[1]
    for j in range(2, us.shape[1]):
        us[i, j] = u[j]


#: The event loop of rigid links (:func:`fl_interval`).
_rigid_interval = event_loop(_rigid_advance, _rigid_save)
