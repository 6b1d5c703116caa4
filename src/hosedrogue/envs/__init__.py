"""Gymnasium environments of the engagement (docs/gym.md). Importing this package registers

* ``hosedrogue/Docking-v1`` - :class:`~hosedrogue.envs.docking_v1.DockingEnvV1`: the agent flies
  the receiver's probe toward the drogue in turbulence by a bounded velocity command, scored as an
  operator would (a closure-speed window, the miss, the probe's load; potential-based shaping),
  float32 and normalized, randomizable, with a TimeLimit of 500 steps in its spec;
* ``hosedrogue/Docking-v0`` - :class:`~hosedrogue.envs.docking.DockingEnv`: the first version, kept
  unchanged so that results obtained with it can be reproduced (its reward can be gamed by
  ramming the drogue near the latch's 3 m/s: use v1);
* ``hosedrogue/StationKeeping-v0`` - :class:`~hosedrogue.envs.station.StationKeepingEnv`: the agent
  is the actuated drogue, holding its balance position in turbulence by a bounded force
  (baseline :class:`~hosedrogue.envs.station.StationPD`);
* ``hosedrogue/WhipSuppression-v0`` - :class:`~hosedrogue.envs.whip.WhipSuppressionEnv`: the agent
  is the reel after contact, taking up the slack the probe's push leaves (baseline
  :class:`~hosedrogue.envs.whip.SlackFeedback`);

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
from .station import STATION_OBSERVATION, STATION_STEPS, StationKeepingEnv, StationPD
from .whip import WHIP_OBSERVATION, WHIP_STEPS, SlackFeedback, WhipSuppressionEnv

#: The registered id of the first docking environment (kept unchanged).
DOCKING_ID = "hosedrogue/Docking-v0"
#: The registered id of the docking environment to use.
DOCKING_V1_ID = "hosedrogue/Docking-v1"
#: The registered id of the station-keeping environment (the agent is the actuated drogue).
STATION_ID = "hosedrogue/StationKeeping-v0"
#: The registered id of the whip-suppression environment (the agent is the reel after contact).
WHIP_ID = "hosedrogue/WhipSuppression-v0"

if DOCKING_ID not in gymnasium.registry:
    gymnasium.register(id=DOCKING_ID, entry_point="hosedrogue.envs.docking:DockingEnv")
if DOCKING_V1_ID not in gymnasium.registry:
    gymnasium.register(id=DOCKING_V1_ID, entry_point="hosedrogue.envs.docking_v1:DockingEnvV1",
                       vector_entry_point="hosedrogue.envs.vector:DockingVectorEnv",
                       max_episode_steps=MAX_EPISODE_STEPS)
if STATION_ID not in gymnasium.registry:
    gymnasium.register(id=STATION_ID, entry_point="hosedrogue.envs.station:StationKeepingEnv",
                       max_episode_steps=STATION_STEPS)
if WHIP_ID not in gymnasium.registry:
    gymnasium.register(id=WHIP_ID, entry_point="hosedrogue.envs.whip:WhipSuppressionEnv", max_episode_steps=WHIP_STEPS)

__all__ = ["DEFAULT_RANGES", "DOCKING_ID", "DOCKING_V1_ID", "DockingEnv", "DockingEnvV1", "DockingReward",
           "DockingRewardV1", "MAX_EPISODE_STEPS", "OBSERVATION", "OBSERVATION_SCALE", "OUTCOMES", "OUTCOMES_V1",
           "PDFeedForward", "POLICIES", "RANDOMIZABLE", "STATION_ID", "STATION_OBSERVATION", "STATION_STEPS",
           "SlackFeedback", "StationKeepingEnv", "StationPD", "StraightLine", "WHIP_ID", "WHIP_OBSERVATION",
           "WHIP_STEPS", "WhipSuppressionEnv", "docking_scenario", "fly"]
