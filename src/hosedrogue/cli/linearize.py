"""``hosedrogue linearize``: the linear model about the balance position, reduced per channel."""

from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError
from ..jsonio import dumps
from .margins import add_loop_options, loop_controller
from .options import add_flight_options, params_from_args, parse_order, prepare_out_file, steady_flight_text

NAME = "linearize"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="linear model about the balance position, reduced transfer functions",
                       description="Linearize about the balance position (inputs u_hor, u_ver [N] at the drogue; "
                                   "outputs the drogue's lateral and vertical offset P_ny, P_nz [m]) and print each "
                                   "channel's transfer function (descending powers of s, denominator monic) at the "
                                   "requested order (balanced truncation) with its poles [rad/s].")
    add_flight_options(s)
    s.add_argument("--order", default="2", metavar="full|N",
                   help="'full' or the reduced order per channel [-], >= 1 (default 2, as the paper's design model)")
    s.add_argument("--turbulence", choices=("light", "moderate", "severe"),
                   help="also predict the drogue's RMS offset [m] in this standard turbulence (MIL-F-8785C intensity "
                        "at the altitude) by covariance analysis, open loop and, with --controller, closed loop "
                        "(JSON: predicted_rms_m, predicted_rms_closed_loop_m); a config's enabled [turbulence] "
                        "is predicted without it (docs/loop-analysis.md)")
    add_loop_options(s, "none")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.add_argument("--format", choices=("table", "json", "mat"), default="table",
                   help="'table' (default), 'json' (same as --json) or 'mat': write --out FILE.mat for MATLAB "
                        "(A, B, C, D in SI units, state/input/output names and units, each channel's reduced "
                        "transfer function) and print the table")
    s.add_argument("--out", metavar="FILE.mat", default="out/linearize/linear_model.mat",
                   help="file written by --format mat (default out/linearize/linear_model.mat)")
    s.set_defaults(func=run)


def run(args) -> int:
    """Linearize, reduce and print (or print JSON).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    import numpy as np

    from ..analysis.linearize import linearize
    from ..analysis.reduction import format_tf, table2_form
    from ..controllers.design import reduced_channels

    order = parse_order(args.order)
    if args.format == "mat":
        prepare_mat_out(args.out)
    params = params_from_args(args)
    lm = linearize(params)
    ctrl = loop_controller(args, params, lm)
    ch = reduced_channels(lm, order)
    data = {}
    for name, sys_ in (("lateral", ch.lateral), ("vertical", ch.vertical)):
        num, den = table2_form(sys_)
        poles = np.sort_complex(sys_.poles())  # from the state matrix, not the polynomial
        data[name] = {"num": num.tolist(), "den": den.tolist(),
                      "poles": [[float(p.real), float(p.imag)] for p in poles]}
    data["order"] = "full" if order is None else order
    data["flight"] = {"altitude_m": params.flight.altitude_m, "airspeed_m_s": params.flight.airspeed_m_s,
                      **({} if params.tanker_motion.is_level else {"bank_deg": params.tanker_motion.bank_deg,
                                                                     "flight_path_deg": params.tanker_motion.flight_path_deg}),
                      "wake": params.wake.enabled, "links": params.hose.links}
    data.update(predicted_rms(args, params, lm, ctrl))
    if args.json or args.format == "json":
        print(dumps(data))
        return 0
    if args.format == "mat":
        from ..interop.matlab import write_linear_mat

        table = {name: (np.array(data[name]["num"]), np.array(data[name]["den"])) for name in ("lateral", "vertical")}
        path = Path(args.out)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_linear_mat(lm, ch, table, path)
        print(f"wrote {path}")
    print(f"Linear model about the balance position: {params.flight.airspeed_m_s:g} m/s at "
          f"{params.flight.altitude_m:g} m, wake {'on' if params.wake.enabled else 'off'}, "
          f"{params.hose.links} links{steady_flight_text(params)}; order {data['order']} per channel "
          "(balanced truncation)")
    for name, label in (("lateral", "u_hor [N] -> P_ny [m]"), ("vertical", "u_ver [N] -> P_nz [m]")):
        print(f"  {name} ({label}):")
        print(f"    G(s) = {format_tf(np.array(data[name]['num']), np.array(data[name]['den']))}")
        poles = ", ".join(f"{re:.4g}{im:+.4g}j" for re, im in data[name]["poles"])
        print(f"    poles [rad/s]: {poles}")
    if "predicted_rms_m" in data:
        t = data["turbulence"]
        print(f"  predicted RMS offset in {t['level']} turbulence (sigma {t['sigma_m_s'][1]:.4g} m/s, covariance "
              f"analysis): open loop lateral {data['predicted_rms_m']['lateral']:.4g} m, vertical "
              f"{data['predicted_rms_m']['vertical']:.4g} m")
        if "predicted_rms_closed_loop_m" in data:
            c = data["predicted_rms_closed_loop_m"]
            print(f"    with the {args.controller} (sample time {args.sample_time:g} s, sensor delay "
                  f"{args.sensor_delay:g} s): lateral {c['lateral']:.4g} m, vertical {c['vertical']:.4g} m")
    return 0


def predicted_rms(args, params, lm, ctrl) -> dict:
    """The JSON keys of the covariance analysis: ``turbulence``, ``predicted_rms_m`` (open loop) and,
    with a controller, ``predicted_rms_closed_loop_m`` [m]; none without turbulence to predict.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (--turbulence and the loop options).
    params : Params
        The model and flight condition.
    lm : LinearModel
        Its linearization.
    ctrl : LinearController or None
        The controller of the loop options.

    Returns
    -------
    dict
    """
    from ..controllers.covariance import disturbance_model, predict, with_standard_turbulence

    if args.turbulence is None and not params.turbulence.enabled:
        if ctrl is not None:
            raise ParameterError(f"--controller = {args.controller!r}: a controller is analysed in turbulence; "
                                 "give --turbulence light|moderate|severe (or a config with [turbulence])")
        return {}
    p = with_standard_turbulence(params, args.turbulence) if args.turbulence else params
    dm = disturbance_model(p, lm=lm)
    t = p.turbulence
    out = {"turbulence": {"level": args.turbulence or "config", "model": t.model, "sigma_m_s": list(t.sigma_m_s),
                          "scale_length_m": list(t.scale_length_m), "distribution": t.distribution},
           "predicted_rms_m": predict(p, dm=dm).as_dict()}
    if ctrl is not None:
        closed = predict(p, ctrl, args.sample_time, args.sensor_delay, dm=dm)
        out["predicted_rms_closed_loop_m"] = closed.as_dict()
        out["controller"] = {"type": args.controller, "sample_time_s": args.sample_time,
                             "sensor_delay_s": args.sensor_delay}
    return out


def prepare_mat_out(out: str) -> None:
    """Refuse a --out that is not a ``.mat`` file name (before anything is computed).

    Parameters
    ----------
    out : str
        The --out value.

    Raises
    ------
    ParameterError
        If it does not end in ``.mat`` or is a directory.
    """
    path = Path(out)
    if path.suffix != ".mat" or path.is_dir():
        raise ParameterError(f"--out = {out!r}: must be a file name ending in .mat")
    prepare_out_file(path)  # its folder can be made and written: a one-line error before the work
