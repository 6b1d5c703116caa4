"""A PID tuned to the paper's Table 3 step figures on the plant it is given, against the paper's
Eq. 33 gains.

:func:`pid_tuning_study` tunes each channel (:func:`hosedrogue.controllers.design.tuned_pid`,
docs/tuning.md) on the paper's Table 2 2nd-order models and on this model's 2nd-order
linearization at a flight condition, and evaluates both sets of gains there: the unit steps on
the design model and on the larger model of the same plant (the paper's 6th order; this model's
full order), and on this model the drogue's peak offsets in the paper's turbulence case
(``paper-turbulence-pid`` with each set of gains, the nonlinear model).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..controllers.pid import PAPER_PID
from ..spec.paper import CHANNELS

__all__ = ["GainsCase", "PIDTuningStudy", "pid_tuning_study", "PLANTS"]

#: The plants by name, as the table and the figure label them.
PLANTS = {"paper": "paper's Table 2 models", "model": "this model"}
#: The larger model of each plant, whose steps the figure draws dashed.
_LARGER = {"paper": "6th order", "model": "full order"}
#: The figure's time axis [s] (logarithmic: rises near 0.05 s, settling up to ~8 s on the full model).
_T_S = np.concatenate([[0.0], np.logspace(-3.0, 1.0, 800)])


@dataclass(frozen=True, eq=False)
class GainsCase:
    """One set of PID gains on one plant.

    Attributes
    ----------
    plant : str
        "paper" (its Table 2 models) or "model" (this model's linearization).
    source : str
        "tuned" or "paper Eq. 33".
    gains : dict
        ``{"lateral": PIDGains, "vertical": PIDGains}``.
    min_damping : dict
        Smallest damping ratio of the closed-loop poles on the design model, per channel [-].
    design_steps : dict
        Unit steps on the 2nd-order design model, ``{channel: StepResponse}``.
    larger_steps : dict or None
        Unit steps on the larger model (paper: 6th order, model: full order); None if that loop
        is unstable.
    peak_offsets_m : tuple of float or None
        Peak lateral and vertical drogue offset [m] in the turbulence case (model only).
    """

    plant: str
    source: str
    gains: dict
    min_damping: dict
    design_steps: dict
    larger_steps: dict | None
    peak_offsets_m: tuple[float, float] | None


@dataclass(frozen=True, eq=False)
class PIDTuningStudy:
    """The study's cases and its flight condition.

    Attributes
    ----------
    cases : tuple of GainsCase
        Paper plant tuned, paper plant Eq. 33, model tuned, model Eq. 33.
    params : Params
        The model's parameters (flight condition, hose).
    """

    cases: tuple[GainsCase, ...]
    params: object

    def rows(self) -> list[dict]:
        """One row per case and channel: the gains, the steps' figures and the turbulence peak.

        Returns
        -------
        list of dict
            ``plant``, ``gains``, ``channel``, ``kp_n_per_m``, ``ki_n_per_m_s``, ``kd_n_s_per_m``,
            ``n_filter_rad_s``, ``min_damping``; ``rise_time_s``, ``settling_time_s``,
            ``overshoot_pct`` on the design model and ``larger_*`` on the larger model (NaN if
            unstable); ``peak_offset_m`` in turbulence (NaN on the paper's plant).
        """
        out = []
        for case in self.cases:
            for k, ch in enumerate(CHANNELS):
                g, m = case.gains[ch], case.design_steps[ch].metrics
                big = case.larger_steps[ch].metrics if case.larger_steps else None
                row = {"plant": case.plant, "gains": case.source, "channel": ch, "kp_n_per_m": g.kp,
                       "ki_n_per_m_s": g.ki, "kd_n_s_per_m": g.kd, "n_filter_rad_s": g.n_filter,
                       "min_damping": case.min_damping[ch]}
                for key in ("rise_time_s", "settling_time_s", "overshoot_pct"):
                    row[key] = getattr(m, key)
                    row[f"larger_{key}"] = getattr(big, key) if big else float("nan")
                row["peak_offset_m"] = case.peak_offsets_m[k] if case.peak_offsets_m else float("nan")
                out.append(row)
        return out

    def figures(self) -> dict:
        """The study's figure: each plant's unit steps, tuned and Eq. 33, on the 2nd-order design
        model and (dashed) on the larger model.

        Returns
        -------
        dict
            ``{"steps": matplotlib.figure.Figure}``.
        """
        from ..plotting.figures import plot_closed_loop_steps

        rows, dashed = {}, {}
        for case in self.cases:
            label = "tuned" if case.source == "tuned" else "Eq. 33"
            name = PLANTS[case.plant]
            rows.setdefault(name, {})[f"{label}, 2nd order"] = {
                ch: np.interp(_T_S, case.design_steps[ch].t_s, case.design_steps[ch].y) for ch in CHANNELS}
            if case.larger_steps:
                dashed.setdefault(name, {})[f"{label}, {_LARGER[case.plant]}"] = {
                    ch: np.interp(_T_S, case.larger_steps[ch].t_s, case.larger_steps[ch].y) for ch in CHANNELS}
        return {"steps": plot_closed_loop_steps(_T_S, rows, log_time=True, reference_rows=dashed)}


def _min_damping(gains, models) -> dict:
    import control

    out = {}
    for ch, g in zip(CHANNELS, models):
        p = control.feedback(gains[ch].transfer_function() * g, 1).poles()
        out[ch] = float(np.min(-p.real / np.abs(p)))
    return out


def _peaks(scenario, gains) -> tuple[float, float]:
    from ..results.statistics import peaks
    from ..scenarios.runner import run
    from ..spec.sections import Controller

    opts = {ch: [g.kp, g.ki, g.kd, g.n_filter] for ch, g in gains.items()}
    sc = dataclasses.replace(scenario, loop=dataclasses.replace(scenario.loop, controller=Controller("pid", opts)))
    return tuple(float(v) for v in peaks(run(sc).drogue_offset_m))


def _cases(plant: str, design, larger, scenario) -> list[GainsCase]:
    from ..controllers.design import tuned_pid
    from ..controllers.table3 import pid_steps, steps_on

    tuned = {ch: t.gains for ch, t in tuned_pid(*design).items()}
    out = []
    for source, gains in (("tuned", tuned), ("paper Eq. 33", dict(PAPER_PID))):
        try:
            big = steps_on(gains, *larger, design_models=design)
        except ValueError:  # the loop around the larger model is unstable
            big = None
        out.append(GainsCase(plant=plant, source=source, gains=gains, min_damping=_min_damping(gains, design),
                             design_steps=pid_steps(*design, gains), larger_steps=big,
                             peak_offsets_m=None if scenario is None else _peaks(scenario, gains)))
    return out


def pid_tuning_study(params=None, duration_s: float | None = None) -> PIDTuningStudy:
    """Tuned PID and Eq. 33 on the paper's plant and on this model's (see the module docstring).

    Parameters
    ----------
    params : Params, optional
        This model's parameters; default ``paper-turbulence-pid``'s (150 m/s, 8000 m, 16 m hose).
        Its turbulence is replaced by the scenario's.
    duration_s : float, optional
        Length of the turbulence runs [s]; default the scenario's 60 s.

    Returns
    -------
    PIDTuningStudy
    """
    from ..analysis.linearize import linearize
    from ..controllers.table3 import channel_models
    from ..scenarios import load_scenario

    scenario = load_scenario("paper-turbulence-pid")
    if params is not None:
        params = params.replace(turbulence=scenario.params.to_dict()["turbulence"])
        scenario = dataclasses.replace(scenario, params=params)
    if duration_s is not None:
        scenario = scenario.with_overrides(duration_s=duration_s)
    lm = linearize(scenario.params)
    cases = (_cases("paper", channel_models("paper", 2), channel_models("paper", 6), None)
             + _cases("model", channel_models("model", 2, lm), channel_models("model", "full", lm), scenario))
    return PIDTuningStudy(cases=tuple(cases), params=scenario.params)
