"""``hosedrogue export-fmu``: an FMI 2.0 co-simulation FMU of the hose-drogue model (the hose of
fixed length, or with ``--engagement`` a scenario's engagement), and its check."""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

from ..errors import ParameterError
from ..jsonio import dumps
from .options import EXIT_BAD_INPUT, bounded_int, finite_float, params_from_args, prepare_out_file

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
                    "a Python with hosedrogue installed; --check validates it with fmpy and runs it here. "
                    "With --engagement SCENARIO: the engagement FMU of that scenario (the hose on its reel, the "
                    "drogue, the receiver's probe, capture and coupling; the scenario's hose, rigid or elastic), "
                    "frozen at export. Its inputs: the probe tip's position probe_cmd_x_m, probe_cmd_y_m, "
                    "probe_cmd_z_m [m] at the end of each "
                    "communication step (parameter probe_position_input true; with probe_velocity_feed true also "
                    "its velocity, probe_cmd_v*_m_s) or its velocity command "
                    "probe_cmd_vx_m_s, probe_cmd_vy_m_s, probe_cmd_vz_m_s [m/s] through the scenario's receiver "
                    "response, reel_speed_cmd_m_s [m/s] (a reel of law python) and u_y_n, u_z_n [N]; outputs: the "
                    "drogue's position [m] and velocity [m/s], the probe tip's, coupled, probe_load_n [N], "
                    "exit_tension_n [N], hose_length_m [m], reel_speed_m_s [m/s]; parameter sample_time_s [s], the "
                    "control sample it steps in (docs/interop.md, 'The engagement FMU').")
    s.add_argument("--config", metavar="PRESET|FILE", action="append", default=[],
                   help="TOML file of parameter overrides ([hose], [flight], [numerics], ...) frozen into the FMU "
                        "(not with --engagement: the scenario holds its tables)")
    s.add_argument("--engagement", metavar="SCENARIO",
                   help="export the engagement FMU of this engagement scenario (name or TOML file; an enabled "
                        "[probe], no [pilot], surfaces commanded by force, equilibrium start, no sensor noise or delay)")
    s.add_argument("--links", metavar="N", type=bounded_int("--links", 1, 1000),
                   help="number of links of the hose [-], >= 1 (default 20, or the scenario's)")
    s.add_argument("--duration", metavar="S", type=finite_float("--duration", 1e-9, 86400, "s"),
                   help="with --engagement: the run's length frozen into the FMU [s] (default the scenario's)")
    s.add_argument("--out", metavar="FILE.fmu",
                   help="the FMU file to write (required, unless --check alone builds one to check and deletes it)")
    s.add_argument("--check", action="store_true",
                   help="then check it on this host (needs fmpy): fmpy's validator, the units, and 1 s in fmpy "
                        "from the balance position; exit status 2 if it finds a problem")
    s.add_argument("--json", action="store_true", help="with --check: print the check's findings as JSON")
    s.set_defaults(func=run)


def _model(args):
    """What to export: the parameter set (fixed length) or the engagement scenario (``--engagement``)."""
    if args.engagement is None:
        if args.duration is not None:
            raise ParameterError("--duration: only with --engagement (the fixed-length FMU runs for any time)")
        return params_from_args(args)
    from ..scenarios import load_scenario

    if args.config:
        raise ParameterError(f"--config {args.config[0]}: not with --engagement (the scenario file holds its tables: "
                             "write them there, or extend it with [scenario] extends)")
    scenario = load_scenario(args.engagement).with_overrides(duration_s=args.duration)
    if args.links is not None:
        scenario = dataclasses.replace(scenario, params=scenario.params.replace(hose={"links": args.links}))
    return scenario


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
        inputs = "start inputs" if sim.get("kind") == "engagement" else "zero inputs"
        print(f"  {sim['duration_s']:g} s in fmpy ({sim['links']} links, step {sim['step_s']:g} s, {inputs}): "
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
        prepare_out_file(args.out)  # its folder can be made and written: a one-line error before the build
    model = _model(args)
    with tempfile.TemporaryDirectory(prefix="hosedrogue_check_") as tmp:
        name = "engagement.fmu" if args.engagement else "hose.fmu"
        path = export_fmu(args.out if args.out is not None else Path(tmp) / name, model)
        if args.out is not None:
            print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
        if not args.check:
            return 0
        report = check_fmu(path)
    if args.json:
        print(dumps(report, indent=1))
    else:
        _print_check(report)
    if not report["ok"]:
        first = report["problems"][0] if report["problems"] else (
            f"it starts {report['simulation']['start_offset_m']:.3g} m from the balance position, more than "
            f"{report['start_tolerance_m']:g} m")
        print(f"hosedrogue: error: FMU check failed ({len(report['problems'])} problem(s)): {first}", file=sys.stderr)
        return EXIT_BAD_INPUT
    return 0
