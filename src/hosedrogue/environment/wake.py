"""Hallock-Burnham wake of the tanker: a pair of trailing vortices (docs/model.md §4).

The tanker's wing sheds two counter-rotating vortices of circulation

    Gamma = W / (rho V b0),    W = m_tanker g0,    b0 = (vortex spacing / span) b,

(elliptic loading gives b0 = pi b / 4), each with the Hallock-Burnham tangential speed

    v_theta(r) = Gamma r / (2 pi (r^2 + rc^2)),    rc = (core radius / span) b.

Coordinates are relative to the tow point, in the tanker trajectory frame S_p (x forward, y right,
z down). The tow point sits ``y_tow = tow_point_y_over_span * b`` right of the centreline, so the
right (starboard) vortex is at ``y = +b0/2 - y_tow`` and the left one at ``y = -b0/2 - y_tow``, both
at ``z = vertical_offset_m``. The air moves down (+z) between the vortices and up outside them; the
field has no x component and does not vary with x (a fully rolled-up, non-decaying vortex pair,
which is the paper's reading of refs 22-23).

The right vortex induces, at an offset ``(dy, dz) = (y - y_v, z - z_v)`` from its axis,

    (v_y, v_z) = Gamma / (2 pi (dy^2 + dz^2 + rc^2)) * (dz, -dy),

a velocity of magnitude ``v_theta(r)`` at right angles to the offset; the left vortex induces the
same with the opposite sign.

The hot path reads six scalars packed by :func:`wake_scalars` (layout in :data:`WAKE_LAYOUT`), so
:func:`wake_velocity` is a pure numba function of floats.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..jit import JIT_NO_ALLOC

from ..constants import G0
from ..spec.params import ParameterError, Tanker, Wake

#: Meaning of the entries of the array returned by :func:`wake_scalars`.
WAKE_LAYOUT = ("enabled", "gamma_m2_s", "y_right_m", "y_left_m", "z_vortex_m", "core_radius_m")
WAKE_SIZE = len(WAKE_LAYOUT)
_W_ON, _W_GAMMA, _W_YR, _W_YL, _W_Z, _W_RC = range(WAKE_SIZE)

_TWO_PI = 2.0 * math.pi


def circulation(tanker: Tanker, wake: Wake, airspeed_m_s: float, rho: float) -> float:
    """Circulation of each trailing vortex.

    Parameters
    ----------
    tanker : Tanker
        Tanker mass [kg] and span [m].
    wake : Wake
        Wake geometry (vortex spacing as a fraction of the span).
    airspeed_m_s : float
        True airspeed V of the tanker [m/s], > 0.
    rho : float
        Air density [kg/m^3], > 0. Pass the physical (ICAO) density: the circulation carries the
        tanker's weight, so it is not meaningful for zero density.

    Returns
    -------
    float
        ``Gamma = m g0 / (rho V b0)`` [m^2/s].

    Raises
    ------
    ParameterError
        If ``airspeed_m_s`` or ``rho`` is not a positive finite number.
    """
    V = float(airspeed_m_s)
    r = float(rho)
    if not (math.isfinite(V) and V > 0.0):
        raise ParameterError(
            f"airspeed_m_s = {airspeed_m_s!r}: the wake needs a positive finite airspeed [m/s]"
        )
    if not (math.isfinite(r) and r > 0.0):
        raise ParameterError(
            f"rho = {rho!r}: the wake circulation W/(rho V b0) needs a positive finite air density "
            "[kg/m^3]; pass the ICAO density or disable the wake"
        )
    b0 = wake.vortex_spacing_over_span * tanker.span_m
    weight_n = tanker.mass_kg * G0
    return weight_n / (r * V * b0)


def wake_scalars(tanker: Tanker, wake: Wake, airspeed_m_s: float, rho: float) -> np.ndarray:
    """Pack the wake into the six floats read by :func:`wake_velocity`.

    Parameters
    ----------
    tanker : Tanker
        Tanker mass [kg] and span [m].
    wake : Wake
        Wake switch and geometry (fractions of the span; vertical offset [m], z down).
    airspeed_m_s : float
        True airspeed V [m/s], > 0.
    rho : float
        Air density [kg/m^3], > 0 (ignored when the wake is disabled).

    Returns
    -------
    numpy.ndarray
        float64, shape (6,): ``[enabled (0 or 1), Gamma [m^2/s], y_right [m], y_left [m],
        z_vortex [m], rc [m]]``, vortex positions relative to the tow point in S_p. With
        ``enabled == 0`` every other entry is zero and the wake induces no velocity.
    """
    wk = np.zeros(WAKE_SIZE, dtype=np.float64)
    if not wake.enabled:
        return wk
    span = tanker.span_m
    half_b0 = 0.5 * wake.vortex_spacing_over_span * span
    y_tow = wake.tow_point_y_over_span * span
    wk[_W_ON] = 1.0
    wk[_W_GAMMA] = circulation(tanker, wake, airspeed_m_s, rho)
    wk[_W_YR] = half_b0 - y_tow
    wk[_W_YL] = -half_b0 - y_tow
    wk[_W_Z] = wake.vertical_offset_m
    wk[_W_RC] = wake.core_radius_over_span * span
    return wk


@njit(**JIT_NO_ALLOC)
def wake_velocity(y, z, wk, at=0):
    """Air velocity induced by the vortex pair at one point (numba).

    Parameters
    ----------
    y, z : float
        Position of the point relative to the tow point along S_p y (right) and z (down) [m].
    wk : numpy.ndarray
        The six scalars of :func:`wake_scalars`, from index ``at`` on.
    at : int
        Index of the first of them in ``wk`` (the kernels pass their ``env`` array whole: a
        slice per call would cost an array view, i.e. reference counting, in the inner loop).

    Returns
    -------
    vy, vz : float
        Induced air velocity along S_p y and z [m/s]; the x component is zero.
    """
    if wk[at + _W_ON] == 0.0:
        return 0.0, 0.0
    gamma = wk[at + _W_GAMMA]
    rc2 = wk[at + _W_RC] * wk[at + _W_RC]
    dz = z - wk[at + _W_Z]
    dz2 = dz * dz
    # right (starboard) vortex
    dy = y - wk[at + _W_YR]
    k = gamma / (_TWO_PI * (dy * dy + dz2 + rc2))
    vy = k * dz
    vz = -k * dy
    # left vortex: opposite sense of rotation
    dy = y - wk[at + _W_YL]
    k = gamma / (_TWO_PI * (dy * dy + dz2 + rc2))
    vy -= k * dz
    vz += k * dy
    return vy, vz


def wake_field(y, z, tanker: Tanker, wake: Wake, airspeed_m_s: float, rho: float):
    """Induced velocity of the vortex pair on arrays of points (numpy; for plots and tests).

    Parameters
    ----------
    y, z : array_like
        Positions relative to the tow point along S_p y (right) and z (down) [m]; broadcast
        against each other.
    tanker, wake, airspeed_m_s, rho
        As for :func:`wake_scalars` (airspeed [m/s], density [kg/m^3]).

    Returns
    -------
    vy, vz : numpy.ndarray
        Induced air velocity along S_p y and z [m/s], of the broadcast shape of ``y`` and ``z``.
    """
    y, z = np.broadcast_arrays(np.asarray(y, dtype=np.float64), np.asarray(z, dtype=np.float64))
    wk = wake_scalars(tanker, wake, airspeed_m_s, rho)
    vy = np.zeros(y.shape)
    vz = np.zeros(y.shape)
    if wk[_W_ON] == 0.0:
        return vy, vz
    dz = z - wk[_W_Z]
    rc2 = wk[_W_RC] ** 2
    for y_v, sense in ((wk[_W_YR], 1.0), (wk[_W_YL], -1.0)):
        dy = y - y_v
        k = sense * wk[_W_GAMMA] / (_TWO_PI * (dy**2 + dz**2 + rc2))
        vy += k * dz
        vz -= k * dy
    return vy, vz
