"""``hosedrogue simulate``: run a scenario and write its time series."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

from .options import EXIT_INCOMPLETE, RUN_FOLDER_FILES, bounded_int, finite_float, prepare_out
from .out_folder import output_folder

NAME = "simulate"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="run a scenario file (time simulation)",
                       description="Run SCENARIO (a shipped name such as 'swing-release' or "
                                   "'paper-turbulence', or a TOML path) and write DIR/timeseries.csv "
                                   "(SI units), DIR/run.json, DIR/hose.npz (the hose's joints at every output time) "
                                   "and DIR/displacement.png (DIR/engagement.png for an engagement).")
    s.add_argument("scenario", metavar="SCENARIO", help="scenario name or TOML file")
    s.add_argument("--duration", metavar="S", type=finite_float("--duration", 1e-9, 86400, "s"),
                   help="simulated time [s] (overrides the file)")
    s.add_argument("--seed", metavar="N", type=bounded_int("--seed", 0, 2**63 - 1),
                   help="turbulence seed [-] (overrides the file)")
    s.add_argument("--out", metavar="DIR", default="out/simulate", help="output folder (default out/simulate)")
    s.add_argument("--format", choices=("csv", "mat"), default="csv",
                   help="'mat': also write DIR/timeseries.mat (MATLAB, full precision, named signals with SI "
                        "units, the state [rad, rad/s]); default 'csv' only")
    s.add_argument("--view", action="store_true",
                   help="also write DIR/view.html: the run in 3D with its time series, one self-contained page "
                        "(hosedrogue view DIR writes the same)")
    s.add_argument("--verify", action="store_true",
                   help="run the scenario again on twice the links at the refined step (RK4 and SDIRK: halved) and "
                        "report for every headline figure the refined value, the change, a Richardson error estimate "
                        "and whether it is converged (within --tolerance); into run.json's 'verification' "
                        "(docs/convergence.md). Without it every figure is 'unverified'")
    s.add_argument("--tolerance", metavar="REL", type=finite_float("--tolerance", 1e-6, 0.5, "-"), default=0.03,
                   help="relative change within which a verified figure is converged [-] (default 0.03)")
    s.add_argument("--ensemble", metavar="N", type=bounded_int("--ensemble", 2, 100_000),
                   help="run N perturbed copies (--perturb) and write DIR/ensemble.json: each figure's median, "
                        "5-95 %% range and 95 %% bootstrap intervals (a chaotic response as a distribution; "
                        "with --verify its quantiles are checked against the refined mesh)")
    s.add_argument("--perturb", metavar="KIND", default="probe-offset=1e-6",
                   help="with --ensemble: 'seed' (turbulence seeds, the campaigns' rule) or 'probe-offset=SIZE_M' "
                        "(the probe's start displaced within a disc of SIZE_M [m]); default probe-offset=1e-6")
    s.add_argument("--workers", metavar="N", type=bounded_int("--workers", 1, 256), default=1,
                   help="with --ensemble: processes [-] (default 1); the figures do not depend on it")
    s.add_argument("--json", action="store_true",
                   help="print one JSON object (run.json's content, or ensemble.json's) instead of text")
    s.set_defaults(func=run)


def run(args) -> int:
    """Simulate (or verify, or run an ensemble), write the files; exit 3 if a run stopped early
    (what it computed is kept).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..errors import ParameterError
    from ..scenarios import load_scenario
    from ..simulation.budget import check_run

    scenario = load_scenario(args.scenario).with_overrides(duration_s=args.duration, seed=args.seed)
    out = Path(args.out)
    if args.ensemble is None and args.perturb != "probe-offset=1e-6":
        raise ParameterError(f"--perturb = {args.perturb!r}: only with --ensemble N")
    if args.ensemble is None and args.workers != 1:
        raise ParameterError(f"--workers = {args.workers}: only with --ensemble N")
    if args.ensemble is not None:
        if args.view or args.format != "csv":
            raise ParameterError("--ensemble: writes DIR/ensemble.json only; leave out --view and --format")
        return _ensemble(args, scenario, out)
    prepare_out(out)
    check_run(scenario.params, scenario.duration_s, "scenario.duration_s", command=True)  # before the work
    if args.verify:
        from ..studies.verify import verify_run

        result = verify_run(scenario, args.tolerance)
    else:
        from ..scenarios.runner import run as run_scenario

        result = run_scenario(scenario)
    paths = _write(result, out, args)
    if args.json:
        from ..jsonio import dumps

        print(dumps({**result.run_document(), "files": [str(p) for p in paths]}, indent=2))
    else:
        for p in paths:
            print(f"wrote {p}")
        print(result.headline())
        spectrum = result.run_document().get("spectrum")
        if spectrum and "predicted" in spectrum:
            pred = spectrum["predicted"]["rms_m"]
            print(f"linear prediction (covariance analysis) of the RMS offset: lateral {pred['lateral']:.4g} m, "
                  f"vertical {pred['vertical']:.4g} m")
        if result.verification is not None:
            print(verification_text(result.verification))
    if not result.completed:
        print(f"hosedrogue: run incomplete: {result.message}", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def _write(result, out: Path, args) -> list:
    from ..scenarios.runner import write

    created = not out.exists()
    try:
        with output_folder(out, "simulate", RUN_FOLDER_FILES) as written:  # no file of an earlier run stays
            paths = write(result, out, formats=("csv", args.format))
            paths += write_spectrum(result, out)
            if args.view:
                from ..viewer import ViewRun, write_view

                paths.append(write_view([ViewRun.from_result(result)], out / "view.html"))
            written.add(*paths)
    except BaseException:  # leave no half-written output folder behind
        if created and out.exists():
            shutil.rmtree(out, ignore_errors=True)
        raise
    return paths


def _number(v) -> str:
    return "none" if v is None else f"{v:.5g}"


def verification_text(doc: dict) -> str:
    """A verification (run.json's ``"verification"``) as lines: the meshes, then per figure its
    value, the refined value, the change [%], the Richardson error estimate and the verdict.

    Parameters
    ----------
    doc : dict
        :func:`hosedrogue.studies.verify.verification`'s document.

    Returns
    -------
    str
    """
    r, f = doc["run"], doc["refined"]
    lines = [f"verification: {r['links']} links at {r['step_s']:g} s against {f['links']} links at {f['step_s']:g} s "
             f"({f['integrator']}), tolerance {100 * doc['tolerance']:g} %, Richardson at order {doc['assumed_order']}"]
    for key, x in doc["figures"].items():
        rel = "" if x["relative_change"] is None else f" ({100 * x['relative_change']:.2f} %"
        err = "" if x["error_estimate"] is None else f", error estimate {x['error_estimate']:.3g})"
        lines.append(f"  {key:34s} {_number(x['value']):>11s} -> {_number(x['refined_value']):>11s}{rel}{err} "
                     f"{'converged' if x['converged'] else 'NOT converged'}")
    lines.extend(f"  note: {n}" for n in doc["notes"])
    return "\n".join(lines)


def ensemble_text(ens) -> str:
    """An ensemble's distributions as lines: per figure its median, 5-95 % range and the bootstrap
    intervals of the median and the 95 % point; with a verification, the refined quantiles.

    Parameters
    ----------
    ens : hosedrogue.studies.ensemble.Ensemble
        The ensemble.

    Returns
    -------
    str
    """
    size = f" of {ens.size_m:g} m" if ens.perturbation == "probe-offset" else ""
    lines = [f"ensemble: {len(ens.figures)} copies of {ens.scenario} ({ens.perturbation}{size}), {ens.links} links "
             f"at {ens.step_s:g} s; median [5 %, 95 %], 95 % bootstrap intervals of the median and the 95 % point"]
    for key, d in ens.distributions.items():
        if d["median"] is None:
            lines.append(f"  {key:34s} none ({d['missing']} copies without it)")
            continue
        ci = "".join(f", {name} [{_number(v[0])}, {_number(v[1])}]" for name, v in
                     (("median", d["median_interval"]), ("p95", d["p95_interval"])) if v is not None)
        lines.append(f"  {key:34s} {_number(d['median'])} [{_number(d['p05'])}, {_number(d['p95'])}]{ci}")
    v = ens.verification
    if v is not None:
        lines.append(f"verification: against {v['refined']['links']} links at {v['refined']['step_s']:g} s, "
                     f"tolerance {100 * v['tolerance']:g} %: "
                     + ("every quantile converged" if v["converged"] else "not converged: " + ", ".join(v["not_converged"])))
    return "\n".join(lines)


def _ensemble(args, scenario, out: Path) -> int:
    from ..jsonio import dumps
    from ..studies.ensemble import run_ensemble

    prepare_out(out)
    ens = run_ensemble(scenario, args.ensemble, args.perturb, args.verify, args.tolerance, args.workers)
    path = out / "ensemble.json"
    with output_folder(out, "simulate --ensemble", ("ensemble.json",)) as written:  # no file of an earlier run stays
        written.add(path)
        path.write_text(dumps(ens.to_dict(), indent=2) + "\n")
    if args.json:
        print(dumps({**ens.to_dict(), "files": [str(path)]}, indent=2))
    else:
        print(f"wrote {path}")
        print(ensemble_text(ens))
    stopped = sum(not c for c in ens.completed)
    if stopped:
        print(f"hosedrogue: {stopped} of {len(ens.completed)} runs stopped early (their figures cover their part)",
              file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def write_spectrum(result, out: Path) -> list:
    """Write ``spectrum.png`` (the drogue offset's PSD beside its linear prediction,
    :func:`hosedrogue.results.spectra.spectrum_figure`) when the run has a spectrum.

    Parameters
    ----------
    result : RunResult
        The run.
    out : Path
        Its output folder.

    Returns
    -------
    list of Path
        The file written, or none.
    """
    from ..plotting.base import save_figure
    from ..results.spectra import spectrum_figure

    fig = spectrum_figure(result)
    return [] if fig is None else [save_figure(fig, out / "spectrum.png")]
