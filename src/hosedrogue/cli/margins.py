"""``hosedrogue margins``: gain, phase and delay margins of each channel's loop on the full-order
model, with the controller's sample time and the sensor delay, and their Bode and Nyquist figure.
Also the loop options (--controller, --lateral-gains, --vertical-gains, --sample-time,
--sensor-delay) that ``hosedrogue linearize --turbulence`` shares."""

from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError
from .options import add_flight_options, finite_float, params_from_args, prepare_out_file, steady_flight_text

NAME = "margins"


def add_loop_options(s, default: str) -> None:
    """Add the controller options of a loop analysis.

    Parameters
    ----------
    s : argparse.ArgumentParser
        The sub-command's parser.
    default : str
        The default of --controller.
    """
    s.add_argument("--controller", choices=("none", "pid", "lqr"), default=default,
                   help=f"the drogue controller: the paper's PID (Eq. 33 gains unless given), the paper's LQR designed "
                        f"on this linearization (the scenarios' 'balanced' design), or none (default {default})")
    for ch in ("lateral", "vertical"):
        s.add_argument(f"--{ch}-gains", metavar=("KP", "KI", "KD", "N"), nargs=4,
                       type=finite_float(f"--{ch}-gains", 0.0, 1e12, "(K_P N/m, K_I N/(m s), K_D N s/m, N rad/s)"),
                       help=f"PID gains of the {ch} channel: K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s] "
                            "(default the paper's)")
    add_sampling_options(s)


def add_sampling_options(s, prefix: str = "") -> None:
    """Add --sample-time and --sensor-delay (the controller's sampling and the sensor's delay).

    Parameters
    ----------
    s : argparse.ArgumentParser
        The sub-command's parser.
    prefix : str
        Put before each help text (e.g. the option they go with).
    """
    s.add_argument("--sample-time", metavar="S", type=finite_float("--sample-time", 0.0, 10.0, "s"), default=0.0,
                   help=prefix + "the controller's sample time [s], 0-10: its zero-order-hold discretization, as the "
                        "simulation runs a sampled controller (default 0: continuous)")
    s.add_argument("--sensor-delay", metavar="S", type=finite_float("--sensor-delay", 0.0, 60.0, "s"), default=0.0,
                   help=prefix + "the sensor's delay [s], a whole multiple of --sample-time (sampled controllers "
                        "only, as [sensor] delay_s; default 0)")


def check_sampling(args) -> None:
    """A sensor delay needs a sampled controller: one line naming the option otherwise.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (--sample-time, --sensor-delay).
    """
    if args.sensor_delay and not args.sample_time:
        raise ParameterError(f"--sensor-delay = {args.sensor_delay!r}: the delay acts on sampled controllers only; "
                             "give --sample-time")


def loop_controller(args, params, lm):
    """The controller the loop options select (None for 'none').

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.
    params : Params
        The model and flight condition.
    lm : LinearModel
        Its linearization (the LQR's design model).

    Returns
    -------
    LinearController or None
    """
    from ..controllers.design import design_controller, lqr_controller_for

    gains = {ch: list(getattr(args, f"{ch}_gains")) for ch in ("lateral", "vertical")
             if getattr(args, f"{ch}_gains", None) is not None}
    if gains and args.controller != "pid":
        raise ParameterError(f"--lateral-gains/--vertical-gains: PID gains need --controller pid "
                             f"(got {args.controller!r})")
    check_sampling(args)
    if args.controller == "lqr":
        return lqr_controller_for(lm, "balanced")
    try:
        return design_controller(args.controller, gains, params)
    except ValueError as exc:
        raise ParameterError(f"--lateral-gains/--vertical-gains: {exc}") from None


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="gain, phase and delay margins of each channel's loop, Bode and Nyquist figure",
                       description="Break each channel's loop at its force input (the other channel closed) on the "
                                   "full-order linear model about the balance position, with the controller sampled "
                                   "(zero-order hold) and the sensor's delay as the simulation runs them, and print "
                                   "the gain margin [-, dB], the phase margin [deg] at the gain crossover [rad/s] "
                                   "and the delay margin [s] (the extra delay that destabilizes the loop); write the "
                                   "Bode and Nyquist figure to --out (docs/loop-analysis.md).")
    add_flight_options(s)
    add_loop_options(s, "pid")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.add_argument("--out", metavar="FILE.png", default="out/margins/margins.png",
                   help="the Bode and Nyquist figure (default out/margins/margins.png)")
    s.set_defaults(func=run)


def run(args) -> int:
    """Compute and print the margins, write the figure.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..analysis.linearize import linearize
    from ..controllers.margins import channel_loop, frequency_grid, loop_margins, response
    from ..jsonio import dumps
    from ..plotting.base import save_figure
    from ..plotting.loop import plot_loops

    out = Path(args.out)
    if out.suffix.lower() not in (".png", ".pdf", ".svg") or out.is_dir():
        raise ParameterError(f"--out = {args.out!r}: must be a figure file name ending in .png, .pdf or .svg")
    prepare_out_file(out)  # its folder can be made and written: a one-line error before the work
    params = params_from_args(args)
    lm = linearize(params)
    ctrl = loop_controller(args, params, lm)
    if ctrl is None:
        raise ParameterError("--controller = 'none': the margins are of a loop; give pid or lqr")
    from ..controllers.covariance import delay_samples

    if args.sample_time:
        delay_samples(args.sensor_delay, args.sample_time)
    found = loop_margins(lm, ctrl, args.sample_time, args.sensor_delay)
    loops = {ch: channel_loop(lm, ctrl, ch, args.sample_time, args.sensor_delay) for ch in found}
    w = {ch: frequency_grid(loop)[::10] for ch, loop in loops.items()}
    data = {"controller": args.controller, "sample_time_s": args.sample_time, "sensor_delay_s": args.sensor_delay,
            "flight": {"altitude_m": params.flight.altitude_m, "airspeed_m_s": params.flight.airspeed_m_s,
                       "links": params.hose.links},
            **{ch: m.as_dict() for ch, m in found.items()}, "figure": str(out)}
    title = (f"{args.controller} at {params.flight.airspeed_m_s:g} m/s, {params.flight.altitude_m:g} m; sample time "
             f"{args.sample_time:g} s, sensor delay {args.sensor_delay:g} s")
    save_figure(plot_loops(w, {ch: response(loops[ch], w[ch]) for ch in loops},
                           {ch: m.as_dict() for ch, m in found.items()}, title), out)
    if args.json:
        print(dumps(data))
        return 0
    print(f"Loop margins of the {args.controller} on the full-order model: {params.flight.airspeed_m_s:g} m/s at "
          f"{params.flight.altitude_m:g} m, {params.hose.links} links{steady_flight_text(params)}; sample time "
          f"{args.sample_time:g} s, sensor delay {args.sensor_delay:g} s; closed loop "
          f"{'stable' if found['lateral'].stable else 'UNSTABLE'}")
    for ch, m in found.items():
        print(f"  {ch:8s}: gain margin {m.gain_margin:.4g} ({m.gain_margin_db:.3g} dB) at "
              f"{m.gain_crossover_phase_rad_s:.4g} rad/s; phase margin {m.phase_margin_deg:.4g} deg at "
              f"{m.crossover_rad_s:.4g} rad/s; delay margin {m.delay_margin_s:.4g} s")
    print(f"wrote {out}")
    return 0
