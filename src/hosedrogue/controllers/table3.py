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
from ..paper import CHANNELS, TABLE3, table2_transfer_function
from .design import DESIGN_ORDER, reduced_channels
from .lqr import lqr_integral_design, lqr_tracking_closed_loop, two_channel_plant
from .lqr_balanced import lqr_balanced_design, lqr_balanced_reference_loop
from .pid import PAPER_PID
from .stepinfo import StepMetrics, StepResponse, closed_loop_step, step_metrics

__all__ = ["CONTROLLERS", "PLANTS", "default_time_grid", "channel_models", "step_responses",
           "table3", "table3_rows"]

CONTROLLERS = ("PID", "LQR", "LQR-integral")
PLANTS = ("paper", "model")


def default_time_grid(controller: str) -> np.ndarray:
    """Time grid [s] that resolves and settles each design's step (from 0, evenly spaced).

    PID: 0.1 ms over 5 s (fastest closed-loop pole -282 rad/s, 3.5 ms; slowest -1.1 rad/s).
    LQR: 1 ms over 10 s (fastest regulator pole -16.8 rad/s, 60 ms; slowest -1.57 rad/s on this
    project's model: 15 time constants). LQR-integral: 1 ms over 60 s (slowest pole -0.21 rad/s).
    """
    if controller == "PID":
        return np.linspace(0.0, 5.0, 50_001)
    if controller == "LQR":
        return np.linspace(0.0, 10.0, 10_001)
    if controller == "LQR-integral":
        return np.linspace(0.0, 60.0, 60_001)
    raise ValueError(f"controller must be one of {CONTROLLERS}, got {controller!r}")


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


def _mimo_steps(loop: control.StateSpace, t: np.ndarray) -> dict[str, StepResponse]:
    """Per-channel unit steps of a loop with inputs [r_ny, r_nz], outputs [P_ny, P_nz, u_hor, u_ver]."""
    if np.any(np.real(loop.poles()) >= 0.0):
        raise ValueError(f"closed loop is unstable: poles {loop.poles()}")
    dc = np.real(control.dcgain(loop))
    out = {}
    for k, ch in enumerate(CHANNELS):
        resp = control.step_response(loop, t, input=k, squeeze=False)
        y, u = resp.outputs[k, 0], resp.outputs[2 + k, 0]
        out[ch] = StepResponse(t_s=t, y=np.asarray(y), u=np.asarray(u),
                               metrics=step_metrics(t, y, final_value=float(dc[k, k])))
    return out


def step_responses(controller: str, plant: str, lm: LinearModel | None = None, *,
                   evaluate_on=DESIGN_ORDER, t=None) -> dict[str, StepResponse]:
    """Unit reference steps of a design, per channel.

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
        Time grid [s] from 0, evenly spaced; default `default_time_grid`.

    Returns
    -------
    dict
        ``{"lateral": StepResponse, "vertical": StepResponse}``: offset y [m] and force u [N] per
        metre of reference step, and the metrics.
    """
    t = default_time_grid(controller) if t is None else np.asarray(t, dtype=float)
    lat, ver = channel_models(plant, evaluate_on, lm)
    if controller == "PID":
        return {ch: closed_loop_step(g, PAPER_PID[ch].transfer_function(), t)
                for ch, g in zip(CHANNELS, (lat, ver))}
    d_lat, d_ver = channel_models(plant, DESIGN_ORDER, lm)
    same = evaluate_on == DESIGN_ORDER
    if controller == "LQR":
        design = lqr_balanced_design(d_lat, d_ver)
        loop = lqr_balanced_reference_loop(design, None if same else two_channel_plant(lat, ver))
    elif controller == "LQR-integral":
        design = lqr_integral_design(two_channel_plant(d_lat, d_ver))
        loop = lqr_tracking_closed_loop(design, None if same else two_channel_plant(lat, ver))
    else:
        raise ValueError(f"controller must be one of {CONTROLLERS}, got {controller!r}")
    return _mimo_steps(loop, t)


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

    Returns
    -------
    list of dict
        Keys ``controller``, ``plant``, ``channel``, ``rise_time_s``, ``settling_time_s``,
        ``overshoot_pct``, and ``paper_rise_time_s``, ``paper_settling_time_s``,
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
