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
hose kernels can add the bow wave at every hose point; :class:`BowWave` is the Python-facing
object.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize
from numba import njit

from ..errors import ParameterError

SHAPES = ("rankine", "source-line")


@njit(cache=True)
def source_velocity(px, py, pz, sx, sy, sz, q):
    """Velocity [m/s] at P induced by a point source of volume flux q [m^3/s] at S (S_p, [m])."""
    dx = px - sx
    dy = py - sy
    dz = pz - sz
    r2 = dx * dx + dy * dy + dz * dz
    c = q / (4.0 * math.pi * r2 * math.sqrt(r2))
    return c * dx, c * dy, c * dz


@njit(cache=True)
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


@dataclass(frozen=True)
class BowWave:
    """The forebody flow field of a receiver whose probe tip is at a given point.

    Parameters
    ----------
    airspeed_m_s : float
        Free-stream speed V [m/s] (the tanker's true airspeed), > 0.
    forebody_radius_m : float
        Fuselage radius R far aft of the nose [m], > 0.
    probe_offset_m : tuple of float
        Probe tip relative to the nose (forward, right, down) [m]; the tip is usually ahead of
        the nose (first component > 0).
    shape : {"rankine", "source-line"}
        Source distribution (see the module docstring).
    nose_length_m : float
        Length of the source line [m] for ``shape = "source-line"``, > 0.
    """

    airspeed_m_s: float
    forebody_radius_m: float = 0.75
    probe_offset_m: tuple = (2.5, 0.0, 0.0)
    shape: str = "rankine"
    nose_length_m: float = 2.0

    def __post_init__(self):
        for name in ("airspeed_m_s", "forebody_radius_m", "nose_length_m"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
                raise ParameterError(f"bow_wave.{name} = {v!r}: must be a finite number > 0")
        if self.shape not in SHAPES:
            raise ParameterError(f"bow_wave.shape = {self.shape!r}: must be one of {', '.join(map(repr, SHAPES))}")
        off = self.probe_offset_m
        if not (isinstance(off, (tuple, list)) and len(off) == 3 and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in off)):
            raise ParameterError(f"bow_wave.probe_offset_m = {off!r}: must be 3 finite numbers [m]")
        object.__setattr__(self, "probe_offset_m", tuple(float(v) for v in off))

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
