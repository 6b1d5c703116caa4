"""hosedrogue: the probe-and-drogue aerial refuelling hose as a Kane-equation chain of rigid
links (after Wu et al., 2018), with its air environment, equilibrium, linearization, model
reduction and PID/LQR control, the refuelling engagement (reel, hose of varying length,
probe, capture), and your own sampled-data controllers in the loop (docs/controllers.md).

Quick start::

    import hosedrogue as hd
    scenario = hd.load_scenario("paper-turbulence-pid")   # or hd.Scenario(...) built in Python
    result = hd.run(scenario)                             # the fixed-length hose or the engagement
    hd.write(result, "out/pid")                           # timeseries.csv, run.json, figure
    eq = hd.solve_equilibrium(hd.PAPER)                   # the balance position
"""

from .version import __version__
from .spec.config import load_params, resolve_config
from .spec.manoeuvres import Manoeuvre, TankerMotion
from .spec.params import PAPER, Params, ParameterError
from .spec.sections import Actuator, BowWave, Controller, DrogueActuator, Engagement, Loop, Pilot, Probe, Receiver, Reel, Sensor

__all__ = ["PAPER", "Params", "ParameterError", "load_params", "resolve_config", "TankerMotion", "Manoeuvre",
           "Actuator", "BowWave", "Controller", "DrogueActuator",
           "Engagement", "Loop", "Pilot", "Probe", "Receiver", "Reel", "Sensor",
           "Scenario", "load_scenario", "run", "write", "solve_equilibrium", "simulate", "simulate_engagement",
           "FixedLengthStepper", "EngagementStepper", "__version__"]

# heavy modules (numba compilation) load on first use: name -> (module, attribute)
_LAZY = {
    "solve_equilibrium": ("analysis.equilibrium", "solve_equilibrium"),
    "simulate": ("simulation", "simulate"),
    "simulate_engagement": ("engagement", "simulate_engagement"),
    "FixedLengthStepper": ("simulation.stepper", "FixedLengthStepper"),
    "EngagementStepper": ("engagement.stepper", "EngagementStepper"),
    "Scenario": ("scenarios", "Scenario"),
    "load_scenario": ("scenarios", "load_scenario"),
    "run": ("scenarios.runner", "run"),
    "write": ("scenarios.runner", "write"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)
    raise AttributeError(name)
