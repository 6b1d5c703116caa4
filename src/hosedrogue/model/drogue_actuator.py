"""The drogue's control surfaces in the compiled loop (numba): the one definition of their force,
drag, mixing and servo dynamics, which the fixed-length loop (:mod:`.integrate`) and the
engagement (:mod:`hosedrogue.model.engagement`) both call (docs/model.md, "Actuated drogue").

The surfaces' parameters follow the ideal actuator's :data:`ACT_IDEAL` entries in the loop's
``act`` array (:func:`actuator_array`; the slots ``DA_*`` of :mod:`hosedrogue.model.layout`); an
``act`` longer than that means an actuated drogue.
Their states follow the controller's: ``n_s`` deflections delta_k [rad] and, for the
second-order servo, ``n_s`` servo rates r_k [rad/s].

One evaluation (:func:`drogue_actuator_law`), after the caller has measured the drogue and
evaluated the controller (:func:`hosedrogue.model.integrate.control_law`):

1. ``q = 1/2 rho |v_drogue - w|^2``, w the air at the drogue
   (:func:`~hosedrogue.model.chain_loads.air_velocity`: free stream, wake, gusts, bow wave);
2. the commands: in ``force`` mode the minimum-norm mixing of the commanded force F_c at the
   measured q, ``delta_c,k = t_k . F_c / ((n_s / 2) q S C_F)`` (t_k the direction surface k
   pushes, ``sum_k t_k t_k^T = (n_s / 2) I``); in ``deflection`` mode the controller's own n_s
   outputs [rad]; each clipped to +-delta_max. The anti-windup error is the force the clipped
   commands make minus F_c (zero when no command is clipped);
3. the servo of each surface: first order ``delta' = clip(omega (delta_c - delta), +-R)``;
   second order as a position loop around a rate loop, ``r_c = clip(omega / (2 zeta) (delta_c -
   delta), +-R)``, ``r' = 2 zeta omega (r_c - r)``, ``delta' = r`` slowed to zero at the stops
   (``min(r, 2 zeta omega (delta_max - delta))`` toward +delta_max), i.e.
   ``omega^2 / (s^2 + 2 zeta omega s + omega^2)`` inside the limits;
4. the force ``q S C_F sum_k t_k delta_k`` in S_p y, z at the drogue and the drag increment
   ``-q S k_D sum_k delta_k^2`` along the relative wind.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..jit import JIT_NO_ALLOC
from .chain_loads import air_velocity
# the ideal actuator's entries at the head of ``act`` (ACT_IDEAL of them) and the surfaces' after
# them (DA_*, to DA_HEAD), declared and documented there; MAX_SURFACES the most surfaces
from .layout import (ACT_IDEAL, DA_DMAX, DA_HEAD, DA_MODE, DA_NC, DA_NS, DA_OMEGA, DA_ORDER, DA_QMIN, DA_RMAX,
                     DA_SCF, DA_SKD, DA_ZETA, MAX_SURFACES, MODE_DEFLECTION, MODE_FORCE)

COMMAND_MODES = {"force": MODE_FORCE, "deflection": MODE_DEFLECTION}
#: Below this dynamic pressure [Pa] the inversion divides by it instead (no air: the commands saturate).
Q_MIN_PA = 1.0


@njit(**JIT_NO_ALLOC)
def is_actuated(act):
    """True when ``act`` carries control surfaces (the drogue steers itself)."""
    return act.shape[0] > ACT_IDEAL


@njit(**JIT_NO_ALLOC)
def servo_state_count(act):
    """Number of the surfaces' states: n_s deflections, and n_s servo rates for the second order."""
    return int(act[DA_NS]) * int(act[DA_ORDER])


@njit(**JIT_NO_ALLOC)
def drogue_motion_from_frames(l, e, a, b, qd):
    """Drogue (joint n) position [m] and velocity [m/s] in S_p of the fixed-length chain whose
    link frames are e, a, b: ``sum l_k e_k`` and ``sum l_k (a_k qd_k1 + b_k qd_k2)``."""
    px = py = pz = vx = vy = vz = 0.0
    for k in range(l.shape[0]):
        lk = l[k]
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        px += lk * e[k, 0]
        py += lk * e[k, 1]
        pz += lk * e[k, 2]
        vx += lk * (a[k, 0] * d1 + b[k, 0] * d2)
        vy += lk * (a[k, 1] * d1 + b[k, 1] * d2)
        vz += lk * (a[k, 2] * d1 + b[k, 2] * d2)
    return px, py, pz, vx, vy, vz


@njit(**JIT_NO_ALLOC)
def local_air(rho, px, py, pz, vx, vy, vz, t, env, gust):
    """Dynamic pressure q [Pa] of the air at the drogue at (px, py, pz) [m] moving at (vx, vy,
    vz) [m/s], and the drogue's velocity relative to that air [m/s] (x, y, z and its magnitude)."""
    wx, wy, wz = air_velocity(px, py, pz, t, env, gust)
    rx = vx - wx
    ry = vy - wy
    rz = vz - wz
    v2 = rx * rx + ry * ry + rz * rz
    return 0.5 * rho * v2, rx, ry, rz, math.sqrt(v2)


@njit(**JIT_NO_ALLOC)
def surface_force(q, z, na, act):
    """Force of the surfaces at the deflections ``z[na:na+n_s]`` [rad] in dynamic pressure q
    [Pa]: ``q S C_F sum t_k delta_k`` in S_p y, z [N], and ``sum delta_k^2`` [rad^2]."""
    fy = fz = ss = 0.0
    for k in range(int(act[DA_NS])):
        d = z[na + k]
        fy += act[DA_HEAD + 2 * k] * d
        fz += act[DA_HEAD + 2 * k + 1] * d
        ss += d * d
    qs = q * act[DA_SCF]
    return qs * fy, qs * fz, ss


@njit(**JIT_NO_ALLOC)
def servo_rates(k, cmd, z, na, act, rates, base):
    """Surface k's servo derivatives into ``rates[base + k]`` (d delta_k/dt [rad/s]) and, for the
    second order, ``rates[base + n_s + k]`` (dr_k/dt [rad/s^2]), toward the command cmd [rad]."""
    ns = int(act[DA_NS])
    rmax = act[DA_RMAX]
    w = act[DA_OMEGA]
    d = z[na + k]
    if act[DA_ORDER] == 1.0:
        rates[base + k] = min(max(w * (cmd - d), -rmax), rmax)
        return
    wr = 2.0 * act[DA_ZETA] * w  # the rate loop's bandwidth; the position loop's is w^2 / wr
    r = z[na + ns + k]
    rc = min(max(w * w / wr * (cmd - d), -rmax), rmax)
    rates[base + ns + k] = wr * (rc - r)
    dmax = act[DA_DMAX]
    if r > 0.0:
        rates[base + k] = min(r, wr * (dmax - d))
    else:
        rates[base + k] = max(r, -wr * (dmax + d))


@njit(**JIT_NO_ALLOC)
def clip_deflection(cmd, dmax):
    """A deflection command [rad] limited to [-dmax, dmax], and whether it was limited."""
    if cmd > dmax:
        return dmax, True
    if cmd < -dmax:
        return -dmax, True
    return cmd, False


@njit(**JIT_NO_ALLOC)
def surface_commands(on, m0, m1, c0, c1, q, z, nx, na, Cc, Dc, act, rates, base):
    """Every surface's clipped deflection command and its servo derivatives (:func:`servo_rates`).

    ``on`` False: every command is zero (the controller is off). In force mode the command is the
    mixing of the commanded force (c0, c1) [N] at the measured q [Pa]; in deflection mode the
    controller's outputs ``Cc xc + Dc m`` [rad] (m = (m0, m1) [m], xc = ``z[nx:]``). Returns the
    anti-windup error [N]: the force the clipped commands make minus the command (force mode,
    some command clipped), else (0, 0).
    """
    ns = int(act[DA_NS])
    dmax = act[DA_DMAX]
    qh = max(q, act[DA_QMIN])
    scale = 0.5 * ns * qh * act[DA_SCF]
    force_mode = act[DA_MODE] == MODE_FORCE
    a0 = a1 = 0.0
    clipped = False
    for k in range(ns):
        ty = act[DA_HEAD + 2 * k]
        tz = act[DA_HEAD + 2 * k + 1]
        cmd = 0.0
        if on and force_mode:
            cmd = (ty * c0 + tz * c1) / scale
        elif on:
            cmd = Dc[k, 0] * m0 + Dc[k, 1] * m1
            for j in range(Cc.shape[1]):
                cmd += Cc[k, j] * z[nx + j]
        cmd, limited = clip_deflection(cmd, dmax)
        clipped = clipped or limited
        a0 += ty * cmd
        a1 += tz * cmd
        servo_rates(k, cmd, z, na, act, rates, base)
    if clipped and on and force_mode:
        s = qh * act[DA_SCF]
        return s * a0 - c0, s * a1 - c1
    return 0.0, 0.0


@njit(**JIT_NO_ALLOC)
def mixing_error(c0, c1, q, act):
    """The anti-windup error [N] of a force command (c0, c1) [N] mixed at the dynamic pressure q
    [Pa] (:func:`surface_commands` in force mode, without the servos): the force the clipped
    deflection commands make minus the command; (0, 0) when no command is clipped. A sampled-data
    controller's measured q gives its discrete anti-windup (:func:`hosedrogue.model.sampled.fl_linear_sampled_run`)."""
    ns = int(act[DA_NS])
    dmax = act[DA_DMAX]
    qh = max(q, act[DA_QMIN])
    scale = 0.5 * ns * qh * act[DA_SCF]
    a0 = a1 = 0.0
    clipped = False
    for k in range(ns):
        ty = act[DA_HEAD + 2 * k]
        tz = act[DA_HEAD + 2 * k + 1]
        cmd = (ty * c0 + tz * c1) / scale
        cmd, limited = clip_deflection(cmd, dmax)
        clipped = clipped or limited
        a0 += ty * cmd
        a1 += tz * cmd
    if not clipped:
        return 0.0, 0.0
    s = qh * act[DA_SCF]
    return s * a0 - c0, s * a1 - c1


@njit(**JIT_NO_ALLOC)
def drogue_actuator_law(on, m0, m1, c0, c1, z, nx, na, px, py, pz, vx, vy, vz, rho, t, env, gust, Cc, Dc, act,
                        u, rates, base):
    """The actuated drogue at one evaluation (the module docstring's steps 1-4).

    The caller has measured the offsets (m0, m1) [m] and evaluated the controller: (c0, c1) is
    its force command [N] (force mode). The drogue is at (px, py, pz) [m] and moves at (vx, vy,
    vz) [m/s]; env is the evaluation's air (with the gust at t when uniform, and the bow wave).
    Writes the surfaces' force [N] into u[0], u[1] and the servo derivatives into
    ``rates[base:]``. Returns the dynamic pressure q [Pa], the anti-windup error (e0, e1) [N]
    and the drag increment (x, y, z) [N] on the drogue.
    """
    q, rx, ry, rz, vr = local_air(rho, px, py, pz, vx, vy, vz, t, env, gust)
    e0, e1 = surface_commands(on, m0, m1, c0, c1, q, z, nx, na, Cc, Dc, act, rates, base)
    fy, fz, ss = surface_force(q, z, na, act)
    u[0] = fy
    u[1] = fz
    k = 0.0
    if vr > 0.0:
        k = -q * act[DA_SKD] * ss / vr
    return q, e0, e1, k * rx, k * ry, k * rz


@njit(**JIT_NO_ALLOC)
def windup_rates(e0, e1, nx, nc, act, dz):
    """Add the anti-windup term ``K_aw e`` to the controller's state derivatives ``dz[nx:nx+nc]``
    (e the error of :func:`surface_commands` [N])."""
    if e0 == 0.0 and e1 == 0.0:
        return
    o = DA_HEAD + 2 * int(act[DA_NS])
    for i in range(nc):
        dz[nx + i] += act[o + 2 * i] * e0 + act[o + 2 * i + 1] * e1


@njit(**JIT_NO_ALLOC)
def add_drogue_load(F, drag, n, dx, dy, dz):
    """Add the surfaces' drag increment (dx, dy, dz) [N] to the drogue joint's load ``F[n]`` and to
    the drogue's aerodynamic force ``drag`` (3,)."""
    F[n, 0] += dx
    F[n, 1] += dy
    F[n, 2] += dz
    drag[0] += dx
    drag[1] += dy
    drag[2] += dz


def actuator_array(head: np.ndarray, section, anti_windup: np.ndarray | None, n_controller_states: int,
                   command: str = "force") -> np.ndarray:
    """The loop's ``act`` of an actuated drogue: the ideal actuator's entries, then the surfaces'.

    Parameters
    ----------
    head : array (ACT_IDEAL,)
        The ideal actuator's entries (:meth:`hosedrogue.spec.sections.Actuator.as_array`; no limits).
    section : hosedrogue.spec.sections.DrogueActuator
        Surfaces [-], roll angle [deg], deflection [deg] and rate [deg/s] limits, servo order [-],
        bandwidth [Hz], damping [-], force slope [1/rad], reference area [m^2], drag slope [1/rad^2].
    anti_windup : array (nc, 2) or None
        The controller's anti-windup gain [state units / N] (None: zeros).
    n_controller_states : int
        Number of the controller's states nc [-].
    command : {"force", "deflection"}
        What the controller's outputs are: a force [N] (lateral, vertical), or one deflection
        [rad] per surface (the hook for controllers that command the surfaces themselves).

    Returns
    -------
    numpy.ndarray
        C-contiguous float64 of length ``DA_HEAD + 2 n_s + 2 nc``.
    """
    ns = section.surfaces
    nc = int(n_controller_states)
    aw = np.zeros((nc, 2)) if anti_windup is None else np.asarray(anti_windup, dtype=np.float64).reshape(nc, 2)
    body = np.zeros(DA_HEAD - ACT_IDEAL)
    values = {DA_NS: ns, DA_ORDER: section.servo_order, DA_OMEGA: 2.0 * math.pi * section.bandwidth_hz,
              DA_ZETA: section.damping, DA_DMAX: math.radians(section.max_deflection_deg),
              DA_RMAX: math.radians(section.max_rate_deg_s),
              DA_SCF: section.reference_area_m2 * section.force_slope_per_rad,
              DA_SKD: section.reference_area_m2 * section.drag_slope_per_rad2, DA_MODE: COMMAND_MODES[command],
              DA_QMIN: Q_MIN_PA, DA_NC: nc}
    for index, value in values.items():
        body[index - ACT_IDEAL] = value
    directions = surface_directions(section).ravel()
    return np.ascontiguousarray(np.concatenate([np.asarray(head, dtype=np.float64), body, directions, aw.ravel()]))


def surface_directions(section) -> np.ndarray:
    """The direction t_k each surface pushes the drogue when deflected positively (S_p y, z).

    Parameters
    ----------
    section : hosedrogue.spec.sections.DrogueActuator
        Its surfaces and roll angle.

    Returns
    -------
    numpy.ndarray (n_s, 2)
        ``t_k = (-sin phi_k, cos phi_k)``: surface k sits at roll angle phi_k (from +y toward +z)
        and its force is tangential there.
    """
    phi = np.asarray(section.roll_angles_rad)
    return np.column_stack([-np.sin(phi), np.cos(phi)])
