"""Controllers for the drogue position: PID and LQR with observer, as linear state-space laws.

The paper's LQR is `lqr_balanced_design` (the paper's Q weighs the balanced states of each
2nd-order channel; reproduces Table 3's lateral LQR row); `lqr_integral_design` is the
integral-action reading of Eq. 34, kept as a sensitivity. `table3` gives the step responses.
`tune_pid_to_step` tunes a PID to rise-time, settling-time and overshoot targets on any channel
model (`hosedrogue design pid`); `tune_pid` places a crossover and phase margin.

Every design returns a `LinearController` that maps the measured drogue offset
y = [P_ny, P_nz] [m] to the force u = [u_hor, u_ver] [N], with the feedback sign inside.
"""

from .linear import LinearController
from .pid import PAPER_PID, PIDGains, pid_controller, tune_pid
from .pid_tuning import PIDTuning, StepTargets, TargetsNotMet, pid_for_poles, tune_pid_to_step
from .lqr import (
    PAPER_LQR_Q,
    PAPER_LQR_R,
    LQRDesign,
    lqr_integral_design,
    lqr_tracking_closed_loop,
    two_channel_plant,
)
from .lqr_balanced import (
    TURBULENCE_FORCE_PSD,
    BalancedLQRChannel,
    BalancedLQRDesign,
    balanced_realization,
    lqr_balanced_design,
    lqr_balanced_reference_loop,
)
from .stepinfo import StepMetrics, StepResponse, closed_loop_step, step_metrics

__all__ = [
    "LinearController",
    "PAPER_PID",
    "PIDGains",
    "pid_controller",
    "tune_pid",
    "PIDTuning",
    "StepTargets",
    "TargetsNotMet",
    "pid_for_poles",
    "tune_pid_to_step",
    "PAPER_LQR_Q",
    "PAPER_LQR_R",
    "LQRDesign",
    "lqr_integral_design",
    "lqr_tracking_closed_loop",
    "two_channel_plant",
    "TURBULENCE_FORCE_PSD",
    "BalancedLQRChannel",
    "BalancedLQRDesign",
    "balanced_realization",
    "lqr_balanced_design",
    "lqr_balanced_reference_loop",
    "StepMetrics",
    "StepResponse",
    "closed_loop_step",
    "step_metrics",
]
