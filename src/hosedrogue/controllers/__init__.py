"""Controllers for the drogue position: PID and LQR with observer, as linear state-space laws.

Every design returns a `LinearController` that maps the measured drogue offset
y = [P_ny, P_nz] [m] to the force u = [u_hor, u_ver] [N], with the feedback sign inside.
"""

from .linear import LinearController
from .pid import PAPER_PID, PIDGains, pid_controller, tune_pid
from .lqr import (
    PAPER_LQR_Q,
    PAPER_LQR_R,
    LQRDesign,
    lqr_integral_design,
    lqr_tracking_closed_loop,
    two_channel_plant,
)
from .stepinfo import StepMetrics, StepResponse, closed_loop_step, step_metrics

__all__ = [
    "LinearController",
    "PAPER_PID",
    "PIDGains",
    "pid_controller",
    "tune_pid",
    "PAPER_LQR_Q",
    "PAPER_LQR_R",
    "LQRDesign",
    "lqr_integral_design",
    "lqr_tracking_closed_loop",
    "two_channel_plant",
    "StepMetrics",
    "StepResponse",
    "closed_loop_step",
    "step_metrics",
]
