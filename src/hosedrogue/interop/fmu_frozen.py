"""The scenario an engagement FMU freezes, independent of pythonfmu and of its simulation: what
the FMU can run of a scenario (:func:`fmu_scenario`), the record of it in the FMU's resources
(:func:`scenario_record`, :func:`load_exported_scenario`) and the sentence that describes it
(:func:`frozen_summary`). The FMU itself: :mod:`hosedrogue.interop.fmu_engagement`.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from ..errors import ParameterError
from ..spec.sections import Controller, Receiver

#: File in the FMU's ``resources`` folder holding the frozen scenario's tables and the start
#: values of the FMU's parameters and inputs (JSON, :func:`scenario_record`).
SCENARIO_RESOURCE = "hosedrogue_scenario.json"

def fmu_scenario(scenario) -> "object":
    """The scenario as the engagement FMU runs it: its inputs fly the probe, command a reel of law
    "python" and the drogue's force; the Python entries are dropped (the master replaces them).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        An engagement scenario with an enabled ``[probe]``.

    Returns
    -------
    hosedrogue.scenarios.Scenario
        Without the entries and options of ``[reel]`` and ``[receiver]`` (a ``[receiver]`` with
        the defaults if it had none: its response serves the velocity input), the drogue
        controller "none" if it was the user's ("python").

    Raises
    ------
    ParameterError
        One line for what the FMU cannot honour: no engagement, no enabled probe, a pilot, the
        drogue's control surfaces commanded by deflection, a displaced start, a built-in drogue
        controller with a sample time, sensor noise or delay.
    """
    e = scenario.engagement
    if e is None:
        raise ParameterError(f"scenario {scenario.name!r}: has no engagement ([reel] or [probe]); the engagement FMU "
                             "exports an engagement scenario (without --engagement: the fixed-length FMU)")
    if e.probe is None or not e.probe.enabled:
        raise ParameterError(f"probe: scenario {scenario.name!r} has no enabled [probe]; the engagement FMU's inputs "
                             "fly the probe tip (its start point, capture test and coupling come from [probe])")
    if e.pilot is not None and e.pilot.enabled:
        raise ParameterError("pilot.enabled = true: the engagement FMU's inputs fly the probe; remove [pilot]")
    surfaces = scenario.loop.drogue_actuator
    if surfaces is not None and surfaces.command == "deflection":
        raise ParameterError("drogue_actuator.command = 'deflection': the engagement FMU's drogue inputs u_y_n, u_z_n "
                             "are a force, mixed to the control surfaces at the measured dynamic pressure; set "
                             "command = 'force'")
    if scenario.initial != "equilibrium":
        raise ParameterError(f"scenario.initial = {scenario.initial!r}: the engagement FMU starts at the balance "
                             "position; use 'equilibrium'")
    ctrl = scenario.loop.controller
    if ctrl.type in ("pid", "lqr") and ctrl.sampled:
        raise ParameterError(f"controller.sample_time_s = {ctrl.sample_time_s!r}: the engagement FMU runs a built-in "
                             "drogue controller continuous, compiled in the loop; set 0, or type 'none' and command "
                             "the force through u_y_n, u_z_n")
    sensor = scenario.loop.sensor
    if sensor.noise_std_m != 0.0 or sensor.delay_s != 0.0:
        raise ParameterError(f"sensor: noise_std_m = {sensor.noise_std_m!r}, delay_s = {sensor.delay_s!r}: the "
                             "engagement FMU's outputs are the true state; a master models its own sensor (set both 0)")
    receiver = e.receiver if e.receiver is not None else Receiver()
    changes = {"receiver": dataclasses.replace(receiver, entry="", options={})}
    if e.reel.law == "python":
        changes["reel"] = dataclasses.replace(e.reel, entry="", options={})
    loop = scenario.loop
    if ctrl.type == "python":
        loop = dataclasses.replace(loop, controller=Controller())
    return dataclasses.replace(scenario, engagement=dataclasses.replace(e, **changes), loop=loop)


def default_sample_time(scenario) -> float:
    """The start of ``sample_time_s`` [s]: the scenario's ``[receiver] sample_time_s`` if it has a
    ``[receiver]``, else its integration step ``numerics.step_s`` (a probe path fed at every step).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario as written (before :func:`fmu_scenario`).

    Returns
    -------
    float
    """
    receiver = scenario.engagement.receiver if scenario.engagement is not None else None
    return receiver.sample_time_s if receiver is not None else scenario.params.numerics.step_s


def frozen_summary(scenario) -> str:
    """What the FMU froze of its scenario, in a sentence (for its description and documentation).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The frozen scenario (:func:`fmu_scenario`).

    Returns
    -------
    str
    """
    p, e = scenario.params, scenario.engagement
    ctrl = scenario.loop.controller.type
    reel = ("commanded by reel_speed_cmd_m_s" if e.reel.law == "python"
            else f"{e.reel.law!r}, built in (reel_speed_cmd_m_s unused)")
    drogue = "u_y_n, u_z_n" if ctrl == "none" else f"the built-in {ctrl.upper()} (u_y_n, u_z_n unused)"
    if scenario.loop.drogue_actuator is not None:
        drogue += ", made by its control surfaces"
    t = p.turbulence
    turbulence = (f"{t.model} turbulence (sigma {', '.join(f'{s:g}' for s in t.sigma_m_s)} m/s), seed {t.seed}"
                  if t.enabled else "no turbulence")
    bow = "bow wave" if e.bow_wave is not None and e.bow_wave.enabled else "no bow wave"
    hose = (f"elastic links (EA {p.hose.axial_stiffness_n:g} N, c_a {p.hose.axial_damping_n_s:g} N s)"
            if p.hose.elastic else "rigid links")
    return (f"Frozen scenario {scenario.name!r}: {p.hose.links} {hose}, {p.numerics.integrator.upper()} step "
            f"{p.numerics.step_s:g} s, "
            f"duration {scenario.duration_s:g} s, {turbulence}, {bow}; reel law {reel}; drogue force: {drogue}")


def scenario_record(scenario, starts: dict) -> dict:
    """The content of :data:`SCENARIO_RESOURCE`: the frozen scenario's tables and the starts.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The frozen scenario (:func:`fmu_scenario`).
    starts : dict
        :func:`fmu_starts`.

    Returns
    -------
    dict
        ``scenario`` (:meth:`~hosedrogue.scenarios.Scenario.to_dict`) and ``starts``.
    """
    return {"scenario": scenario.to_dict(), "starts": starts}


def load_exported_scenario(resources: str | Path) -> tuple:
    """The frozen scenario and the starts stored in an FMU's ``resources`` folder by the export.

    Parameters
    ----------
    resources : str or Path
        The unpacked FMU's ``resources`` folder.

    Returns
    -------
    scenario : hosedrogue.scenarios.Scenario
    starts : dict
    """
    from ..scenarios import scenario_from_dict

    record = json.loads((Path(resources) / SCENARIO_RESOURCE).read_text())
    return scenario_from_dict(record["scenario"], source="FMU resources"), record["starts"]
