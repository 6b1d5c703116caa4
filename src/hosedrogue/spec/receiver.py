"""The ``[receiver]`` section: the receiver flown by the user's docking controller, as a point (the
probe tip through a velocity lag) or as an aircraft (``model``: the F-16 of Stevens, Lewis &
Johnson or a model file, flown by its inner loop; docs/receiver.md, "In the engagement").
Validated at construction like the other sections (:class:`hosedrogue.spec.fields.Section`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ParameterError
from .fields import Section, entry, real, table, text, vec3

#: The receiver models shipped with the package (``hosedrogue.aircraft.model_file.SHIPPED``'s names).
SHIPPED_AIRCRAFT = ("f16",)


@dataclass(frozen=True)
class Receiver(Section):
    """The receiver flown by the user's sampled-data docking controller (``entry``): every
    ``sample_time_s`` it returns the probe tip's velocity command (v_x, v_y, v_z) [m/s] in the
    tanker frame, which the receiver follows per axis through a first-order lag with bounded
    speed and acceleration (the pilot model's response, docs/engagement.md, "Pilot model"). The
    probe starts at the ``[probe]`` start point moving forward at its closure speed; the
    ``[probe]`` capture test and coupling apply, its prescribed path does not
    (docs/controllers.md).

    With ``model`` (``"f16"`` or a model file) the receiver is that aircraft instead: trimmed behind
    the tanker, its built-in inner loop tracking the commanded velocity, the probe tip at
    ``probe_mount_m`` on the airframe (docs/receiver.md, "In the engagement"); the lag and bounds
    below then only bound the command."""

    _section = "receiver"
    #: the docking controller's factory "package.module:factory" (docs/controllers.md); needed
    #: to run the scenario ("" when the stepping API flies the receiver)
    entry: Any = field(default="", metadata=entry())
    #: time between the controller's calls [s]; the command is held in between
    sample_time_s: float = field(default=0.02, metadata=real(0.0, 10.0, unit="s"))
    #: keyword options of the factory
    options: dict = field(default_factory=dict, hash=False, metadata=table())
    #: time constant tau_v [s] of the receiver's speed following the command (the pilot model's)
    velocity_time_constant_s: float = field(default=0.1, metadata=real(0.0, 10.0, unit="s"))
    #: bound on the commanded speed per axis [m/s] (forward: up to the latch's 3 m/s; lateral and
    #: vertical: the pilot model's 1 m/s)
    max_speed_m_s: tuple = field(default=(3.0, 1.0, 1.0),
                                 metadata=vec3(0.0, 20.0, lo_open=True, unit="m/s", labels=("forward", "right", "down")))
    #: bound on the acceleration per axis [m/s^2] (the pilot model's 2 m/s^2)
    max_acceleration_m_s2: tuple = field(default=(2.0, 2.0, 2.0),
                                         metadata=vec3(0.0, 50.0, lo_open=True, unit="m/s^2",
                                                       labels=("forward", "right", "down")))
    #: the receiver flown: "" the point of the velocity lag above, "f16" the F-16 of Stevens, Lewis &
    #: Johnson, or the path of a receiver model file (docs/receiver.md; relative to the working directory)
    model: str = field(default="", metadata=text())
    #: the probe tip on the airframe, body axes from the centre of gravity (forward, right, down)
    #: [m]; the default is the F-16's (docs/receiver.md, "In the engagement")
    probe_mount_m: tuple = field(default=(8.5, 0.0, 0.0),
                                 metadata=vec3(-50.0, 50.0, unit="m", labels=("forward", "right", "down")))
    #: the aircraft's RK4 step and its inner loop's sample time [s]; the control step must be a
    #: whole multiple of it
    aircraft_step_s: float = field(default=0.01, metadata=real(0.0, 0.1, unit="s"))

    def _check_consistency(self) -> None:
        if self.model not in ("",) + SHIPPED_AIRCRAFT and not Path(self.model).is_file():
            raise ParameterError(f"receiver.model = {self.model!r}: \"\" (the point receiver), "
                                 f"{', '.join(repr(m) for m in SHIPPED_AIRCRAFT)} or the path of a receiver model file")
        if self.model and self.probe_mount_m[0] <= 0.0:
            raise ParameterError(f"receiver.probe_mount_m = {list(self.probe_mount_m)!r}: the probe tip must be "
                                 "ahead of the centre of gravity (forward > 0 m)")
        steps = self.sample_time_s / self.aircraft_step_s
        if self.model and abs(steps - round(steps)) > 1e-9 * steps:
            raise ParameterError(f"receiver.aircraft_step_s = {self.aircraft_step_s!r}: must divide "
                                 f"receiver.sample_time_s = {self.sample_time_s!r} s a whole number of times")
