"""``hosedrogue export-fmu``: an FMI 2.0 co-simulation FMU of the hose-drogue model."""

from __future__ import annotations

from .options import bounded_int, params_from_args

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
                    "a Python with hosedrogue installed.")
    s.add_argument("--config", metavar="FILE",
                   help="TOML file of parameter overrides ([hose], [flight], [numerics], ...) frozen into the FMU")
    s.add_argument("--links", metavar="N", type=bounded_int("--links", 1, 1000),
                   help="number of rigid links of the hose [-], >= 1 (default 20)")
    s.add_argument("--out", metavar="FILE.fmu", required=True, help="the FMU file to write")
    s.set_defaults(func=run)


def run(args) -> int:
    """Export the FMU and print its path; exit status 0.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..interop.fmu import check_out_path, export_fmu

    check_out_path(args.out, "--out")
    path = export_fmu(args.out, params_from_args(args))
    print(f"wrote {path}")
    return 0
