"""``hosedrogue design pid --rms-target M M``: the PID tuned to a predicted RMS offset of the drogue
in standard turbulence (:func:`hosedrogue.controllers.rms_tuning.tune_pid_to_rms`; docs/loop-analysis.md,
"Tuning to an RMS target") instead of to step bounds: its options, their check and the design's
description for the design command's table, JSON and MATLAB file."""

from __future__ import annotations

from ..errors import ParameterError
from .margins import add_sampling_options, check_sampling
from .options import finite_float

__all__ = ["add_rms_options", "check_rms_args", "rms_pid"]


def add_rms_options(s) -> None:
    """Add --rms-target, --turbulence, --sample-time and --sensor-delay to ``design``'s parser.

    Parameters
    ----------
    s : argparse.ArgumentParser
        The design command's parser.
    """
    s.add_argument("--rms-target", metavar="M", nargs=2, type=finite_float("--rms-target", 1e-6, 100.0, "m"),
                   help="PID only, --plant model: tune to these RMS drogue offsets [m] (lateral, vertical) in "
                        "--turbulence, predicted by covariance analysis on the full-order model, the least gain "
                        "crossover that meets them (instead of step bounds; docs/loop-analysis.md)")
    s.add_argument("--turbulence", choices=("light", "moderate", "severe"), default=None,
                   help="with --rms-target: the standard turbulence (MIL-F-8785C at the altitude; default moderate)")
    add_sampling_options(s, "with --rms-target: ")


def check_rms_args(args) -> None:
    """The RMS options' combinations: one line naming the option when they do not apply.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.
    """
    loop = [(opt, v) for opt, v in (("--turbulence", args.turbulence), ("--sample-time", args.sample_time or None),
                                    ("--sensor-delay", args.sensor_delay or None)) if v is not None]
    if args.rms_target is None:
        if loop:
            raise ParameterError(f"{loop[0][0]} = {loop[0][1]!r}: applies with --rms-target only")
        return
    text = " ".join(f"{v:g}" for v in args.rms_target)
    if args.controller != "pid" or args.plant != "model" or args.gains != "tuned":
        raise ParameterError(f"--rms-target = {text}: applies to a tuned PID on --plant model only")
    steps = [opt for opt, v in (("--rise-time", args.rise_time), ("--settling-time", args.settling_time),
                                ("--overshoot", args.overshoot)) if v is not None]
    if steps or args.min_damping:
        raise ParameterError(f"--rms-target = {text}: tunes to the RMS offset, not to step bounds; leave out "
                             f"{(steps or ['--min-damping'])[0]}")
    check_sampling(args)


def rms_pid(args, params):
    """The PID tuned to the RMS targets: (description, gains per channel, every target met).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (--rms-target, --turbulence, --sample-time, --sensor-delay).
    params : Params
        The model and flight condition.

    Returns
    -------
    tuple
        ``(ctrl, gains, met)``: ``ctrl`` JSON-ready (each channel's gains, target, predicted RMS
        [m], crossover [rad/s], ``met`` and ``shortfalls``).
    """
    from ..controllers.covariance import with_standard_turbulence
    from ..controllers.rms_tuning import PHASE_MARGIN_DEG, meets, tune_pid_to_rms
    from ..spec.paper import CHANNELS

    level = args.turbulence or "moderate"
    design = tune_pid_to_rms(with_standard_turbulence(params, level), tuple(args.rms_target), args.sample_time,
                             args.sensor_delay)
    ctrl = {"type": "pid", "source": "tuned to RMS", "method": "docs/loop-analysis.md",
            "turbulence": level, "sample_time_s": args.sample_time, "sensor_delay_s": args.sensor_delay,
            "rule": f"least gain crossover of the loop-shaping PID ({PHASE_MARGIN_DEG:g} deg phase margin on the "
                    "2nd-order design model) whose predicted RMS offset, both loops closed on the full-order "
                    "model, is at most the target"}
    for ch in CHANNELS:
        g, rms, target = design.gains[ch], float(design.rms_m[ch]), float(design.targets_m[ch])
        met = meets(rms, target)
        ctrl[ch] = {"kp_n_per_m": g.kp, "ki_n_per_m_s": g.ki, "kd_n_s_per_m": g.kd, "n_filter_rad_s": g.n_filter,
                    "rms_target_m": target, "predicted_rms_m": rms,
                    "crossover_rad_s": float(design.crossover_rad_s[ch]), "met": met,
                    "shortfalls": [] if met else [f"predicted RMS {rms:.4g} m > {target:.4g} m"]}
    ctrl["met"] = all(ctrl[ch]["met"] for ch in CHANNELS)
    return ctrl, dict(design.gains), ctrl["met"]
