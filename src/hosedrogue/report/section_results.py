"""Section results that more than one report module reads: defined here, below the sections that
make and use them, so that no two report modules import each other."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..analysis.linearize import LinearModel
    from ..controllers.design import ReducedChannels

__all__ = ["LinearResult"]


@dataclass(frozen=True)
class LinearResult:
    """The linear model and its reductions, used by the controller section.

    Parameters
    ----------
    model : hosedrogue.analysis.linearize.LinearModel
        The full linearization at the paper's flight condition (inputs u_hor, u_ver [N];
        outputs P_ny, P_nz [m]).
    full, sixth, second : hosedrogue.controllers.design.ReducedChannels
        Each channel at full (minimal) order, balanced-truncated to 6th and to 2nd order.
    """

    model: LinearModel
    full: ReducedChannels
    sixth: ReducedChannels
    second: ReducedChannels
