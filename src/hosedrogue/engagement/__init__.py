"""The refuelling engagement (docs/engagement.md; the hose of varying length: docs/model.md §8): a
hose drum unit, a hose of varying free length, a prescribed receiver probe, capture and the
coupled phase."""

from ..results import EngagementResult
from ..sections import BowWave, Engagement, Pilot, Probe, Reel
from .driver import simulate_engagement

__all__ = ["BowWave", "Engagement", "EngagementResult", "Pilot", "Probe", "Reel", "simulate_engagement"]
