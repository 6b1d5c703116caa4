"""A campaign's runs verified by sample (``hosedrogue montecarlo --verify-sample N``; docs/campaigns.md,
"Verifying a sample of the runs").

A campaign's statistics come from runs on one mesh; whether that mesh resolves them is measured,
not assumed: ``N`` of its runs are run again, and once more on twice the links at the refined
step (:func:`hosedrogue.studies.verify.verify_run`), and every headline figure of each
(:func:`hosedrogue.results.convergence.headline_figures`) is compared with the tolerance.

Which runs: the first ``N`` of a permutation of the run indices by numpy's PCG64 seeded with
``[campaign seed, VERIFY_STREAM]`` (:func:`sampled_runs`), sorted; every controller of the campaign
for each. The same in every process, and a larger ``N`` keeps the smaller's runs (their entries
in ``verification.json`` are reused when the tolerance is the same).

Files in the campaign folder
----------------------------
``verification.json``
    ``status`` ("verified"), ``sample_rule``, ``tolerance``, ``runs`` (the verified indices),
    ``controllers``, ``converged`` (every figure of every verified run), ``figures`` (per figure:
    the runs checked, in how many it converged, the largest relative change), ``not_converged``
    ([run, controller, figure]) and ``verified_runs`` (per run its index, controller, seed and
    ``verification``: its :func:`~hosedrogue.studies.verify.verification` document).
``verification.csv``
    One row per run, controller and figure: value, refined value, change, relative change,
    Richardson's error estimate, converged.

``summary.json``'s ``"verification"`` is ``verification.json`` without ``verified_runs``, or
``{"status": "unverified", ...}`` when no run of the campaign was verified.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .. import jsonio
from ..errors import ParameterError
from .seeds import run_seed
from .store import csv_line, write_atomic

__all__ = ["VERIFY_STREAM", "SAMPLE_RULE", "FILE", "CSV_FILE", "sampled_runs", "check_sample",
           "campaign_verification"]

#: Second word of the sample's seed (``[campaign seed, VERIFY_STREAM]``) [-]: the issue's number.
VERIFY_STREAM = 32
#: The rule of :func:`sampled_runs` as recorded in verification.json.
SAMPLE_RULE = ("the first N of numpy.random.Generator(numpy.random.PCG64([campaign seed, 32])).permutation(runs), "
               "sorted; every controller of the campaign for each")
FILE, CSV_FILE = "verification.json", "verification.csv"
#: summary.json's block when no run was verified.
UNVERIFIED = {"status": "unverified", "notes": [
    "no run of this campaign was checked against a finer mesh: run it again with --verify-sample N "
    "(verify_sample=N in Python); the finished runs are kept"]}
CSV_COLUMNS = ("run", "controller", "seed", "figure", "value", "refined_value", "change", "relative_change",
               "error_estimate", "converged")


def check_sample(sample) -> int:
    """``sample`` as a whole number >= 0, or a one-line error.

    Parameters
    ----------
    sample : int
        Runs to verify [-].

    Returns
    -------
    int

    Raises
    ------
    ParameterError
    """
    if isinstance(sample, bool) or not isinstance(sample, (int, np.integer)) or sample < 0:
        raise ParameterError(f"verify_sample = {sample!r}: must be a whole number of runs >= 0 (0: none)")
    return int(sample)


def sampled_runs(runs: int, sample: int, seed: int) -> list[int]:
    """The run indices a campaign verifies (the module's rule).

    Parameters
    ----------
    runs : int
        The campaign's runs [-].
    sample : int
        How many to verify [-] (at most all).
    seed : int
        The campaign seed.

    Returns
    -------
    list of int
        Sorted.
    """
    order = np.random.Generator(np.random.PCG64([seed, VERIFY_STREAM])).permutation(runs)
    return sorted(int(i) for i in order[:min(sample, runs)])


def _previous(out: Path, tolerance: float) -> dict:
    """(run, controller) -> entry of a verification.json of the same tolerance already in ``out``."""
    try:
        old = json.loads((out / FILE).read_text())
    except (OSError, ValueError):
        return {}
    if not isinstance(old, dict) or old.get("tolerance") != tolerance:
        return {}
    return {(e["run"], e["controller"]): e for e in old.get("verified_runs", [])}


def _verify(scenario, index: int, controller: str, seed: int, tolerance: float) -> dict:
    from .verify import verify_run

    s = run_seed(seed, index)
    r = verify_run(scenario.with_overrides(seed=s).with_controller(controller), tolerance)
    return {"run": index, "controller": controller, "seed": s, "verification": r.verification}


def _figures(entries: list) -> dict:
    out = {}
    for e in entries:
        for k, f in e["verification"]["figures"].items():
            d = out.setdefault(k, {"runs_checked": 0, "converged_in": 0, "largest_relative_change": None})
            d["runs_checked"] += 1
            d["converged_in"] += bool(f["converged"])
            rel = f.get("relative_change")
            if rel is not None and (d["largest_relative_change"] is None or rel > d["largest_relative_change"]):
                d["largest_relative_change"] = rel
    for d in out.values():
        d["converged"] = d["converged_in"] == d["runs_checked"]
    return out


def _csv(entries: list) -> str:
    rows = [csv_line(CSV_COLUMNS)]
    for e in entries:
        for k, f in e["verification"]["figures"].items():
            values = (e["run"], e["controller"], e["seed"], k, f["value"], f["refined_value"], f["change"],
                      f["relative_change"], f["error_estimate"], f["converged"])
            rows.append(csv_line("" if v is None else v for v in values))
    return "".join(rows)


def campaign_verification(out: Path, scenario, settings: dict, sample: int, tolerance: float,
                          progress: bool = False) -> dict:
    """Verify ``sample`` runs of the campaign in ``out`` (the module's rules) and write
    verification.json and verification.csv; return summary.json's ``"verification"`` block. With
    ``sample`` 0 nothing is run: the block of a verification.json already in ``out``, else
    :data:`UNVERIFIED`.

    Parameters
    ----------
    out : Path
        The campaign folder (locked by the caller).
    scenario : hosedrogue.scenarios.Scenario
        The campaign's scenario (its duration).
    settings : dict
        The campaign's settings (campaign.json): runs, seed, controllers.
    sample : int
        Runs to verify [-] (:func:`check_sample`).
    tolerance : float
        Relative tolerance [-] (:func:`hosedrogue.studies.verify.check_tolerance`).
    progress : bool
        A progress bar on stderr (a terminal only).

    Returns
    -------
    dict
    """
    from .progress import progress_bar, progress_enabled

    if sample == 0:
        try:
            doc = json.loads((out / FILE).read_text())
        except (OSError, ValueError):
            return dict(UNVERIFIED)
        return {k: v for k, v in doc.items() if k != "verified_runs"}
    indices = sampled_runs(settings["runs"], sample, settings["seed"])
    controllers = list(settings["controllers"])
    done = _previous(out, tolerance)
    pairs = [(i, c) for i in indices for c in controllers]
    bar = progress_bar(len(pairs), "verify", enabled=progress_enabled(progress), unit="run", leave=True)
    entries = []
    try:
        for i, c in pairs:
            entries.append(done.get((i, c)) or _verify(scenario, i, c, settings["seed"], tolerance))
            bar.update(1)
    finally:
        bar.close()
    figures = _figures(entries)
    doc = {"status": "verified", "sample_rule": SAMPLE_RULE, "tolerance": tolerance, "runs": indices,
           "controllers": controllers, "converged": all(f["converged"] for f in figures.values()),
           "figures": figures,
           "not_converged": [[e["run"], e["controller"], k] for e in entries for k in e["verification"]["not_converged"]],
           "files": [FILE, CSV_FILE], "verified_runs": entries}
    write_atomic(out / FILE, jsonio.dumps(doc, indent=2) + "\n")
    write_atomic(out / CSV_FILE, _csv(entries))
    return {k: v for k, v in doc.items() if k != "verified_runs"}
