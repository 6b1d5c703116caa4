"""The engagement's sections (``[reel]``, ``[probe]``, ``[bow_wave]``, ``[pilot]``), defined in
:mod:`hosedrogue.sections` with the control loop's; re-exported here under their former names."""

from __future__ import annotations

from ..sections import ENGAGEMENT_SECTIONS, REEL_LAWS, BowWave, Pilot, Probe, Reel

#: Former name of :class:`hosedrogue.sections.BowWave`.
BowWaveSection = BowWave

__all__ = ["BowWave", "BowWaveSection", "ENGAGEMENT_SECTIONS", "Pilot", "Probe", "REEL_LAWS", "Reel"]
