"""``hosedrogue steady``: the balance position."""

from __future__ import annotations

import json

import numpy as np

from .options import add_flight_options, params_from_args, steady_flight_text

NAME = "steady"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="balance position (equilibrium) of the hose and drogue",
                       description="Print the balance position: drogue position [m] in S_p (the tanker's body axes at "
                                   "the tow point), drogue drag [N], tow-point force [N], exit tension [N] and D = "
                                   "V_D/L_H (drogue drop over hose length); in level flight, or in a steady coordinated "
                                   "turn (--bank-deg) and/or climb or descent (--climb-deg).")
    add_flight_options(s)
    s.add_argument("--continuum", action="store_true",
                   help="solve the continuous hose (towed-cable limit of infinitely many links, bending "
                        "neglected) instead of the link model")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=run)


def run(args) -> int:
    """Solve and print the balance position; exit status 0.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..analysis.equilibrium import solve_equilibrium

    params = params_from_args(args)
    if args.continuum:
        from ..analysis.continuum import solve_continuum

        eq = solve_continuum(params)
        model = "continuous hose (bending neglected)"
        drag = float(np.linalg.norm(eq.drogue_drag_n))
    else:
        eq = solve_equilibrium(params, narrow=True)  # nothing else of the chain runs: compile the least
        model = f"{params.hose.links} links"
        drag = eq.drogue_drag_magnitude_n
    motion = params.tanker_motion
    steady_flight = {"bank_deg": motion.bank_deg, "flight_path_deg": motion.flight_path_deg}
    if args.json:
        doc = eq.to_dict()
        if steady_flight != {"bank_deg": 0.0, "flight_path_deg": 0.0}:
            doc["tanker_motion"] = steady_flight
        print(json.dumps(doc))
        return 0
    x, y, z = eq.drogue_position_m
    fx, fy, fz = eq.tow_force_n
    print(f"Balance position: {model}, {params.hose.length_m:g} m hose, "
          f"{params.flight.airspeed_m_s:g} m/s at {params.flight.altitude_m:g} m, "
          f"wake {'on' if params.wake.enabled else 'off'}{steady_flight_text(params)}")
    print(f"  drogue position (x fwd, y right, z down) [m]: {x:9.4f} {y:9.4f} {z:9.4f}")
    print(f"  drogue drag [N]:                               {drag:9.2f}")
    print(f"  tow-point force [N]:                           {fx:9.2f} {fy:9.2f} {fz:9.2f}")
    print(f"  exit tension [N]:                              {eq.exit_tension_n:9.2f}")
    print(f"  balance ratio D = V_D / L_H:                   {eq.balance_ratio:9.4f}")
    return 0

