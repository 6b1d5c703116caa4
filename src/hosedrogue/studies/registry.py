"""Every study of the package, in one table: ``hosedrogue study NAME`` runs each on its own,
the report renders each (its section), and a study that runs a scenario takes the user's.

A :class:`Study` names its library module, the report section that presents it, the scenario it
runs by default and what it takes from one of the user's (``--scenario NAME|FILE``), its
settings (:class:`Setting`: the command line's options, each with its unit and range), and a
``run(scenario, **settings) -> (result, record)`` function: the study's result object (the one the
report renders) and its numbers as plain JSON types (SI units in the keys; what ``--json``
prints). The docking grid, the whip loads, the actuated drogue and the receiver aircraft have command
lines of their own (:mod:`hosedrogue.cli.study`, ``custom_cli``); their entries here still say what they are.

A scenario file names Python code only through the entry points its sections allow
(``controller``, ``reel.law = "python"``): running one runs that code, as a script would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

__all__ = ["Setting", "Study", "STUDIES", "check_scenario"]


@dataclass(frozen=True)
class Setting:
    """One setting of a study, as its command line takes it.

    Parameters
    ----------
    name : str
        Keyword of the study's run function; the option is ``--`` + name with ``-`` for ``_``.
    kind : str
        ``"float"``, ``"int"``, ``"floats"``, ``"ints"``, ``"choice"`` or ``"choices"`` (the plural
        kinds take one or more values).
    default : object
        The study's default (None: the study's own choice, said in ``help``).
    help : str
        What it is, with its unit.
    lo, hi : float
        Allowed range (inclusive) of numbers.
    unit : str
        Unit of numbers ("" for none).
    choices : tuple of str
        Allowed values of the choice kinds.
    """

    name: str
    kind: str
    default: Any
    help: str
    lo: float = -math.inf
    hi: float = math.inf
    unit: str = ""
    choices: tuple = ()


@dataclass(frozen=True)
class Study:
    """One study (see the module docstring).

    Parameters
    ----------
    name : str
        ``hosedrogue study NAME``.
    summary : str
        One line: what it finds.
    module : str
        Its library module under :mod:`hosedrogue.studies`.
    section : str or None
        The report section that renders it (a key of :data:`hosedrogue.report.plan.SECTIONS`).
    scenario : str
        The scenario it runs by default ("" if it runs none).
    takes : str
        What it takes from the user's scenario ("" if it takes none).
    kind : str
        The kind of scenario it takes: ``"fixed-length"``, ``"engagement"`` or "" (none).
    settings : tuple of Setting
        Its other settings.
    run : callable or None
        ``run(scenario, **settings) -> (result, record)``; None for a study with a command line
        of its own. A result with a ``figures()`` method (name -> matplotlib Figure) has its
        figures written by ``--out``.
    custom_cli : bool
        Whether :mod:`hosedrogue.cli.study` writes its command line by hand.
    """

    name: str
    summary: str
    module: str
    section: str | None
    scenario: str
    takes: str
    kind: str = ""
    settings: tuple = ()
    run: Callable | None = None
    custom_cli: bool = False


def check_scenario(study: Study, scenario):
    """The user's scenario if it is of the kind ``study`` takes (:meth:`Scenario.require_model`).

    Parameters
    ----------
    study : Study
        The study.
    scenario : hosedrogue.scenarios.Scenario
        The user's scenario.

    Returns
    -------
    hosedrogue.scenarios.Scenario

    Raises
    ------
    ParameterError
        The study takes no scenario, or another kind.
    """
    from ..errors import ParameterError

    if not study.kind:
        raise ParameterError(f"scenario: the {study.name} study takes no scenario")
    want = "an engagement (with [probe])" if study.kind == "engagement" else "a fixed-length scenario (no [probe])"
    return scenario.require_model(study.kind, "scenario", f"the {study.name} study takes {want}: {study.takes}")


def _checked(scenario, name: str):
    """The user's scenario, checked against the study ``name``'s kind."""
    return check_scenario(STUDIES[name], scenario)


def _pid_tuning(scenario, duration_s=None):
    from .pid_tuning import pid_tuning_study

    params = None if scenario is None else _checked(scenario, "pid-tuning").params
    study = pid_tuning_study(params, duration_s)
    return study, {"rows": study.rows()}


def _convergence(scenario, case="swing", steps_s=(0.02, 0.01, 0.005, 0.0025), reference_step_s=0.000625,
                 links=(5, 10, 20, 40, 80)):
    from ..spec.params import PAPER
    from .convergence import ConvergenceStudy, link_convergence, step_convergence

    params = PAPER if scenario is None else _checked(scenario, "convergence").params
    step = step_convergence(case, steps_s, reference_step_s, params)
    link = link_convergence(links, params)
    record = {"step": {"case": step.case, "steps_s": step.steps_s, "max_error_m": step.max_error_m,
                       "observed_order": step.observed_order, "reference_step_s": step.reference_step_s,
                       "duration_s": step.duration_s},
              "links": {"links": link.links, "drogue_position_m": link.drogue_position_m,
                        "lowest_lateral_rad_s": link.lowest_lateral_rad_s,
                        "lowest_vertical_rad_s": link.lowest_vertical_rad_s}}
    return ConvergenceStudy((step,), link), record


def _accuracy(scenario, steps_s=(0.01, 0.02, 0.025), reference_step_s=0.000625):
    from ..scenarios import load_scenario
    from .accuracy import scenario_step_study

    sc = _checked(load_scenario("paper-turbulence") if scenario is None else scenario, "accuracy")
    study = scenario_step_study(sc, steps_s, reference_step_s)
    return study, {"scenario": sc.name, "steps_s": study.steps_s, "max_error_m": study.max_error_m,
                   "reference_step_s": study.reference_step_s, "reading_change_m": study.reading_change_m,
                   "duration_s": study.duration_s}


def _long_runs(scenario, intensities=("light", "moderate", "severe"), seeds=(2018, 2019, 2020), cap_s=3600.0,
               hour_s=None):
    from ..spec.params import PAPER
    from .long_runs import long_runs_study

    base = PAPER if scenario is None else _checked(scenario, "long-runs").params
    study = long_runs_study(intensities, seeds, cap_s, hour_s, base)
    return study, {"blowup": study.blowup.to_dict(orient="records"), "modes": study.modes.to_dict(orient="records"),
                   "damping_gain": study.damping_gain, "cap_s": study.cap_s,
                   "hour": {"completed": study.hour.completed, **study.hour.statistics()}}


def _manoeuvres(scenario, banks_deg=(0.0, 15.0, 30.0, 45.0), paths_deg=(-10.0, 0.0, 10.0)):
    from ..spec.params import PAPER
    from .manoeuvres import steady_flight_study

    params = PAPER if scenario is None else _checked(scenario, "manoeuvres").params
    study = steady_flight_study(params, banks_deg, paths_deg)

    def sweep(s):
        return {"angles_deg": s.angles_deg, "drogue_position_m": s.drogue_position_m}

    return study, {"bank": sweep(study.bank), "flight_path": sweep(study.flight_path)}


def _bow_wave(scenario):
    from .bow_wave import bow_wave_study

    study = bow_wave_study(scenario=scenario)  # the study checks the scenario's kind
    return study, {"distances_m": study.distances_m, "displacement_m": study.displacement_m,
                   "radii_m": study.radii_m, "radii_displacement_m": study.radii_displacement_m,
                   "radius_limit_m": study.radius_limit_m, "radius_m": study.radius_m, "near_m": study.near_m,
                   "far_m": study.far_m}


def _steps(default, lo=1e-5, hi=0.1) -> Setting:
    return Setting("steps_s", "floats", default, "RK4 steps to compare [s]", lo, hi, "s")


def _reference(default) -> Setting:
    return Setting("reference_step_s", "float", default, "RK4 step of the reference run [s]", 1e-6, 0.1, "s")


#: The studies, by name.
STUDIES: dict[str, Study] = {s.name: s for s in (
    Study("docking", "capture rate of the approach per turbulence level, drogue controller, bow wave and pilot",
          "docking", "docking", "approach-LEVEL", "your approach, flown in each level's turbulence (--scenario)",
          "engagement", custom_cli=True),
    Study("whip-loads", "the whip's loads against the hose's axial stiffness and the closure speed",
          "whip_loads", "whip_loads", "engage-locked, engage-constant-tension, engage-response",
          "engagement scenarios (--scenarios NAME|FILE ...)", custom_cli=True),
    Study("actuator", "the paper's controllers through the drogue's control surfaces, against the ideal force",
          "drogue_actuator", "drogue_actuator", "paper-turbulence, approach-LEVEL",
          "a fixed-length scenario for the claims and margins (--scenario), an approach for the capture cells "
          "(--approach)", custom_cli=True),
    Study("pid-tuning", "a PID tuned to Table 3's step figures on the paper's plant and this model's, in turbulence",
          "pid_tuning", "pid_tuning", "paper-turbulence-pid", "its model and flight condition (the plant tuned)", "fixed-length",
          (Setting("duration_s", "float", None, "length of the turbulence runs [s] (default 60)", 1.0, 3600.0, "s"),),
          _pid_tuning),
    Study("convergence", "RK4's error against its step, and the balance position and lowest modes against the links",
          "convergence", "convergence", "the paper's case", "its model and flight condition", "fixed-length",
          (Setting("case", "choice", "swing", "the step study's case", choices=("swing", "turbulence", "turbulence+pid")),
           _steps((0.02, 0.01, 0.005, 0.0025)), _reference(0.000625),
           Setting("links", "ints", (5, 10, 20, 40, 80), "link counts [-]", 2, 1000)),
          _convergence),
    Study("accuracy", "a turbulence scenario's RK4 step error and its gust reading against the paper's",
          "accuracy", "accuracy", "paper-turbulence", "the whole fixed-length scenario (its turbulence run)", "fixed-length",
          (_steps((0.01, 0.02, 0.025)), _reference(0.000625)), _accuracy),
    Study("long-runs", "which turbulence makes the paper's model blow up, and an hour of the converged model",
          "long_runs", "long_runs", "the paper's case, long-turbulence-severe", "its model (the blow-up runs' base)", "fixed-length",
          (Setting("intensities", "choices", ("light", "moderate", "severe"), "standard turbulence intensities",
                   choices=("light", "moderate", "severe")),
           Setting("seeds", "ints", (2018, 2019, 2020), "turbulence seeds of the blow-up runs [-]", 0, 2**63 - 1),
           Setting("cap_s", "float", 3600.0, "length of the blow-up runs [s]", 1.0, 86400.0, "s"),
           Setting("hour_s", "float", None, "length of the converged model's run [s] (default an hour)", 1.0,
                   86400.0, "s")),
          _long_runs),
    Study("manoeuvres", "the balance position in steady turns and climbs", "manoeuvres", "manoeuvres",
          "the paper's case", "its model and flight condition", "fixed-length",
          (Setting("banks_deg", "floats", (0.0, 15.0, 30.0, 45.0), "bank angles [deg]", -80.0, 80.0, "deg"),
           Setting("paths_deg", "floats", (-10.0, 0.0, 10.0), "flight-path angles [deg]", -45.0, 45.0, "deg")),
          _manoeuvres),
    Study("receiver", "the F-16's trim against the book, and its docking beside the point receiver on the same seeds",
          "receiver", "receiver", "approach-f16-moderate, approach-moderate-docking",
          "your approach (--scenario) beside another (--against), each an engagement", "engagement", custom_cli=True),
    Study("bow-wave", "the receiver's bow wave around the probe and the drogue's steady displacement by it",
          "bow_wave", "docking", "approach-moderate", "an engagement scenario's model, flight condition and "
          "[bow_wave]", "engagement", (), _bow_wave),
)}
