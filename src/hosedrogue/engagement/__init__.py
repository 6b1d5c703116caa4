"""The refuelling engagement (docs/engagement.md; the hose of varying length: docs/model.md §8): a
hose drum unit, a hose of varying free length, a prescribed receiver probe, capture and the
coupled phase."""

from .driver import EngagementResult, simulate_engagement
from .spec import Probe, Reel

__all__ = ["EngagementResult", "Probe", "Reel", "simulate_engagement"]
