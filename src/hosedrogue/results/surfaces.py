"""The drogue's control surfaces in a run's result (docs/model.md, "Actuated drogue"): their
series (:class:`SurfaceSeries`), their statistics (:func:`surface_statistics`, columns
:data:`SURFACE_STATISTICS`), and the mix-in that joins both to a run's (:class:`WithSurfaces`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .statistics import in_window

#: (column, unit) of a drogue actuator's statistics (:func:`surface_statistics`), in column order.
SURFACE_STATISTICS = (("peak_deflection_deg", "deg"), ("peak_deflection_rate_deg_s", "deg/s"),
                      ("deflection_saturated_frac", "1"), ("rate_saturated_frac", "1"))
#: A surface counts as at its limit within this fraction of it [-] (the second-order servo's soft
#: stop approaches the deflection limit exponentially, so "at the limit" needs a margin).
SATURATION_MARGIN = 0.01


def surface_statistics(t_s: np.ndarray, deflection_rad: np.ndarray, rate_rad_s: np.ndarray,
                       window_s: tuple[float, float], max_deflection_rad: float, max_rate_rad_s: float) -> dict:
    """A drogue actuator's statistics inside a window (:data:`SURFACE_STATISTICS`): the largest
    deflection [deg] and deflection rate [deg/s] of any surface, and the fractions of the window's
    samples in which some surface is within :data:`SATURATION_MARGIN` of its deflection limit
    (saturated in authority) or of its rate limit (saturated in rate) [-].

    Parameters
    ----------
    t_s : array (N,)
        Sample times [s].
    deflection_rad, rate_rad_s : array (N, n_s)
        Each surface's deflection [rad] and deflection rate [rad/s].
    window_s : (float, float)
        Statistics window [s] (:func:`in_window`).
    max_deflection_rad, max_rate_rad_s : float
        The deflection [rad] and rate [rad/s] limits.

    Returns
    -------
    dict
        Column -> value; NaN where the window holds no sample.
    """
    inside = in_window(t_s, window_s)
    d = np.abs(np.asarray(deflection_rad)[inside])
    r = np.abs(np.asarray(rate_rad_s)[inside])
    keep = 1.0 - SATURATION_MARGIN
    if not d.size:
        return {name: math.nan for name, _ in SURFACE_STATISTICS}
    return {"peak_deflection_deg": math.degrees(float(d.max())),
            "peak_deflection_rate_deg_s": math.degrees(float(r.max())),
            "deflection_saturated_frac": float(np.mean(np.any(d >= keep * max_deflection_rad, axis=1))),
            "rate_saturated_frac": float(np.mean(np.any(r >= keep * max_rate_rad_s, axis=1)))}


@dataclass(frozen=True)
class SurfaceSeries:
    """The drogue's control surfaces over a run (docs/model.md, "Actuated drogue")."""

    deflection_rad: np.ndarray  #: (N, n_s) each surface's deflection [rad]
    rate_rad_s: np.ndarray  #: (N, n_s) each surface's deflection rate [rad/s]
    q_pa: np.ndarray  #: (N,) dynamic pressure of the air at the drogue [Pa]
    max_deflection_rad: float  #: the deflection limit [rad]
    max_rate_rad_s: float  #: the rate limit [rad/s]

    def columns(self) -> dict[str, np.ndarray]:
        """``deflection_k_deg`` and ``deflection_rate_k_deg_s`` of each surface k = 1..n_s, then
        ``drogue_q_pa``."""
        d, r = np.degrees(self.deflection_rad), np.degrees(self.rate_rad_s)
        cols = {f"deflection_{k + 1}_deg": d[:, k] for k in range(d.shape[1])}
        cols.update({f"deflection_rate_{k + 1}_deg_s": r[:, k] for k in range(r.shape[1])})
        cols["drogue_q_pa"] = self.q_pa
        return cols


@dataclass(frozen=True, kw_only=True)
class WithSurfaces:
    """A run's result whose drogue may steer itself with control surfaces (``surfaces``): their
    columns after the run's, their statistics with the run's, a line in the headline. Mixed into
    :class:`hosedrogue.results.run.SimulationResult` and :class:`~hosedrogue.results.run.EngagementResult`."""

    surfaces: SurfaceSeries | None = None  #: the control surfaces' series (None: the ideal force)

    def columns(self) -> dict[str, np.ndarray]:
        """The run's columns, then the surfaces' (:meth:`SurfaceSeries.columns`)."""
        cols = super().columns()
        if self.surfaces is not None:
            cols.update(self.surfaces.columns())
        return cols

    def statistics(self, capture_radii_m=None) -> dict[str, float]:
        """The run's window statistics and the surfaces' (:meth:`surface_statistics`)."""
        return {**super().statistics(capture_radii_m), **self.surface_statistics()}

    def surface_statistics(self, window_s: tuple | None = None) -> dict[str, float]:
        """The surfaces' statistics (:func:`surface_statistics`; empty with the ideal force) over
        ``window_s`` [s] (default the run's statistics window), ended at contact in an engagement
        (after it the controller is off and the surfaces only return to neutral).

        Parameters
        ----------
        window_s : (float, float), optional
            Window [start, end) [s].

        Returns
        -------
        dict
        """
        if self.surfaces is None:
            return {}
        start, end = self.statistics_window_s if window_s is None else window_s
        contact = (getattr(self, "outcome", None) or {}).get("contact_time_s")
        end = end if contact is None else min(end, float(contact))
        s = self.surfaces
        return surface_statistics(self.t_s, s.deflection_rad, s.rate_rad_s, (start, end), s.max_deflection_rad,
                                  s.max_rate_rad_s)

    def headline(self) -> str:
        """The run's headline, then the surfaces' largest deflection [deg] and rate [deg/s] and the
        time at their limits [%]."""
        text = super().headline()
        if self.surfaces is not None:
            st = self.surface_statistics()
            text += (f"\ncontrol surfaces: largest deflection {st['peak_deflection_deg']:.3g} deg, rate "
                     f"{st['peak_deflection_rate_deg_s']:.3g} deg/s; at the deflection limit "
                     f"{100 * st['deflection_saturated_frac']:.3g} % and at the rate limit "
                     f"{100 * st['rate_saturated_frac']:.3g} % of the window")
        return text


def surface_fields(deflection_rad: np.ndarray, rate_rad_s: np.ndarray, q_pa: np.ndarray, section) -> dict:
    """A drogue actuator's result field (keyword argument of the results, :class:`WithSurfaces`).

    Parameters
    ----------
    deflection_rad, rate_rad_s : array (N, n_s)
        Each surface's deflection [rad] and deflection rate [rad/s] at the output times.
    q_pa : array (N,)
        Dynamic pressure at the drogue [Pa].
    section : hosedrogue.spec.sections.DrogueActuator
        The surfaces (their deflection [deg] and rate [deg/s] limits).

    Returns
    -------
    dict
        ``{"surfaces": SurfaceSeries}``.
    """
    return {"surfaces": SurfaceSeries(np.ascontiguousarray(deflection_rad), np.ascontiguousarray(rate_rad_s),
                                      np.ascontiguousarray(q_pa), math.radians(section.max_deflection_deg),
                                      math.radians(section.max_rate_deg_s))}
