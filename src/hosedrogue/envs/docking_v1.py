"""The docking environment's second version, ``hosedrogue/Docking-v1`` (docs/gym.md,
"Docking-v1"): the same flight as v0's, with

* a reward that cannot be gamed by speed (:class:`~hosedrogue.spec.rewards.DockingRewardV1`):
  a capture pays only inside an operational closure-speed window, less its radial miss and the
  probe's peak load after contact; a potential-based shaping term makes a slow, precise approach
  learnable without changing the optimal policy, and a time penalty makes waiting cost more
  than an attempt; every term in ``info["reward_terms"]``;
* Gymnasium's conventions: float32 spaces, the observation divided by :data:`OBSERVATION_SCALE`,
  the time limit in the registered spec (``max_episode_steps``, Gymnasium's TimeLimit);
* randomized episodes and curricula (:mod:`hosedrogue.envs.randomize`) through the constructor's
  ``randomize=`` and ``reset(options={"randomize": ...})``, the seed deciding every draw.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from gymnasium import spaces

from ..errors import ParameterError
from ..model.sampled import M_REL, M_REL_V
from ..scenarios import Scenario
from ..spec.rewards import DockingRewardV1
from . import randomize as RZ
from .docking import OUTCOMES, POSITION_BOUND_M, VELOCITY_BOUND_M_S, DockingEnv

#: The observation's unit per component: v1's observation is the measurement divided by it
#: (3 m, the start's standoff, for the relative position; 3 m/s, the latch's highest closure
#: speed, for every velocity; 1 m for the drogue's displacement from its balance position).
OBSERVATION_SCALE = np.array([3.0] * 3 + [3.0] * 9 + [1.0] * 3)
#: How a v1 episode ends (``info["outcome"]``): v0's, and a capture outside the closure window.
OUTCOMES_V1 = (*OUTCOMES, "outside window")
#: Steps of the registered spec's TimeLimit: the default 10 s at the default 0.02 s control step.
MAX_EPISODE_STEPS = 500
#: The options ``reset`` takes.
RESET_OPTIONS = ("turbulence_seed", "randomize")


class DockingEnvV1(DockingEnv):
    """The receiver's probe flown toward the drogue, scored as an operator would (docs/gym.md,
    "Docking-v1"). Action and observation as :class:`~hosedrogue.envs.docking.DockingEnv`'s, in
    float32, the observation divided by :data:`OBSERVATION_SCALE`.

    Parameters
    ----------
    render_mode : str, optional
        None or "rgb_array".
    scenario : str, Path or Scenario
        The engagement flown (default "approach-moderate").
    turbulence, bow_wave, reel, drogue_controller, model : optional
        As :class:`~hosedrogue.envs.docking.DockingEnv`'s (None: the scenario's).
    control_step_s : float
        Time between actions [s].
    time_limit_s : float
        The length of the episode's gust record [s], in (0, 600]: the episode is truncated there
        if the spec's ``max_episode_steps`` has not truncated it before (by default both at 10 s).
    breakaway_distance_m : float
        Breakaway distance [m].
    reward : DockingRewardV1 or dict, optional
        The reward's weights and closure window (:class:`~hosedrogue.spec.rewards.DockingRewardV1`).
    randomize : bool or dict, optional
        The episodes' randomization (:mod:`hosedrogue.envs.randomize`): True for its default
        ranges, or ``{name: (low, high) or value}``; None: every episode the scenario's.
    receiver_model : str, optional
        The receiver as an aircraft ("f16" or a model file; v0's option).
    """

    _reward_kind = DockingRewardV1
    _STATE = (*DockingEnv._STATE, "_ranges", "_values", "_potential", "_peak_load_n")
    observation_scale = OBSERVATION_SCALE

    def __init__(self, render_mode: str | None = None, *, scenario: str | Path | Scenario = "approach-moderate",
                 turbulence: str | float | None = None, bow_wave: bool | None = None, reel: str | None = None,
                 drogue_controller: str | None = None, model: str | None = None, control_step_s: float = 0.02,
                 time_limit_s: float = 10.0, breakaway_distance_m: float = 6.0,
                 reward: DockingRewardV1 | dict | None = None, randomize: bool | dict | None = None,
                 receiver_model: str | None = None):
        self._ranges = RZ.ranges(randomize)
        super().__init__(render_mode, scenario=scenario, turbulence=turbulence, bow_wave=bow_wave, reel=reel,
                         drogue_controller=drogue_controller, model=model, control_step_s=control_step_s,
                         time_limit_s=time_limit_s, breakaway_distance_m=breakaway_distance_m, reward=reward,
                         receiver_model=receiver_model)
        self.base_scenario = self.scenario
        RZ.check_start(self._ranges, self.scenario.engagement.probe, self.breakaway_distance_m)
        high = np.concatenate([[POSITION_BOUND_M] * 3, [VELOCITY_BOUND_M_S] * 9, [POSITION_BOUND_M] * 3])
        high = (high / OBSERVATION_SCALE).astype(np.float32)
        self.observation_space = spaces.Box(-high, high, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(3,), dtype=np.float32)
        self._values, self._potential, self._peak_load_n = {}, 0.0, math.nan

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: its turbulence seed, then (with a randomization) its drawn values,
        from the environment's generator.

        Parameters
        ----------
        seed : int, optional
            Seeds the environment's generator.
        options : dict, optional
            ``"turbulence_seed"``: this episode's gusts; ``"randomize"``: the randomization from
            this episode on (a curriculum), as the constructor's ``randomize``.

        Returns
        -------
        observation : numpy.ndarray (15,) float32
        info : dict
            As v0's, with ``randomized`` (the drawn values).
        """
        options = dict(options or {})
        unknown = [k for k in options if k not in RESET_OPTIONS]
        if unknown:
            raise ParameterError(f"options: unknown key(s) {', '.join(map(repr, unknown))}; allowed: "
                                 f"{', '.join(map(repr, RESET_OPTIONS))}")
        if "randomize" in options:
            table = RZ.ranges(options.pop("randomize"))
            RZ.check_start(table, self.base_scenario.engagement.probe, self.breakaway_distance_m)
            self._ranges = table
        if seed is not None:
            super(DockingEnv, self).reset(seed=seed)
        if options.get("turbulence_seed") is None:
            options["turbulence_seed"] = int(self.np_random.integers(0, 2**63 - 1))
        values = RZ.draw(self._ranges, self.np_random)
        if values or self._values:  # this episode or the last one randomized
            scenario = RZ.episode_scenario(self.base_scenario, values, self.control_step_s) if values else \
                self.base_scenario
            self._build(scenario, self.control_step_s)
            self._renderer = None
        self._values, self._peak_load_n = values, math.nan
        obs, info = super().reset(options=options)
        self._potential = self._phi(self.stepper.measurement.as_array())
        info.update(reward_terms=self._terms(), randomized=dict(values))
        return self._normalize(obs), info

    def step(self, action):
        """Hold the velocity command of ``action`` for one control step (as v0's).

        Parameters
        ----------
        action : array_like (3,)
            Fractions of the receiver's speed bounds [-], forward, right, down; clipped to [-1, 1].

        Returns
        -------
        observation : numpy.ndarray (15,) float32
        reward : float
            The sum of ``info["reward_terms"]``.
        terminated, truncated : bool
        info : dict
            As v0's, without a number the capture test has not given (v0's None), with
            ``peak_load_n`` at a capture and ``randomized``.
        """
        a = self._action(action)
        buf, obs, distance, outcome = self._advance(a)
        w = self.reward_weights
        terms = self._terms(control=-w.control_penalty_1_s * float(a @ a) * self.control_step_s,
                            time=-w.time_penalty_1_s * self.control_step_s)
        t_s = self.stepper.t_s  # the step's time, before the load window's steps
        if outcome == "captured":
            out = self.stepper.outcome
            self._peak_load_n = self._load_after_contact()
            terms.update(w.capture_terms(out["closure_speed_m_s"], out["miss_distance_m"], self._peak_load_n))
            if not w.in_window(out["closure_speed_m_s"]):
                outcome = "outside window"
        else:
            terms["terminal"] = w.terminal(outcome)
        ended = outcome != "approaching"
        potential = 0.0 if ended and outcome != "time-out" else self._phi(buf)
        terms["shaping"] = float(w.discount * potential - self._potential)
        self._potential, self._distance, self._outcome = potential, distance, outcome
        info = self._info(buf, terms)
        info.update(t_s=t_s, randomized=dict(self._values))
        return self._normalize(obs), float(sum(terms.values())), ended and outcome != "time-out", \
            outcome == "time-out", info

    def _info(self, buf: np.ndarray, terms: dict) -> dict:
        """v0's info without the numbers not known yet (the capture test's before it decides, the
        peak load but at a capture): one type per key, as a vector environment's batched info
        needs (its ``_key`` mask says who has the key)."""
        info = super()._info(buf, terms)
        info["peak_load_n"] = None if math.isnan(self._peak_load_n) else self._peak_load_n
        for key in ("miss_distance_m", "closure_speed_m_s", "contact_time_s", "peak_load_n"):
            if info[key] is None:
                del info[key]
        return info

    @staticmethod
    def _terms(**given) -> dict:
        """Every term of v1's reward, zero unless given."""
        return {"shaping": 0.0, "time": 0.0, "control": 0.0, "terminal": 0.0, "capture": 0.0, "miss": 0.0, "load": 0.0,
                **given}

    def _phi(self, buf: np.ndarray) -> float:
        """The shaping potential of a measurement (0 for a failed one)."""
        x, y, z, vx = buf[M_REL], buf[M_REL + 1], buf[M_REL + 2], buf[M_REL_V]
        phi = self.reward_weights.potential(math.hypot(y, z), x, -vx)
        return phi if math.isfinite(phi) else self._potential

    def _load_after_contact(self) -> float:
        """The probe's peak load [N] over the reward's load window after the capture, the last
        command held (the episode has ended: these steps are not the agent's)."""
        st, peak = self.stepper, float(np.linalg.norm(self.stepper.probe_force_n))
        end = st.t_s + self.reward_weights.load_window_s - 1e-9
        while not st.done and st.t_s < end:
            st.step(receiver=self._command)
            peak = max(peak, float(np.linalg.norm(st.probe_force_n)))
        return peak

    def _normalize(self, obs: np.ndarray) -> np.ndarray:
        out = (obs / OBSERVATION_SCALE).astype(np.float32)
        return np.clip(out, self.observation_space.low, self.observation_space.high, out=out)
