"""``hosedrogue study NAME`` for every study of :data:`hosedrogue.studies.registry.STUDIES` whose
command line is not written by hand: its settings as options (units and ranges from the
registry), ``--scenario NAME|FILE`` where it takes the user's scenario, ``--json`` for its numbers."""

from __future__ import annotations

import math
from pathlib import Path

from .options import bounded_int, finite_float

__all__ = ["add_registry_studies", "run_registry_study"]


def _option(setting) -> tuple[str, dict]:
    """The argparse option of a study's setting."""
    flag = "--" + setting.name.replace("_", "-")
    kw: dict = {"dest": setting.name, "default": setting.default}
    default = "" if setting.default is None else (
        " ".join(map(str, setting.default)) if isinstance(setting.default, tuple) else str(setting.default))
    kw["help"] = setting.help + (f" (default {default})" if default else "")
    if setting.kind in ("float", "floats"):
        kw["type"], kw["metavar"] = finite_float(flag, setting.lo, setting.hi, setting.unit), "X"
    elif setting.kind in ("int", "ints"):
        kw["type"], kw["metavar"] = bounded_int(flag, int(setting.lo), int(min(setting.hi, 2**63 - 1))), "N"
    else:
        kw["choices"], kw["metavar"] = setting.choices, "NAME"
    if setting.kind in ("floats", "ints", "choices"):
        kw["nargs"] = "+"
    return flag, kw


def add_registry_studies(studies) -> None:
    """Register ``study NAME`` for every registry study without a hand-written command line.

    Parameters
    ----------
    studies : argparse._SubParsersAction
        The subparsers of ``hosedrogue study``.
    """
    from ..studies.registry import STUDIES

    for study in STUDIES.values():
        if study.custom_cli:
            continue
        p = studies.add_parser(
            study.name, help=study.summary,
            description=(f"{study.summary[0].upper()}{study.summary[1:]} (library: hosedrogue.studies.{study.module}"
                         + (f"; the report's section '{study.section}'" if study.section else "") + "). "
                         f"Runs {study.scenario} by default"
                         + (f"; --scenario takes yours: {study.takes}." if study.takes else ".")))
        if study.takes:
            p.add_argument("--scenario", metavar="NAME|FILE",
                           help=f"a shipped scenario or your TOML file: {study.takes}")
        for setting in study.settings:
            flag, kw = _option(setting)
            p.add_argument(flag, **kw)
        p.add_argument("--out", metavar="DIR", type=Path,
                       help="also write DIR/study.json (the --json record) and the study's figures as PNG")
        p.add_argument("--json", action="store_true", help="print the study's numbers as one JSON object (SI units)")
        p.set_defaults(func=run_registry_study, registry_study=study.name)


def _lines(value, indent: str = "") -> list[str]:
    """A record as indented ``key: value`` lines (numbers to 5 significant digits)."""
    def num(v):
        return "null" if v is None else (f"{v:.5g}" if isinstance(v, float) and math.isfinite(v) else str(v))

    out = []
    for key, v in value.items():
        if isinstance(v, dict):
            out += [f"{indent}{key}:"] + _lines(v, indent + "  ")
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            out.append(f"{indent}{key}:")
            out += [f"{indent}  " + ", ".join(f"{k} {num(x)}" for k, x in row.items()) for row in v]
        elif isinstance(v, list):
            out.append(f"{indent}{key}: " + " ".join(num(x) if not isinstance(x, list) else
                                                      "(" + " ".join(map(num, x)) + ")" for x in v))
        else:
            out.append(f"{indent}{key}: {num(v)}")
    return out


def run_registry_study(args) -> int:
    """Run a registry study; print its record (or JSON), write it with ``--out``.

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
    from ..jsonio import dumps, plain
    from ..studies.registry import STUDIES, check_scenario
    from .options import prepare_out
    from .out_folder import output_folder

    study = STUDIES[args.registry_study]
    scenario = check_scenario(study, load_scenario(args.scenario)) if getattr(args, "scenario", None) else None
    settings = {s.name: getattr(args, s.name) for s in study.settings}
    settings = {k: tuple(v) if isinstance(v, list) else v for k, v in settings.items() if v is not None}
    if args.out is not None:
        prepare_out(args.out)
    result, record = study.run(scenario, **settings)
    record = {"study": study.name, "scenario": scenario.name if scenario is not None else study.scenario,
              **plain(record)}
    text = dumps(record, indent=2)
    if args.out is not None:
        from ..plotting.base import save_figure

        with output_folder(args.out, f"study {study.name}", ("study.json",)) as written:  # none of an earlier study's
            written.add(args.out / "study.json")
            (args.out / "study.json").write_text(text + "\n")
            for name, fig in (result.figures() if hasattr(result, "figures") else {}).items():
                written.add(save_figure(fig, args.out / f"{name}.png"))
    print(text if args.json else "\n".join(_lines(record)))
    return 0
