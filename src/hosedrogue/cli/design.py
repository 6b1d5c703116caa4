"""``hosedrogue design {pid,lqr}``: a PID tuned to step targets (or the paper's gains), or the paper's
LQR, on a reduced model; the step metrics, the full-order check and the MATLAB file."""

from __future__ import annotations

from ..errors import ParameterError
from ..jsonio import dumps
from .design_rms import add_rms_options, check_rms_args, rms_pid
from .options import EXIT_INCOMPLETE, add_flight_options, bounded_int, finite_float, params_from_args

NAME = "design"

#: Upper bound of a weight entry [-]; far beyond any useful design, it keeps the Riccati solve finite.
MAX_WEIGHT = 1e15


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="tune a PID to step bounds (or use the paper's) or design the paper's LQR, "
                                  "on a reduced model, with step metrics",
                       description="Design a controller on a reduced model of each channel (lateral u_hor [N] -> "
                                   "P_ny [m], vertical u_ver [N] -> P_nz [m]) and print it with the unit reference "
                                   "step's rise time (10-90 %), settling time (2 %) and overshoot per channel, on the "
                                   "design model and on the full-order model. PID (default 'tuned'): the gains of least "
                                   "high-frequency gain K_P + K_D N whose step rises, settles and overshoots at most "
                                   "the targets (bounds; Table 3's PID rows unless given) and, with --min-damping, "
                                   "whose closed-loop poles are damped at least that much (docs/tuning.md: a global "
                                   "search on the exact step); '--gains paper': the paper's Eq. 33 gains. LQR 'balanced' (default): the paper's Q weighs the balanced states of "
                                   "each channel, u = -K x, prefilter for unit DC gain, Kalman observer; 'integral': "
                                   "Q weighs the offsets and their integrals (Eq. 34). Exit 3 when no design meets "
                                   "the bounds: the closest one is printed and written, marked as not meeting them.")
    s.add_argument("controller", choices=("pid", "lqr"), help="pid or lqr")
    s.add_argument("--plant", choices=("paper", "model"), default="model",
                   help="design model: 'paper' = the paper's Table 2 models (flight options not allowed), "
                        "'model' = this project's linearization at the flight condition (default)")
    add_flight_options(s)
    s.add_argument("--order", metavar="N", type=bounded_int("--order", 1, 50), default=None,
                   help="order of each channel's design model [-] (default 2 as in the paper; "
                        "--plant paper: 2 or 6)")
    s.add_argument("--design", choices=("balanced", "integral"), default="balanced",
                   help="LQR reading: 'balanced' (the paper's, default) or 'integral' (Eq. 34)")
    s.add_argument("--q", metavar="Q", nargs="+", type=finite_float("--q", 0.0, MAX_WEIGHT, "(a weight)"),
                   help="LQR state weights, the diagonal of Q: balanced = lateral then vertical balanced "
                        "states [1/(m N)], 2 x order values (default the paper's 12000 8000 8000 10000); "
                        "integral = [P_ny, P_nz] [1/m^2] then their integrals [1/(m s)^2], 4 values")
    s.add_argument("--r", metavar="R", nargs=2, type=finite_float("--r", 1e-12, MAX_WEIGHT, "1/N^2"),
                   help="LQR force weights [1/N^2], the diagonal of R for u_hor, u_ver "
                        "(default the paper's 0.4 0.5)")
    s.add_argument("--gains", choices=("tuned", "paper"), default="tuned",
                   help="PID gains: 'tuned' to the step bounds (default) or 'paper' (Eq. 33, designed on the paper's "
                        "Table 2 models)")
    from ..spec.paper import CHANNELS, TABLE3

    def table3(key: str) -> str:
        return " ".join(f"{TABLE3[('PID', ch)][key]:g}" for ch in CHANNELS)

    s.add_argument("--rise-time", metavar="S", nargs=2, type=finite_float("--rise-time", 1e-4, 1e4, "s"),
                   help=f"PID bounds: largest 10-90 %% rise time [s], lateral then vertical (default Table 3's "
                        f"{table3('rise_time_s')})")
    s.add_argument("--settling-time", metavar="S", nargs=2, type=finite_float("--settling-time", 1e-4, 1e5, "s"),
                   help=f"PID bounds: largest 2 %% settling time [s], lateral then vertical, each above its rise time "
                        f"(default Table 3's {table3('settling_time_s')})")
    s.add_argument("--overshoot", metavar="PCT", nargs=2, type=finite_float("--overshoot", 0.0, 99.0, "%"),
                   help=f"PID bounds: largest overshoot [%%] of the step, lateral then vertical, 0-99 (default Table 3's "
                        f"{table3('overshoot_pct')})")
    s.add_argument("--min-damping", metavar="ZETA", type=finite_float("--min-damping", 0.0, 1.0, "[-]"), default=0.0,
                   help="PID bound: smallest damping ratio [-] every closed-loop pole must have, 0-1 (default 0: any "
                        "stable loop)")
    add_rms_options(s)
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.add_argument("--format", choices=("table", "json", "mat"), default="table",
                   help="'table' (default), 'json' (same as --json) or 'mat': also write --out FILE.mat for MATLAB "
                        "(PID: K_P, K_I, K_D, N per channel, targets_met false for the closest design when the bounds "
                        "are not met; LQR: K, prefilter, observer gain; both: the controller's A, B, C, D with input, "
                        "output and state names and units)")
    s.add_argument("--out", metavar="FILE.mat", help="file written by --format mat (required with it)")
    s.set_defaults(func=run)


def _poles(p) -> list[list[float]]:
    import numpy as np

    return [[float(z.real), float(z.imag)] for z in np.sort_complex(np.asarray(p, dtype=complex))]


def _check_args(args) -> int:
    """Validate option combinations; return the design order."""
    if args.plant == "paper":
        for opt, given in (("--altitude", args.altitude), ("--airspeed", args.airspeed), ("--links", args.links),
                           ("--bank-deg", getattr(args, "bank_deg", None)),
                           ("--climb-deg", getattr(args, "climb_deg", None)),
                           ("--config", args.config or None), ("--no-wake", args.no_wake or None)):
            if given is not None:
                raise ParameterError(f"{opt} = {given!r}: applies to --plant model only (the paper's "
                                     f"Table 2 models have no stated flight condition)")
    order = 2 if args.order is None else args.order
    if args.plant == "paper" and order not in (2, 6):
        raise ParameterError(f"--order = {order}: the paper's Table 2 has orders 2 and 6 only")
    _check_output(args)
    check_rms_args(args)
    if args.controller == "pid":
        for opt, given in (("--q", args.q), ("--r", args.r)):
            if given is not None:
                raise ParameterError(f"{opt} = {' '.join(f'{v:g}' for v in given)}: applies to lqr only")
        if args.design != "balanced":
            raise ParameterError(f"--design = {args.design!r}: applies to lqr only")
        _check_targets(args)
        return order
    for opt, given in (("--rise-time", args.rise_time), ("--settling-time", args.settling_time),
                       ("--overshoot", args.overshoot)):
        if given is not None:
            raise ParameterError(f"{opt} = {' '.join(f'{v:g}' for v in given)}: applies to pid only")
    for opt, given, default in (("--gains", args.gains, "tuned"), ("--min-damping", args.min_damping, 0.0)):
        if given != default:
            raise ParameterError(f"{opt} = {given!r}: applies to pid only")
    if args.q is not None:
        need = 2 * order if args.design == "balanced" else 4
        if len(args.q) != need:
            what = (f"2 x --order = {need} values (balanced states, lateral then vertical)" if args.design == "balanced"
                    else "4 values (P_ny, P_nz, and their integrals)")
            raise ParameterError(f"--q = {' '.join(f'{v:g}' for v in args.q)}: give {what}")
    elif args.design == "balanced" and order != 2:
        raise ParameterError(f"--order = {order}: the paper's Q weighs 2 balanced states per channel; "
                             f"give --q with {2 * order} values for order {order}")
    return order


def _check_output(args) -> None:
    """--format mat needs --out FILE.mat, and --out needs --format mat."""
    if args.format == "mat":
        from .linearize import prepare_mat_out

        if args.out is None:
            raise ParameterError("--format mat: give --out FILE.mat (the file to write)")
        prepare_mat_out(args.out)
    elif args.out is not None:
        raise ParameterError(f"--out = {args.out!r}: applies to --format mat only")


def _check_targets(args) -> None:
    """The PID targets: only with tuned gains, each settling time above its rise time."""
    given = [(opt, v) for opt, v in (("--rise-time", args.rise_time), ("--settling-time", args.settling_time),
                                     ("--overshoot", args.overshoot), ("--min-damping", args.min_damping or None))
             if v is not None]
    if args.gains == "paper" and given:
        opt, v = given[0]
        text = " ".join(f"{x:g}" for x in v) if isinstance(v, list) else f"{v:g}"
        raise ParameterError(f"{opt} = {text}: applies to --gains tuned only (--gains paper uses Eq. 33's gains)")
    for ch, target in _targets(args).items():
        if not target["settling_time_s"] > target["rise_time_s"]:
            raise ParameterError(f"--settling-time = {target['settling_time_s']:g} ({ch}): must exceed the "
                                 f"{ch} rise time {target['rise_time_s']:g} s")


def _targets(args) -> dict:
    """Per channel the step targets: the options where given, Table 3's PID rows otherwise."""
    from ..spec.paper import CHANNELS, TABLE3

    out = {}
    for k, ch in enumerate(CHANNELS):
        t = dict(TABLE3[("PID", ch)])
        for key, given in (("rise_time_s", args.rise_time), ("settling_time_s", args.settling_time),
                           ("overshoot_pct", args.overshoot)):
            if given is not None:
                t[key] = given[k]
        out[ch] = t
    return out


def _metrics(m) -> dict:
    """Step metrics as JSON numbers; NaN (not reached or not settled within the record) -> null."""
    import math

    vals = {"rise_time_s": m.rise_time_s, "settling_time_s": m.settling_time_s,
            "overshoot_pct": m.overshoot_pct, "final_value": m.final_value}
    return {k: (None if math.isnan(v) else float(v)) for k, v in vals.items()}


def _plant(args, order: int):
    """The design models, the full-order models of both channels and their description (JSON-ready)."""
    from ..analysis.reduction import table2_form
    from ..controllers.table3 import channel_models
    from ..spec.paper import CHANNELS

    info: dict = {"source": args.plant, "order": order}
    lm = None
    if args.plant == "model":
        from ..analysis.linearize import linearize

        params = params_from_args(args)
        lm = linearize(params)
        info["flight"] = {"altitude_m": params.flight.altitude_m, "airspeed_m_s": params.flight.airspeed_m_s,
                          "wake": params.wake.enabled, "links": params.hose.links,
                          "hose_length_m": params.hose.length_m}
    lat, ver = channel_models(args.plant, order, lm)
    full = channel_models(args.plant, 6 if args.plant == "paper" else "full", lm)
    info["full_order"] = "paper Table 2, 6th order" if args.plant == "paper" else f"{lm.A.shape[0]} states"
    for ch, g in zip(CHANNELS, (lat, ver)):
        num, den = table2_form(g)
        info[ch] = {"num": num.tolist(), "den": den.tolist(), "poles_rad_s": _poles(g.poles())}
    return (lat, ver), full, info


def _gains_json(g) -> dict:
    return {"kp_n_per_m": g.kp, "ki_n_per_m_s": g.ki, "kd_n_s_per_m": g.kd, "n_filter_rad_s": g.n_filter}


def _pid(args, lat, ver):
    """The PID (tuned or the paper's): description, gains, whether the bounds are met and, tuned,
    each channel's exact step figures on the design model (what the table and the message show)."""
    from ..controllers.pid import PAPER_PID
    from ..spec.paper import CHANNELS

    if args.rms_target is not None:
        ctrl, gains, met = rms_pid(args, params_from_args(args))
        return ctrl, gains, met, None
    if args.gains == "paper":
        ctrl = {"type": "pid", "source": "paper Eq. 33"}
        for ch in CHANNELS:
            ctrl[ch] = _gains_json(PAPER_PID[ch])
        return ctrl, dict(PAPER_PID), True, None
    from ..controllers import pid_tuning as pt

    ctrl = {"type": "pid", "source": "tuned", "method": "docs/tuning.md", "min_damping_required": args.min_damping,
            "rule": "least K_P + K_D N among the designs whose step meets the bounds (rise, settling, overshoot at "
                    "most the targets; every closed-loop pole damped at least min_damping_required)"}
    gains, metrics = {}, {}
    for ch, g in zip(CHANNELS, (lat, ver)):
        try:
            tuning = pt.tune_pid_to_step(g, pt.StepTargets(**_targets(args)[ch]), min_damping=args.min_damping)
        except pt.TargetsNotMet as exc:
            tuning = exc.closest
        gains[ch], metrics[ch] = tuning.gains, tuning.metrics
        ctrl[ch] = {**_gains_json(tuning.gains), "targets": tuning.targets.as_dict(), "met": tuning.met,
                    "shortfalls": tuning.shortfalls(), "closed_loop_poles_rad_s": _poles(tuning.poles_rad_s),
                    "min_damping": tuning.min_damping, "high_frequency_gain_n_per_m": tuning.high_frequency_gain_n_per_m}
    ctrl["met"] = all(ctrl[ch]["met"] for ch in CHANNELS)
    return ctrl, gains, ctrl["met"], metrics


def _lqr_balanced(lat, ver, Q, R):
    """The balanced-state LQR with its observer: description and design."""
    import numpy as np

    from ..controllers.lqr import POSITION_NOISE_PSD
    from ..controllers.lqr_balanced import TURBULENCE_FORCE_PSD, lqr_balanced_design
    from ..spec.paper import CHANNELS

    try:
        d = lqr_balanced_design(lat, ver, Q, R)
    except ValueError as exc:
        raise ParameterError(f"--q/--r: no balanced-state LQR for these weights and plant ({exc})")
    ctrl = {"type": "lqr", "design": "balanced",
            "observer": {"kind": "steady-state Kalman filter per channel",
                         "force_noise_psd_n2_s": TURBULENCE_FORCE_PSD,
                         "position_noise_psd_m2_s": POSITION_NOISE_PSD}}
    for ch in CHANNELS:
        c = getattr(d, ch)
        ctrl[ch] = {"q_diag_per_m_n": np.diag(c.Q).tolist(), "r_per_n2": c.R,
                    "hankel_singular_values_m_per_n": c.hsv.tolist(),
                    "balanced_A_1_s": c.balanced.A.tolist(), "balanced_B": c.balanced.B[:, 0].tolist(),
                    "balanced_C": c.balanced.C[0].tolist(),
                    "gain_K": c.gain[0].tolist(), "prefilter_n_per_m": c.prefilter,
                    "regulator_poles_rad_s": _poles(c.regulator_poles),
                    "observer_gain_L": c.observer_gain[:, 0].tolist(),
                    "observer_poles_rad_s": _poles(c.observer_poles)}
    return ctrl, d


def _lqr_integral(lat, ver, Q, R):
    """The integral-action LQR with its observer: description and design."""
    import numpy as np

    from ..controllers.lqr import lqr_integral_design, two_channel_plant

    try:
        d = lqr_integral_design(two_channel_plant(lat, ver), Q, R)
    except ValueError as exc:
        raise ParameterError(f"--q/--r: no integral-action LQR for these weights and plant ({exc})")
    ctrl = {"type": "lqr", "design": "integral",
            "q_diag": np.diag(d.Q).tolist(), "r_diag_per_n2": np.diag(d.R).tolist(),
            "gain_state": d.gain_state.tolist(), "gain_integral_n_per_m_s": d.gain_integral.tolist(),
            "regulator_poles_rad_s": _poles(d.regulator_poles),
            "observer_gain_L": d.observer_gain.tolist(), "observer_poles_rad_s": _poles(d.observer_poles)}
    return ctrl, d


def _controller(args, lat, ver):
    """(description, design, step responses per channel, Table 3 row key, bounds met, the tuned PID's
    exact step figures per channel or None) of the design."""
    import numpy as np

    from ..controllers.lqr import PAPER_LQR_Q, PAPER_LQR_R
    from ..controllers.table3 import lqr_steps, pid_steps

    if args.controller == "pid":
        ctrl, gains, met, metrics = _pid(args, lat, ver)
        return ctrl, gains, pid_steps(lat, ver, gains), "PID", met, metrics
    R = PAPER_LQR_R if args.r is None else np.diag(args.r)
    Q = PAPER_LQR_Q if args.q is None else np.diag(args.q)
    ctrl, d = (_lqr_balanced if args.design == "balanced" else _lqr_integral)(lat, ver, Q, R)
    return ctrl, d, lqr_steps(d), "LQR", True, None


def _full_order(design, design_models, full) -> dict:
    """The design's unit steps closed around the full-order channels: {channel: metrics or unstable}."""
    from ..controllers.table3 import steps_on
    from ..spec.paper import CHANNELS

    try:
        out = steps_on(design, *full, design_models=design_models)
    except ValueError as exc:
        if not isinstance(design, dict):  # the LQR's two channels form one loop
            return {ch: {"stable": False, "message": str(exc).splitlines()[0][:200]} for ch in CHANNELS}
        result = {}
        for k, ch in enumerate(CHANNELS):  # which PID loop is unstable: each channel alone
            one = {c: design[ch] for c in CHANNELS}
            try:
                m = steps_on(one, full[k], full[k], design_models=(design_models[k],) * 2)["lateral"].metrics
                result[ch] = {"stable": True, **_metrics(m)}
            except ValueError as exc_ch:
                result[ch] = {"stable": False, "message": str(exc_ch).splitlines()[0][:200]}
        return result
    return {ch: {"stable": True, **_metrics(out[ch].metrics)} for ch in CHANNELS}


def _pole_list(poles) -> str:
    return ", ".join(f"{re:.4g}{im:+.4g}j" for re, im in poles)


def _fmt(v, spec: str) -> str:
    return "n/a" if v is None else format(v, spec)


def _print_channel(args, ch: str, p: dict, c: dict | None) -> None:
    import numpy as np

    from ..analysis.reduction import format_tf

    print(f"  {ch}: G(s) = {format_tf(np.array(p['num']), np.array(p['den']))}")
    if c and args.controller == "pid":
        print(f"    K_P {c['kp_n_per_m']:g} N/m, K_I {c['ki_n_per_m_s']:g} N/(m s), "
              f"K_D {c['kd_n_s_per_m']:g} N s/m, N {c['n_filter_rad_s']:g} rad/s")
        if "predicted_rms_m" in c:
            print(f"    predicted RMS offset {c['predicted_rms_m']:.4g} m in {args.turbulence or 'moderate'} turbulence "
                  f"(target {c['rms_target_m']:g} m: {'met' if c['met'] else 'NOT met'}), crossover "
                  f"{c['crossover_rad_s']:.4g} rad/s")
        if "closed_loop_poles_rad_s" in c:
            print(f"    closed-loop poles [rad/s]: {_pole_list(c['closed_loop_poles_rad_s'])}; smallest damping "
                  f"ratio {c['min_damping']:.3f}; K_P + K_D N {c['high_frequency_gain_n_per_m']:.6g} N/m")
            if not c["met"]:
                print(f"    bounds NOT met, the closest design found: {', '.join(c['shortfalls'])}")
            if c["min_damping"] < LIGHT_DAMPING:
                print(f"    note: the least damped closed-loop pole (damping {c['min_damping']:.3f}) rings in the "
                      f"response to disturbances; --min-damping forbids it (docs/tuning.md)")
    elif c:
        print(f"    K = {np.round(c['gain_K'], 4).tolist()} on the balanced states, prefilter "
              f"{c['prefilter_n_per_m']:.1f} N/m")
        print(f"    regulator poles [rad/s]: {_pole_list(c['regulator_poles_rad_s'])}")
        print(f"    observer poles [rad/s]:  {_pole_list(c['observer_poles_rad_s'])}")


def _print_table(args, data: dict, order: int, paper_key: str) -> None:
    """The human-readable form of ``data``."""
    import numpy as np

    from ..spec.paper import CHANNELS

    plant, ctrl = data["plant"], data["controller"]
    where = ("the paper's Table 2 models" if args.plant == "paper" else
             f"this model at {plant['flight']['airspeed_m_s']:g} m/s, {plant['flight']['altitude_m']:g} m, "
             f"{plant['flight']['hose_length_m']:g} m hose, wake {'on' if plant['flight']['wake'] else 'off'}")
    tuned = args.controller == "pid" and args.gains == "tuned" and args.rms_target is None
    what = ("PID tuned to step bounds" if tuned else "PID tuned to an RMS offset" if args.rms_target is not None
            else "PID (paper Eq. 33 gains)" if args.controller == "pid" else f"LQR ({args.design})")
    print(f"{what} on {where}, order {order} per channel")
    for ch in CHANNELS:
        _print_channel(args, ch, plant[ch], ctrl.get(ch))
    if args.controller == "lqr" and args.design == "integral":
        print(f"  K_x = {np.round(ctrl['gain_state'], 4).tolist()}, "
              f"K_z = {np.round(ctrl['gain_integral_n_per_m_s'], 4).tolist()} N/(m s)")
        print(f"  regulator poles [rad/s]: {_pole_list(ctrl['regulator_poles_rad_s'])}")
    ref_name = "at most" if tuned else f"paper Table 3 {paper_key}"
    print(f"  unit step             rise [s]  settling [s]  overshoot [%]   ({ref_name})   "
          f"full order ({plant['full_order']})")
    for ch in CHANNELS:
        m, ref, fo = data[ch], data[ch]["target"] if tuned else data[ch]["paper_table3"], data[ch]["full_order"]
        full = (f"{_fmt(fo['rise_time_s'], '.4f')} / {_fmt(fo['settling_time_s'], '.4f')} / "
                f"{_fmt(fo['overshoot_pct'], '.2f')}" if fo["stable"] else "unstable")
        print(f"    {ch:9s}           {_fmt(m['rise_time_s'], '8.4f')}  {_fmt(m['settling_time_s'], '12.4f')}  "
              f"{_fmt(m['overshoot_pct'], '13.2f')}   ({ref['rise_time_s']:g} / {ref['settling_time_s']:g} / "
              f"{ref['overshoot_pct']:g})   {full}"
              + ("" if not tuned else "   meets the bounds" if ctrl[ch]["met"] else "   bounds NOT met"))
    if args.controller == "pid":
        rows = ", ".join(f"{ch} = [{ctrl[ch]['kp_n_per_m']:.6g}, {ctrl[ch]['ki_n_per_m_s']:.6g}, "
                         f"{ctrl[ch]['kd_n_s_per_m']:.6g}, {ctrl[ch]['n_filter_rad_s']:.6g}]" for ch in CHANNELS)
        print(f"  in a scenario: [controller] type = \"pid\", {rows}")


#: Smallest damping ratio [-] below which a tuned design gets a note: a pole pair damped less than
#: 0.2 rings with 53 % overshoot of its own and decays by half only after 0.55 periods.
LIGHT_DAMPING = 0.2


def _write_mat(args, data: dict, design, steps_json: dict) -> None:
    from pathlib import Path

    from ..interop.matlab import lqr_mat_dict, pid_mat_dict, write_controller_mat

    if args.controller == "pid":
        from ..controllers.pid import pid_controller

        content = pid_mat_dict(design, pid_controller(design["lateral"], design["vertical"]),
                               source=data["controller"]["source"], plant=data["plant"], steps=steps_json)
    else:
        content = lqr_mat_dict(design, reading=args.design, plant=data["plant"], steps=steps_json)
    path = Path(args.out)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_controller_mat(content, path)


def run(args) -> int:
    """Design, compute the step metrics, print (or print JSON), write the MATLAB file.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`): 0, 2 for bad options, 3 when no PID meets the
        bounds (the closest design printed and written, marked as not meeting them).
    """
    import sys

    import numpy as np

    from ..spec.paper import CHANNELS, TABLE3

    order = _check_args(args)
    (lat, ver), full, plant_info = _plant(args, order)
    try:
        ctrl, design, steps, paper_key, met, tuned = _controller(args, lat, ver)
    except ValueError as exc:  # the closest design of a failed tuning can leave the loop unstable
        print(f"hosedrogue: design {args.controller}: no stable design found: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    data = {"controller": ctrl, "plant": plant_info}
    full_order = _full_order(design, (lat, ver), full)
    for ch in CHANNELS:
        resp = steps[ch]
        exact = None if tuned is None else tuned[ch]  # a tuned PID: the figures its bounds were checked on
        data[ch] = {**_metrics(resp.metrics if exact is None else exact), "peak_force_n_per_m": float(np.max(np.abs(resp.u))),
                    "paper_table3": dict(TABLE3[(paper_key, ch)]), "full_order": full_order[ch]}
        if "targets" in ctrl.get(ch, {}):
            data[ch]["target"] = ctrl[ch]["targets"]
    if args.json or args.format == "json":
        print(dumps(data))
    else:
        _print_table(args, data, order, paper_key)
    if args.format == "mat":
        _write_mat(args, data, design, {ch: {**data[ch], "targets": data[ch].get("target"),
                                             **({"targets_met": ctrl[ch]["met"]} if "met" in ctrl[ch] else {})} for ch in CHANNELS})
        if not (args.json or args.format == "json"):
            print(f"wrote {args.out}" + ("" if met else " (the closest design, marked targets_met = false)"))
    if not met:
        misses = "; ".join(f"{ch}: {', '.join(ctrl[ch]['shortfalls'])}" for ch in CHANNELS if not ctrl[ch]["met"])
        print(f"hosedrogue: design pid: no design meets the bounds, the closest found is "
              f"{'written' if args.format == 'mat' else 'printed'}: {misses}", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
