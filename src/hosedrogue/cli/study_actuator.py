"""``hosedrogue study actuator``: the drogue steered by control surfaces against the paper's ideal
force (:mod:`hosedrogue.studies.drogue_actuator`): the servo margins, the claims cases and, with
``--runs``, the capture rate against the surfaces' deflection limit and servo bandwidth."""

from __future__ import annotations

import math
import sys
from pathlib import Path

from ..jsonio import dumps
from .options import EXIT_INCOMPLETE, MAX_RUNS, bounded_int, finite_float, prepare_out

__all__ = ["add_study_parser", "run_actuator"]


def add_study_parser(studies) -> None:
    """Register ``study actuator`` on the study command's subparsers.

    Parameters
    ----------
    studies : argparse._SubParsersAction
        The subparsers of ``hosedrogue study``.
    """
    from ..studies.docking_grid import ACTUATOR_LEVELS, DEFLECTION_LIMITS_DEG, SERVO_BANDWIDTHS_HZ
    from ..studies.drogue_actuator import LEVELS, MARGIN_BANDWIDTHS_HZ

    a = studies.add_parser(
        "actuator", help="the paper's controllers through the drogue's control surfaces, against the ideal force",
        description=(
            "The drogue steered by its control surfaces ([drogue_actuator] defaults) against the paper's ideal force: "
            "the phase margin [deg] of the paper's PID and LQR with a servo of each bandwidth [Hz] (linearized hose); "
            "the paper's turbulence case and light/moderate/severe turbulence at 150 m/s, 8000 m, ideal force and "
            "surfaces (defaults, 5 deg, 12 Hz): peaks [m], RMS [m], peak force [N], time at the deflection and rate "
            "limits [-], and where the paper's 'within 1 cm' holds; with --runs, the capture rate [-] (Wilson 95 %) "
            "of the approach scenarios against the deflection limit and the servo bandwidth (docking campaigns in "
            "DIR/<cell>/). docs/model.md, 'Actuated drogue'."))
    a.add_argument("--scenario", metavar="NAME|FILE",
                   help="your fixed-length scenario for the claims cases and the margins: its model, flight condition, "
                        "turbulence (level 'paper' keeps it) and [drogue_actuator] (the actuated variants start from it), "
                        "flown with each controller (default the paper's turbulence case)")
    a.add_argument("--approach", metavar="NAME|FILE",
                   help="your approach (an engagement scenario) for the capture cells, flown in each level's turbulence "
                        "(default the shipped approach-LEVEL)")
    a.add_argument("--seeds", metavar="N", type=bounded_int("--seeds", 0, MAX_RUNS), default=1,
                   help="turbulence realisations per claims case [-] (0: no claims; default 1)")
    a.add_argument("--levels", metavar="LEVEL", nargs="+", choices=LEVELS, default=list(LEVELS),
                   help=f"claims turbulence cases (default {' '.join(LEVELS)})")
    a.add_argument("--margins", metavar="HZ", nargs="+", type=finite_float("--margins", 0.01, 1e4, "Hz"),
                   default=list(MARGIN_BANDWIDTHS_HZ), help="servo bandwidths of the margin table [Hz]")
    a.add_argument("--runs", metavar="N", type=bounded_int("--runs", 0, MAX_RUNS), default=0,
                   help="runs per capture cell [-] (0: no campaigns; default 0)")
    a.add_argument("--deflections", metavar="DEG", nargs="+", type=finite_float("--deflections", 0.01, 90.0, "deg"),
                   default=list(DEFLECTION_LIMITS_DEG), help="deflection limits of the capture cells [deg]")
    a.add_argument("--bandwidths", metavar="HZ", nargs="+", type=finite_float("--bandwidths", 0.01, 1000.0, "Hz"),
                   default=list(SERVO_BANDWIDTHS_HZ), help="servo bandwidths of the capture cells [Hz]")
    a.add_argument("--capture-levels", metavar="LEVEL", nargs="+", choices=("light", "moderate", "severe"),
                   default=list(ACTUATOR_LEVELS), help=f"capture cells' turbulence (default {' '.join(ACTUATOR_LEVELS)})")
    a.add_argument("--out", metavar="DIR", type=Path, default=Path("out/study-actuator"),
                   help="parent folder of the capture campaigns (default out/study-actuator)")
    a.add_argument("--workers", metavar="K", type=bounded_int("--workers", 1, 4096),
                   help="dask worker processes of the campaigns [-] (default: this process)")
    a.add_argument("--json", action="store_true", help="print one JSON object instead of the tables")
    a.set_defaults(func=run_actuator)


def _records(df) -> list:
    """Table rows for JSON: infinities (the ideal force) as null."""
    return [{k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}
            for row in df.to_dict(orient="records")]


def _print(margins, claims, one_cm, capture) -> None:
    for r in margins.itertuples():
        print(f"{r.controller} servo {r.bandwidth_hz:g} Hz: phase margin {r.lateral_margin_deg:.1f} / "
              f"{r.vertical_margin_deg:.1f} deg (lateral / vertical), {'stable' if r.stable else 'UNSTABLE'}")
    if claims is not None:
        for r in claims.itertuples():
            print(f"{r.level} {r.controller} {r.force}: largest peak {1000 * max(r.peak_dy_m_max, r.peak_dz_m_max):.2f} mm, "
                  f"median RMS {1000 * r.rms_radial_m_median:.2f} mm, peak force {r.peak_u_n_max:.0f} N, "
                  f"completed {r.completed_fraction:.2f}, within 1 cm {r.within_1cm_fraction:.2f}")
        for key, v in one_cm.items():
            print(f"within 1 cm, {key}: holds in {', '.join(v['holds']) or 'none'}; not in {', '.join(v['fails']) or 'none'}")
    if capture is not None:
        for _, r in capture.iterrows():
            what = "ideal force" if not math.isfinite(r["max_deflection_deg"]) else (
                f"{r['max_deflection_deg']:g} deg, {r['bandwidth_hz']:g} Hz")
            print(f"{r['level']} {r['controller']} {what}: capture rate {r['rate']:.3f} (Wilson 95 %: "
                  f"{r['ci95_low']:.3f}-{r['ci95_high']:.3f}) over {int(r['runs'])} runs")


def run_actuator(args) -> int:
    """Run the actuated-drogue studies; print the tables (or JSON). Exit 3 if a capture run stopped.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..scenarios import load_scenario
    from ..studies import drogue_actuator as study
    from ..studies.docking_grid import level_scenario

    base = approach = None
    if args.scenario is not None:  # both checked before anything runs
        base = load_scenario(args.scenario)
        study.claims_scenario(args.levels[0], study.CONTROLLERS[0], base=base)
    if args.approach is not None:
        approach = load_scenario(args.approach)
        for level in args.capture_levels:
            level_scenario(approach, level)
    if args.runs:
        prepare_out(args.out)
    margins = study.servo_margins(tuple(args.margins), params=None if base is None else base.params)
    claims = one_cm = capture = None
    if args.seeds:
        claims = study.claims_table(study.claims_runs(args.seeds, levels=tuple(args.levels), base=base))
        one_cm = study.within_one_cm(claims)
    stopped = 0
    if args.runs:
        from ..studies.docking import run_grid
        from ..studies.docking_grid import actuator_specs
        from ..studies.docking_statistics import actuator_table

        specs = actuator_specs(tuple(args.deflections), tuple(args.bandwidths), tuple(args.capture_levels))
        cells = run_grid(specs, args.runs, args.out, workers=args.workers, base=approach)
        capture = actuator_table(specs, cells)
        stopped = int(capture.drop_duplicates("campaign")["stopped"].sum())
    if args.json:
        print(dumps({"servo_margins": _records(margins),
                          "claims": None if claims is None else _records(claims), "within_1cm": one_cm,
                          "capture": None if capture is None else _records(capture)}, indent=2))
    else:
        _print(margins, claims, one_cm, capture)
    if stopped:
        print(f"hosedrogue: {stopped} capture runs stopped early (a diverging loop; completed = false in runs.csv)",
              file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
