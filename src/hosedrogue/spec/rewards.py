"""The rewards of the Gymnasium environments (hosedrogue.envs, docs/gym.md "Reward"), as validated
sections so that the scenario reference page lists their fields with the scenario tables':

* :class:`DockingReward` - ``hosedrogue/Docking-v0``'s: the distance closed, less the control
  effort, plus a bonus or a penalty at the end;
* :class:`DockingRewardV1` - ``hosedrogue/Docking-v1``'s: a capture pays only inside an
  operational closure-speed window, less its radial miss and the probe's load after contact,
  with a potential-based shaping term (Ng, Harada and Russell 1999) that leaves the optimal
  policy unchanged;
* :class:`StationKeepingReward` - ``hosedrogue/StationKeeping-v0``'s: the drogue's squared
  displacement from its balance position and the force spent;
* :class:`WhipReward` - ``hosedrogue/WhipSuppression-v0``'s: the hose's slack and the exit
  tension's excursion after contact, and the take-up command spent.

They are the environments' ``reward=`` keyword (a table of weights), not tables of a scenario file.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import ParameterError
from .fields import Section, real

#: The terminal outcomes both rewards price, besides a capture (the environment's ``info["outcome"]``).
_PENALTIES = {"miss": "miss_penalty", "failed latch": "failed_latch_penalty", "breakaway": "breakaway_penalty",
              "diverged": "failure_penalty"}


@dataclass(frozen=True)
class DockingReward(Section):
    """The reward of one control step (docs/gym.md, "Reward"): the distance the probe closed on
    the drogue, less the control effort, plus a bonus or a penalty when the episode ends::

        r = progress_per_m (d_before - d_after) - control_penalty_1_s |a|^2 dt + terminal

    with d the measured distance from the probe tip to the drogue [m], a the action (the velocity
    command as fractions of the receiver's speed bounds) and dt the control step [s]; ``terminal``
    is ``capture_bonus`` at a capture and minus the penalty of a miss, a failed latch, a breakaway
    or a failed state (a time-out adds nothing: it is a truncation, not an outcome).
    """

    _section = "reward"
    #: reward per metre the probe-drogue distance closes (negative when it opens) [1/m]
    progress_per_m: float = field(default=1.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/m"))
    #: penalty per second of full-scale command on all three axes, |a|^2 dt [1/s]
    control_penalty_1_s: float = field(default=0.01, metadata=real(0.0, 1e6, lo_open=False, unit="1/s"))
    #: bonus of a capture: the probe in the basket within the capture radius and latch window [-]
    capture_bonus: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a miss: the coupler plane crossed beyond the capture radius [-]
    miss_penalty: float = field(default=5.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a failed latch: within the radius, the closure speed outside the window [-]
    failed_latch_penalty: float = field(default=5.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a breakaway: the probe strayed beyond the breakaway distance from the drogue [-]
    breakaway_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a failed state (the simulation diverged) [-]
    failure_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))

    def terminal(self, outcome: str) -> float:
        """The end-of-episode term of an outcome.

        Parameters
        ----------
        outcome : str
            One of :data:`hosedrogue.envs.docking.OUTCOMES`.

        Returns
        -------
        float
        """
        return self.capture_bonus if outcome == "captured" else _penalty(self, outcome)


@dataclass(frozen=True)
class DockingRewardV1(Section):
    """The reward of ``hosedrogue/Docking-v1`` (docs/gym.md, "Reward of Docking-v1")::

        r = F - (time_penalty_1_s + control_penalty_1_s |a|^2) dt + terminal,   F = discount Phi(s') - Phi(s)
        Phi(s) = potential_offset - (radial_per_m rho + axial_per_m |x| + speed_per_m_s e_v),  Phi(end) = 0

    with rho the measured radial offset of the drogue from the probe's line [m], x its distance
    along it [m] and e_v how far the closure speed lies outside [min_closure_m_s,
    max_closure_m_s] [m/s]. F is potential-based shaping (Ng, Harada and Russell 1999): with the
    agent's discount it changes every policy's return by -Phi(s_0) alone, so the optimal policy
    is that of the other terms. The offset keeps Phi positive where the probe is flown, so that
    a step spent waiting costs (1 - discount) Phi instead of paying it; the time penalty, not
    shaping, makes waiting worse than an attempt. At the capture test, within the capture radius and the latch:
    ``capture_bonus - miss_penalty_per_m miss - load_penalty_per_kn F_peak`` inside the window,
    ``-window_penalty - load_penalty_per_kn F_peak`` outside it (F_peak the probe's peak load
    over ``load_window_s`` after contact [kN]); the other outcomes as v0's.
    """

    _section = "reward"
    #: lowest closure speed of the operational window at the coupler plane [m/s]
    min_closure_m_s: float = field(default=1.5, metadata=real(0.0, 10.0, lo_open=False, unit="m/s"))
    #: highest closure speed of the operational window at the coupler plane [m/s]
    max_closure_m_s: float = field(default=2.6, metadata=real(0.0, 10.0, unit="m/s"))
    #: bonus of a capture inside the closure window [-]
    capture_bonus: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty per metre of radial miss at a capture [1/m]
    miss_penalty_per_m: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/m"))
    #: penalty per kN of the probe's peak load over load_window_s after contact [1/kN]
    load_penalty_per_kn: float = field(default=1.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/kN"))
    #: time after contact over which the probe's peak load is taken, the last command held [s]
    load_window_s: float = field(default=0.5, metadata=real(0.0, 5.0, lo_open=False, unit="s"))
    #: penalty of a capture outside the closure window (the latch holds, the operator would not fly it) [-]
    window_penalty: float = field(default=5.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a miss: the coupler plane crossed beyond the capture radius [-]
    miss_penalty: float = field(default=5.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a failed latch: within the radius, the closure speed outside the latch's 0.5-3 m/s [-]
    failed_latch_penalty: float = field(default=5.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a breakaway: the probe strayed beyond the breakaway distance from the drogue [-]
    breakaway_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty of a failed state (the simulation diverged) [-]
    failure_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: penalty per second of full-scale command on all three axes, |a|^2 dt [1/s]
    control_penalty_1_s: float = field(default=0.01, metadata=real(0.0, 1e6, lo_open=False, unit="1/s"))
    #: penalty per second of the episode, a truncated one's included: waiting is not free [1/s]
    time_penalty_1_s: float = field(default=3.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/s"))
    #: shaping potential's value at the drogue, in the window: its positive offset, for a step spent waiting to cost [-]
    potential_offset: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
    #: shaping potential's weight on the radial offset of the drogue from the probe's line [1/m]
    radial_per_m: float = field(default=2.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/m"))
    #: shaping potential's weight on the distance along the line to the drogue [1/m]
    axial_per_m: float = field(default=1.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/m"))
    #: shaping potential's weight on the closure speed's distance outside the window [s/m]
    speed_per_m_s: float = field(default=1.0, metadata=real(0.0, 1e6, lo_open=False, unit="s/m"))
    #: the shaping's discount: the agent's discount factor, for the optimal policy to stay unchanged [-]
    discount: float = field(default=0.99, metadata=real(0.0, 1.0))

    def _check_consistency(self) -> None:
        if not self.min_closure_m_s < self.max_closure_m_s:
            raise ParameterError(f"reward.min_closure_m_s = {self.min_closure_m_s!r}: must be below "
                                 f"reward.max_closure_m_s = {self.max_closure_m_s!r} m/s")

    def potential(self, radial_m: float, axial_m: float, closure_m_s: float) -> float:
        """The shaping potential Phi of a non-terminal state.

        Parameters
        ----------
        radial_m : float
            The drogue's radial offset from the probe's line [m].
        axial_m : float
            The drogue's distance ahead of the probe tip along the line [m].
        closure_m_s : float
            The probe's closure speed on the drogue [m/s].

        Returns
        -------
        float
        """
        outside = max(self.min_closure_m_s - closure_m_s, closure_m_s - self.max_closure_m_s, 0.0)
        cost = self.radial_per_m * radial_m + self.axial_per_m * abs(axial_m) + self.speed_per_m_s * outside
        return self.potential_offset - cost

    def in_window(self, closure_m_s: float) -> bool:
        """Whether a closure speed [m/s] is inside the operational window.

        Parameters
        ----------
        closure_m_s : float
            Closure speed at the coupler plane [m/s].

        Returns
        -------
        bool
        """
        return self.min_closure_m_s <= closure_m_s <= self.max_closure_m_s

    def capture_terms(self, closure_m_s: float, miss_m: float, peak_load_n: float) -> dict:
        """The terminal terms of a capture (the latch held).

        Parameters
        ----------
        closure_m_s : float
            Closure speed at the coupler plane [m/s].
        miss_m : float
            Radial miss [m].
        peak_load_n : float
            The probe's peak load over ``load_window_s`` after contact [N].

        Returns
        -------
        dict
            ``capture`` (the bonus or minus the window's penalty), ``miss`` and ``load``.
        """
        inside = self.in_window(closure_m_s)
        return {"capture": self.capture_bonus if inside else -self.window_penalty,
                "miss": -self.miss_penalty_per_m * miss_m if inside else 0.0,
                "load": -self.load_penalty_per_kn * peak_load_n / 1000.0}

    def terminal(self, outcome: str) -> float:
        """The terminal term of an outcome other than a capture (0 for none).

        Parameters
        ----------
        outcome : str
            One of :data:`hosedrogue.envs.docking_v1.OUTCOMES_V1`.

        Returns
        -------
        float
        """
        return _penalty(self, outcome)


def _penalty(reward, outcome: str) -> float:
    """Minus the penalty of a miss, a failed latch, a breakaway or a failed state; 0 for another outcome."""
    return -getattr(reward, _PENALTIES[outcome]) if outcome in _PENALTIES else 0.0


@dataclass(frozen=True)
class StationKeepingReward(Section):
    """The reward of ``hosedrogue/StationKeeping-v0`` (docs/gym.md, "Station keeping"): the
    drogue's squared displacement from its balance position and the force spent, per second::

        r = -(position_per_m2 (dy^2 + dz^2) + control_penalty_1_s |a|^2) dt - terminal

    with dy, dz the drogue's lateral and vertical displacement [m] (the axes its force acts on),
    a the action (the force as fractions of the actuator's bound) and dt the control step [s];
    ``terminal`` is ``failure_penalty`` when the simulation fails, else 0.
    """

    _section = "reward"
    #: penalty per second of squared lateral and vertical displacement from the balance position [1/(m^2 s)]
    position_per_m2: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/(m^2 s)"))
    #: penalty per second of full-scale force on both axes, |a|^2 dt [1/s]
    control_penalty_1_s: float = field(default=0.01, metadata=real(0.0, 1e6, lo_open=False, unit="1/s"))
    #: penalty of a failed state (the simulation diverged) [-]
    failure_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))


@dataclass(frozen=True)
class WhipReward(Section):
    """The reward of ``hosedrogue/WhipSuppression-v0`` (docs/gym.md, "Whip suppression"): the
    hose's slack and the exit tension's excursion from the trail tension, per second::

        r = -(slack_per_m s + tension_per_kn |T_0 - T_trail| / 1000 + control_penalty_1_s a^2) dt - terminal

    with s the slack [m] (the hose length less the drogue's distance from the tow point, floored
    at 0), T_0 the tension at the hose exit [N], T_trail its value at contact [N], a the action
    (the take-up speed as a fraction of the reel's bound) and dt the control step [s];
    ``terminal`` is ``failure_penalty`` when the run fails (a failed state or a drum end stop).
    """

    _section = "reward"
    #: penalty per second of a metre of slack [1/(m s)]
    slack_per_m: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/(m s)"))
    #: penalty per second of a kN of exit tension away from the trail tension at contact [1/(kN s)]
    tension_per_kn: float = field(default=1.0, metadata=real(0.0, 1e6, lo_open=False, unit="1/(kN s)"))
    #: penalty per second of a full-scale take-up or payout command, a^2 dt [1/s]
    control_penalty_1_s: float = field(default=0.01, metadata=real(0.0, 1e6, lo_open=False, unit="1/s"))
    #: penalty of a failed run (a failed state or a drum end stop) [-]
    failure_penalty: float = field(default=10.0, metadata=real(0.0, 1e6, lo_open=False))
