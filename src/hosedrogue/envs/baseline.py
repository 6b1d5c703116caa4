"""Scripted policies for the docking environment (docs/gym.md, "Baseline"), each reading the
environment's observation and returning its action:

* :class:`PDFeedForward` - the baseline: proportional-derivative control of the measured
  drogue-minus-probe offset with the drogue's velocity fed forward, at a steady closure speed
  (the law of the shipped docking controller :class:`hosedrogue.examples.controllers.PDDocking`);
* :class:`StraightLine` - the prescribed probe of the approach scenarios: straight ahead at the
  closure speed, at the drogue's balance position (what the baseline is compared with);

and :func:`fly`, which flies episodes of a policy and returns how each ended.

::

    env = gymnasium.make("hosedrogue/Docking-v0")
    policy = PDFeedForward(env)
    obs, info = env.reset(seed=0)
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        if terminated or truncated:
            break
"""

from __future__ import annotations

import numpy as np


class PDFeedForward:
    """Velocity command ``v = (v_c, ff v_d,y + kp e_y + kd e'_y, ff v_d,z + kp e_z + kd e'_z)``
    with e the drogue minus the probe tip [m] (observation 0-2), e' its rate [m/s] (3-5) and
    v_d the drogue's velocity [m/s] (9-11), as the action: v divided by the receiver's speed
    bounds, clipped to [-1, 1] (the receiver would clip the command there too).

    Parameters
    ----------
    env : gymnasium.Env
        The docking environment (its ``max_speed_m_s``, through any wrappers).
    kp_1_s : float
        Proportional gain [1/s]: the offset decays at about this rate.
    kd : float
        Derivative gain on the offset's rate [-].
    feedforward : float
        Fraction of the drogue's lateral and vertical velocity fed forward [-].
    closure_speed_m_s : float, optional
        Forward speed relative to the tanker [m/s] (the latch needs 0.5-3 m/s at the coupler);
        default 1 m/s, and on Docking-v1 the middle of its reward's closure window (2.05 m/s).
    """

    def __init__(self, env, kp_1_s: float = 2.0, kd: float = 0.2, feedforward: float = 1.0,
                 closure_speed_m_s: float | None = None):
        base = env.unwrapped
        self.max_speed_m_s = np.array(base.max_speed_m_s, dtype=np.float64)
        #: the observation's unit per component (Docking-v1's observation is normalized)
        self.scale = np.asarray(base.observation_scale, dtype=np.float64)
        self.kp, self.kd, self.ff = float(kp_1_s), float(kd), float(feedforward)
        if closure_speed_m_s is None:
            w = base.reward_weights
            closure_speed_m_s = (w.min_closure_m_s + w.max_closure_m_s) / 2 if hasattr(w, "min_closure_m_s") else 1.0
        self.closure = float(closure_speed_m_s)

    def command(self, obs) -> np.ndarray:
        """The velocity command [m/s] (forward, right, down) for an observation.

        Parameters
        ----------
        obs : array_like (15,)
            The environment's observation.

        Returns
        -------
        numpy.ndarray (3,)
        """
        obs = np.asarray(obs, dtype=np.float64) * self.scale
        e, de, vd = obs[0:3], obs[3:6], obs[9:12]
        return np.array([self.closure,
                         self.ff * vd[1] + self.kp * e[1] + self.kd * de[1],
                         self.ff * vd[2] + self.kp * e[2] + self.kd * de[2]])

    def __call__(self, obs) -> np.ndarray:
        """The action for an observation.

        Parameters
        ----------
        obs : array_like (15,)
            The environment's observation.

        Returns
        -------
        numpy.ndarray (3,)
            In [-1, 1].
        """
        return np.clip(self.command(obs) / self.max_speed_m_s, -1.0, 1.0)


class StraightLine:
    """The prescribed probe as a policy: ``v = (v_c, 0, 0)``, straight ahead from the start point
    (the drogue's balance position plus the probe's offsets), whatever the drogue does.

    Parameters
    ----------
    env : gymnasium.Env
        The docking environment (its speed bounds; the closure speed of its scenario's probe).
    closure_speed_m_s : float, optional
        Forward speed [m/s]; default the scenario's ``probe.closure_speed_m_s`` (1 m/s in the
        approach scenarios: below Docking-v1's closure window, so give it there).
    """

    def __init__(self, env, closure_speed_m_s: float | None = None):
        base = env.unwrapped
        v = base.scenario.engagement.probe.closure_speed_m_s if closure_speed_m_s is None else closure_speed_m_s
        self.action = np.clip(np.array([float(v), 0.0, 0.0]) / base.max_speed_m_s, -1.0, 1.0)

    def __call__(self, obs) -> np.ndarray:
        """The action (the same at every step).

        Parameters
        ----------
        obs : array_like (15,)
            The environment's observation (not read).

        Returns
        -------
        numpy.ndarray (3,)
        """
        return self.action.copy()


#: The scripted policies by name (the command line's ``--policy``).
POLICIES = {"baseline": PDFeedForward, "straight": StraightLine}


def fly(env, policy, turbulence_seeds, seed: int | None = None) -> list[dict]:
    """Fly one episode per turbulence seed; the last ``info`` of each.

    Parameters
    ----------
    env : gymnasium.Env
        The docking environment.
    policy : callable
        Observation -> action.
    turbulence_seeds : sequence of int
        One episode per seed (``reset(options={"turbulence_seed": seed})``), >= 0.
    seed : int, optional
        Seeds the environment's generator at the first episode (``reset(seed=seed)``): what a
        randomized environment draws besides the turbulence seed.

    Returns
    -------
    list of dict
        The final ``info`` of every episode (``outcome``, ``miss_distance_m``, ``t_s``, ...),
        with ``steps`` (actions taken) and ``return`` (the sum of its rewards) added.
    """
    out = []
    for k, turbulence_seed in enumerate(turbulence_seeds):
        obs, info = env.reset(seed=seed if k == 0 else None, options={"turbulence_seed": int(turbulence_seed)})
        steps, total = 0, 0.0
        while True:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            steps += 1
            total += reward
            if terminated or truncated:
                break
        out.append({**info, "steps": steps, "return": total})
    return out
