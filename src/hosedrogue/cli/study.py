"""``hosedrogue study``: the studies of the report run on their own; ``study docking`` runs the
docking grid (:mod:`hosedrogue.studies.docking`), ``study whip-loads`` the whip's loads against
the hose's axial stiffness and the closure speed (:mod:`hosedrogue.studies.whip_loads`),
``study actuator`` the actuated drogue's studies (:mod:`.study_actuator`), ``study receiver`` the
receiver aircraft's (:mod:`.study_receiver`)."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import ParameterError
from ..jsonio import dumps
from .options import EXIT_INCOMPLETE, MAX_RUNS, bounded_int, finite_float, prepare_out
from .study_actuator import add_study_parser
from .study_receiver import add_receiver_parser
from .study_registry import add_registry_studies

NAME = "study"


def add_parser(sub) -> None:
    """Register the sub-command (and its studies) on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    from ..studies.docking_grid import CONTROLLERS, LEVELS

    s = sub.add_parser(NAME, help="run one of the report's studies on its own",
                       description="Run one of the report's studies without building the report.")
    studies = s.add_subparsers(dest="study", required=True, parser_class=type(s))
    d = studies.add_parser(
        "docking", help="capture rate of the approach scenarios per turbulence level, controller and bow wave",
        description=(
            "Run the docking grid: a Monte Carlo campaign of the shipped approach-LEVEL scenario per cell "
            "(turbulence level x drogue controller x bow wave on/off, and the pilot model flying the probe with "
            "the bow wave on), optionally with the closure-speed and the force-limit cells, RUNS turbulence seeds "
            "per cell (run i: run_seed(--seed, i) in every cell). Each cell is a campaign folder DIR/<cell>/ "
            "(campaign.json with the cell's scenario, runs.csv, summary.json); running again with the same "
            "settings resumes. Prints per cell the capture rate [-] with its Wilson 95 % interval [-] and the "
            "counts by result, then the grid's comparisons (significant: the intervals apart). "
            "docs/engagement.md, 'Docking statistics'."))
    d.add_argument("--runs", metavar="N", type=bounded_int("--runs", 1, MAX_RUNS), required=True,
                   help="runs (turbulence seeds) per cell [-], >= 1")
    d.add_argument("--out", metavar="DIR", type=Path, default=Path("out/study-docking"),
                   help="parent folder of the cells' campaigns (default out/study-docking)")
    d.add_argument("--levels", metavar="LEVEL", nargs="+", choices=LEVELS, default=list(LEVELS),
                   help=f"turbulence levels (default {' '.join(LEVELS)})")
    d.add_argument("--controllers", metavar="TYPE", nargs="+", choices=CONTROLLERS, default=list(CONTROLLERS),
                   help=f"drogue controllers (default {' '.join(CONTROLLERS)})")
    d.add_argument("--no-pilot", action="store_true", help="leave out the pilot model's cells")
    d.add_argument("--scenario", metavar="NAME|FILE",
                   help="your approach (an engagement scenario) instead of the shipped approach-LEVEL: each cell flies "
                        "it in the level's standard turbulence at its altitude; the cells are named after it")
    d.add_argument("--closure-speeds", metavar="V", nargs="+", type=finite_float("--closure-speeds", 0.05, 10.0, "m/s"),
                   help="also the closure-speed cells: probe closure speeds [m/s] (each level and controller, bow "
                        "wave on, the run as long as the probe's path)")
    d.add_argument("--force-limits", metavar="F", nargs="+", type=finite_float("--force-limits", 0.001, 1e6, "N"),
                   help="also the force-limit cells: the drogue controllers' force limits per axis [N] (each level "
                        "and controller but none, bow wave on)")
    d.add_argument("--workers", metavar="K", type=bounded_int("--workers", 1, 4096),
                   help="dask worker processes shared by the cells [-] (default: run in this process)")
    d.add_argument("--seed", metavar="S", type=bounded_int("--seed", 0, 2**63 - 1), default=0,
                   help="campaign seed of every cell [-], >= 0 (default 0)")
    d.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    d.add_argument("--quiet", action="store_true", help="no progress bars")
    d.set_defaults(func=run_docking)
    _add_whip_loads(studies)
    add_study_parser(studies)
    add_receiver_parser(studies)
    add_registry_studies(studies)


def _add_whip_loads(studies) -> None:
    """Register ``study whip-loads``."""
    from ..studies.whip_loads import CLOSURE_SPEEDS_M_S, SCENARIOS, STIFFNESSES_N

    w = studies.add_parser(
        "whip-loads", help="the whip's loads against the hose's axial stiffness and the closure speed",
        description=(
            "Run engagement scenarios (default the shipped ones, one per reel law; or your own files) over a grid "
            "of the hose's axial stiffness EA "
            "[N] (its axial damping at the shipped loss factor 0.1 of the first axial mode) and the probe's "
            "closure speed [m/s], one run per point (no turbulence: deterministic). Prints per run the peak exit "
            "tension [N], its rise above the trail tension [N], the drogue-end tension [N], the probe load [N] "
            "and the slack [m]; with --verify N, N of the runs are run again on twice the links at half the step "
            "and their peaks flagged: * not converged (a peak of a row not verified is unverified). "
            "docs/engagement.md, 'Whip loads'."))
    w.add_argument("--stiffness", metavar="EA", nargs="+", type=finite_float("--stiffness", 1e3, 1e10, "N"),
                   default=list(STIFFNESSES_N), help="axial stiffnesses [N] (default 1e5 1e6 1e7 1e8)")
    w.add_argument("--closure-speeds", metavar="V", nargs="+", type=finite_float("--closure-speeds", 0.3, 3.0, "m/s"),
                   default=list(CLOSURE_SPEEDS_M_S), help="probe closure speeds [m/s] (default 0.5 1 1.5 2 2.5)")
    w.add_argument("--scenarios", metavar="NAME|FILE", nargs="+", default=list(SCENARIOS),
                   help=f"engagement scenarios: shipped names or TOML files with [probe] (default {' '.join(SCENARIOS)}); "
                        "all are checked before the first run")
    w.add_argument("--links", metavar="N", type=bounded_int("--links", 2, 1000),
                   help="links of every run [-] (default the scenarios' 160)")
    w.add_argument("--step", metavar="H", type=finite_float("--step", 1e-5, 0.01, "s"),
                   help="integration step with --links [s] (default the scenarios')")
    w.add_argument("--verify", metavar="N", type=bounded_int("--verify", 0, 10_000), default=0,
                   help="verify N of the runs, spread over the grid (each run again on twice the links at half "
                        "the step; docs/convergence.md); default 0")
    w.add_argument("--tolerance", metavar="REL", type=finite_float("--tolerance", 1e-6, 0.5, "-"), default=0.03,
                   help="relative change within which a verified peak is converged [-] (default 0.03)")
    w.add_argument("--ensemble", metavar="N", type=bounded_int("--ensemble", 2, 100_000),
                   help="the locked reel's rows (a chaotic flail): also N copies with the probe displaced by up to "
                        "1 um, each peak's median and 5-95 %% range")
    w.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    w.set_defaults(func=run_whip_loads)


def run_whip_loads(args) -> int:
    """Run the whip-load grid; print its rows (or JSON). Exit 3 if any run stopped early.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..jsonio import dumps
    from ..studies.whip_loads import PEAKS, whip_load_study

    if args.step is not None and args.links is None:
        raise ParameterError(f"--step = {args.step:g}: applies with --links only (the scenarios keep their own step)")
    rows = whip_load_study(args.stiffness, args.closure_speeds, args.scenarios, args.links, args.step,
                           verify=args.verify, tolerance=args.tolerance, ensemble=args.ensemble or 0)
    if args.json:
        print(dumps({"rows": [r.to_dict() for r in rows]}, indent=2))
    else:
        print("scenario (law), EA [N], closure [m/s]: " + ", ".join(PEAKS) + " (* not converged, ? unverified)")
        for r in rows:
            vals = ", ".join(f"{r.peaks[k]:.4g}{_flag(r.converged[k])}" for k in PEAKS)
            print(f"{r.scenario} ({r.law}), {r.stiffness_n:g}, {r.closure_speed_m_s:g}: {vals}; {r.result}")
            for k, d in (r.distributions or {}).items():
                print(f"    {k} over {d['copies']} perturbed copies: median {d['median']:.4g} "
                      f"[5 %: {d['p05']:.4g}, 95 %: {d['p95']:.4g}]")
    if not all(r.completed for r in rows):
        print(f"hosedrogue: {sum(not r.completed for r in rows)} runs stopped early", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def _flag(converged) -> str:
    """A verified peak's mark in the whip-load table: '' converged, '*' not, '?' unverified."""
    return "" if converged is True else ("*" if converged is False else "?")


def _specs(args) -> tuple[list, list, list]:
    """The main grid's, the closure-speed study's and the force-limit study's cells of the command line."""
    from ..studies.docking_grid import force_specs, grid_specs, speed_specs

    grid = grid_specs(args.levels, args.controllers, () if args.no_pilot else args.levels)
    speeds = [] if not args.closure_speeds else [
        s for level in args.levels for s in speed_specs(args.closure_speeds, level, args.controllers)]
    limited = [c for c in args.controllers if c != "none"]
    forces = force_specs(args.force_limits, args.levels, limited) if args.force_limits and limited else []
    return grid, speeds, forces


def _cell_record(spec, cell) -> dict:
    return {"cell": spec.name, "campaign": cell.name, "level": spec.level, "controller": spec.controller,
            "pilot": spec.pilot, "bow_wave": spec.bow_wave, "closure_speed_m_s": cell.closure_speed_m_s,
            "duration_s": cell.duration_s, **({} if spec.max_force_n is None else {"max_force_n": spec.max_force_n}),
            **cell.capture}


def _findings(grid, speeds, forces, every) -> dict:
    """The comparisons of the main grid and, where run, the two studies' findings."""
    from ..studies import docking_statistics as ds

    n, m = len(grid), len(grid) + len(speeds)
    out = {"comparisons": ds.comparisons(ds.capture_table(every[:n]))}
    if speeds:  # per level: the findings compare the speeds of one level
        latch = every[n].scenario.engagement.probe.min_closure_speed_m_s
        pairs = list(zip(speeds, every[n:m]))
        out["closure_speed"] = {
            level: ds.speed_findings(ds.speed_table(*zip(*[(s, c) for s, c in pairs if s.level == level])), latch)
            for level in dict.fromkeys(s.level for s in speeds)}
    if forces:
        out["force_limit"] = ds.force_findings(ds.force_table(forces, every[m:]))
    return out


def _print_table(specs, every, findings: dict) -> None:
    for spec, cell in zip(specs, every):
        cap = cell.capture
        lo, hi = cap["ci95"]
        by = ", ".join(f"{k} {v}" for k, v in cap["by_result"].items() if v)
        same = "" if cell.name == spec.name else f" (= {cell.name})"
        print(f"{spec.name}{same}: capture rate {cap['rate']:.3f} (Wilson 95 %: {lo:.3f}-{hi:.3f}) over "
              f"{cap['runs']} runs: {by}")
    for key, c in findings["comparisons"].items():
        sig = "significant" if c["significant"] else "intervals overlap: not significant"
        print(f"{key}: {c['rate_a']:.3f} against {c['rate_b']:.3f} ({sig})")


def run_docking(args) -> int:
    """Run the docking grid; print the capture rates (or JSON). Exit 3 if any run stopped early.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    # here, not at the top: the model's modules (numba) load only when the study runs
    from ..studies.docking import run_grid

    from ..scenarios import load_scenario
    from ..studies.docking_grid import level_scenario

    base = None
    if args.scenario is not None:  # checked before anything runs
        base = load_scenario(args.scenario)
        for level in args.levels:
            level_scenario(base, level)
    prepare_out(args.out)
    grid, speeds, forces = _specs(args)
    specs = grid + speeds + forces
    every = run_grid(specs, args.runs, args.out, workers=args.workers, seed=args.seed, progress=not args.quiet,
                     base=base)
    findings = _findings(grid, speeds, forces, every)
    if args.json:
        record = {"scenario": "approach-LEVEL" if base is None else base.name, "runs_per_cell": args.runs,
                  "seed": args.seed, "out": str(args.out),
                  "cells": [_cell_record(s, c) for s, c in zip(specs, every)], **findings}
        print(dumps(record, indent=2))
    else:
        _print_table(specs, every, findings)
        print(f"wrote {len({c.name for c in every})} campaigns into {args.out}")
    stopped = sum(int((~c.runs["completed"].astype(bool)).sum()) for c in {c.name: c for c in every}.values())
    if stopped:
        print(f"hosedrogue: {stopped} runs stopped early (completed = false in the cells' runs.csv)", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
