"""Step-response figures of merit (paper Table 3) from a sampled response.

Definitions (docs/model.md §6), for a response y(t) that moves from its initial value y0 to
its final value yf, with amplitude delta = yf - y0:

- rise time: time for y to go from y0 + 10 % delta to y0 + 90 % delta, each instant taken at
  the first crossing of the level and located by linear interpolation between samples;
- settling time: time from the start of the record t[0] (the step instant) until y last enters
  the band |y - yf| <= 2 % |delta| for good, the entry instant located by linear interpolation;
- overshoot: largest excursion beyond yf in the direction of the step, in percent of |delta|
  (0 if the response never passes yf).

Interpolated crossings make the figures independent of the time grid to first order: a grid
step h gives errors O(h^2) in the crossing instants instead of O(h) (the sample-index approach
of `control.step_info`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import control

from ..analysis.reduction import require_siso
from ..analysis.responses import step_outputs

__all__ = ["StepMetrics", "StepResponse", "step_metrics", "closed_loop_step"]


@dataclass(frozen=True)
class StepMetrics:
    """Figures of merit of a step response.

    Attributes
    ----------
    rise_time_s : float
        10-90 % rise time [s]; NaN if the response never reaches 90 %.
    settling_time_s : float
        2 % settling time [s] measured from the step instant t[0]; NaN if the last sample is
        outside the band (not settled within the record).
    overshoot_pct : float
        Peak overshoot [% of the step amplitude], >= 0.
    final_value : float
        Final value yf used for the figures, in the units of the response.
    """

    rise_time_s: float
    settling_time_s: float
    overshoot_pct: float
    final_value: float


def _first_crossing(t: np.ndarray, s: np.ndarray, level: float) -> float:
    """First instant where the normalized response s reaches `level`, interpolated."""
    above = np.nonzero(s >= level)[0]
    if above.size == 0:
        return float("nan")
    i = above[0]
    if i == 0:
        return float(t[0])
    frac = (level - s[i - 1]) / (s[i] - s[i - 1])
    return float(t[i - 1] + frac * (t[i] - t[i - 1]))


def step_metrics(
    t,
    y,
    final_value: float | None = None,
    *,
    initial_value: float | None = None,
    settling_band: float = 0.02,
    rise_limits: tuple[float, float] = (0.1, 0.9),
) -> StepMetrics:
    """Rise time, settling time and overshoot of a sampled step response.

    Parameters
    ----------
    t : array_like, shape (N,)
        Strictly increasing sample times [s]; t[0] is the step instant.
    y : array_like, shape (N,)
        Response samples (any unit, e.g. drogue offset [m]).
    final_value : float, optional
        Final value yf. Default: the last sample y[-1] (the record must then be long enough
        for the response to have settled).
    initial_value : float, optional
        Initial value y0. Default: the first sample y[0].
    settling_band : float, optional
        Half-width of the settling band as a fraction of |yf - y0| (default 0.02, the
        paper's 2 %).
    rise_limits : (float, float), optional
        Lower and upper rise levels as fractions of the amplitude (default 10 % and 90 %).

    Returns
    -------
    StepMetrics

    Raises
    ------
    ValueError
        If the arrays have different lengths or fewer than two samples, `t` is not strictly
        increasing, the step amplitude yf - y0 is zero, or the band/limits are out of range.
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.ndim != 1 or y.ndim != 1 or t.size != y.size:
        raise ValueError(f"t and y must be 1-D of equal length, got shapes {t.shape} and {y.shape}")
    if t.size < 2:
        raise ValueError(f"need at least two samples, got {t.size}")
    if np.any(np.diff(t) <= 0.0):
        raise ValueError("t must be strictly increasing")
    if not 0.0 < settling_band < 1.0:
        raise ValueError(f"settling_band must be in (0, 1), got {settling_band}")
    lo, hi = rise_limits
    if not 0.0 <= lo < hi <= 1.0:
        raise ValueError(f"rise_limits must satisfy 0 <= low < high <= 1, got {rise_limits}")

    y0 = float(y[0]) if initial_value is None else float(initial_value)
    yf = float(y[-1]) if final_value is None else float(final_value)
    delta = yf - y0
    if delta == 0.0:
        raise ValueError(f"step amplitude is zero (initial value = final value = {yf})")

    # Normalized response: 0 at the initial value, 1 at the final value, whatever the sign.
    s = (y - y0) / delta

    rise = _first_crossing(t, s, hi) - _first_crossing(t, s, lo)

    outside = np.nonzero(np.abs(s - 1.0) > settling_band)[0]
    if outside.size == 0:
        settling = 0.0
    elif outside[-1] == s.size - 1:
        settling = float("nan")
    else:
        j = outside[-1]
        edge = 1.0 + settling_band * np.sign(s[j] - 1.0)
        frac = (edge - s[j]) / (s[j + 1] - s[j])
        settling = float(t[j] + frac * (t[j + 1] - t[j]) - t[0])

    overshoot = max(0.0, float(np.max(s)) - 1.0) * 100.0
    return StepMetrics(
        rise_time_s=float(rise),
        settling_time_s=settling,
        overshoot_pct=overshoot,
        final_value=yf,
    )


@dataclass(frozen=True)
class StepResponse:
    """Unit-step response of a unity-feedback loop.

    Attributes
    ----------
    t_s : numpy.ndarray
        Sample times [s].
    y : numpy.ndarray
        Plant output (drogue offset [m] per metre of reference step).
    u : numpy.ndarray
        Controller output (force [N] per metre of reference step).
    metrics : StepMetrics
        Figures of merit of `y`, final value = the loop's DC gain (1 with integral action).
    """

    t_s: np.ndarray
    y: np.ndarray
    u: np.ndarray
    metrics: StepMetrics


def closed_loop_step(plant_siso, controller_tf, t) -> StepResponse:
    """Unit reference step of a SISO plant under unity negative feedback.

    The loop is u = C(s) (r - y), y = G(s) u, with r a unit step at t[0].

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        G(s), force [N] -> offset [m].
    controller_tf : control.TransferFunction or control.StateSpace
        C(s) acting on the error r - y [m], output force [N] (positive form: the negative
        sign is the summing junction's, unlike `LinearController`).
    t : array_like
        Sample times [s], starting at 0 and evenly spaced.

    Returns
    -------
    StepResponse
        Output and control force, and the metrics with the final value set to the
        closed-loop DC gain r -> y (exact, independent of the record length).

    Raises
    ------
    ValueError
        If plant or controller is not SISO, or the closed loop is unstable.
    """
    for name, sys in (("plant_siso", plant_siso), ("controller_tf", controller_tf)):
        require_siso(name, sys)
    g = control.ss(plant_siso)
    c = control.ss(controller_tf)
    # Outputs [y, u] of the loop r -> (e = r - y) -> C -> u -> G -> y.
    open_loop = control.series(c, g)
    t_ry = control.feedback(open_loop, 1)
    t_ru = control.feedback(c, g)
    if np.any(np.real(t_ry.poles()) >= 0.0):
        raise ValueError(f"closed loop is unstable: poles {t_ry.poles()}")
    t = np.asarray(t, dtype=float)
    y = step_outputs(t_ry, t)[0]
    u = step_outputs(t_ru, t)[0]
    yf = float(np.real(control.dcgain(t_ry)))
    return StepResponse(t_s=t, y=np.asarray(y), u=np.asarray(u), metrics=step_metrics(t, y, final_value=yf))
