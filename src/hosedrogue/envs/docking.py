"""The docking environment, ``hosedrogue/Docking-v0`` (docs/gym.md): the agent flies the
receiver's probe toward the drogue in turbulence by a velocity command, one control step at a
time, on the engagement's stepper (:class:`hosedrogue.engagement.EngagementStepper`: the compiled
loop of the hose, reel, drogue, probe, bow wave and capture test runs between two actions).

The structure is Gymnasium's classic-control one: the spaces are declared in ``__init__``,
``reset(seed=...)`` seeds the environment's one generator (``super().reset``) from which each
episode draws its turbulence seed, ``step`` returns ``(obs, reward, terminated, truncated, info)``,
and ``render()`` draws an RGB array (matplotlib's Agg canvas, no display).
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import gymnasium
import numpy as np
from gymnasium import spaces

from ..engagement.stepper import EngagementStepper
from ..errors import ParameterError
from ..model.sampled import (M_BALANCE, M_COUPLED, M_DROGUE, M_DROGUE_V, M_L, M_PROBE, M_PROBE_V, M_REEL_V,
                             M_REL, M_REL_V, M_T, M_T0)
from ..scenarios import Scenario
from ..scenarios.runner import drogue_controller as design_drogue_controller
from .options import DockingReward, docking_scenario, episode_receiver, reward_weights

#: The observation's components, in order: (name, unit). All in the tanker frame S_p (x forward,
#: y right, z down), from the measurement (the sensor's noise and delay included).
OBSERVATION = (
    ("relative_x_m", "m"), ("relative_y_m", "m"), ("relative_z_m", "m"),  # drogue minus probe tip
    ("relative_vx_m_s", "m/s"), ("relative_vy_m_s", "m/s"), ("relative_vz_m_s", "m/s"),
    ("probe_vx_m_s", "m/s"), ("probe_vy_m_s", "m/s"), ("probe_vz_m_s", "m/s"),  # the receiver's own speed
    ("drogue_vx_m_s", "m/s"), ("drogue_vy_m_s", "m/s"), ("drogue_vz_m_s", "m/s"),
    ("drogue_dx_m", "m"), ("drogue_dy_m", "m"), ("drogue_dz_m", "m"),  # drogue minus its balance position
)
#: Bounds of the observation's positions [m] and velocities [m/s]: the values are clipped to
#: them (reached only past a breakaway or in a failed state).
POSITION_BOUND_M = 20.0
VELOCITY_BOUND_M_S = 20.0
#: How an episode ends (``info["outcome"]``); "approaching" while it runs.
OUTCOMES = ("approaching", "captured", "miss", "failed latch", "breakaway", "diverged", "time-out")
#: Largest breakaway distance [m] (below the observation's position bound).
MAX_BREAKAWAY_M = 15.0

#: Where the observation's components are in the measurement's array (``hosedrogue.model.sampled.M_*``).
_OBS_INDEX = np.r_[M_REL:M_REL + 3, M_REL_V:M_REL_V + 3, M_PROBE_V:M_PROBE_V + 3, M_DROGUE_V:M_DROGUE_V + 3,
                   M_DROGUE:M_DROGUE + 3]
#: The measurement's vectors in ``info["measurement"]``: name -> start in its array.
_MEASURED = {"drogue_position_m": M_DROGUE, "drogue_velocity_m_s": M_DROGUE_V, "probe_position_m": M_PROBE,
             "probe_velocity_m_s": M_PROBE_V, "relative_position_m": M_REL, "relative_velocity_m_s": M_REL_V,
             "drogue_balance_m": M_BALANCE}


class DockingEnv(gymnasium.Env):
    """The receiver's probe flown toward the drogue in turbulence (docs/gym.md).

    Action: the probe tip's velocity command (v_x, v_y, v_z) as fractions of the receiver's speed
    bounds, each in [-1, 1] (``command = action * max_speed_m_s``, default (3, 1, 1) m/s forward,
    right, down), followed through the receiver's lag and acceleration bound. Observation: 15
    numbers of :data:`OBSERVATION` [m, m/s]. An episode ends at the capture test (the coupler
    plane crossed: captured, miss or failed latch), at a breakaway or a failed state
    (terminated), or at the time limit (truncated).

    Parameters
    ----------
    render_mode : str, optional
        None or "rgb_array" (:meth:`render` returns an (H, W, 3) uint8 image).
    scenario : str, Path or Scenario
        The engagement flown (default the shipped "approach-moderate": 150 m/s, 8000 m, the
        converged 20-link model, responsive reel, bow wave, probe 3 m behind the drogue).
    turbulence : str or float, optional
        "none", "light", "moderate", "severe" (MIL-F-8785C at the altitude) or an isotropic
        intensity [m/s]; None: the scenario's.
    bow_wave : bool, optional
        The receiver's bow wave on or off; None: the scenario's.
    reel : str, optional
        Reel law "locked", "constant-tension" or "response"; None: the scenario's.
    drogue_controller : str, optional
        The drogue's built-in controller "none", "pid" or "lqr"; None: the scenario's.
    model : str, optional
        Model preset "converged" or "paper"; None: the scenario's.
    control_step_s : float
        Time between actions [s], a whole multiple of the scenario's RK4 step.
    time_limit_s : float
        Episode length [s] (truncation), in (0, 600].
    breakaway_distance_m : float
        The episode ends (breakaway) when the measured probe-drogue distance exceeds this [m].
    reward : DockingReward or dict, optional
        The reward's weights (:class:`~hosedrogue.envs.options.DockingReward`).
    receiver_model : str, optional
        The receiver as an aircraft: "f16" or a receiver model file (docs/receiver.md), trimmed behind
        the tanker, the action its inner loop's velocity command (None: the scenario's ``[receiver]
        model``; "" the point receiver).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}
    _reward_kind = DockingReward
    #: what :meth:`get_state` keeps: every attribute an episode changes
    _STATE = ("scenario", "receiver", "stepper", "max_speed_m_s", "turbulence_seed", "_distance", "_last_obs",
              "_command", "_outcome", "_np_random", "_np_random_seed")
    #: the observation's unit per component (v0: 1, the observation in m and m/s)
    observation_scale = np.ones(len(OBSERVATION))

    def __init__(self, render_mode: str | None = None, *, scenario: str | Path | Scenario = "approach-moderate",
                 turbulence: str | float | None = None, bow_wave: bool | None = None, reel: str | None = None,
                 drogue_controller: str | None = None, model: str | None = None, control_step_s: float = 0.02,
                 time_limit_s: float = 10.0, breakaway_distance_m: float = 6.0,
                 reward: DockingReward | dict | None = None, receiver_model: str | None = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ParameterError(f"render_mode = {render_mode!r}: must be None or 'rgb_array'")
        self.render_mode = render_mode
        self.scenario = docking_scenario(scenario, turbulence=turbulence, bow_wave=bow_wave, reel=reel,
                                         drogue_controller=drogue_controller, model=model, time_limit_s=time_limit_s,
                                         receiver_model=receiver_model)
        if isinstance(breakaway_distance_m, bool) or not isinstance(breakaway_distance_m, (int, float)) or not (
                0 < breakaway_distance_m <= MAX_BREAKAWAY_M):
            raise ParameterError(f"breakaway_distance_m = {breakaway_distance_m!r}: must be a finite number in "
                                 f"(0, {MAX_BREAKAWAY_M:g}] m")
        self.breakaway_distance_m = float(breakaway_distance_m)
        self.reward_weights = reward_weights(reward, self._reward_kind)
        self._build(self.scenario, control_step_s)
        self.control_step_s = self.stepper.control_step_s
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.control_step_s}
        self.action_space = spaces.Box(-1.0, 1.0, shape=(3,), dtype=np.float64)
        bound = np.array([POSITION_BOUND_M] * 3 + [VELOCITY_BOUND_M_S] * 9 + [POSITION_BOUND_M] * 3)
        self.observation_space = spaces.Box(-bound, bound, dtype=np.float64)
        self._low, self._high = -bound, bound
        self.turbulence_seed = None
        self._distance = math.nan
        self._obs = np.zeros(len(OBSERVATION))
        self._last_obs = np.zeros(len(OBSERVATION))
        self._command = np.zeros(3)
        self._outcome = "approaching"
        self._renderer = None

    def _build(self, scenario: Scenario, control_step_s: float) -> None:
        """The stepper of a scenario, the receiver and its speed bounds."""
        sc, e = scenario, scenario.engagement
        self.scenario = sc
        self.receiver = episode_receiver(sc)
        kind = EngagementStepper
        if self.receiver.model:  # the aircraft: the action is its inner loop's velocity command
            from ..engagement.aircraft_receiver import AircraftEngagementStepper as kind
        self.stepper = kind(
            sc.params, sc.duration_s, control_step_s=control_step_s, reel=e.reel, probe=e.probe,
            bow_wave=e.bow_wave, receiver=self.receiver, control=design_drogue_controller(sc), actuator=sc.loop.actuator,
            sensor=sc.loop.sensor, drogue_actuator=sc.loop.drogue_actuator, record=False)
        #: the receiver's speed bounds [m/s]: an action of 1 commands them
        self.max_speed_m_s = np.array(self.receiver.max_speed_m_s, dtype=np.float64)

    # --- snapshots -------------------------------------------------------------------------------------
    def get_state(self) -> dict:
        """A snapshot of everything that evolves: the run, the episode's bookkeeping and the
        environment's generator (docs/gym.md, "Snapshots"). :meth:`set_state` of it, on this
        environment or on another made with the same arguments, continues bit for bit as this one
        does from here. The snapshot is a deep copy (about 0.1 MB): keep it, pickle it, restore it
        as often as wanted.

        Returns
        -------
        dict
        """
        return copy.deepcopy({name: self.__dict__[name] for name in self._STATE if name in self.__dict__})

    def set_state(self, state: dict) -> None:
        """Restore a snapshot of :meth:`get_state` (copied, so it can be restored again).

        Parameters
        ----------
        state : dict
            From :meth:`get_state` of an environment made with the same arguments.
        """
        if not isinstance(state, dict) or set(state) - set(self._STATE) or "stepper" not in state:
            raise ParameterError("state: must be a dict from get_state() of this kind of environment")
        self.__dict__.update(copy.deepcopy(state))
        self._renderer = None

    def __getstate__(self) -> dict:
        """Pickled and deep-copied without the picture's figure (drawn again on the next render)."""
        return {**self.__dict__, "_renderer": None}

    # --- the episode -------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: the probe at the scenario's start point, the hose at rest in its
        balance position, the turbulence of a seed drawn from the environment's generator (or
        ``options["turbulence_seed"]``).

        Parameters
        ----------
        seed : int, optional
            Seeds the environment's generator (Gymnasium's rule: the same seed, the same episodes).
        options : dict, optional
            ``{"turbulence_seed": k}``: this episode's turbulence and sensor-noise seed, >= 0 (a
            campaign's run ``i`` has ``hosedrogue.studies.seeds.run_seed(campaign_seed, i)``).

        Returns
        -------
        observation : numpy.ndarray (15,)
        info : dict
        """
        super().reset(seed=seed)
        options = dict(options or {})
        turbulence_seed = options.pop("turbulence_seed", None)
        if options:
            raise ParameterError(f"options: unknown key(s) {', '.join(map(repr, options))}; allowed: 'turbulence_seed'")
        if turbulence_seed is None:
            turbulence_seed = int(self.np_random.integers(0, 2**63 - 1))
        m = self.stepper.reset(seed=turbulence_seed)
        self.turbulence_seed = int(turbulence_seed)
        buf = m.as_array()
        self._distance = math.hypot(buf[M_REL], buf[M_REL + 1], buf[M_REL + 2])
        self._outcome = "approaching"
        self._command = np.zeros(3)
        obs = self._observe(buf)
        return obs, self._info(buf, {"progress": 0.0, "control": 0.0, "terminal": 0.0})

    def step(self, action):
        """Hold the velocity command of ``action`` for one control step.

        Parameters
        ----------
        action : array_like (3,)
            Fractions of the receiver's speed bounds [-], forward, right, down; clipped to [-1, 1].

        Returns
        -------
        observation : numpy.ndarray (15,)
        reward : float
        terminated : bool
            The capture test decided (captured, miss, failed latch), a breakaway, or a failed state.
        truncated : bool
            The time limit.
        info : dict
            ``outcome`` (:data:`OUTCOMES`), the capture test's ``result``, ``miss_distance_m``,
            ``closure_speed_m_s``, ``contact_time_s``, ``t_s``, ``distance_m``, ``command_m_s``,
            ``reward_terms``, ``turbulence_seed`` and the ``measurement`` (its attributes).
        """
        a = self._action(action)
        buf, obs, distance, outcome = self._advance(a)
        w = self.reward_weights
        terms = {"progress": w.progress_per_m * (self._distance - distance),
                 "control": -w.control_penalty_1_s * float(a @ a) * self.control_step_s,
                 "terminal": w.terminal(outcome)}
        self._distance = distance
        self._outcome = outcome
        terminated = outcome not in ("approaching", "time-out")
        truncated = outcome == "time-out"
        return obs, terms["progress"] + terms["control"] + terms["terminal"], terminated, truncated, \
            self._info(buf, terms)

    def _advance(self, a: np.ndarray) -> tuple:
        """One control step of the command of action ``a``: the measurement's array, the
        observation, the probe-drogue distance (the last one in a failed state: no progress
        counted) and the outcome."""
        self._command = a * self.max_speed_m_s
        buf = self.stepper.step(receiver=self._command).as_array()
        obs = self._observe(buf)
        distance = math.hypot(buf[M_REL], buf[M_REL + 1], buf[M_REL + 2])
        if not math.isfinite(distance):
            distance = self._distance
        return buf, obs, distance, self._classify(distance)

    def _action(self, action) -> np.ndarray:
        """The action as 3 float64 numbers clipped to [-1, 1]; an episode that has ended refused."""
        if self.stepper.done or self._outcome != "approaching":
            raise RuntimeError(f"the episode has ended ({self._outcome}); call reset() to start another")
        try:
            a = np.clip(np.asarray(action, dtype=np.float64).reshape(3), -1.0, 1.0)
        except (TypeError, ValueError):
            a = None
        if a is None or not math.isfinite(a[0] + a[1] + a[2]):
            raise ParameterError(f"action = {action!r}: must be 3 finite numbers in [-1, 1]")
        return a

    def _classify(self, distance: float) -> str:
        """The outcome after a step: the capture test first, then a failed state, a breakaway, the time limit."""
        st = self.stepper
        result = st.outcome["result"]
        if result == "captured":
            return "captured"
        if result.startswith("miss"):
            return "miss"
        if result.startswith("failed latch"):
            return "failed latch"
        if st.done and not st.completed:
            return "diverged"
        if distance > self.breakaway_distance_m:
            return "breakaway"
        return "time-out" if st.done else "approaching"

    def _observe(self, buf: np.ndarray) -> np.ndarray:
        """The observation of a measurement's array: clipped to the space; in a failed state the last valid one."""
        obs = buf[_OBS_INDEX]
        obs[12:15] -= buf[M_BALANCE:M_BALANCE + 3]
        if math.isfinite(obs.sum()):
            np.clip(obs, self._low, self._high, out=obs)
            self._last_obs = obs
        else:
            obs = self._last_obs
        return obs.copy()

    def _info(self, buf: np.ndarray, terms: dict) -> dict:
        """The step's info: the outcome, the capture test's numbers and the measurement (views of
        ``buf``, a copy made for this step)."""
        st, out = self.stepper, self.stepper.outcome
        measurement = {name: buf[i:i + 3] for name, i in _MEASURED.items()}
        measurement.update(t_s=float(buf[M_T]), hose_length_m=float(buf[M_L]), reel_speed_m_s=float(buf[M_REEL_V]),
                           exit_tension_n=float(buf[M_T0]), coupled=bool(buf[M_COUPLED] != 0.0))
        contact = out.get("contact_time_s")
        return {"outcome": self._outcome, "result": out["result"], "miss_distance_m": out.get("miss_distance_m"),
                "closure_speed_m_s": out.get("closure_speed_m_s"),
                "contact_time_s": None if contact is None else float(contact), "t_s": st.t_s,
                "distance_m": self._distance, "command_m_s": self._command.copy(), "reward_terms": dict(terms),
                "turbulence_seed": self.turbulence_seed, "message": st.message, "measurement": measurement}

    # --- drawing -----------------------------------------------------------------------------------
    def render(self):
        """The run as it is now, seen from behind and from the side (``render_mode="rgb_array"``).

        Returns
        -------
        numpy.ndarray (H, W, 3) uint8 or None
            None without a render mode.
        """
        if self.render_mode is None:
            gymnasium.logger.warn("render() without a render_mode: make the environment with render_mode='rgb_array'")
            return None
        if self._renderer is None:
            from .render import DockingRenderer

            e = self.scenario.engagement
            self._renderer = DockingRenderer(self.stepper.balance, e.probe.standoff_m, e.probe.capture_radius_m)
        joints, probe = self.stepper.hose_shape()
        return self._renderer.draw(self.stepper.t_s, joints, probe, self._outcome)

    def close(self):
        """Release the figure of :meth:`render`."""
        self._renderer = None
