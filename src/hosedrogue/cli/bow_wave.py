"""``hosedrogue bow-wave``: the drogue's steady displacement by the receiver's bow wave."""

from __future__ import annotations

import numpy as np

from ..jsonio import dumps
from .options import finite_float

NAME = "bow-wave"

#: Probe distances aft of the drogue printed by default [m].
DEFAULT_DISTANCES_M = (0.5, 1.0, 2.0, 5.0, 10.0)


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="steady drogue displacement by the receiver's bow wave",
                       description="Hold the probe tip still on the drogue's axis at each distance aft of the drogue, "
                                   "solve the balance position in steady air with the receiver's bow wave and print "
                                   "the drogue's displacement from its balance position without it [m] (S_p: x "
                                   "forward, y right, z down), and the bow wave's speed at the undisplaced drogue "
                                   "[m/s]. Model, flight condition and forebody from SCENARIO's [bow_wave] section "
                                   "(docs/engagement.md, 'Bow wave').")
    s.add_argument("scenario", metavar="SCENARIO", nargs="?", default="approach-moderate",
                   help="engagement scenario name or TOML file (default approach-moderate)")
    s.add_argument("--distances", metavar="M", nargs="+", type=finite_float("--distances", 1e-3, 1e3, "m"),
                   default=list(DEFAULT_DISTANCES_M),
                   help=f"probe tip distances aft of the drogue [m] (default {' '.join(map(str, DEFAULT_DISTANCES_M))})")
    s.add_argument("--radius", metavar="R", type=finite_float("--radius", 1e-3, 5.0, "m"),
                   help="forebody radius far aft of the nose [m] (overrides the scenario)")
    s.add_argument("--offset", metavar=("FWD", "RIGHT", "DOWN"), nargs=3,
                   type=finite_float("--offset", -20.0, 20.0, "m"),
                   help="probe tip relative to the nose: forward, right, down [m] (overrides the scenario)")
    s.add_argument("--shape", choices=("rankine", "source-line"),
                   help="forebody singularity: 'rankine' point source or 'source-line' (overrides the scenario)")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=run)


def _forebody(scenario, args):
    """The scenario's [bow_wave] section with the command line's overrides, enabled."""
    from ..spec.sections import BowWave

    e = scenario.engagement
    base = (e.bow_wave if e is not None else None) or BowWave()
    changes = {"enabled": True}
    if args.radius is not None:
        changes["forebody_radius_m"] = args.radius
    if args.offset is not None:
        changes["probe_offset_m"] = list(args.offset)
    if args.shape is not None:
        changes["shape"] = args.shape
    return BowWave.from_mapping(changes, base=base)


def run(args) -> int:
    """Solve the displaced balance positions and print them; exit status 0.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..engagement.bow_wave import bow_wave_displacement, bow_wave_speed_at_drogue
    from ..scenarios import load_scenario

    scenario = load_scenario(args.scenario)
    bow = _forebody(scenario, args)
    d = np.asarray(args.distances, dtype=np.float64)
    disp = bow_wave_displacement(scenario.params, bow, d)
    speed = bow_wave_speed_at_drogue(scenario.params, bow, d)
    p = scenario.params
    doc = {
        "scenario": scenario.name, "airspeed_m_s": p.flight.airspeed_m_s, "altitude_m": p.flight.altitude_m,
        "wake": bool(p.wake.enabled), "links": p.hose.links, "forebody_radius_m": bow.forebody_radius_m,
        "probe_offset_m": list(bow.probe_offset_m), "shape": bow.shape,
        "rows": [{"distance_m": float(di), "displacement_m": [float(v) for v in dv],
                  "displacement_magnitude_m": float(np.linalg.norm(dv)),
                  "bow_wave_speed_at_drogue_m_s": float(si)} for di, dv, si in zip(d, disp, speed)],
    }
    if args.json:
        print(dumps(doc))
        return 0
    print(f"Bow wave of a {bow.forebody_radius_m:g} m {bow.shape} forebody, probe tip {tuple(bow.probe_offset_m)} m "
          f"from its nose; {scenario.name}: {p.flight.airspeed_m_s:g} m/s at {p.flight.altitude_m:g} m, "
          f"wake {'on' if p.wake.enabled else 'off'}, {p.hose.links} links, steady air")
    print("  distance [m]   dx [mm]    dy [mm]    dz [mm]   |d| [mm]   bow-wave speed at drogue [m/s]")
    for row in doc["rows"]:
        dx, dy, dz = (1e3 * v for v in row["displacement_m"])
        print(f"  {row['distance_m']:10.3f} {dx:9.3f} {dy:10.3f} {dz:10.3f} {1e3 * row['displacement_magnitude_m']:10.3f}"
              f"   {row['bow_wave_speed_at_drogue_m_s']:.4f}")
    return 0
