"""Controllers for the drogue position: PID and LQR with observer, as linear state-space laws.

The paper's LQR is `lqr_balanced_design` (the paper's Q weighs the balanced states of each
2nd-order channel; reproduces Table 3's lateral LQR row); `lqr_integral_design` is the
integral-action reading of Eq. 34, kept as a sensitivity. `table3` gives the step responses.
`tune_pid_to_step` tunes a PID to rise-time, settling-time and overshoot targets on any channel
model (`hosedrogue design pid`); `tune_pid` places a crossover and phase margin.

Every design returns a `LinearController` that maps the measured drogue offset
y = [P_ny, P_nz] [m] to the force u = [u_hor, u_ver] [N], with the feedback sign inside.
"""

# each name loads its module on first use (as the package's own top level does): a run that only
# applies a designed controller (a campaign's worker, a subprocess) does not import python-control,
# scipy.signal and matplotlib with the design code (0.8 s of CPU per process): name -> module
_LAZY = {
    "LinearController": "linear",
    **dict.fromkeys(("PAPER_PID", "PIDGains", "pid_controller", "tune_pid"), "pid"),
    **dict.fromkeys(("PIDTuning", "StepTargets", "TargetsNotMet", "pid_for_poles", "tune_pid_to_step"), "pid_tuning"),
    **dict.fromkeys(("PAPER_LQR_Q", "PAPER_LQR_R", "LQRDesign", "lqr_integral_design", "lqr_tracking_closed_loop",
                     "two_channel_plant"), "lqr"),
    **dict.fromkeys(("TURBULENCE_FORCE_PSD", "BalancedLQRChannel", "BalancedLQRDesign", "balanced_realization",
                     "lqr_balanced_design", "lqr_balanced_reference_loop"), "lqr_balanced"),
    **dict.fromkeys(("StepMetrics", "StepResponse", "closed_loop_step", "step_metrics"), "stepinfo"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = list(_LAZY)  # the public names are the lazily loaded ones
