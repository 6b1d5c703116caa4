"""The real-time schedule of a live flight: one control sample per sample period of wall-clock
time, never faster; when the computation falls behind, the schedule slips (the lost time is
counted, not caught up in a burst the pilot could not follow).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

__all__ = ["RealTimeClock", "Pace", "MAX_LATE_RECORDED"]

#: Late samples whose times a flight's record lists [-].
MAX_LATE_RECORDED = 100


@dataclass
class Pace:
    """How a flight kept to real time (``run.json`` ``flight.real_time``).

    All times are wall-clock seconds [s] except ``simulated_s``.
    """

    simulated_s: float = 0.0  #: simulated time flown [s] (pauses excluded)
    wall_s: float = 0.0  #: wall-clock time it took, pauses excluded [s]
    busy_s: float = 0.0  #: of it, computing (the steps and the frames) [s]
    late_samples: int = 0  #: samples that started more than one sample period late [-]
    lost_s: float = 0.0  #: wall-clock time the schedule slipped by in all [s]
    max_late_s: float = 0.0  #: the largest lateness of a sample [s]
    paused_s: float = 0.0  #: wall-clock time paused [s]
    speed: float = 1.0  #: simulated seconds per wall second asked for [-] (1: real time)
    #: simulated times of the first late samples [s] (at most :data:`MAX_LATE_RECORDED`)
    late_at_s: list = dataclasses.field(default_factory=list)

    @property
    def ratio(self) -> float:
        """Simulated seconds per wall second while flying [-]: 1 in real time, below when behind."""
        return self.simulated_s / self.wall_s if self.wall_s > 0 else 1.0

    @property
    def capacity(self) -> float:
        """Simulated seconds per wall second of computation [-]: how many times faster than real
        time the flight could have run (the real-time margin)."""
        return self.simulated_s / self.busy_s if self.busy_s > 0 else float("inf")

    def to_dict(self) -> dict:
        """The record as ``run.json`` holds it.

        Returns
        -------
        dict
        """
        return {"speed": self.speed if math.isfinite(self.speed) else None, "simulated_s": self.simulated_s, "wall_s": self.wall_s, "busy_s": self.busy_s,
                "real_time_ratio": self.ratio, "capacity": self.capacity, "late_samples": self.late_samples,
                "lost_s": self.lost_s, "max_late_s": self.max_late_s, "paused_s": self.paused_s,
                "behind": self.late_samples > 0, "late_at_s": list(self.late_at_s)}


class RealTimeClock:
    """Wall-clock times of a flight's samples: sample k at simulated time t_k is due at
    ``anchor_wall + (t_k - anchor_t)``; :meth:`due` says how long to wait, :meth:`reached` books a
    sample, re-anchoring when it came more than one period late or after a pause.

    Parameters
    ----------
    period_s : float
        The sample period [s] (a lateness of one period of wall time counts as behind).
    now : callable
        Wall clock [s] (default :func:`time.monotonic`).
    speed : float
        Simulated seconds per wall second the schedule asks for [-]: 1 real time, 0.5 slow
        motion, ``inf`` as fast as the computation goes (no waiting, nothing counted late: a
        benchmark's schedule).
    """

    def __init__(self, period_s: float, now=time.monotonic, speed: float = 1.0):
        if not speed > 0:
            raise ValueError(f"speed = {speed!r}: must be > 0 (1 real time, inf as fast as possible)")
        self.period = float(period_s)
        self.now = now
        self.speed = float(speed)
        self.pace = Pace(speed=self.speed)
        self._anchor_wall = self._anchor_t = None
        self._last_return = None
        self._started = self._paused_at = None

    def start(self, t_s: float) -> None:
        """Start the schedule at simulated time ``t_s`` [s], now."""
        self._started = self._anchor_wall = self._last_return = self.now()
        self._anchor_t = float(t_s)

    def arrive(self) -> None:
        """The simulation asks for the next sample's command (its computing stops now)."""
        if self._last_return is not None:
            now = self.now()
            self.pace.busy_s += now - self._last_return
            self._last_return = None

    def wait_s(self, t_s: float) -> float:
        """Wall time [s] until simulated time ``t_s`` is due (<= 0: due or late)."""
        return self._due(t_s) - self.now()

    def _due(self, t_s: float) -> float:
        if math.isinf(self.speed):
            return -math.inf
        return self._anchor_wall + (t_s - self._anchor_t) / self.speed

    def reached(self, t_s: float) -> float:
        """Book the sample at ``t_s`` [s] as reached now; return its lateness [s] (0 if on time).
        Later than one period, the schedule slips to now."""
        now = self.now()
        late = max(now - self._due(t_s), 0.0) if math.isfinite(self.speed) else 0.0
        if late > self.period / self.speed:
            self.pace.late_samples += 1
            self.pace.lost_s += late
            if len(self.pace.late_at_s) < MAX_LATE_RECORDED:
                self.pace.late_at_s.append(float(t_s))
            self._anchor_wall, self._anchor_t = now, float(t_s)
        self.pace.max_late_s = max(self.pace.max_late_s, late)
        self.pace.simulated_s = float(t_s)
        self.pace.wall_s = now - self._started - self.pace.paused_s
        return max(late, 0.0)

    def returned(self, busy_s: float = 0.0) -> None:
        """The sample's command was given back to the simulation (the computing starts again now);
        ``busy_s`` [s] of computing done since :meth:`reached` (drawing the frame) counts too."""
        self.pace.busy_s += busy_s
        self._last_return = self.now()

    def pause(self) -> None:
        """Stop the schedule (a pause: the simulation waits)."""
        if self._paused_at is None:
            self._paused_at = self.now()

    def resume(self, t_s: float) -> None:
        """Go on from simulated time ``t_s`` [s], now (the pause is not counted as late)."""
        if self._paused_at is not None:
            now = self.now()
            self.pace.paused_s += now - self._paused_at
            self._paused_at = None
            self._anchor_wall, self._anchor_t = now, float(t_s)
            self._last_return = now
