"""Gymnasium environments of the engagement (docs/gym.md). Importing this package registers

* ``hosedrogue/Docking-v0`` - :class:`~hosedrogue.envs.docking.DockingEnv`: the agent flies the
  receiver's probe toward the drogue in turbulence by a bounded velocity command;

so that ``gymnasium.make("hosedrogue/Docking-v0", turbulence="severe")`` and
``gymnasium.make_vec(...)`` build it. A scripted baseline,
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
from .options import DockingReward, docking_scenario

#: The registered id of the docking environment.
DOCKING_ID = "hosedrogue/Docking-v0"

if DOCKING_ID not in gymnasium.registry:
    gymnasium.register(id=DOCKING_ID, entry_point="hosedrogue.envs.docking:DockingEnv")

__all__ = ["DOCKING_ID", "DockingEnv", "DockingReward", "OBSERVATION", "OUTCOMES", "PDFeedForward", "POLICIES",
           "StraightLine", "docking_scenario", "fly"]
