"""Command line: parse, call, print. Exit status 0 success, 2 bad input, 3 a run that stopped
early (its partial output is written and marked ``completed: false``), 1 anything unexpected.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import sys
from pathlib import Path

from .analysis.equilibrium import EquilibriumError
from .params import PAPER, ParameterError, Params, load_params

EXIT_BAD_INPUT = 2
EXIT_INCOMPLETE = 3


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump) and exit status 2."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(EXIT_BAD_INPUT, f"hosedrogue: error: {message} (see '{self.prog} --help')\n")


def _finite_float(name: str, lo: float, hi: float, unit: str):
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be a number in [{lo:g}, {hi:g}] {unit}")
        if not (math.isfinite(v) and lo <= v <= hi):
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be a number in [{lo:g}, {hi:g}] {unit}")
        return v

    return parse


def _positive_int(name: str, lo: int, hi: int):
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be an integer in [{lo}, {hi}]")
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be an integer in [{lo}, {hi}]")
        return v

    return parse


def _flight_overrides(args) -> dict:
    """Parameter overrides from --altitude, --airspeed, --links, --no-wake (validated later)."""
    over: dict = {}
    if getattr(args, "altitude", None) is not None:
        over.setdefault("flight", {})["altitude_m"] = args.altitude
    if getattr(args, "airspeed", None) is not None:
        over.setdefault("flight", {})["airspeed_m_s"] = args.airspeed
    if getattr(args, "links", None) is not None:
        over.setdefault("hose", {})["links"] = args.links
    if getattr(args, "no_wake", False):
        over.setdefault("wake", {})["enabled"] = False
    return over


def _params_from_args(args) -> Params:
    base = load_params(args.config) if getattr(args, "config", None) else PAPER
    over = _flight_overrides(args)
    return base.replace(**over) if over else base


# --- commands ------------------------------------------------------------------------------------
def cmd_steady(args) -> int:
    from .analysis.equilibrium import solve_equilibrium

    params = _params_from_args(args)
    eq = solve_equilibrium(params)
    if args.json:
        print(json.dumps(eq.to_dict()))
        return 0
    x, y, z = eq.drogue_position_m
    fx, fy, fz = eq.tow_force_n
    print(f"Balance position: {params.hose.links} links, {params.hose.length_m:g} m hose, "
          f"{params.flight.airspeed_m_s:g} m/s at {params.flight.altitude_m:g} m, "
          f"wake {'on' if params.wake.enabled else 'off'}")
    print(f"  drogue position (x fwd, y right, z down) [m]: {x:9.4f} {y:9.4f} {z:9.4f}")
    print(f"  drogue drag [N]:                               {eq.drogue_drag_magnitude_n:9.2f}")
    print(f"  tow-point force [N]:                           {fx:9.2f} {fy:9.2f} {fz:9.2f}")
    print(f"  balance ratio D = V_D / L_H:                   {eq.balance_ratio:9.4f}")
    return 0


def _prepare_out(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise ParameterError(f"--out = {str(out)!r}: exists and is not a directory")


def cmd_simulate(args) -> int:
    from .runner import run_scenario, write_run
    from .scenarios import load_scenario

    scenario = load_scenario(args.scenario).with_overrides(duration_s=args.duration, seed=args.seed)
    out = Path(args.out)
    _prepare_out(out)
    result = run_scenario(scenario)
    created = not out.exists()
    try:
        paths = write_run(result, out)
    except BaseException:  # leave no half-written output folder behind
        if created and out.exists():
            shutil.rmtree(out, ignore_errors=True)
        raise
    for p in paths:
        print(f"wrote {p}")
    if not result.completed:
        print(f"hosedrogue: run incomplete: {result.message}", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def cmd_sweep(args) -> int:
    from .analysis.sweep import DEFAULT_AIRSPEEDS_M_S, DEFAULT_ALTITUDES_M, steady_sweep
    from .plotting.figures import plot_sweep, save_figure
    from .progress import progress_bar

    params = _params_from_args(args)
    alts = args.altitudes or DEFAULT_ALTITUDES_M
    vels = args.airspeeds or DEFAULT_AIRSPEEDS_M_S
    out = Path(args.out)
    _prepare_out(out)
    with progress_bar(total=len(alts) * len(vels), desc="equilibria") as bar:
        result = steady_sweep(params, alts, vels, progress=lambda: bar.update(1))
    out.mkdir(parents=True, exist_ok=True)
    result.to_csv(out / "sweep.csv")
    save_figure(plot_sweep(result), out / "sweep.png")
    failed = sum(not r["converged"] for r in result.rows)
    print(f"wrote {out / 'sweep.csv'}\nwrote {out / 'sweep.png'}")
    if failed:
        print(f"hosedrogue: {failed} grid points did not converge (NaN in sweep.csv)", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def _parse_order(text: str):
    if text == "full":
        return None
    try:
        order = int(text)
    except ValueError:
        order = 0
    if order < 1:
        raise ParameterError(f"--order = {text!r}: must be 'full' or an integer >= 1")
    return order


def cmd_linearize(args) -> int:
    import numpy as np

    from .analysis.linearize import linearize
    from .analysis.reduction import format_tf, table2_form
    from .controllers.design import reduced_channels

    order = _parse_order(args.order)
    params = _params_from_args(args)
    lm = linearize(params)
    ch = reduced_channels(lm, order)
    data = {}
    for name, sys_ in (("lateral", ch.lateral), ("vertical", ch.vertical)):
        num, den = table2_form(sys_)
        poles = np.sort_complex(sys_.poles())  # from the state matrix, not the polynomial
        data[name] = {"num": num.tolist(), "den": den.tolist(),
                      "poles": [[float(p.real), float(p.imag)] for p in poles]}
    data["order"] = "full" if order is None else order
    data["flight"] = {"altitude_m": params.flight.altitude_m, "airspeed_m_s": params.flight.airspeed_m_s,
                      "wake": params.wake.enabled, "links": params.hose.links}
    if args.json:
        print(json.dumps(data))
        return 0
    print(f"Linear model about the balance position: {params.flight.airspeed_m_s:g} m/s at "
          f"{params.flight.altitude_m:g} m, wake {'on' if params.wake.enabled else 'off'}, "
          f"{params.hose.links} links; order {data['order']} per channel (balanced truncation)")
    for name, label in (("lateral", "u_hor [N] -> P_ny [m]"), ("vertical", "u_ver [N] -> P_nz [m]")):
        print(f"  {name} ({label}):")
        print(f"    G(s) = {format_tf(np.array(data[name]['num']), np.array(data[name]['den']))}")
        poles = ", ".join(f"{re:.4g}{im:+.4g}j" for re, im in data[name]["poles"])
        print(f"    poles [rad/s]: {poles}")
    return 0


def cmd_reproduce(args) -> int:
    from .report.build import build_report

    out = Path(args.out)
    _prepare_out(out)
    build_report(out, fast=args.fast)
    print(f"wrote {out / 'index.html'}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="hosedrogue", description=(
        "Probe-and-drogue aerial refuelling hose: Kane-equation rigid-link model (Wu et al., 2018). "
        "Frame S_p: origin at the tow point, x forward, y right, z down; SI units."))
    from . import __version__

    p.add_argument("--version", action="version", version=f"hosedrogue {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    def flight_options(sp, links=True):
        sp.add_argument("--altitude", metavar="M", type=_finite_float("--altitude", 0, 20000, "m"),
                        help="flight altitude [m], 0-20000 (default: paper, 8000 m)")
        sp.add_argument("--airspeed", metavar="M_PER_S", type=_finite_float("--airspeed", 1e-9, 400, "m/s"),
                        help="true airspeed [m/s], > 0 (default: paper, 150 m/s)")
        if links:
            sp.add_argument("--links", metavar="N", type=_positive_int("--links", 1, 1000),
                            help="number of rigid links of the hose, >= 1 (default 20)")
        sp.add_argument("--config", metavar="FILE", help="TOML file of parameter overrides ([hose], [flight], ...)")
        sp.add_argument("--no-wake", action="store_true", help="switch the tanker wake off (free stream only)")

    s = sub.add_parser("steady", help="balance position (equilibrium) of the hose and drogue",
                       description="Print the balance position: drogue position [m] in S_p, drogue drag [N], "
                                   "tow-point force [N] and D = V_D/L_H (drogue drop over hose length).")
    flight_options(s)
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=cmd_steady)

    s = sub.add_parser("simulate", help="run a scenario file (time simulation)",
                       description="Run SCENARIO (a shipped name such as 'swing-release' or "
                                   "'paper-turbulence', or a TOML path) and write DIR/timeseries.csv "
                                   "(SI units), DIR/run.json and DIR/displacement.png.")
    s.add_argument("scenario", metavar="SCENARIO", help="scenario name or TOML file")
    s.add_argument("--duration", metavar="S", type=_finite_float("--duration", 1e-9, 86400, "s"),
                   help="simulated time [s] (overrides the file)")
    s.add_argument("--seed", metavar="N", type=_positive_int("--seed", 0, 2**63 - 1),
                   help="turbulence seed (overrides the file)")
    s.add_argument("--out", metavar="DIR", default="out/simulate", help="output folder (default out/simulate)")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("sweep", help="balance position over a grid of altitudes and airspeeds (paper Fig. 3)",
                       description="Solve the balance position at every altitude [m] x airspeed [m/s] and write "
                                   "DIR/sweep.csv (drogue position [m], drag [N], tow force [N], V_D/L_H) and "
                                   "DIR/sweep.png (drogue drag and V_D/L_H against airspeed, one curve per altitude).")
    s.add_argument("--altitudes", metavar="M", type=_finite_float("--altitudes", 0, 20000, "m"), nargs="+",
                   help="altitudes [m] (default 2000 4000 6000 8000 10000)")
    s.add_argument("--airspeeds", metavar="M_PER_S", type=_finite_float("--airspeeds", 1e-9, 400, "m/s"), nargs="+",
                   help="airspeeds [m/s] (default 100 to 250 in steps of 10)")
    s.add_argument("--links", metavar="N", type=_positive_int("--links", 1, 1000), help="number of links (default 20)")
    s.add_argument("--config", metavar="FILE", help="TOML file of parameter overrides")
    s.add_argument("--no-wake", action="store_true", help="switch the tanker wake off")
    s.add_argument("--out", metavar="DIR", default="out/sweep", help="output folder (default out/sweep)")
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser("linearize", help="linear model about the balance position, reduced transfer functions",
                       description="Linearize about the balance position (inputs u_hor, u_ver [N] at the drogue; "
                                   "outputs the drogue's lateral and vertical offset P_ny, P_nz [m]) and print each "
                                   "channel's transfer function (descending powers of s, denominator monic) at the "
                                   "requested order (balanced truncation) with its poles [rad/s].")
    flight_options(s)
    s.add_argument("--order", default="2", metavar="full|N",
                   help="'full' or the reduced order per channel, >= 1 (default 2, as the paper's design model)")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=cmd_linearize)

    s = sub.add_parser("reproduce", help="regenerate the paper's results as an HTML report",
                       description="Regenerate every result of the paper's Sections 2.3 and 3 from this model and "
                                   "write DIR/index.html with figures (PNG), data (CSV), report.json and an animation.")
    s.add_argument("--out", metavar="DIR", default="out/report", help="output folder (default out/report)")
    s.add_argument("--fast", action="store_true", help="coarser grids and shorter runs (< 1 min); marked as such")
    s.set_defaults(func=cmd_reproduce)

    from .campaign import add_montecarlo_parser

    add_montecarlo_parser(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except ParameterError as exc:
        print(f"hosedrogue: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except EquilibriumError as exc:
        print(f"hosedrogue: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    except KeyboardInterrupt:
        print("hosedrogue: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
