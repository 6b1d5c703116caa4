"""The covariance analysis's prediction of a scenario's drogue displacement spectrum
(:mod:`hosedrogue.controllers.covariance`), recorded in its run's ``meta`` as
``"spectrum_prediction"`` and put beside the run's Welch estimate in ``run.json`` and its figure
(:mod:`hosedrogue.results.spectra`).

A prediction exists for a fixed-length rigid hose in uniform turbulence, steady flight, with no
controller or a built-in linear one (continuous or sampled, with the sensor's delay), no actuator
limits, no drogue control surfaces and no sensor noise: the linear loop the analysis models. Any
other run gets a ``"note"`` saying why there is none.
"""

from __future__ import annotations

import json
import math

import numpy as np

from ..errors import ParameterError

__all__ = ["spectrum_prediction"]

#: Predictions of this process by key (the parameters without the turbulence seed, the loop's
#: sections): a campaign of seeds predicts once per worker.
_PREDICTIONS: dict = {}


def _why_not(scenario) -> str | None:
    p, loop = scenario.params, scenario.loop
    checks = (
        (scenario.engagement is not None, "an engagement (the hose's length varies)"),
        (not p.turbulence.enabled, "no turbulence"),
        (p.turbulence.distribution != "uniform", "a frozen gust field (the analysis models a uniform gust)"),
        (p.hose.elastic, "an elastic hose (the linearization is of rigid links)"),
        (not p.tanker_motion.is_steady, "a manoeuvring tanker"),
        (loop.controller.type == "python", "a user's controller (not a linear design)"),
        (math.isfinite(loop.actuator.max_force_n) or loop.actuator.rate_limited, "actuator limits"),
        (loop.drogue_actuator is not None, "drogue control surfaces"),
        (loop.sensor.noise_std_m > 0.0, "sensor noise"),
    )
    reasons = [why for bad, why in checks if bad]
    return "; ".join(reasons) if reasons else None


def spectrum_prediction(scenario, controller=None) -> dict:
    """The predicted spectrum of a scenario's drogue offset, or why there is none.

    Parameters
    ----------
    scenario : Scenario
        The case run.
    controller : LinearController, optional
        Its designed drogue controller (None: open loop).

    Returns
    -------
    dict
        ``rms_m`` {lateral, vertical} [m], ``frequency_hz`` [Hz], ``lateral_m2_hz``,
        ``vertical_m2_hz`` [m^2/Hz], ``sample_time_s`` [s], ``delay_s`` [s]; or ``{"note": why}``.
    """
    why = _why_not(scenario)
    if why is not None:
        return {"note": f"no linear prediction: {why}"}
    params = scenario.params.to_dict()
    params["turbulence"] = {k: v for k, v in params["turbulence"].items() if k != "seed"}
    loop = scenario.loop
    key = json.dumps([params, loop.controller.to_dict(), loop.sensor.to_dict()], sort_keys=True, default=repr)
    if key not in _PREDICTIONS:
        _PREDICTIONS[key] = _predict(scenario, controller)
    return _PREDICTIONS[key]


def _predict(scenario, controller) -> dict:
    from ..controllers.covariance import predict
    from ..results.spectra import F_MAX_HZ

    ctrl = scenario.loop.controller
    sample = ctrl.sample_time_s if ctrl.type in ("pid", "lqr") else 0.0
    delay = scenario.loop.sensor.delay_s if sample > 0.0 else 0.0
    f_max = min(F_MAX_HZ, 0.5 / sample) if sample else F_MAX_HZ
    try:
        pr = predict(scenario.params, controller, sample, delay, frequency_hz=np.geomspace(1e-3, f_max, 300))
    except (ParameterError, ValueError, np.linalg.LinAlgError) as exc:  # an unstable loop, a singular solve:
        return {"note": f"no linear prediction: {exc}"}                # the run stands without it
    return {"rms_m": pr.as_dict(), "sample_time_s": sample, "delay_s": delay,
            "frequency_hz": pr.frequency_hz.tolist(), "lateral_m2_hz": pr.psd_m2_hz[0].tolist(),
            "vertical_m2_hz": pr.psd_m2_hz[1].tolist()}
