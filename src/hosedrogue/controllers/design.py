"""Design pipeline on the nonlinear model (paper Sec. 3): linearize about the balance position,
reduce each channel by balanced truncation, and design the paper's controllers on the reduced
model.

* :func:`reduced_channels` - lateral and vertical SISO models of a given order;
* :func:`paper_pid` - the paper's PID gains (Eq. 33) as a controller;
* :func:`lqr_design_for` - LQR with integral action and Kalman observer (Eqs. 34-37; the paper's
  Q, R by default) designed on the 2nd-order channels of *this* flight condition's linearization.
"""

from __future__ import annotations

from dataclasses import dataclass

import control

from ..analysis.linearize import LinearModel
from ..analysis.reduction import balanced_truncation, split_channels
from .linear import LinearController
from .lqr import PAPER_LQR_Q, PAPER_LQR_R, LQRDesign, lqr_integral_design, two_channel_plant
from .pid import PAPER_PID, pid_controller

#: Order of the design model (paper Sec. 3.2: "the 2nd order reduced model is chosen").
DESIGN_ORDER = 2


@dataclass(frozen=True)
class ReducedChannels:
    lateral: control.StateSpace  #: u_hor [N] -> P_ny [m]
    vertical: control.StateSpace  #: u_ver [N] -> P_nz [m]
    order: int | None  #: None: full order (minimal realization of each channel)


def reduced_channels(lm: LinearModel, order: int | None) -> ReducedChannels:
    """Each channel of the linear model, balanced-truncated to ``order`` (None: full)."""
    lat, ver = split_channels(lm.ss)
    if order is not None:
        lat = balanced_truncation(lat, order)
        ver = balanced_truncation(ver, order)
    return ReducedChannels(lat, ver, order)


def paper_pid() -> LinearController:
    """The paper's PID gains on both channels, acting on the drogue's offset."""
    return pid_controller(PAPER_PID["lateral"], PAPER_PID["vertical"])


def lqr_design_for(lm: LinearModel, Q=PAPER_LQR_Q, R=PAPER_LQR_R) -> LQRDesign:
    """LQR with integral action on the 2nd-order channels of ``lm``."""
    ch = reduced_channels(lm, DESIGN_ORDER)
    return lqr_integral_design(two_channel_plant(ch.lateral, ch.vertical), Q, R)
