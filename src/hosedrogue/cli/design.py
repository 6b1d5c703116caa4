"""``hosedrogue design {pid,lqr}``: the paper's controller on a reduced model, and its step metrics."""

from __future__ import annotations

import json

from ..errors import ParameterError
from .options import add_flight_options, bounded_int, finite_float, params_from_args

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
    s = sub.add_parser(NAME, help="design the paper's PID or LQR on a reduced model, with step metrics",
                       description="Design the paper's PID (Eq. 33 gains) or LQR (Eqs. 35-37) on a reduced model "
                                   "of each channel (lateral u_hor [N] -> P_ny [m], vertical u_ver [N] -> P_nz [m]) "
                                   "and print the controller and the unit reference step's rise time (10-90 %), "
                                   "settling time (2 %) and overshoot per channel, beside the paper's Table 3. "
                                   "LQR 'balanced' (default): the paper's Q weighs the balanced states of each "
                                   "channel, u = -K x, prefilter for unit DC gain, Kalman observer; 'integral': Q "
                                   "weighs the offsets and their integrals (Eq. 34).")
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
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=run)


def _poles(p) -> list[list[float]]:
    import numpy as np

    return [[float(z.real), float(z.imag)] for z in np.sort_complex(np.asarray(p, dtype=complex))]


def _check_args(args) -> int:
    """Validate option combinations; return the design order."""
    if args.plant == "paper":
        for opt, given in (("--altitude", args.altitude), ("--airspeed", args.airspeed), ("--links", args.links),
                           ("--config", args.config or None), ("--no-wake", args.no_wake or None)):
            if given is not None:
                raise ParameterError(f"{opt} = {given!r}: applies to --plant model only (the paper's "
                                     f"Table 2 models have no stated flight condition)")
    order = 2 if args.order is None else args.order
    if args.plant == "paper" and order not in (2, 6):
        raise ParameterError(f"--order = {order}: the paper's Table 2 has orders 2 and 6 only")
    if args.controller == "pid":
        for opt, given in (("--q", args.q), ("--r", args.r)):
            if given is not None:
                raise ParameterError(f"{opt} = {' '.join(f'{v:g}' for v in given)}: applies to lqr only "
                                     f"(pid uses the paper's Eq. 33 gains)")
        if args.design != "balanced":
            raise ParameterError(f"--design = {args.design!r}: applies to lqr only")
        return order
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


def _metrics(m) -> dict:
    """Step metrics as JSON numbers; NaN (not reached or not settled within the record) -> null."""
    import math

    vals = {"rise_time_s": m.rise_time_s, "settling_time_s": m.settling_time_s,
            "overshoot_pct": m.overshoot_pct, "final_value": m.final_value}
    return {k: (None if math.isnan(v) else v) for k, v in vals.items()}


def _plant(args, order: int):
    """The design models of both channels and their description (JSON-ready)."""
    from ..analysis.reduction import table2_form
    from ..controllers.table3 import channel_models
    from ..paper import CHANNELS

    info: dict = {"source": args.plant, "order": order}
    lm = None
    if args.plant == "model":
        from ..analysis.linearize import linearize

        params = params_from_args(args)
        lm = linearize(params)
        info["flight"] = {"altitude_m": params.flight.altitude_m, "airspeed_m_s": params.flight.airspeed_m_s,
                          "wake": params.wake.enabled, "links": params.hose.links}
    lat, ver = channel_models(args.plant, order, lm)
    for ch, g in zip(CHANNELS, (lat, ver)):
        num, den = table2_form(g)
        info[ch] = {"num": num.tolist(), "den": den.tolist(), "poles_rad_s": _poles(g.poles())}
    return lat, ver, info


def _pid(lat, ver):
    """The paper's PID: its description and the step responses."""
    from ..controllers.pid import PAPER_PID
    from ..controllers.table3 import pid_steps
    from ..paper import CHANNELS

    ctrl = {"type": "pid", "source": "paper Eq. 33"}
    for ch in CHANNELS:
        g = PAPER_PID[ch]
        ctrl[ch] = {"kp_n_per_m": g.kp, "ki_n_per_m_s": g.ki, "kd_n_s_per_m": g.kd, "n_filter_rad_s": g.n_filter}
    return ctrl, pid_steps(lat, ver)


def _lqr_balanced(lat, ver, Q, R):
    """The balanced-state LQR with its observer: description and design."""
    import numpy as np

    from ..controllers.lqr import POSITION_NOISE_PSD
    from ..controllers.lqr_balanced import TURBULENCE_FORCE_PSD, lqr_balanced_design
    from ..paper import CHANNELS

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
    """(description, step responses per channel, the Table 3 row key) of the requested design."""
    import numpy as np

    from ..controllers.lqr import PAPER_LQR_Q, PAPER_LQR_R
    from ..controllers.table3 import lqr_steps

    if args.controller == "pid":
        ctrl, steps = _pid(lat, ver)
        return ctrl, steps, "PID"
    R = PAPER_LQR_R if args.r is None else np.diag(args.r)
    Q = PAPER_LQR_Q if args.q is None else np.diag(args.q)
    ctrl, d = (_lqr_balanced if args.design == "balanced" else _lqr_integral)(lat, ver, Q, R)
    return ctrl, lqr_steps(d), "LQR"


def _pole_list(poles) -> str:
    return ", ".join(f"{re:.4g}{im:+.4g}j" for re, im in poles)


def _print_table(args, data: dict, order: int, paper_key: str) -> None:
    """The human-readable form of ``data``."""
    import numpy as np

    from ..analysis.reduction import format_tf
    from ..paper import CHANNELS

    plant, ctrl = data["plant"], data["controller"]
    where = ("the paper's Table 2 models" if args.plant == "paper" else
             f"this model at {plant['flight']['airspeed_m_s']:g} m/s, {plant['flight']['altitude_m']:g} m, "
             f"wake {'on' if plant['flight']['wake'] else 'off'}")
    what = "PID (paper Eq. 33 gains)" if args.controller == "pid" else f"LQR ({args.design})"
    print(f"{what} designed on {where}, order {order} per channel")
    for ch in CHANNELS:
        p = plant[ch]
        print(f"  {ch}: G(s) = {format_tf(np.array(p['num']), np.array(p['den']))}")
        c = ctrl.get(ch)
        if c and args.controller == "pid":
            print(f"    K_P {c['kp_n_per_m']:g} N/m, K_I {c['ki_n_per_m_s']:g} N/(m s), "
                  f"K_D {c['kd_n_s_per_m']:g} N s/m, N {c['n_filter_rad_s']:g} rad/s")
        elif c:
            print(f"    K = {np.round(c['gain_K'], 4).tolist()} on the balanced states, prefilter "
                  f"{c['prefilter_n_per_m']:.1f} N/m")
            print(f"    regulator poles [rad/s]: {_pole_list(c['regulator_poles_rad_s'])}")
            print(f"    observer poles [rad/s]:  {_pole_list(c['observer_poles_rad_s'])}")
    if args.controller == "lqr" and args.design == "integral":
        print(f"  K_x = {np.round(ctrl['gain_state'], 4).tolist()}, "
              f"K_z = {np.round(ctrl['gain_integral_n_per_m_s'], 4).tolist()} N/(m s)")
        print(f"  regulator poles [rad/s]: {_pole_list(ctrl['regulator_poles_rad_s'])}")
    print(f"  unit step             rise [s]  settling [s]  overshoot [%]   (paper Table 3 {paper_key})")
    for ch in CHANNELS:
        m, ref = data[ch], data[ch]["paper_table3"]
        rise, settle = (float("nan") if v is None else v for v in (m["rise_time_s"], m["settling_time_s"]))
        print(f"    {ch:9s}           {rise:8.4f}  {settle:12.4f}  {m['overshoot_pct']:13.2f}"
              f"   ({ref['rise_time_s']:g} / {ref['settling_time_s']:g} / {ref['overshoot_pct']:g})")


def run(args) -> int:
    """Design, compute the step metrics, print (or print JSON).

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

    from ..paper import CHANNELS, TABLE3

    order = _check_args(args)
    lat, ver, plant_info = _plant(args, order)
    ctrl, steps, paper_key = _controller(args, lat, ver)
    data = {"controller": ctrl, "plant": plant_info}
    for ch in CHANNELS:
        resp = steps[ch]
        data[ch] = {**_metrics(resp.metrics), "peak_force_n_per_m": float(np.max(np.abs(resp.u))),
                    "paper_table3": dict(TABLE3[(paper_key, ch)])}
    if args.json:
        print(json.dumps(data))
    else:
        _print_table(args, data, order, paper_key)
    return 0
