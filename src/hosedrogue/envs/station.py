"""``hosedrogue/StationKeeping-v0`` (docs/gym.md, "Station keeping"): the agent is the actuated
drogue, holding its balance position in turbulence by a lateral and vertical force, one control
step at a time, on the fixed-length stepper (:class:`hosedrogue.simulation.stepper.FixedLengthStepper`:
the compiled loop of the trailed hose, its drogue and the force's actuator runs between two
actions). No receiver: the hose trails behind the tanker at its fixed length.

A scripted baseline, :class:`StationPD`, pushes the drogue back by the paper's PID gains without
the integrator (the paper's Eq. 33 PD part on the measured displacement and velocity).
"""

from __future__ import annotations

from pathlib import Path

import gymnasium
import numpy as np
from gymnasium import spaces

from ..errors import ParameterError
from ..scenarios import Scenario, scenario_from_dict
from ..simulation.budget import positive_number
from ..simulation.stepper import FixedLengthStepper
from ..spec.rewards import StationKeepingReward
from ..spec.sections import Actuator
from .options import on_grid, reward_weights, set_turbulence
from .task_common import checked_action, scaled, scenario_source, turbulence_seed_option

#: The observation's components: (name, unit, scale); the observation is each divided by its scale.
STATION_OBSERVATION = (
    ("drogue_dx_m", "m", 1.0), ("drogue_dy_m", "m", 1.0), ("drogue_dz_m", "m", 1.0),  # minus its balance position
    ("drogue_vx_m_s", "m/s", 3.0), ("drogue_vy_m_s", "m/s", 3.0), ("drogue_vz_m_s", "m/s", 3.0),
)
#: The observation's scale per component [m, m/s]: 1 m, the drogue's swing in severe turbulence;
#: 3 m/s for the velocities.
STATION_SCALE = np.array([s for _, _, s in STATION_OBSERVATION])
#: The observation's bound (after scaling): 20 m and 20 m/s, reached only in a failed state.
_BOUND = np.array([20.0] * 3 + [20.0 / 3.0] * 3)
#: Steps of the registered spec's TimeLimit: the default 10 s at the default 0.02 s control step.
STATION_STEPS = 500
#: How a station-keeping episode ends (``info["outcome"]``); "holding" while it runs.
STATION_OUTCOMES = ("holding", "time-out", "diverged")


def station_scenario(scenario: str | Path | Scenario = "approach-moderate", turbulence=None,
                     time_limit_s: float = 10.0) -> Scenario:
    """The scenario a station-keeping episode runs: its model, flight and turbulence (its probe,
    reel and bow wave are not flown), the turbulence option applied, its duration the episode's.

    Parameters
    ----------
    scenario : str, Path or Scenario
        A shipped name, a TOML file or a Scenario whose integrator is RK4.
    turbulence : str or float, optional
        "none", "light", "moderate", "severe" or an isotropic intensity [m/s]; None: the scenario's.
    time_limit_s : float
        The episode's length [s], in (0, 600].

    Returns
    -------
    Scenario
    """
    limit = positive_number("time_limit_s", time_limit_s, 600.0)
    base, source, tables, name = scenario_source(scenario)
    set_turbulence(tables, turbulence, base, limit)
    tables["scenario"] = {**tables.get("scenario", {}), "duration_s": limit}
    out = on_grid(scenario_from_dict(tables, name=name, source=source))
    if out.params.numerics.integrator != "rk4":
        raise ParameterError(f"scenario = {name!r}: numerics.integrator = {out.params.numerics.integrator!r}: "
                             "station keeping steps the fixed-length RK4 loop; give a scenario with 'rk4'")
    return out


class StationKeepingEnv(gymnasium.Env):
    """The actuated drogue holding its balance position in turbulence (docs/gym.md, "Station keeping").

    Action: the drogue's force (u_y, u_z), lateral and vertical, as fractions of ``max_force_n``,
    each in [-1, 1] (clipped). Observation: :data:`STATION_OBSERVATION`, each divided by its
    scale, float32. An episode lasts ``time_limit_s`` (truncated) unless the simulation fails
    (terminated).

    Parameters
    ----------
    render_mode : None
        No picture.
    scenario : str, Path or Scenario
        The model, flight and turbulence (default "approach-moderate": 150 m/s, 8000 m, the
        converged 20-link model, RK4 at 5 ms, MIL-F-8785C moderate turbulence).
    turbulence : str or float, optional
        As :class:`~hosedrogue.envs.docking.DockingEnv`'s (None: the scenario's).
    max_force_n : float
        The actuator's bound per axis [N] (an action of 1 commands it), in (0, 10000]; default
        100 N, at which the paper's PID keeps its capture rate in moderate turbulence (docs/docking-results.md).
    control_step_s : float
        Time between actions [s], a whole multiple of the scenario's RK4 step.
    time_limit_s : float
        Episode length [s], in (0, 600].
    reward : StationKeepingReward or dict, optional
        The reward's weights (:class:`~hosedrogue.spec.rewards.StationKeepingReward`).
    """

    metadata = {"render_modes": [], "render_fps": 50}

    def __init__(self, render_mode: str | None = None, *, scenario: str | Path | Scenario = "approach-moderate",
                 turbulence: str | float | None = None, max_force_n: float = 100.0, control_step_s: float = 0.02,
                 time_limit_s: float = 10.0, reward: StationKeepingReward | dict | None = None):
        if render_mode is not None:
            raise ParameterError(f"render_mode = {render_mode!r}: must be None (no picture)")
        self.render_mode = None
        self.scenario = station_scenario(scenario, turbulence, time_limit_s)
        self.max_force_n = positive_number("max_force_n", max_force_n, 1e4, unit="N")
        self.reward_weights = reward_weights(reward, StationKeepingReward)
        self.stepper = FixedLengthStepper(self.scenario.params, self.scenario.duration_s,
                                          control_step_s=control_step_s, actuator=Actuator(max_force_n=self.max_force_n),
                                          record=False)
        self.control_step_s = self.stepper.control_step_s
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.control_step_s}
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.observation_space = spaces.Box(-_BOUND.astype(np.float32), _BOUND.astype(np.float32), dtype=np.float32)
        self.turbulence_seed, self._outcome, self._last = None, "holding", np.zeros(len(STATION_OBSERVATION))

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: the hose at rest in its balance position, the turbulence of a seed drawn
        from the environment's generator (or ``options["turbulence_seed"]``).

        Parameters
        ----------
        seed : int, optional
            Seeds the environment's generator.
        options : dict, optional
            ``{"turbulence_seed": k}``: this episode's gusts, k >= 0.

        Returns
        -------
        observation : numpy.ndarray (6,) float32
        info : dict
        """
        super().reset(seed=seed)
        turbulence_seed = turbulence_seed_option(options)
        if turbulence_seed is None:
            turbulence_seed = int(self.np_random.integers(0, 2**63 - 1))
        m = self.stepper.reset(seed=turbulence_seed)
        self.turbulence_seed, self._outcome = int(turbulence_seed), "holding"
        obs = self._observe(m)
        return obs, self._info(m, {"position": 0.0, "control": 0.0, "terminal": 0.0}, np.zeros(2))

    def step(self, action):
        """Hold the force of ``action`` for one control step.

        Parameters
        ----------
        action : array_like (2,)
            Fractions of ``max_force_n`` [-], lateral (right) and vertical (down); clipped to [-1, 1].

        Returns
        -------
        observation : numpy.ndarray (6,) float32
        reward : float
            The sum of ``info["reward_terms"]``.
        terminated, truncated : bool
            A failed state; the time limit.
        info : dict
            ``outcome``, ``reward_terms``, ``displacement_m`` (y, z), ``force_n``, ``t_s``, ``turbulence_seed``.
        """
        if self.stepper.done:
            raise RuntimeError(f"the episode has ended ({self._outcome}); call reset() to start another")
        a = checked_action(action, 2)
        force = a * self.max_force_n
        m = self.stepper.step(drogue=force)
        st, w = self.stepper, self.reward_weights
        d = np.asarray(m.drogue_position_m) - np.asarray(m.drogue_balance_m)
        failed = st.done and not st.completed
        self._outcome = "diverged" if failed else "time-out" if st.done else "holding"
        position = 0.0 if failed else -w.position_per_m2 * float(d[1] ** 2 + d[2] ** 2) * self.control_step_s
        terms = {"position": position, "control": -w.control_penalty_1_s * float(a @ a) * self.control_step_s,
                 "terminal": -w.failure_penalty if failed else 0.0}
        return self._observe(m), float(sum(terms.values())), failed, st.done and not failed, self._info(m, terms, force)

    def _observe(self, m) -> np.ndarray:
        """The scaled observation of a measurement; in a failed state the last valid one."""
        raw = np.concatenate([np.asarray(m.drogue_position_m) - np.asarray(m.drogue_balance_m), m.drogue_velocity_m_s])
        self._last = scaled(raw, STATION_SCALE, _BOUND, self._last)
        return self._last.astype(np.float32)

    def _info(self, m, terms: dict, force: np.ndarray) -> dict:
        d = np.asarray(m.drogue_position_m) - np.asarray(m.drogue_balance_m)
        return {"outcome": self._outcome, "reward_terms": dict(terms), "displacement_m": d[1:].copy(),
                "force_n": np.asarray(force, dtype=np.float64).copy(), "t_s": self.stepper.t_s,
                "turbulence_seed": self.turbulence_seed, "message": self.stepper.message}


class StationPD:
    """The scripted station-keeping baseline: ``u = -(K_P d + K_D v)`` per axis, d the drogue's
    lateral or vertical displacement [m] and v its velocity [m/s] (observation 1-2 and 4-5),
    with the paper's PID gains (:data:`hosedrogue.controllers.pid.PAPER_PID`, its proportional
    and derivative parts), divided by the actuator's bound and clipped.

    Parameters
    ----------
    env : gymnasium.Env
        The station-keeping environment (its ``max_force_n``, through any wrappers).
    """

    def __init__(self, env):
        from ..controllers.pid import PAPER_PID  # python-control with it: only for this baseline

        base = env.unwrapped
        self.max_force_n = float(base.max_force_n)
        g = (PAPER_PID["lateral"], PAPER_PID["vertical"])
        self.kp = np.array([g[0].kp, g[1].kp])
        self.kd = np.array([g[0].kd, g[1].kd])

    def __call__(self, obs) -> np.ndarray:
        """The action for an observation.

        Parameters
        ----------
        obs : array_like (6,)
            The environment's observation.

        Returns
        -------
        numpy.ndarray (2,)
            In [-1, 1].
        """
        x = np.asarray(obs, dtype=np.float64) * STATION_SCALE
        u = -(self.kp * x[1:3] + self.kd * x[4:6])
        return np.clip(u / self.max_force_n, -1.0, 1.0)
