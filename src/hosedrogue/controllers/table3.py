"""Closed-loop step responses of the paper's controllers (paper Table 3, Figs. 10 and 11).

Designs (`CONTROLLERS`):

* ``"PID"`` - the paper's gains (Eq. 33), unity feedback per channel;
* ``"LQR"`` - the paper's LQR read on the balanced states of each channel, reference through a
  static prefilter (:mod:`.lqr_balanced`); the reading that reproduces Table 3's lateral row;
* ``"LQR-integral"`` - the integral-action reading (Eq. 34), reference into the integrator
  (:mod:`.lqr`); a sensitivity.

Design plants (`PLANTS`): ``"paper"``, the paper's Table 2 2nd-order models; ``"model"``, this
project's linearization reduced to 2nd order by balanced truncation. A design can be evaluated on
its design model or on a higher-order model of the same plant (Fig. 11): ``evaluate_on`` = 2, 6
or ``"full"`` (the paper publishes 2nd and 6th order models only).

Every step is a unit reference step [m] of one channel; the figures of merit use the closed
loop's exact DC gain as final value (1 on the design model).
"""

from __future__ import annotations

import numpy as np
import control

from ..analysis.linearize import LinearModel
from ..analysis.reduction import split_channels
from ..analysis.responses import step_outputs
from ..spec.paper import CHANNELS, TABLE3, table2_transfer_function
from .design import DESIGN_ORDER, reduced_channels
from .lqr import LQRDesign, lqr_integral_design, lqr_tracking_closed_loop, two_channel_plant
from .lqr_balanced import BalancedLQRDesign, lqr_balanced_design, lqr_balanced_reference_loop
from .pid import PAPER_PID
from .stepinfo import StepMetrics, StepResponse, closed_loop_step, step_metrics

__all__ = ["CONTROLLERS", "PLANTS", "time_grid_for", "channel_models", "pid_steps", "lqr_steps",
           "step_responses", "steps_on", "table3", "table3_rows"]

CONTROLLERS = ("PID", "LQR", "LQR-integral")
PLANTS = ("paper", "model")


def time_grid_for(poles, length_factor: float = 1.0) -> np.ndarray:
    """Time grid [s] that resolves and settles a closed loop with the given poles [rad/s].

    Length 10 / |Re p|_min (10 time constants of the slowest pole: a residual below 5e-5 of the
    step, far inside the 2 % band), at least 5 s; step 0.1 / |p|_max (10 samples per time
    constant of the fastest pole; crossings are interpolated, so their error is ~1e-3 of that
    time constant), at most 1 ms; at most 100 000 samples (the step grows for very stiff loops).

    Parameters
    ----------
    poles : array_like
        Closed-loop poles [rad/s], all with negative real part.
    length_factor : float, optional
        Multiplies the length [-] (e.g. 3 when a higher-order plant adds slower tails).

    Returns
    -------
    numpy.ndarray
        Evenly spaced times from 0 [s].
    """
    p = np.asarray(poles, dtype=complex)
    t_end = length_factor * max(5.0, 10.0 / float(np.min(np.abs(p.real))))
    h = min(1e-3, 0.1 / float(np.max(np.abs(p))))
    n = min(100_000, int(np.ceil(t_end / h))) + 1
    return np.linspace(0.0, t_end, n)


def channel_models(plant: str, order, lm: LinearModel | None = None):
    """Lateral and vertical SISO models of a design plant at an order.

    Parameters
    ----------
    plant : {"paper", "model"}
        The paper's Table 2 models, or this project's linearization ``lm``.
    order : int or "full"
        2 or 6 for "paper"; an integer >= 1 or "full" for "model".
    lm : LinearModel, optional
        Required for "model".

    Returns
    -------
    tuple of control.StateSpace or control.TransferFunction
        (lateral u_hor [N] -> P_ny [m], vertical u_ver [N] -> P_nz [m]).

    Raises
    ------
    ValueError
        If ``plant`` is not in `PLANTS`, or is "model" without ``lm``.
    """
    if plant == "paper":
        return tuple(table2_transfer_function(ch, order) for ch in CHANNELS)
    if plant == "model":
        if lm is None:
            raise ValueError("plant 'model' needs the linear model lm")
        if order == "full":
            return split_channels(lm.ss)
        ch = reduced_channels(lm, int(order))
        return ch.lateral, ch.vertical
    raise ValueError(f"plant must be one of {PLANTS}, got {plant!r}")


def _check_stable(loop) -> np.ndarray:
    poles = loop.poles()
    if np.any(np.real(poles) >= 0.0):
        raise ValueError(f"closed loop is unstable: poles {poles}")
    return poles


def lqr_steps(design, plant=None, t=None) -> dict[str, StepResponse]:
    """Unit reference steps of an LQR design, per channel.

    Parameters
    ----------
    design : BalancedLQRDesign or LQRDesign
        Balanced-state LQR (reference through the prefilter) or integral-action LQR (reference
        into the integrator).
    plant : control.StateSpace, optional
        Strictly proper [u_hor, u_ver] [N] -> [P_ny, P_nz] [m] plant to close the loop around
        (through the observer); default the design model.
    t : array_like, optional
        Time grid [s] from 0, evenly spaced; default `time_grid_for` the loop's poles.

    Returns
    -------
    dict
        ``{"lateral": StepResponse, "vertical": StepResponse}``, final value = the loop's DC gain.

    Raises
    ------
    TypeError
        If ``design`` is neither a BalancedLQRDesign nor an LQRDesign.
    ValueError
        If the closed loop is unstable.
    """
    if isinstance(design, BalancedLQRDesign):
        loop = lqr_balanced_reference_loop(design, plant)
    elif isinstance(design, LQRDesign):
        loop = lqr_tracking_closed_loop(design, plant)
    else:
        raise TypeError(f"design must be a BalancedLQRDesign or LQRDesign, got {type(design).__name__}")
    poles = _check_stable(loop)
    t = time_grid_for(poles) if t is None else np.asarray(t, dtype=float)
    dc = np.real(control.dcgain(loop))
    out = {}
    for k, ch in enumerate(CHANNELS):
        outputs = step_outputs(loop, t, k)
        y, u = outputs[k], outputs[2 + k]
        out[ch] = StepResponse(t_s=t, y=np.asarray(y), u=np.asarray(u),
                               metrics=step_metrics(t, y, final_value=float(dc[k, k])))
    return out


def pid_steps(lateral, vertical, gains=None, t=None) -> dict[str, StepResponse]:
    """Unit reference steps of per-channel PIDs under unity feedback.

    Parameters
    ----------
    lateral, vertical : control.TransferFunction or control.StateSpace
        Channel models, force [N] -> offset [m].
    gains : dict, optional
        ``{"lateral": PIDGains, "vertical": PIDGains}``; default the paper's (Eq. 33).
    t : array_like, optional
        Time grid [s]; default `time_grid_for` each loop's poles.

    Returns
    -------
    dict
        ``{"lateral": StepResponse, "vertical": StepResponse}``: offset y [m] and force u [N]
        per metre of reference step, and the metrics.

    Raises
    ------
    ValueError
        If a closed loop is unstable.
    """
    gains = PAPER_PID if gains is None else gains
    out = {}
    for ch, g in zip(CHANNELS, (lateral, vertical)):
        c = gains[ch].transfer_function()
        poles = _check_stable(control.feedback(control.series(c, g), 1))
        tt = time_grid_for(poles) if t is None else np.asarray(t, dtype=float)
        out[ch] = closed_loop_step(g, c, tt)
    return out


def step_responses(controller: str, plant: str, lm: LinearModel | None = None, *,
                   evaluate_on=DESIGN_ORDER, t=None) -> dict[str, StepResponse]:
    """Unit reference steps of one of the paper's designs, per channel.

    Parameters
    ----------
    controller : {"PID", "LQR", "LQR-integral"}
        The design (see the module docstring); the paper's gains or weights.
    plant : {"paper", "model"}
        Design plant: the LQRs are designed on its 2nd-order channels.
    lm : LinearModel, optional
        This project's linearization; required for ``plant="model"``.
    evaluate_on : int or "full", optional
        Order of the model the loop is closed around (default 2, the design model).
    t : array_like, optional
        Time grid [s] from 0, evenly spaced; default `time_grid_for` the loop's poles.

    Returns
    -------
    dict
        ``{"lateral": StepResponse, "vertical": StepResponse}``: offset y [m] and force u [N] per
        metre of reference step, and the metrics.

    Raises
    ------
    ValueError
        If ``controller`` or ``plant`` is unknown, ``lm`` is missing for ``plant="model"``, or a
        closed loop is unstable.
    """
    lat, ver = channel_models(plant, evaluate_on, lm)
    d_lat, d_ver = channel_models(plant, DESIGN_ORDER, lm)
    other = evaluate_on != DESIGN_ORDER
    if controller == "PID":
        design = dict(PAPER_PID)
    elif controller == "LQR":
        design = lqr_balanced_design(d_lat, d_ver)
    elif controller == "LQR-integral":
        design = lqr_integral_design(two_channel_plant(d_lat, d_ver))
    else:
        raise ValueError(f"controller must be one of {CONTROLLERS}, got {controller!r}")
    if other:
        return steps_on(design, lat, ver, design_models=(d_lat, d_ver), t=t)
    return pid_steps(lat, ver, t=t) if controller == "PID" else lqr_steps(design, None, t)


def steps_on(design, lateral, vertical, *, design_models, t=None) -> dict[str, StepResponse]:
    """Unit reference steps of a design closed around other channel models (e.g. full order).

    Parameters
    ----------
    design : dict or BalancedLQRDesign or LQRDesign
        PID gains ``{"lateral": PIDGains, "vertical": PIDGains}``, or an LQR design.
    lateral, vertical : control.StateSpace or control.TransferFunction
        The channel models to close the loops around, force [N] -> offset [m].
    design_models : (lateral, vertical)
        The design's own channel models: the time grid is theirs (a larger model's fast, barely
        excited poles would make it needlessly fine), three times as long for slower tails.
    t : array_like, optional
        Time grid [s] instead.

    Returns
    -------
    dict
        ``{"lateral": StepResponse, "vertical": StepResponse}``.

    Raises
    ------
    ValueError
        If a closed loop is unstable.
    """
    if isinstance(design, dict):
        if t is None:
            poles = np.concatenate([control.feedback(design[ch].transfer_function() * g, 1).poles()
                                    for ch, g in zip(CHANNELS, design_models)])
            t = time_grid_for(poles, 3.0)
        return pid_steps(lateral, vertical, design, t=t)
    if t is None:
        t = time_grid_for(_design_loop_poles(design), 3.0)
    return lqr_steps(design, two_channel_plant(lateral, vertical), t)


def _design_loop_poles(design) -> np.ndarray:
    """Poles [rad/s] of an LQR design's reference loop on its design model."""
    if isinstance(design, BalancedLQRDesign):
        return lqr_balanced_reference_loop(design).poles()
    return lqr_tracking_closed_loop(design).poles()


def table3(lm: LinearModel | None = None) -> dict[tuple[str, str, str], StepMetrics]:
    """Table 3 for every design on the paper's plant and (given ``lm``) on this project's.

    Parameters
    ----------
    lm : LinearModel, optional
        This project's linearization (e.g. at 150 m/s, 8000 m); without it only the paper's
        plant is evaluated.

    Returns
    -------
    dict
        ``{(controller, plant, channel): StepMetrics}`` on each design model (2nd order),
        controller in `CONTROLLERS`, plant in `PLANTS`, channel "lateral"/"vertical".
    """
    plants = ("paper",) if lm is None else PLANTS
    out = {}
    for controller in CONTROLLERS:
        for plant in plants:
            for ch, resp in step_responses(controller, plant, lm).items():
                out[(controller, plant, ch)] = resp.metrics
    return out


def table3_rows(lm: LinearModel | None = None) -> list[dict]:
    """`table3` as flat rows with the paper's Table 3 values beside ours.

    Parameters
    ----------
    lm : LinearModel, optional
        This project's linearization (e.g. at 150 m/s, 8000 m); without it only the paper's
        plant is evaluated (see `table3`).

    Returns
    -------
    list of dict
        Keys ``controller``, ``plant``, ``channel``, ``rise_time_s`` [s], ``settling_time_s`` [s],
        ``overshoot_pct`` [%], and ``paper_rise_time_s``, ``paper_settling_time_s``,
        ``paper_overshoot_pct`` (the paper's PID row beside "PID", its LQR row beside "LQR" and
        "LQR-integral").
    """
    rows = []
    for (controller, plant, ch), m in table3(lm).items():
        ref = TABLE3[("PID" if controller == "PID" else "LQR", ch)]
        rows.append({
            "controller": controller, "plant": plant, "channel": ch,
            "rise_time_s": m.rise_time_s, "settling_time_s": m.settling_time_s, "overshoot_pct": m.overshoot_pct,
            **{f"paper_{k}": v for k, v in ref.items()},
        })
    return rows
