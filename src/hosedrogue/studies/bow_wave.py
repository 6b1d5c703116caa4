"""The bow-wave study: the receiver's forebody flow around the probe, the drogue's steady
displacement against the probe distance, and the forebody radius that keeps the displacement at a
distance below a level (docs/engagement.md, "Bow wave").

The field is that of :mod:`hosedrogue.environment.bow_wave` and the displacement that of
:func:`hosedrogue.engagement.bow_wave.bow_wave_displacement` (the balance position with the probe
held still on the drogue's axis, minus the one without). Example::

    from hosedrogue.studies.bow_wave import bow_wave_study, radius_for_displacement

    bw = bow_wave_study("moderate")
    print(bw.near_m, bw.far_m)                            # [m] at NEAR_M and FAR_M
    print(radius_for_displacement(1e-3, 10.0))            # [m]: 1 mm at 10 m
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

__all__ = ["BowWaveStudy", "bow_wave_study", "bow_wave_field", "radius_for_displacement", "DISTANCES_M", "RADII_M",
           "NEAR_M", "FAR_M", "LEVEL_M", "FIELD_X_M", "FIELD_Z_M"]

#: Probe distances aft of the drogue of the displacement curve [m]: 16 points evenly spaced in log
#: from 0.3 m (just before contact) to 20 m (deep in the 1/r^2 tail).
DISTANCES_M = tuple(float(d) for d in np.geomspace(0.3, 20.0, 16))

#: Forebody radii of the far-displacement table [m]: 0.3 m to 1 m around the shipped 0.75 m; the
#: radius of the 1 mm requirement at 10 m (about 0.46 m) lies inside, so they bracket its search.
RADII_M = (0.3, 0.45, 0.6, 0.75, 1.0)

#: The near and far probe distances read out [m], and the far displacement's requirement [m].
NEAR_M, FAR_M, LEVEL_M = 0.5, 10.0, 1e-3

#: Field grid forward of the probe tip [m] (start, end, points): from 7 m aft, past the nose 2.5 m
#: aft of the tip and the forebody's widening, to 3 m ahead, where the drogue is met; 0.1 m spacing.
FIELD_X_M = (-7.0, 3.0, 101)

#: Field grid down from the probe tip [m] (start, end, points): +-2.5 m, over three forebody radii
#: (0.75 m) either side, at 0.1 m spacing.
FIELD_Z_M = (-2.5, 2.5, 51)

#: Polar angles of the Rankine half-body's outline about its source, from the forward axis [rad]
#: (start, end, points): inside the surface formula's open range (0, pi), from 1 mrad (the nose,
#: 0.4 mm off the axis) to 0.12 rad short of the downstream axis, where the surface is 9.1 m aft of
#: the tip (past the field grid's aft edge) and within 0.2 % of the far radius R.
OUTLINE_THETA_RAD = (1e-3, np.pi - 0.12, 160)

#: Tolerance of :func:`radius_for_displacement` on the radius [m] (0.1 mm: far below the table's steps).
RADIUS_XTOL_M = 1e-4


@dataclass(frozen=True)
class BowWaveStudy:
    """The bow-wave field around the probe and the drogue's steady displacement."""

    x_m: np.ndarray  #: (nx,) field grid, forward of the probe tip [m]
    z_m: np.ndarray  #: (nz,) field grid, down [m]
    velocity_m_s: np.ndarray  #: (nz, nx, 3) perturbation velocity [m/s], NaN inside the forebody
    outline_m: np.ndarray  #: (k, 2) forebody outline (x, z) [m] (None for the source line)
    stagnation_m: tuple  #: nose (x, z) [m]
    source_ahead_of_tip_m: float  #: distance from the probe tip aft to the source [m]
    distances_m: np.ndarray  #: (m,) probe tip aft of the drogue [m]
    displacement_m: np.ndarray  #: (m, 3) steady displacement (forward, right, down) [m]
    radii_m: np.ndarray  #: (k,) forebody radii [m]
    radii_displacement_m: np.ndarray  #: (k, 2) total displacement at NEAR_M and FAR_M [m]
    radius_limit_m: float  #: forebody radius whose displacement at FAR_M is LEVEL_M [m]
    radius_m: float  #: the scenario's forebody radius [m]
    near_m: float  #: total displacement at NEAR_M with the scenario's forebody [m]
    far_m: float  #: total displacement at FAR_M with it [m]

    def figures(self) -> dict:
        """The study's figure: the field around the probe, the displacement against the distance
        and against the forebody radius (:func:`hosedrogue.studies.bow_wave_figures.plot_bow_wave`).

        Returns
        -------
        dict
            ``{"bow_wave": matplotlib.figure.Figure}``.
        """
        from .bow_wave_figures import plot_bow_wave

        return {"bow_wave": plot_bow_wave(
            self.x_m, self.z_m, self.velocity_m_s, self.distances_m, self.displacement_m, outline_m=self.outline_m,
            stagnation_m=self.stagnation_m, source_distance_m=self.distances_m + self.source_ahead_of_tip_m,
            level_m=LEVEL_M, radii_m=self.radii_m, far_displacement_m=self.radii_displacement_m[:, 1],
            far_distance_m=FAR_M, radius_limit_m=self.radius_limit_m)}


def bow_wave_field(scenario):
    """The bow-wave field in the x-z plane through the probe tip (tip at the origin) on the grid
    :data:`FIELD_X_M` x :data:`FIELD_Z_M`, blanked (NaN) inside the forebody.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        An engagement scenario with a ``[bow_wave]`` section; its airspeed [m/s].

    Returns
    -------
    tuple
        ``x_m`` (nx,) [m], ``z_m`` (nz,) [m], ``velocity_m_s`` (nz, nx, 3) [m/s], the outline
        (k, 2) [m] (None for the source line), the nose (x, z) [m] and the source's distance aft
        of the tip [m].
    """
    from ..environment.bow_wave import BowWaveField

    bw = scenario.engagement.bow_wave
    airspeed = scenario.params.flight.airspeed_m_s
    field = BowWaveField.of(bw, airspeed)
    x, z = np.linspace(*FIELD_X_M), np.linspace(*FIELD_Z_M)
    tip = np.zeros(3)
    pts = np.stack(np.meshgrid(x, [0.0], z, indexing="xy"), axis=-1)[0].transpose(1, 0, 2)
    vel = field.velocity(pts, tip)
    src = field.source_position_m(tip)
    if bw.shape == "rankine":
        rel = pts - src
        r = np.linalg.norm(rel, axis=-1)
        # the half-body's surface r = R / (2 cos(theta / 2)); the guards keep the axis points finite
        theta = np.arccos(np.clip(rel[..., 0] / np.maximum(r, 1e-12), -1.0, 1.0))
        inside = r < bw.forebody_radius_m / (2.0 * np.maximum(np.cos(theta / 2.0), 1e-9))
        theta_s = np.linspace(*OUTLINE_THETA_RAD)
        below, above = (field.rankine_surface_m(theta_s, tip, phi_rad=phi) for phi in (np.pi / 2, -np.pi / 2))
        outline = np.vstack([below[::-1][:, [0, 2]], above[:, [0, 2]]])  # the x-z plane's two halves
    else:
        inside = np.linalg.norm(vel, axis=-1) > airspeed  # the source line's body: faster than the stream
        outline = None
    vel[inside] = np.nan
    nose = -np.asarray(bw.probe_offset_m)
    return x, z, vel, outline, (float(nose[0]), float(nose[2])), float(-src[0])


def _total(scenario, radius_m: float, distances_m) -> np.ndarray:
    """Total steady displacement [m] at the distances [m] with the forebody radius [m]."""
    from ..engagement.bow_wave import bow_wave_displacement

    bw = dataclasses.replace(scenario.engagement.bow_wave, forebody_radius_m=radius_m)
    return np.linalg.norm(bow_wave_displacement(scenario.params, bw, distances_m), axis=1)


def radius_for_displacement(displacement_m: float = LEVEL_M, distance_m: float = FAR_M, level: str = "moderate",
                            bounds_m=(RADII_M[0], RADII_M[-1])) -> float:
    """The forebody radius whose steady displacement of the drogue at ``distance_m`` is
    ``displacement_m`` (the displacement grows with the radius, about as R^2).

    Parameters
    ----------
    displacement_m : float
        Total displacement [m].
    distance_m : float
        Probe tip distance aft of the drogue [m].
    level : str
        Which ``approach-LEVEL`` scenario (model, flight condition, forebody shape).
    bounds_m : (float, float)
        Radii bracketing the answer [m].

    Returns
    -------
    float
        Forebody radius [m], to :data:`RADIUS_XTOL_M`.

    Raises
    ------
    ParameterError
        When the displacement at ``distance_m`` does not cross ``displacement_m`` between the bounds.
    """
    from ..scenarios import load_scenario

    return _radius_for(load_scenario(f"approach-{level}"), displacement_m, distance_m, bounds_m)


def _radius_for(sc, displacement_m: float, distance_m: float, bounds_m) -> float:
    import scipy.optimize

    from ..errors import ParameterError

    lo, hi = (float(b) for b in bounds_m)

    def excess(radius):
        return _total(sc, radius, [distance_m])[0] - displacement_m

    try:
        return float(scipy.optimize.brentq(excess, lo, hi, xtol=RADIUS_XTOL_M))
    except ValueError:  # brentq's "f(a) and f(b) must have different signs"
        raise ParameterError(f"bounds_m = {tuple(bounds_m)!r}: the displacement at {distance_m:g} m does not cross "
                             f"{displacement_m:g} m between these forebody radii") from None


def bow_wave_study(level: str = "moderate", scenario=None) -> BowWaveStudy:
    """The field and the steady displacement of the ``approach-LEVEL`` scenario's bow wave (its
    model and flight condition, wake on), and the far displacement against the forebody radius.

    Parameters
    ----------
    level : str
        Which approach scenario (they share the bow wave and the model).
    scenario : str, Path or hosedrogue.scenarios.Scenario, optional
        Instead, an engagement scenario of one's own (a name, a TOML file or a Scenario): its
        model, flight condition and ``[bow_wave]`` (on, whatever its ``enabled``).

    Returns
    -------
    BowWaveStudy
    """
    from ..engagement.bow_wave import bow_wave_displacement
    from ..scenarios import Scenario, load_scenario

    if scenario is None:
        scenario = f"approach-{level}"
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    sc.require_model("engagement", "scenario", "the bow-wave study takes an engagement's [bow_wave] (a scenario "
                     "with [probe], e.g. approach-moderate)")
    bw = dataclasses.replace(sc.engagement.bow_wave, enabled=True)
    sc = dataclasses.replace(sc, engagement=dataclasses.replace(sc.engagement, bow_wave=bw))
    x, z, vel, outline, stagnation, source_aft = bow_wave_field(sc)
    d = np.asarray(DISTANCES_M)
    disp = bow_wave_displacement(sc.params, bw, d)
    radii = np.asarray(RADII_M)
    table = np.array([_total(sc, R, [NEAR_M, FAR_M]) for R in radii])
    limit = _radius_for(sc, LEVEL_M, FAR_M, (radii[0], radii[-1]))
    near, far = _total(sc, bw.forebody_radius_m, [NEAR_M, FAR_M])
    return BowWaveStudy(x, z, vel, outline, stagnation, source_aft, d, disp, radii, table, float(limit),
                        float(bw.forebody_radius_m), float(near), float(far))
