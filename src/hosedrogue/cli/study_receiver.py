"""``hosedrogue study receiver``: the receiver aircraft's study (:mod:`hosedrogue.studies.receiver`):
the F-16's trim against Stevens, Lewis & Johnson (2015) Table 3.6-2 and, with ``--runs``, the
docking campaigns of two approaches on the same seeds (by default the F-16 receiver beside the
point receiver; ``--scenario`` and ``--against`` take yours)."""

from __future__ import annotations

import sys
from pathlib import Path

from ..jsonio import dumps
from .options import EXIT_INCOMPLETE, MAX_RUNS, bounded_int, prepare_out

__all__ = ["add_receiver_parser", "run_receiver"]


def add_receiver_parser(studies) -> None:
    """Register ``study receiver`` on the study command's subparsers.

    Parameters
    ----------
    studies : argparse._SubParsersAction
        The subparsers of ``hosedrogue study``.
    """
    from ..studies.receiver import CAMPAIGN_SEED, SCENARIOS

    r = studies.add_parser(
        "receiver", help="the F-16 receiver's trim against the book, and its docking beside the point receiver",
        description=(
            "The receiver aircraft's study (docs/receiver.md): the F-16's level-flight trim at sea level against "
            "Stevens, Lewis & Johnson (2015) Table 3.6-2 (throttle [-], angle of attack and elevator [deg] at each "
            "book airspeed, within the printed digits or not) and, with --runs, a docking campaign of each of two "
            f"approaches on the same turbulence seeds (default {SCENARIOS[0]} beside {SCENARIOS[1]}): capture rates "
            "[-] with their Wilson 95 % intervals and the paired difference of the miss distances [m]. Campaign "
            "folders DIR/<scenario>/ (running again with the same settings resumes); figures receiver_trim.png and "
            "receiver_miss_cdf.png and study.json (the --json record) in DIR."))
    r.add_argument("--runs", metavar="N", type=bounded_int("--runs", 0, MAX_RUNS), default=0,
                   help="runs (turbulence seeds) per campaign [-] (0: the trim check only; default 0)")
    r.add_argument("--scenario", metavar="NAME|FILE", default=SCENARIOS[0],
                   help=f"your approach (an engagement scenario, e.g. with your receiver model) (default {SCENARIOS[0]})")
    r.add_argument("--against", metavar="NAME|FILE", default=SCENARIOS[1],
                   help=f"the approach it is compared with, on the same seeds (default {SCENARIOS[1]})")
    r.add_argument("--trim-points", metavar="N", type=bounded_int("--trim-points", 2, 10_000), default=68,
                   help="airspeeds of the trim curve drawn through the book's points [-] (default 68)")
    r.add_argument("--out", metavar="DIR", type=Path, default=Path("out/study-receiver"),
                   help="folder of the figures and the campaigns (default out/study-receiver)")
    r.add_argument("--workers", metavar="K", type=bounded_int("--workers", 1, 4096),
                   help="dask worker processes of the campaigns [-] (default: this process)")
    r.add_argument("--seed", metavar="S", type=bounded_int("--seed", 0, 2**63 - 1), default=CAMPAIGN_SEED,
                   help=f"campaign seed of both campaigns [-] (default {CAMPAIGN_SEED})")
    r.add_argument("--json", action="store_true", help="print one JSON object instead of the lines")
    r.add_argument("--quiet", action="store_true", help="no progress bars")
    r.set_defaults(func=run_receiver)


def run_receiver(args) -> int:
    """Run the receiver study; print its findings (or JSON). Exit 3 if a campaign run stopped early.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    import numpy as np

    from ..plotting.base import save_figure
    from ..studies.receiver import receiver_campaigns, receiver_scenarios, trim_check

    receiver_scenarios(args.scenario, args.against)  # checked before anything runs, --runs 0 too
    prepare_out(args.out)
    check = trim_check(args.trim_points)
    args.out.mkdir(parents=True, exist_ok=True)
    save_figure(check.figure(), args.out / "receiver_trim.png")
    record = {"trim": {"points": len(check.table), "within_printed_digits": check.within,
                       "table": check.table.to_dict(orient="records")},
              "out": str(args.out)}
    lines = [f"trim (F-16, sea level): {check.within} of Table 3.6-2's {len(check.table)} points within their "
             "printed digits (throttle, angle of attack, elevator)"]
    stopped = 0
    if args.runs:
        camp = receiver_campaigns(args.runs, args.out, seed=args.seed, workers=args.workers, progress=not args.quiet,
                                  scenarios=(args.scenario, args.against))
        save_figure(camp.figure(), args.out / "receiver_miss_cdf.png")
        p = camp.paired()
        stopped = sum(camp.stopped.values())
        record.update({"runs_per_campaign": args.runs, "seed": args.seed,
                       "scenarios": list(camp.names),
                       "capture": {n: camp.capture[n] for n in camp.names},
                       "stopped_runs": camp.stopped,
                       "miss_paired_difference": p})
        for n in camp.names:
            c = camp.capture[n]
            lines.append(f"{n}: capture rate {c['rate']:.3f} (Wilson 95 %: {c['ci95'][0]:.3f}-{c['ci95'][1]:.3f}) "
                         f"over {c['runs']} runs")
        if p["runs"]:
            se = f", standard error {1e3 * p['se_m']:.1f} mm" if np.isfinite(p["se_m"]) else ""
            lines.append(f"paired misses over {p['runs']} seeds: {camp.names[0]} minus {camp.names[1]} "
                         f"{1e3 * p['mean_m']:+.1f} mm on average{se}; the first misses by more in {p['first_larger']}")
        lines.append(f"wrote 2 campaigns, 2 figures and study.json into {args.out}")
    else:
        lines.append(f"wrote receiver_trim.png and study.json into {args.out} (--runs N adds the docking campaigns)")
    text = dumps(record, indent=2)
    (args.out / "study.json").write_text(text + "\n")
    if args.json:
        print(text)
    else:
        print("\n".join(lines))
    if stopped:
        print(f"hosedrogue: {stopped} campaign runs stopped early (completed = false in the campaigns' runs.csv)",
              file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
