"""The tanker's motion in the compiled core: the frame terms of the hose equations (numba).

The hose equations are written in the tanker's body axes B at the tow point (x forward along the
flight path, y right, z down; docs/model.md §9), the frame every output is given in. When the
tanker manoeuvres B is not inertial: its origin accelerates at ``a_0``, it turns at ``Omega``
with the angular acceleration ``alpha`` (all in B's components). A joint of mass M at r with
velocity v relative to B then obeys Newton's law in B with the apparent force

    M (g b_g - a_0 - alpha x r - Omega x (Omega x r) - 2 Omega x v),

``b_g`` the direction of gravity in B; a link of inertia ``J (1 - e e)`` feels the moment
``-(J Pdot Omega + J P alpha + Omega x J P (Omega + w))`` (P = 1 - e e, w its angular velocity
relative to B, Pdot = -(edot e + e edot)), the difference between its angular momentum's inertial
rate and the rate seen in B; and the air, at rest far from the tanker, moves relative to B at
``-(V x + Omega x r)``. Everything here is a pure function of float arrays:

* :func:`ramp_profile` - one smooth change (half-sine ramps of its rate, docs/model.md §9);
* :func:`flight_state` - bank, flight-path angle, airspeed, their rates and the path flown at t;
* :func:`frame_terms` - b_g, a_0, Omega, alpha, the air's speed, the path time and the wake's
  circulation factor at t, into the evaluation's copy of ``env`` (called by
  :func:`hosedrogue.model.chain_loads.fill_env`, so both chains see the one evaluation);
* :func:`frame_loads` - the apparent forces and moments (both chains call it after their
  ``joint_forces``); :func:`frame_wind` - the air's rotation seen at a point.

The motion table sits in the model's ``env`` after the ``ENV_SIZE`` scalars:
``[ramps, phi_0, gamma_0, g]`` then per ramp ``[quantity, start_s, rate, ramp_s, cruise_s]``
(:class:`hosedrogue.spec.manoeuvres.Ramp`); env's slots of the motion (``ENV_M_*``) and the table's
(``MT_*``, ``MR_*``) are declared in :mod:`hosedrogue.model.layout`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..constants import G0
from ..jit import JIT_NO_ALLOC
from ..spec.manoeuvres import AIRSPEED, BANK, TankerMotion

from .layout import (  # the env slots of the tanker's motion and the motion table's, declared there
    ENV_M_A0, ENV_M_D, ENV_M_END, ENV_M_G, ENV_M_ON, ENV_M_T, ENV_M_V0, ENV_M_W, MR_CRUISE, MR_QUANTITY, MR_RAMP,
    MR_RATE, MR_START, MT_G, MT_GAMMA0, MT_PHI0, MT_RAMPS, TABLE_HEAD, TABLE_ROW,
)


@njit(**JIT_NO_ALLOC)
def ramp_profile(tau, rate, ta, tc):
    """One ramp at ``tau`` [s] after its start: ``(integral, change, rate, rate')`` of a change
    whose rate rises along a half-sine pulse of ``ta`` [s] to ``rate``, holds ``tc`` [s] and falls
    back the same way (units of the quantity times s, the quantity, per s, per s^2)."""
    if tau <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    w = math.pi / ta
    h = 0.5 * rate
    if tau < ta:
        c = math.cos(w * tau)
        s = math.sin(w * tau)
        return h * (0.5 * tau * tau + (c - 1.0) / (w * w)), h * (tau - s / w), h * (1.0 - c), h * w * s
    i1 = h * (0.5 * ta * ta - 2.0 / (w * w))
    v1 = h * ta
    if tau < ta + tc:
        u = tau - ta
        return i1 + v1 * u + h * u * u, v1 + rate * u, rate, 0.0
    i2 = i1 + v1 * tc + h * tc * tc
    v2 = v1 + rate * tc
    if tau < 2.0 * ta + tc:
        u = tau - ta - tc
        c = math.cos(w * u)
        s = math.sin(w * u)
        return i2 + v2 * u + h * (0.5 * u * u + (1.0 - c) / (w * w)), v2 + h * (u + s / w), h * (1.0 + c), -h * w * s
    i3 = i2 + v2 * ta + h * (0.5 * ta * ta + 2.0 / (w * w))
    v3 = v2 + h * ta
    return i3 + v3 * (tau - 2.0 * ta - tc), v3, 0.0, 0.0


@njit(**JIT_NO_ALLOC)
def flight_state(t, env, at):
    """The tanker's flight at t [s] from the motion table at ``env[at:]``: bank phi, phi', phi''
    [rad, rad/s, rad/s^2], flight path gamma, gamma', gamma'' (the same units), airspeed V, V'
    [m/s, m/s^2] and the path flown since t = 0 [m]."""
    phi = env[at + MT_PHI0]
    gam = env[at + MT_GAMMA0]
    V0 = env[ENV_M_V0]
    V = V0
    s = V0 * t
    phid = phidd = gamd = gamdd = Vd = 0.0
    for i in range(int(env[at + MT_RAMPS])):
        b = at + TABLE_HEAD + TABLE_ROW * i
        integral, change, rate, acc = ramp_profile(t - env[b + MR_START], env[b + MR_RATE], env[b + MR_RAMP],
                                                   env[b + MR_CRUISE])
        if env[b + MR_QUANTITY] == BANK:
            phi += change
            phid += rate
            phidd += acc
        elif env[b + MR_QUANTITY] == AIRSPEED:
            V += change
            Vd += rate
            s += integral
        else:
            gam += change
            gamd += rate
            gamdd += acc
    return phi, phid, phidd, gam, gamd, gamdd, V, Vd, s


@njit(**JIT_NO_ALLOC)
def frame_terms(t, env, at, scratch):
    """The frame terms at t [s] into ``scratch`` (the evaluation's copy of env): the direction of
    gravity b_g, the tow point's acceleration a_0, Omega and alpha in B (slots ENV_M_*) and the
    path time; returns the airspeed V [m/s] and the wake's circulation factor ``n V_0 / V``
    (n = L / W, the load factor: the circulation carries the lift, Gamma = L / (rho V b_0)).

    Coordinated flight (no sideslip, no lateral load: ``(g b_g - a_0) . y = 0``) fixes the
    heading rate, ``psi' = tan(phi) (g / V + gamma' / cos(gamma))``; with the 3-2-1 angles
    (psi, gamma, phi) of B, ``Omega = [phi' - psi' s_gamma, gamma' c_phi + psi' c_gamma s_phi,
    -gamma' s_phi + psi' c_gamma c_phi]``, ``a_0 = [V', V r, -V q]``."""
    phi, phid, phidd, gam, gamd, gamdd, V, Vd, s = flight_state(t, env, at)
    g = env[at + MT_G]
    cf = math.cos(phi)
    sf = math.sin(phi)
    cg = math.cos(gam)
    sg = math.sin(gam)
    tf = sf / cf
    k = g / V + gamd / cg
    kd = -g * Vd / (V * V) + gamdd / cg + gamd * gamd * sg / (cg * cg)
    psid = tf * k
    psidd = phid * k / (cf * cf) + tf * kd
    p = phid - psid * sg
    q = gamd * cf + psid * cg * sf
    r = -gamd * sf + psid * cg * cf
    scratch[ENV_M_W] = p
    scratch[ENV_M_W + 1] = q
    scratch[ENV_M_W + 2] = r
    scratch[ENV_M_D] = phidd - psidd * sg - psid * gamd * cg
    scratch[ENV_M_D + 1] = gamdd * cf - gamd * phid * sf + psidd * cg * sf - psid * gamd * sg * sf + psid * phid * cg * cf
    scratch[ENV_M_D + 2] = -gamdd * sf - gamd * phid * cf + psidd * cg * cf - psid * gamd * sg * cf - psid * phid * cg * sf
    scratch[ENV_M_G] = -sg
    scratch[ENV_M_G + 1] = cg * sf
    scratch[ENV_M_G + 2] = cg * cf
    scratch[ENV_M_A0] = Vd
    scratch[ENV_M_A0 + 1] = V * r
    scratch[ENV_M_A0 + 2] = -V * q
    V0 = env[ENV_M_V0]
    scratch[ENV_M_T] = s / V0
    load_factor = (g * cg * cf + V * q) / g
    return V, load_factor * V0 / V


@njit(**JIT_NO_ALLOC)
def frame_wind(px, py, pz, env):
    """The air's velocity relative to B at (px, py, pz) [m] due to B's rotation, ``-Omega x r``
    [m/s] (the free stream's -V x aside)."""
    wx, wy, wz = env[ENV_M_W], env[ENV_M_W + 1], env[ENV_M_W + 2]
    return -(wy * pz - wz * py), -(wz * px - wx * pz), -(wx * py - wy * px)


@njit(**JIT_NO_ALLOC)
def frame_loads(g, m_tow, l, M, J, n, e, r, v, env, F, Mom):
    """Add the apparent forces of the tanker's motion to the joint forces F (n+1, 3) [N] and the
    moments on the links Mom (n, 3) [N m] (nothing in straight and level flight, ``env[ENV_M_ON]
    == 0``, where the kernels' ``joint_forces`` applies gravity itself).

    Joint k+1 (mass M[k] [kg] at r[k+1] [m], velocity v[k+1] [m/s] in B) gets
    ``M (g b_g - a_0 - alpha x r - Omega x (Omega x r) - 2 Omega x v)``; the tow point's own
    mass ``m_tow`` [kg] (fixed in B) ``m_tow (g b_g - a_0) - m_tow g z`` (its weight ``m_tow g z``
    is added with the tow force by each chain); link k (inertia ``J[k] (1 - e e)`` [kg m^2], axis
    e[k], ``edot = (v[k+1] - v[k]) / l[k]``) the moment ``-P (J Pdot Omega + J P alpha +
    Omega x J P (Omega + w))`` with ``w = e x edot``. g [m/s^2]."""
    if env[ENV_M_ON] == 0.0:
        return
    ax = g * env[ENV_M_G] - env[ENV_M_A0]
    ay = g * env[ENV_M_G + 1] - env[ENV_M_A0 + 1]
    az = g * env[ENV_M_G + 2] - env[ENV_M_A0 + 2]
    wx, wy, wz = env[ENV_M_W], env[ENV_M_W + 1], env[ENV_M_W + 2]
    dx, dy, dz = env[ENV_M_D], env[ENV_M_D + 1], env[ENV_M_D + 2]
    F[0, 0] += m_tow * ax
    F[0, 1] += m_tow * ay
    F[0, 2] += m_tow * (az - g)
    for k in range(n):
        rx, ry, rz = r[k + 1, 0], r[k + 1, 1], r[k + 1, 2]
        vx, vy, vz = v[k + 1, 0], v[k + 1, 1], v[k + 1, 2]
        cx = wy * rz - wz * ry  # Omega x r
        cy = wz * rx - wx * rz
        cz = wx * ry - wy * rx
        m = M[k]
        F[k + 1, 0] += m * (ax - (dy * rz - dz * ry) - (wy * cz - wz * cy) - 2.0 * (wy * vz - wz * vy))
        F[k + 1, 1] += m * (ay - (dz * rx - dx * rz) - (wz * cx - wx * cz) - 2.0 * (wz * vx - wx * vz))
        F[k + 1, 2] += m * (az - (dx * ry - dy * rx) - (wx * cy - wy * cx) - 2.0 * (wx * vy - wy * vx))
    for k in range(n):
        Jk = J[k]
        if Jk == 0.0:
            continue
        ex, ey, ez = e[k, 0], e[k, 1], e[k, 2]
        tx = (v[k + 1, 0] - v[k, 0]) / l[k]  # edot
        ty = (v[k + 1, 1] - v[k, 1]) / l[k]
        tz = (v[k + 1, 2] - v[k, 2]) / l[k]
        eW = ex * wx + ey * wy + ez * wz
        tW = tx * wx + ty * wy + tz * wz
        eD = ex * dx + ey * dy + ez * dz
        # P (Omega + w) with w = e x edot (perpendicular to e already)
        hx = wx - eW * ex + (ey * tz - ez * ty)
        hy = wy - eW * ey + (ez * tx - ex * tz)
        hz = wz - eW * ez + (ex * ty - ey * tx)
        # J Pdot Omega + J P alpha + Omega x J P (Omega + w)
        mx = Jk * (-tx * eW - ex * tW + dx - eD * ex + (wy * hz - wz * hy))
        my = Jk * (-ty * eW - ey * tW + dy - eD * ey + (wz * hx - wx * hz))
        mz = Jk * (-tz * eW - ez * tW + dz - eD * ez + (wx * hy - wy * hx))
        axial = mx * ex + my * ey + mz * ez  # zero up to rounding: only the perpendicular part acts
        Mom[k, 0] -= mx - axial * ex
        Mom[k, 1] -= my - axial * ey
        Mom[k, 2] -= mz - axial * ez


def motion_table(motion: TankerMotion, airspeed_m_s: float, steady: bool = False) -> np.ndarray | None:
    """The motion table of the compiled core (see the module docstring), or None in straight and
    level flight (the kernels then skip every frame term).

    Parameters
    ----------
    motion : TankerMotion
        The tanker's motion.
    airspeed_m_s : float
        ``flight.airspeed_m_s``, the airspeed at the start [m/s].
    steady : bool
        The initial steady flight only (no segments): the frame of the balance position and the
        linearization.

    Returns
    -------
    numpy.ndarray or None
        float64 ``[ramps, phi_0 [rad], gamma_0 [rad], g [m/s^2], rows ...]``.
    """
    ramps = () if steady else motion.ramps(airspeed_m_s)
    if motion.bank_deg == 0.0 and motion.flight_path_deg == 0.0 and not ramps:
        return None
    phi0, gam0, _ = motion.initial(airspeed_m_s)
    table = [float(len(ramps)), phi0, gam0, G0]
    for rp in ramps:
        table += [float(rp.quantity), rp.start_s, rp.rate, rp.ramp_s, rp.cruise_s]
    return np.array(table, dtype=np.float64)


def with_motion(env: np.ndarray, table: np.ndarray | None, airspeed_m_s: float) -> np.ndarray:
    """``env`` (the kernels' ``ENV_SIZE`` scalars) with the motion table appended and the flags
    set; ``env`` itself when ``table`` is None.

    Parameters
    ----------
    env : numpy.ndarray
        The model's air scalars.
    table : numpy.ndarray or None
        :func:`motion_table`.
    airspeed_m_s : float
        The airspeed the gust record and the wake scalars were made for [m/s].

    Returns
    -------
    numpy.ndarray
    """
    if table is None:
        return env
    out = np.concatenate([env, table])
    out[ENV_M_ON] = 1.0
    out[ENV_M_V0] = float(airspeed_m_s)
    return out


@dataclass(frozen=True)
class SteadyFrame:
    """The frame terms of a steady flight (a coordinated turn and/or a climb at constant speed),
    in the tanker's body axes B: what the continuum's loads (:mod:`hosedrogue.analysis.continuum`)
    need. Straight and level flight is ``SteadyFrame((0, 0, g), (0, 0, 0), 1)``."""

    #: the uniform part of the apparent acceleration, ``g b_g - a_0`` (3,) [m/s^2]
    acceleration_m_s2: tuple
    #: B's angular velocity Omega (3,) [rad/s]: the centrifugal field ``-Omega x (Omega x r)`` and
    #: the air's rotation ``-Omega x r`` relative to B
    omega_rad_s: tuple
    #: the wake's circulation over its level-flight value at the model's airspeed, ``n V_0 / V`` [-]
    wake_factor: float
    #: the rotation the air is seen with, ``-Omega_air x r`` [rad/s] (3,); None: ``omega_rad_s``, as
    #: in flight (a study of a turn's parts may separate the two)
    air_omega_rad_s: tuple | None = None

    @property
    def air_omega(self) -> tuple:
        """The rotation the air is seen with [rad/s]."""
        return self.omega_rad_s if self.air_omega_rad_s is None else self.air_omega_rad_s

    @property
    def is_level(self) -> bool:
        """Straight and level flight: no rotation, gravity along z, the level wake."""
        return (tuple(self.acceleration_m_s2) == (0.0, 0.0, G0) and not any(self.omega_rad_s)
                and not any(self.air_omega) and self.wake_factor == 1.0)


def steady_frame(motion: TankerMotion, airspeed_m_s: float) -> SteadyFrame:
    """The frame terms of the motion's initial steady flight, from :func:`frame_terms` (the
    compiled core's one definition).

    Parameters
    ----------
    motion : TankerMotion
        Its ``bank_deg`` and ``flight_path_deg`` (the segments are ignored).
    airspeed_m_s : float
        The airspeed [m/s].

    Returns
    -------
    SteadyFrame
    """
    table = motion_table(motion, airspeed_m_s, steady=True)
    if table is None:
        return SteadyFrame((0.0, 0.0, G0), (0.0, 0.0, 0.0), 1.0)
    env = with_motion(np.zeros(ENV_M_END), table, airspeed_m_s)
    scratch = np.zeros(ENV_M_END)
    _, factor = frame_terms(0.0, env, ENV_M_END, scratch)
    acc = G0 * scratch[ENV_M_G:ENV_M_G + 3] - scratch[ENV_M_A0:ENV_M_A0 + 3]
    return SteadyFrame(tuple(float(a) for a in acc), tuple(float(w) for w in scratch[ENV_M_W:ENV_M_W + 3]),
                       float(factor))
