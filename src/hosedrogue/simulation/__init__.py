"""Time simulation of the nonlinear model: one run (:func:`simulate`) or many turbulence seeds in
one compiled call (:func:`simulate_batch`).

``Actuator`` and ``Sensor`` are defined in :mod:`hosedrogue.spec.params` (every parameter
specification lives there) and importable from here.
"""

from ..spec.params import Actuator, Sensor
from ..results.run import SimulationResult
from .batch import simulate_batch
from .simulate import ControlFunction, simulate

__all__ = ["Actuator", "ControlFunction", "Sensor", "SimulationResult", "simulate", "simulate_batch"]
