"""``gymnasium.make_vec("hosedrogue/Docking-v1", num_envs=N)``: the docking environment's own
vector environment (docs/gym.md, "Many environments"), built through the spec's
``vector_entry_point``.

Its N sub-environments are :class:`~hosedrogue.envs.docking_v1.DockingEnvV1` objects stepped in
turn in one process; the batch's actions, observations, rewards and ends are numpy arrays, and
the time limit, the autoreset (Gymnasium's three modes) and the batched ``info`` are done once
for the batch. It is not one compiled call for the N episodes: a step of one environment spends
most of its time in its own compiled control step (benchmarks/gym_vector.py measures the share),
which a batched call could not shorten; docs/gym.md gives the figures. Sub-environment ``i``
gives, step for step, what ``gymnasium.make`` gives on seed ``seed + i`` and the same actions.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..errors import ParameterError
from .docking_v1 import MAX_EPISODE_STEPS, DockingEnvV1

#: Gymnasium's autoreset modes, by their names.
AUTORESET_MODES = {m.value: m for m in AutoresetMode}


class DockingVectorEnv(VectorEnv):
    """N docking environments (v1) as one Gymnasium vector environment.

    Parameters
    ----------
    num_envs : int
        The number of sub-environments, >= 1.
    max_episode_steps : int
        Each episode's time limit [steps] (Gymnasium's TimeLimit: ``truncated`` at that step).
    autoreset_mode : str or gymnasium.vector.AutoresetMode
        "NextStep" (the default: the step after an episode's end resets it, with reward 0),
        "SameStep" (it resets in the step that ends it; ``info["final_obs"]``, ``info["final_info"]``)
        or "Disabled" (``reset(options={"reset_mask": mask})`` resets the ended ones).
    render_mode : str, optional
        None or "rgb_array" (:meth:`render` returns the sub-environments' images).
    **kwargs
        The keyword arguments of :class:`~hosedrogue.envs.docking_v1.DockingEnvV1`, the same for
        every sub-environment.
    """

    metadata = {"render_modes": ["rgb_array"], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, max_episode_steps: int = MAX_EPISODE_STEPS,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP, render_mode: str | None = None,
                 **kwargs: Any):
        for name, value in (("num_envs", num_envs), ("max_episode_steps", max_episode_steps)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise ParameterError(f"{name} = {value!r}: must be a whole number >= 1")
        mode = AUTORESET_MODES.get(autoreset_mode, autoreset_mode)
        if not isinstance(mode, AutoresetMode):
            raise ParameterError(f"autoreset_mode = {autoreset_mode!r}: must be one of "
                                 f"{', '.join(map(repr, AUTORESET_MODES))}")
        self.num_envs, self.max_episode_steps, self.render_mode = int(num_envs), int(max_episode_steps), render_mode
        self.envs = [DockingEnvV1(render_mode, **kwargs) for _ in range(self.num_envs)]
        first = self.envs[0]
        self.metadata = {**self.metadata, "autoreset_mode": mode, "render_fps": first.metadata["render_fps"]}
        self.single_observation_space, self.single_action_space = first.observation_space, first.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        n = self.num_envs
        self._obs = np.zeros((n, *self.single_observation_space.shape), dtype=np.float32)
        self._steps = np.zeros(n, dtype=np.int64)
        self._ended = np.zeros(n, dtype=np.bool_)  # the episode ended at the last step: NEXT_STEP resets it now

    def reset(self, *, seed: int | list | None = None, options: dict | None = None):
        """Reset every sub-environment (or, with ``options["reset_mask"]``, those of the mask).

        Parameters
        ----------
        seed : int or list, optional
            An int s seeds sub-environment i with s + i; a list gives one seed (or None) each.
        options : dict, optional
            ``reset_mask`` (a bool array of shape (N,)); the rest goes to every sub-environment's
            ``reset`` (``turbulence_seed``, ``randomize``).

        Returns
        -------
        observations : numpy.ndarray (N, 15) float32
        infos : dict
            Gymnasium's batched info (each key with its ``_key`` mask).
        """
        n = self.num_envs
        seeds = [None] * n if seed is None else [seed + i for i in range(n)] if isinstance(seed, int) else list(seed)
        if len(seeds) != n:
            raise ParameterError(f"seed = {seed!r}: must be None, an int or a list of {n} seeds")
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        if mask is None:
            mask = np.ones(n, dtype=np.bool_)
        elif not (isinstance(mask, np.ndarray) and mask.dtype == np.bool_ and mask.shape == (n,)):
            raise ParameterError(f"options['reset_mask'] = {mask!r}: must be a numpy bool array of shape ({n},)")
        infos: list = [None] * n
        for i in np.flatnonzero(mask):
            self._obs[i], infos[i] = self.envs[i].reset(seed=seeds[i], options=options or None)
        self._steps[mask] = 0
        self._ended[mask] = False
        return self._obs.copy(), batch_infos(infos)

    def step(self, actions):
        """Step every sub-environment with its row of ``actions`` (autoresetting as the mode says).

        Parameters
        ----------
        actions : array_like (N, 3)
            One action per sub-environment, as :meth:`DockingEnvV1.step`'s.

        Returns
        -------
        observations : numpy.ndarray (N, 15) float32
        rewards : numpy.ndarray (N,) float64
        terminations, truncations : numpy.ndarray (N,) bool
        infos : dict
        """
        actions = np.asarray(actions, dtype=np.float64)
        n, mode = self.num_envs, self.metadata["autoreset_mode"]
        if actions.shape != (n, 3):
            raise ParameterError(f"actions: shape {actions.shape}: must be ({n}, 3)")
        rewards = np.zeros(n)
        terminated, truncated = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
        infos: list = [None] * n
        for i, env in enumerate(self.envs):
            if self._ended[i]:
                if mode is AutoresetMode.DISABLED:
                    raise RuntimeError(f"sub-environment {i}'s episode has ended: reset it with "
                                       "options={'reset_mask': mask}")
                self._obs[i], infos[i] = env.reset()
                self._steps[i], self._ended[i] = 0, False
                continue
            self._obs[i], rewards[i], terminated[i], truncated[i], info = env.step(actions[i])
            self._steps[i] += 1
            truncated[i] |= self._steps[i] >= self.max_episode_steps
            ended = terminated[i] or truncated[i]
            if ended and mode is AutoresetMode.SAME_STEP:
                final = {"final_obs": self._obs[i].copy(), "final_info": info}
                self._obs[i], info = env.reset()
                info = {**final, **info}
                self._steps[i] = 0
            else:
                self._ended[i] = ended
            infos[i] = info
        infos = batch_infos(infos)
        return self._obs.copy(), rewards, terminated, truncated, infos

    def render(self):
        """The sub-environments' pictures (``render_mode="rgb_array"``).

        Returns
        -------
        tuple of numpy.ndarray or None
        """
        return None if self.render_mode is None else tuple(env.render() for env in self.envs)

    def close_extras(self, **kwargs: Any):
        """Release the sub-environments' figures.

        Parameters
        ----------
        **kwargs
            Not used (Gymnasium's signature).
        """
        for env in self.envs:
            env.close()


def batch_infos(infos: list) -> dict:
    """Gymnasium's batched info of the sub-environments' infos (None: no info), as
    ``VectorEnv._add_info`` builds it one sub-environment at a time, built once per key: each
    key's values in an array (``final_obs`` and values of no number type in an object array),
    a dict batched again, and a ``_key`` bool mask of who has the key.

    Parameters
    ----------
    infos : list of dict or None
        One per sub-environment.

    Returns
    -------
    dict
    """
    n = len(infos)
    out: dict = {}
    for key in dict.fromkeys(k for info in infos if info for k in info):
        have = [i for i, info in enumerate(infos) if info is not None and key in info]
        first = infos[have[0]][key]
        if isinstance(first, dict) and key != "final_obs":
            array = batch_infos([info.get(key) if info is not None else None for info in infos])
        else:
            if key != "final_obs" and (type(first) in (int, float, bool) or isinstance(first, np.number)):
                array = np.zeros(n, dtype=type(first))
            elif key != "final_obs" and isinstance(first, np.ndarray):
                array = np.zeros((n, *first.shape), dtype=first.dtype)
            else:
                array = np.full(n, None, dtype=object)
            for i in have:
                array[i] = infos[i][key]
        mask = np.zeros(n, dtype=np.bool_)
        mask[have] = True
        out[key], out[f"_{key}"] = array, mask
    return out
