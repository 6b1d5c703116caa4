"""The engagement's sections (``[reel]``, ``[probe]``, ``[bow_wave]``, ``[pilot]``), defined in
:mod:`hosedrogue.spec.sections` with the control loop's; re-exported here under their former names."""

from __future__ import annotations

from ..spec.sections import ENGAGEMENT_SECTIONS, REEL_LAWS, BowWave, Pilot, Probe, Reel

#: Former name of :class:`hosedrogue.spec.sections.BowWave`.
BowWaveSection = BowWave

__all__ = ["BowWave", "BowWaveSection", "ENGAGEMENT_SECTIONS", "Pilot", "Probe", "REEL_LAWS", "Reel"]
