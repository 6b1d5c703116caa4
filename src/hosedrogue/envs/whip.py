"""``hosedrogue/WhipSuppression-v0`` (docs/gym.md, "Whip suppression"): the agent is the reel
after contact. The probe closes on the drogue, is captured and pushes on (the scenario's
``[probe]``: by default engage-response's 1.5 m/s and 2 m push, then it holds); the hose the push
leaves slack forms a loop that whips unless the reel takes it up. From contact on, every control
step the agent commands the reel's take-up speed, which the drive follows (the ``python`` reel
law of docs/engagement.md: a first-order response within its torque and speed limits), on the
engagement's stepper (:class:`hosedrogue.engagement.EngagementStepper`, the elastic 160-link hose
of engage-response by default). Before contact the reel holds its length (a zero command).

A scripted baseline, :class:`SlackFeedback`, commands a take-up speed proportional to the
measured slack (the law of the shipped ``engage-slack-law``, :class:`hosedrogue.examples.controllers.SlackTakeup`).
"""

from __future__ import annotations

import math
from pathlib import Path

import gymnasium
import numpy as np
from gymnasium import spaces

from ..engagement.stepper import EngagementStepper
from ..errors import ParameterError
from ..scenarios import Scenario, scenario_from_dict
from ..simulation.budget import positive_number
from ..spec.rewards import WhipReward
from .options import on_grid, reward_weights, set_turbulence
from .task_common import checked_action, scaled, scenario_source, turbulence_seed_option

#: The observation's components: (name, unit, scale); the observation is each divided by its scale.
WHIP_OBSERVATION = (
    ("slack_m", "m", 1.0),  # hose length less the drogue's distance from the tow point
    ("reel_speed_m_s", "m/s", 3.0),  # the hose's speed at the drum, positive reeling in
    ("exit_tension_change_kn", "kN", 1.0),  # exit tension less its value at contact
    ("hose_length_change_m", "m", 1.0),  # hose length less its value at contact
    ("drogue_dx_m", "m", 1.0), ("drogue_dy_m", "m", 1.0), ("drogue_dz_m", "m", 1.0),  # minus its balance position
    ("drogue_vx_m_s", "m/s", 3.0), ("drogue_vy_m_s", "m/s", 3.0), ("drogue_vz_m_s", "m/s", 3.0),
)
#: The observation's scale per component [m, m/s, kN]: 1 m of slack or length, 3 m/s (the reel's
#: speed limit), 1 kN.
WHIP_SCALE = np.array([s for _, _, s in WHIP_OBSERVATION])
#: The observation's bound (after scaling); values beyond are clipped.
_BOUND = np.full(len(WHIP_OBSERVATION), 50.0)
#: Steps of the registered spec's TimeLimit: the default 4 s after contact at the default 0.02 s control step.
WHIP_STEPS = 200
#: Gust records a reset draws at most for an episode in which the probe couples (a miss draws the next).
MAX_DRAWS = 100
#: How a whip episode ends (``info["outcome"]``); "coupled" while it runs.
WHIP_OUTCOMES = ("coupled", "time-out", "diverged")


def whip_scenario(scenario: str | Path | Scenario = "engage-response", turbulence=None,
                  after_contact_s: float = 4.0) -> Scenario:
    """The scenario a whip episode runs: ``scenario`` with its reel commanded (law "python", no
    entry), the turbulence option applied, and its duration the probe's time to contact plus
    ``after_contact_s`` and 1 s of margin.

    Parameters
    ----------
    scenario : str, Path or Scenario
        An engagement with an enabled ``[probe]``, no ``[pilot]``, no ``[receiver]``.
    turbulence : str or float, optional
        "none", "light", "moderate", "severe" or an isotropic intensity [m/s]; None: the scenario's.
    after_contact_s : float
        The episode's length after contact [s], in (0, 60].

    Returns
    -------
    Scenario
    """
    after = positive_number("after_contact_s", after_contact_s, 60.0)
    base, source, tables, name = scenario_source(scenario)
    e = base.engagement
    if e is None or e.probe is None or not e.probe.enabled or (e.pilot is not None and e.pilot.enabled) \
            or e.receiver is not None:
        raise ParameterError(f"scenario = {name!r}: the probe must fly the scenario's prescribed path; give an "
                             "engagement with an enabled [probe] and no [pilot] or [receiver] (e.g. 'engage-response')")
    limit = e.probe.standoff_m / e.probe.closure_speed_m_s + after + 1.0
    set_turbulence(tables, turbulence, base, limit)
    tables["reel"] = {k: v for k, v in tables.get("reel", {}).items() if k not in ("entry", "options")}
    tables["reel"]["law"] = "python"
    tables["scenario"] = {**tables.get("scenario", {}), "duration_s": limit}
    return on_grid(scenario_from_dict(tables, name=name, source=source))


class WhipSuppressionEnv(gymnasium.Env):
    """The reel after contact, taking up the slack the probe's push leaves (docs/gym.md, "Whip suppression").

    Action: the take-up speed command as a fraction of the reel's take-up limit (an action of 1
    reels in at ``reel.max_takeup_speed_m_s``, -1 pays out at it), clipped to [-1, 1].
    Observation: :data:`WHIP_OBSERVATION`, each divided by its scale, float32. An episode starts
    at contact and lasts ``after_contact_s`` (truncated) unless the run fails (terminated).

    Parameters
    ----------
    render_mode : None
        No picture.
    scenario : str, Path or Scenario
        The engagement (default "engage-response": 150 m/s, 8000 m, the elastic 160-link hose,
        SDIRK at 5 ms; the probe closes at 1.5 m/s from 3 m, pushes 2 m and holds).
    turbulence : str or float, optional
        As :class:`~hosedrogue.envs.docking.DockingEnv`'s; default "light" (each episode its gusts).
    control_step_s : float
        Time between actions [s], a whole multiple of the scenario's step.
    after_contact_s : float
        Episode length after contact [s], in (0, 60].
    reward : WhipReward or dict, optional
        The reward's weights (:class:`~hosedrogue.spec.rewards.WhipReward`).
    """

    metadata = {"render_modes": [], "render_fps": 50}

    def __init__(self, render_mode: str | None = None, *, scenario: str | Path | Scenario = "engage-response",
                 turbulence: str | float | None = "light", control_step_s: float = 0.02, after_contact_s: float = 4.0,
                 reward: WhipReward | dict | None = None):
        if render_mode is not None:
            raise ParameterError(f"render_mode = {render_mode!r}: must be None (no picture)")
        self.render_mode = None
        self.scenario = sc = whip_scenario(scenario, turbulence, after_contact_s)
        self.after_contact_s = float(after_contact_s)
        self.reward_weights = reward_weights(reward, WhipReward)
        e = sc.engagement
        self.stepper = EngagementStepper(sc.params, sc.duration_s, control_step_s=control_step_s, reel=e.reel,
                                         probe=e.probe, bow_wave=e.bow_wave, sensor=sc.loop.sensor, record=False)
        self.max_takeup_m_s = float(e.reel.max_takeup_speed_m_s)
        self.control_step_s = self.stepper.control_step_s
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.control_step_s}
        self.action_space = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
        self.observation_space = spaces.Box(-_BOUND.astype(np.float32), _BOUND.astype(np.float32), dtype=np.float32)
        self.turbulence_seed, self._outcome, self._last = None, "coupled", np.zeros(len(WHIP_OBSERVATION))
        self._at_contact = (0.0, 0.0, 0.0)  # time [s], exit tension [N], hose length [m]

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode at contact: the run from the scenario's start (the reel holding its
        length) to the step the probe couples, with the turbulence of a seed drawn from the
        environment's generator (or ``options["turbulence_seed"]``). A gust record in which the
        prescribed probe misses the drogue has no episode: the next seed is drawn (up to
        :data:`MAX_DRAWS`; a given seed is refused in one line).

        Parameters
        ----------
        seed : int, optional
            Seeds the environment's generator.
        options : dict, optional
            ``{"turbulence_seed": k}``: this episode's gusts, k >= 0.

        Returns
        -------
        observation : numpy.ndarray (10,) float32
        info : dict
        """
        super().reset(seed=seed)
        turbulence_seed = turbulence_seed_option(options)
        given, st = turbulence_seed is not None, self.stepper
        for _ in range(MAX_DRAWS):
            if not given:
                turbulence_seed = int(self.np_random.integers(0, 2**63 - 1))
            m = st.reset(seed=turbulence_seed)
            while not m.coupled and not st.done:
                m = st.step(reel=0.0)
            if m.coupled or given:
                break
        if not m.coupled:
            raise ParameterError(f"turbulence_seed = {turbulence_seed}: the probe does not couple in its gusts "
                                 f"({st.outcome['result']}); give another seed" if given else
                                 f"the probe did not couple in {MAX_DRAWS} gust records of this scenario; lower "
                                 "its turbulence")
        self.turbulence_seed, self._outcome = int(turbulence_seed), "coupled"
        self._at_contact = (st.t_s, m.exit_tension_n, m.hose_length_m)
        return self._observe(m), self._info(m, {"slack": 0.0, "tension": 0.0, "control": 0.0, "terminal": 0.0}, 0.0)

    def step(self, action):
        """Hold the take-up command of ``action`` for one control step.

        Parameters
        ----------
        action : array_like (1,)
            Fraction of the reel's take-up speed limit [-], positive reeling in; clipped to [-1, 1].

        Returns
        -------
        observation : numpy.ndarray (10,) float32
        reward : float
            The sum of ``info["reward_terms"]``.
        terminated, truncated : bool
            A failed run; the episode's end.
        info : dict
            ``outcome``, ``reward_terms``, ``slack_m``, ``exit_tension_n``, ``probe_force_n``,
            ``command_m_s``, ``t_s`` (since the run's start), ``turbulence_seed``.
        """
        st = self.stepper
        if self._outcome != "coupled":
            raise RuntimeError(f"the episode has ended ({self._outcome}); call reset() to start another")
        a = float(checked_action(action, 1)[0])
        command = a * self.max_takeup_m_s
        m = st.step(reel=command)
        failed = st.done and not st.completed
        ended = st.done or st.t_s >= self._at_contact[0] + self.after_contact_s - 1e-9
        self._outcome = "diverged" if failed else "time-out" if ended else "coupled"
        w, dt = self.reward_weights, self.control_step_s
        slack, tension = self._slack(m), m.exit_tension_n - self._at_contact[1]
        terms = {"slack": 0.0 if failed else -w.slack_per_m * max(slack, 0.0) * dt,
                 "tension": 0.0 if failed else -w.tension_per_kn * abs(tension) / 1000.0 * dt,
                 "control": -w.control_penalty_1_s * a * a * dt, "terminal": -w.failure_penalty if failed else 0.0}
        return self._observe(m), float(sum(terms.values())), failed, ended and not failed, self._info(m, terms, command)

    @staticmethod
    def _slack(m) -> float:
        """The slack [m]: the hose length less the drogue's distance from the tow point (the frame's origin)."""
        r = np.asarray(m.drogue_position_m)
        return m.hose_length_m - math.sqrt(float(r @ r))

    def _observe(self, m) -> np.ndarray:
        """The scaled observation of a measurement; in a failed state the last valid one."""
        d = np.asarray(m.drogue_position_m) - np.asarray(m.drogue_balance_m)
        raw = np.concatenate([[self._slack(m), m.reel_speed_m_s, (m.exit_tension_n - self._at_contact[1]) / 1000.0,
                               m.hose_length_m - self._at_contact[2]], d, m.drogue_velocity_m_s])
        self._last = scaled(raw, WHIP_SCALE, _BOUND, self._last)
        return self._last.astype(np.float32)

    def _info(self, m, terms: dict, command: float) -> dict:
        return {"outcome": self._outcome, "reward_terms": dict(terms), "slack_m": self._slack(m),
                "exit_tension_n": float(m.exit_tension_n),
                "probe_force_n": float(np.linalg.norm(self.stepper.probe_force_n)), "command_m_s": float(command),
                "t_s": self.stepper.t_s, "contact_time_s": self._at_contact[0],
                "turbulence_seed": self.turbulence_seed, "message": self.stepper.message}


class SlackFeedback:
    """The scripted whip baseline: the take-up speed ``gain (s - dead_band)`` beyond the dead band
    (0 within it), s the measured slack (observation 0), up to the reel's limit, as the action.
    The law of :class:`hosedrogue.examples.controllers.SlackTakeup` (``engage-slack-law``'s 8 /s).

    Parameters
    ----------
    env : gymnasium.Env
        The whip environment (its ``max_takeup_m_s``, through any wrappers).
    gain_1_s : float
        Take-up speed per metre of slack [1/s].
    dead_band_m : float
        Slack without take-up [m].
    """

    def __init__(self, env, gain_1_s: float = 8.0, dead_band_m: float = 0.02):
        self.max_takeup_m_s = float(env.unwrapped.max_takeup_m_s)
        self.gain, self.dead_band = float(gain_1_s), float(dead_band_m)

    def __call__(self, obs) -> np.ndarray:
        """The action for an observation.

        Parameters
        ----------
        obs : array_like (10,)
            The environment's observation.

        Returns
        -------
        numpy.ndarray (1,)
            In [0, 1].
        """
        slack = float(obs[0]) * WHIP_SCALE[0]
        return np.array([min(self.gain * max(slack - self.dead_band, 0.0) / self.max_takeup_m_s, 1.0)])
