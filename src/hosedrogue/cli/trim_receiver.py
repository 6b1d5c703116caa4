"""``hosedrogue trim-receiver``: the receiver aircraft trimmed in steady flight, and its linear model."""

from __future__ import annotations

from .options import finite_float

NAME = "trim-receiver"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(
        NAME, help="trim the receiver aircraft (F-16 or your model file) and give its linear model and modes",
        description="Trim the receiver aircraft in steady flight (a coordinated turn when banked, a climb when "
                    "--climb-deg is not 0): angle of attack, sideslip, throttle (0-1), elevator, aileron and rudder "
                    "[deg] and the residual accelerations. --linear adds the linear model about the trim (states "
                    "airspeed, alpha, beta, phi, theta, psi, p, q, r, north, east, altitude, power; inputs throttle, "
                    "elevator, aileron, rudder [deg]; SI) and its modes (short period, phugoid, Dutch roll, roll, "
                    "spiral). A model FILE is read, never run (docs/receiver.md).")
    s.add_argument("--airspeed", type=finite_float("--airspeed", 1.0, 600.0, "m/s"), required=True, metavar="M_PER_S",
                   help="true airspeed [m/s]")
    s.add_argument("--altitude", type=finite_float("--altitude", 0.0, 20000.0, "m"), required=True, metavar="M",
                   help="altitude [m], 0 to 20000")
    s.add_argument("--climb-deg", type=finite_float("--climb-deg", -60.0, 60.0, "deg"), default=0.0, metavar="DEG",
                   help="flight-path climb angle [deg] (default 0)")
    s.add_argument("--bank-deg", type=finite_float("--bank-deg", -80.0, 80.0, "deg"), default=0.0, metavar="DEG",
                   help="bank angle of a coordinated turn [deg], positive right (default 0: straight)")
    s.add_argument("--model", default="f16", metavar="f16|FILE",
                   help="'f16' (Stevens, Lewis & Johnson 2015, the default) or a receiver-model TOML file")
    s.add_argument("--xcg", type=finite_float("--xcg", 0.0, 1.0, "of the chord"), default=None, metavar="FRACTION",
                   help="centre of gravity, fraction of the mean aerodynamic chord (default the model's: F-16 0.35)")
    s.add_argument("--linear", action="store_true", help="also give the linear model (A, B, C, D) and its modes")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=run)


def run(args) -> int:
    """Trim (and linearize), then print.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..aircraft.linear import INPUT_NAMES, OUTPUT_NAMES, STATE_NAMES, linearize_receiver
    from ..aircraft.model_file import load_model
    from ..aircraft.trim import trim
    from ..jsonio import dumps

    model = load_model(args.model)
    if args.xcg is not None:
        model = model.with_xcg(args.xcg)
    t = trim(model, args.airspeed, args.altitude, args.climb_deg, args.bank_deg)
    doc = {"model": model.name, "source": model.source, "trim": t.as_dict()}
    if args.linear:
        lm = linearize_receiver(t)
        doc["linear"] = {"states": STATE_NAMES, "inputs": INPUT_NAMES, "outputs": OUTPUT_NAMES, "A": lm.A,
                         "B": lm.B, "C": lm.C, "D": lm.D, "modes": [m.as_dict() for m in lm.modes]}
    if args.json:
        print(dumps(doc))
        return 0
    _print_table(doc)
    return 0


def _print_table(doc: dict) -> None:
    d = doc["trim"]
    print(f"Receiver {doc['model']} trimmed at {d['airspeed_m_s']:g} m/s, {d['altitude_m']:g} m, climb "
          f"{d['climb_deg']:g} deg, bank {d['bank_deg']:g} deg (xcg {d['xcg']:g}):")
    for key, unit in (("alpha_deg", "deg"), ("beta_deg", "deg"), ("theta_deg", "deg"), ("turn_rate_deg_s", "deg/s"),
                      ("throttle", "0-1"), ("elevator_deg", "deg"), ("aileron_deg", "deg"), ("rudder_deg", "deg"),
                      ("power_pct", "%")):
        print(f"  {key:<16} {d[key]: .6g} [{unit}]")
    worst = max(d["residuals"].items(), key=lambda kv: abs(kv[1]))
    print(f"  largest residual {worst[0]} = {worst[1]:.2g}")
    if "linear" not in doc:
        return
    print("Modes (airspeed, alpha, beta, phi, theta, p, q, r; altitude and power held):")
    for m in doc["linear"]["modes"]:
        re, im = m["eigenvalues"][0]
        root = f"{re:.4g} +/- {abs(im):.4g}j" if im else f"{re:.4g}"
        shape = (f"frequency {m['frequency_rad_s']:.4g} rad/s, damping {m['damping']:.3g}" if im else
                 f"time constant {m['time_constant_s']:.4g} s" + (" (unstable)" if re > 0 else ""))
        print(f"  {m['name']:<13} {root:<24} {shape}")
    print("A, B, C, D: --json (or hosedrogue.aircraft.linear.linearize_receiver in Python)")
