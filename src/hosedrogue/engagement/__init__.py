"""The refuelling engagement (docs/engagement.md; the hose of varying length: docs/model.md §8): a
hose drum unit, a hose of varying free length, a receiver probe (prescribed, flown by the pilot
model or by your docking controller), capture and the coupled phase; the stepping API
(:class:`EngagementStepper`, docs/controllers.md)."""

from ..results.run import EngagementResult
from ..spec.sections import BowWave, Engagement, Pilot, Probe, Receiver, Reel
from .simulate import simulate_engagement
from .stepper import EngagementStepper

__all__ = ["BowWave", "Engagement", "EngagementResult", "EngagementStepper", "Pilot", "Probe", "Receiver", "Reel",
           "simulate_engagement"]
