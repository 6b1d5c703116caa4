"""The receiver's bow wave: steady potential flow of its forebody, moving with the probe.

The receiver flies with the tanker, so in the tanker frame S_p (x forward, y right, z down) its
forebody sits still in the free stream ``[-V, 0, 0]`` and displaces the air ahead of it. The
perturbation velocity it adds to the air at a point P is that of a source distribution on the
fuselage axis (the axis points forward, along +x):

* ``"rankine"`` (default): a point source of volume flux ``Q = pi R^2 V`` [m^3/s] in the stream
  ``V``. Its dividing stream surface is the Rankine half-body: radius ``R`` far aft, nose (the
  stagnation point) a distance ``R/2`` ahead of the source. In spherical coordinates about the
  source with ``theta`` measured from the forward axis the surface is ``r = R / (2 cos(theta/2))``,
  i.e. ``rho = R sin(theta/2)`` from the axis (Stokes stream function
  ``psi = -V r^2 sin^2(theta)/2 - Q cos(theta)/(4 pi)``, equal to ``-Q/(4 pi)`` on the surface).
* ``"source-line"``: the same flux spread uniformly over a segment of length ``nose_length_m``
  along the axis, aft of the nose: a blunter-shouldered, more slender nose for the same far-aft
  radius (the line-singularity forebodies of Dai, Wei & Quan, Chinese J. Aeronautics 2016, in
  their simplest form). Its velocity has the closed form of a uniform line source.

Both fields are irrotational and divergence-free away from the singularities, and decay like
``Q / (4 pi r^2)`` far away. The source position follows from the probe tip: the tip is
``probe_offset_m`` = (ahead of the nose, right, down) [m] from the nose, and the nose is the
stagnation point of the chosen field.

The functions :func:`source_velocity` and :func:`line_source_velocity` are compiled (numba) so the
hose kernels can add the bow wave at every hose point; :class:`BowWaveField` is the Python-facing
object (its geometry is the ``[bow_wave]`` section, :class:`hosedrogue.spec.sections.BowWave`).
"""

from __future__ import annotations

import math
import numpy as np
import scipy.optimize
from numba import njit

from ..jit import JIT_NO_ALLOC

from ..errors import ParameterError
from ..spec.sections import BOW_WAVE_SHAPES as SHAPES  # noqa: F401 - the one list of shapes
from ..spec.sections import BowWave as _Geometry


@njit(**JIT_NO_ALLOC)
def source_velocity(px, py, pz, sx, sy, sz, q):
    """Velocity [m/s] at P induced by a point source of volume flux q [m^3/s] at S (S_p, [m])."""
    dx = px - sx
    dy = py - sy
    dz = pz - sz
    r2 = dx * dx + dy * dy + dz * dz
    c = q / (4.0 * math.pi * r2 * math.sqrt(r2))
    return c * dx, c * dy, c * dz


@njit(**JIT_NO_ALLOC)
def line_source_velocity(px, py, pz, sx, sy, sz, length, q):
    """Velocity [m/s] at P of a uniform line source of total flux q [m^3/s] on the segment from
    S (its forward end) to S - length * x_hat (aft along the axis), [m] in S_p.

    With xi the axial coordinate of P from the forward end, rho its distance from the axis,
    ``r_f`` and ``r_a`` its distances to the forward and aft ends and sigma = q / length:
    ``v_xi = sigma/(4 pi) (1/r_f - 1/r_a)`` and
    ``v_rho = sigma/(4 pi rho) ((xi + length)/r_a - xi/r_f)``.
    """
    sigma = q / length
    xi = px - sx
    dy = py - sy
    dz = pz - sz
    rho = math.sqrt(dy * dy + dz * dz)
    ra = math.sqrt(xi * xi + rho * rho)
    xb = xi + length
    rb = math.sqrt(xb * xb + rho * rho)
    c = sigma / (4.0 * math.pi)
    vx = c * (1.0 / ra - 1.0 / rb)
    if rho == 0.0:
        return vx, 0.0, 0.0
    vr = c / rho * (xb / rb - xi / ra)
    return vx, vr * dy / rho, vr * dz / rho


class BowWaveField:
    """The forebody flow field of a receiver whose probe tip is at a given point.

    Parameters
    ----------
    airspeed_m_s : float
        Free-stream speed V [m/s] (the tanker's true airspeed), > 0.
    forebody_radius_m, probe_offset_m, shape, nose_length_m
        The forebody's geometry, validated as the ``[bow_wave]`` section
        (:class:`hosedrogue.spec.sections.BowWave`): fuselage radius R far aft of the nose [m]; probe
        tip relative to the nose (forward, right, down) [m]; ``"rankine"`` or ``"source-line"``
        (see the module docstring); length of the source line [m].
    """

    def __init__(self, airspeed_m_s: float, forebody_radius_m: float = 0.75, probe_offset_m=(2.5, 0.0, 0.0),
                 shape: str = "rankine", nose_length_m: float = 2.0):
        v = airspeed_m_s
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
            raise ParameterError(f"flight.airspeed_m_s = {v!r}: the bow wave needs a finite airspeed > 0 m/s")
        self.airspeed_m_s = float(v)
        self.geometry = _Geometry(enabled=True, forebody_radius_m=forebody_radius_m, probe_offset_m=probe_offset_m,
                                shape=shape, nose_length_m=nose_length_m)

    @classmethod
    def of(cls, section: _Geometry, airspeed_m_s: float) -> "BowWaveField":
        """The field of a ``[bow_wave]`` section in the free stream ``airspeed_m_s`` [m/s].

        Parameters
        ----------
        section : hosedrogue.spec.sections.BowWave
            The forebody's geometry.
        airspeed_m_s : float
            Free-stream speed [m/s].

        Returns
        -------
        BowWaveField
        """
        return cls(airspeed_m_s, section.forebody_radius_m, section.probe_offset_m, section.shape,
                   section.nose_length_m)

    @property
    def forebody_radius_m(self) -> float:
        """Fuselage radius R [m]."""
        return self.geometry.forebody_radius_m

    @property
    def probe_offset_m(self) -> tuple:
        """Probe tip relative to the nose (forward, right, down) [m]."""
        return self.geometry.probe_offset_m

    @property
    def shape(self) -> str:
        """``"rankine"`` or ``"source-line"``."""
        return self.geometry.shape

    @property
    def nose_length_m(self) -> float:
        """Length of the source line [m]."""
        return self.geometry.nose_length_m

    @property
    def flux_m3_s(self) -> float:
        """Source volume flux Q = pi R^2 V [m^3/s]."""
        return math.pi * self.forebody_radius_m**2 * self.airspeed_m_s

    @property
    def nose_ahead_of_source_m(self) -> float:
        """Distance [m] from the source (the forward end of the line) ahead to the nose."""
        if self.shape == "rankine":
            return 0.5 * self.forebody_radius_m  # stagnation: V = Q / (4 pi d^2), Q = pi R^2 V
        L, q, V = self.nose_length_m, self.flux_m3_s, self.airspeed_m_s

        def axial(d):  # induced axial speed at distance d ahead of the line's forward end
            return q / (4.0 * math.pi * L) * (1.0 / d - 1.0 / (d + L)) - V

        hi = max(self.forebody_radius_m, 1.0)
        while axial(hi) > 0.0:
            hi *= 2.0
        return scipy.optimize.brentq(axial, 1e-12 * hi, hi, xtol=1e-15, rtol=1e-15)

    def source_position_m(self, probe_tip_m) -> np.ndarray:
        """Source (or the line's forward end) in S_p [m] for a probe tip at ``probe_tip_m``."""
        tip = np.asarray(probe_tip_m, dtype=np.float64)
        nose = tip - np.asarray(self.probe_offset_m)
        return nose - np.array([self.nose_ahead_of_source_m, 0.0, 0.0])

    def velocity(self, points_m, probe_tip_m) -> np.ndarray:
        """Perturbation velocity [m/s] (..., 3) at points (..., 3) [m] in S_p (add to the air)."""
        s = self.source_position_m(probe_tip_m)
        pts = np.asarray(points_m, dtype=np.float64)
        flat = pts.reshape(-1, 3)
        out = np.empty_like(flat)
        q = self.flux_m3_s
        for i, (x, y, z) in enumerate(flat):
            if self.shape == "rankine":
                out[i] = source_velocity(x, y, z, s[0], s[1], s[2], q)
            else:
                out[i] = line_source_velocity(x, y, z, s[0], s[1], s[2], self.nose_length_m, q)
        return out.reshape(pts.shape)

    def rankine_surface_m(self, theta_rad, probe_tip_m, phi_rad=0.0) -> np.ndarray:
        """Points on the Rankine half-body's surface [m] (S_p) at polar angle(s) theta from the
        forward axis (0 < theta < pi) and azimuth phi about it."""
        theta = np.asarray(theta_rad, dtype=np.float64)
        r = self.forebody_radius_m / (2.0 * np.cos(theta / 2.0))
        s = self.source_position_m(probe_tip_m)
        rho = r * np.sin(theta)
        return np.stack([s[0] + r * np.cos(theta), s[1] + rho * np.cos(phi_rad), s[2] + rho * np.sin(phi_rad)],
                        axis=-1)


#: Shape codes of the compiled field (:func:`bow_wave_velocity`): none, point source, line source.
SHAPE_OFF, SHAPE_RANKINE, SHAPE_LINE = 0, 1, 2
#: Inside this distance of the source [m] (1 mm, deep inside the forebody, never reached by the
#: hose) the field is taken as zero instead of the singularity.
CORE_M = 1e-3


@njit(**JIT_NO_ALLOC)
def bow_wave_velocity(px, py, pz, shape, sx, sy, sz, q, length):
    """Bow-wave perturbation velocity [m/s] at P of the source (``shape`` SHAPE_RANKINE) or the
    line's forward end (SHAPE_LINE, ``length`` [m]) at S, flux q [m^3/s]; zero for SHAPE_OFF and
    within :data:`CORE_M` of S."""
    if shape == SHAPE_OFF:
        return 0.0, 0.0, 0.0
    dx = px - sx
    dy = py - sy
    dz = pz - sz
    if dx * dx + dy * dy + dz * dz < CORE_M * CORE_M:
        return 0.0, 0.0, 0.0
    if shape == SHAPE_RANKINE:
        return source_velocity(px, py, pz, sx, sy, sz, q)
    return line_source_velocity(px, py, pz, sx, sy, sz, length, q)
