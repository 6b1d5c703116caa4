"""The receiver as an aircraft: a rigid body in six degrees of freedom with a table-driven
aerodynamic and engine model read from a file (the F-16 of Stevens, Lewis & Johnson, 2015, is
shipped), its trim anywhere in the envelope and its linear model with its modes (docs/receiver.md).

The names most used are here: ``from hosedrogue.aircraft import load_model, trim, linearize_receiver, fly``.
"""

from .linear import ReceiverLinearModel, linearize_receiver
from .model_file import AircraftModel, load_model
from .simulate import Flight, fly
from .trim import Trim, trim

__all__ = ["AircraftModel", "load_model", "Trim", "trim", "ReceiverLinearModel", "linearize_receiver", "Flight",
           "fly"]
