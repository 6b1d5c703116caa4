"""Gymnasium environments of the engagement (docs/gym.md). Importing this package registers

* ``hosedrogue/Docking-v1`` - :class:`~hosedrogue.envs.docking_v1.DockingEnvV1`: the agent flies
  the receiver's probe toward the drogue in turbulence by a bounded velocity command, scored as an
  operator would (a closure-speed window, the miss, the probe's load; potential-based shaping),
  float32 and normalized, randomizable, with a TimeLimit of 500 steps in its spec;
* ``hosedrogue/Docking-v0`` - :class:`~hosedrogue.envs.docking.DockingEnv`: the first version, kept
  unchanged so that results obtained with it can be reproduced (its reward can be gamed by
  ramming the drogue near the latch's 3 m/s: use v1);

so that ``gymnasium.make("hosedrogue/Docking-v1", turbulence="severe")`` and
``gymnasium.make_vec(...)`` build them. A scripted baseline,
:class:`~hosedrogue.envs.baseline.PDFeedForward`, flies it by PD control with feed-forward
(:func:`~hosedrogue.envs.baseline.fly` flies episodes of a policy).

Gymnasium is an optional dependency: ``pip install 'hosedrogue[gym]'``.
"""

try:
    import gymnasium
except ImportError:  # the one thing missing, said in one line
    raise ImportError("hosedrogue.envs needs Gymnasium: pip install 'hosedrogue[gym]'") from None

from .baseline import POLICIES, PDFeedForward, StraightLine, fly
from .docking import OBSERVATION, OUTCOMES, DockingEnv
from .docking_v1 import MAX_EPISODE_STEPS, OBSERVATION_SCALE, OUTCOMES_V1, DockingEnvV1
from .options import DockingReward, DockingRewardV1, docking_scenario
from .randomize import DEFAULT_RANGES, RANDOMIZABLE

#: The registered id of the first docking environment (kept unchanged).
DOCKING_ID = "hosedrogue/Docking-v0"
#: The registered id of the docking environment to use.
DOCKING_V1_ID = "hosedrogue/Docking-v1"

if DOCKING_ID not in gymnasium.registry:
    gymnasium.register(id=DOCKING_ID, entry_point="hosedrogue.envs.docking:DockingEnv")
if DOCKING_V1_ID not in gymnasium.registry:
    gymnasium.register(id=DOCKING_V1_ID, entry_point="hosedrogue.envs.docking_v1:DockingEnvV1",
                       vector_entry_point="hosedrogue.envs.vector:DockingVectorEnv",
                       max_episode_steps=MAX_EPISODE_STEPS)

__all__ = ["DEFAULT_RANGES", "DOCKING_ID", "DOCKING_V1_ID", "DockingEnv", "DockingEnvV1", "DockingReward",
           "DockingRewardV1", "MAX_EPISODE_STEPS", "OBSERVATION", "OBSERVATION_SCALE", "OUTCOMES", "OUTCOMES_V1",
           "PDFeedForward", "POLICIES", "RANDOMIZABLE", "StraightLine", "docking_scenario", "fly"]
