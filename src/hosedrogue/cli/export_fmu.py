"""``hosedrogue export-fmu``: an FMI 2.0 co-simulation FMU of the hose-drogue model, and its check."""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from ..errors import ParameterError
from .options import EXIT_BAD_INPUT, bounded_int, params_from_args

NAME = "export-fmu"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(
        NAME, help="write an FMI 2.0 co-simulation FMU of the model (for Simulink, OpenModelica, fmpy, ...)",
        description="Write FILE.fmu, an FMI 2.0 co-simulation FMU (pythonfmu) of the hose-drogue model. Inputs: "
                    "u_y_n, u_z_n [N] (control force at the drogue along S_p y and z) and gust_u_m_s, gust_v_m_s, "
                    "gust_w_m_s [m/s] (uniform gust along S_p x, y, z), held over each communication step; "
                    "outputs: drogue_x_m, drogue_y_m, drogue_z_m [m] and drogue_vx_m_s, drogue_vy_m_s, "
                    "drogue_vz_m_s [m/s] (S_p: x forward, y right, z down) and tow_tension_n [N] (force at the "
                    "tow point); parameters: altitude_m [m], airspeed_m_s [m/s], wake_enabled. It starts at the "
                    "balance position and integrates with RK4 sub-steps of numerics.step_s [s]. Running it needs "
                    "a Python with hosedrogue installed; --check validates it with fmpy and runs it here.")
    s.add_argument("--config", metavar="PRESET|FILE", action="append", default=[],
                   help="TOML file of parameter overrides ([hose], [flight], [numerics], ...) frozen into the FMU")
    s.add_argument("--links", metavar="N", type=bounded_int("--links", 1, 1000),
                   help="number of rigid links of the hose [-], >= 1 (default 20)")
    s.add_argument("--out", metavar="FILE.fmu",
                   help="the FMU file to write (required, unless --check alone builds one to check and deletes it)")
    s.add_argument("--check", action="store_true",
                   help="then check it on this host (needs fmpy): fmpy's validator, the units, and 1 s in fmpy "
                        "from the balance position; exit status 2 if it finds a problem")
    s.add_argument("--json", action="store_true", help="with --check: print the check's findings as JSON")
    s.set_defaults(func=run)


def _print_check(report: dict) -> None:
    """The check's findings, a few lines for a reader."""
    host = report["host"]
    print(f"FMU check of {report['fmu']} (fmpy {host['fmpy']}; this host: {host['platform']}, Python "
          f"{host['python']}, hosedrogue {host['hosedrogue']}, pythonfmu {host['pythonfmu']})")
    print(f"  fmpy.validation.validate_fmu and units: {len(report['problems'])} problem(s)")
    for problem in report["problems"]:
        print(f"    {problem}")
    print(f"  FMI {report['fmi_version']} co-simulation, binaries for {', '.join(report['platforms'])}; "
          f"{len(report['units'])} of {report['variables']} variables have a unit")
    sim = report["simulation"]
    if sim is not None:
        print(f"  {sim['duration_s']:g} s in fmpy ({sim['links']} links, step {sim['step_s']:g} s, zero inputs): "
              f"start {sim['start_offset_m']:.3g} m from the balance position (bound "
              f"{report['start_tolerance_m']:g} m), drift {sim['drift_m']:.3g} m, {sim['wall_s']:.2f} s wall")
    print("  ok" if report["ok"] else "  FAILED")


def run(args) -> int:
    """Export the FMU and print its path; with ``--check``, check it (exit status 2 on a problem).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..interop.fmu import check_fmu, check_out_path, export_fmu

    if args.out is None and not args.check:
        raise ParameterError("--out: required (the FMU file to write), unless --check")
    if args.json and not args.check:
        raise ParameterError("--json: only with --check")
    if args.out is not None:
        check_out_path(args.out, "--out")
    params = params_from_args(args)
    with tempfile.TemporaryDirectory(prefix="hosedrogue_check_") as tmp:
        path = export_fmu(args.out if args.out is not None else Path(tmp) / "hose.fmu", params)
        if args.out is not None:
            print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
        if not args.check:
            return 0
        report = check_fmu(path)
    if args.json:
        print(json.dumps(report, indent=1))
    else:
        _print_check(report)
    if not report["ok"]:
        first = report["problems"][0] if report["problems"] else (
            f"it starts {report['simulation']['start_offset_m']:.3g} m from the balance position, more than "
            f"{report['start_tolerance_m']:g} m")
        print(f"hosedrogue: error: FMU check failed ({len(report['problems'])} problem(s)): {first}", file=sys.stderr)
        return EXIT_BAD_INPUT
    return 0
