"""What the viewer shows of one run, from a run's folder or from a result in memory.

A run's folder (``hosedrogue simulate --out DIR``, :func:`hosedrogue.write`) holds
``timeseries.csv``, ``run.json`` and ``hose.npz`` (the hose's joints at every output time,
:mod:`hosedrogue.results.hose_file`). :func:`read_run` reads them and
:meth:`ViewRun.from_result` takes the same three things from a
:class:`~hosedrogue.results.run.RunResult`, so the page is the same for a run written to disk and
one that never was.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..results.hose_file import DIGEST_KEY, FILE as HOSE_FILE, read_hose_npz, run_digests, split_joints
from ..results.run import RunResult

__all__ = ["ViewRun", "read_run", "SERIES", "AIRCRAFT", "RUN_FILES"]

#: The files that make a folder a run's folder: the time series, what was run, the hose's shape.
RUN_FILES = ("timeseries.csv", "run.json", HOSE_FILE)

#: Time-series columns the page charts (those a run has): drogue offset from its balance position
#: [m], exit tension [N], probe load [N], probe tip [m], coupled flag [-] and links [-].
SERIES = ("drogue_dx_m", "drogue_dy_m", "drogue_dz_m", "exit_tension_n", "probe_load_n", "probe_x_m", "probe_y_m",
          "probe_z_m", "coupled", "links")

#: The receiver aircraft's columns the page draws it from (a run whose receiver is an aircraft,
#: docs/receiver.md): its centre of gravity [m] and attitude [rad] in S_p.
AIRCRAFT = ("aircraft_x_m", "aircraft_y_m", "aircraft_z_m", "aircraft_roll_rad", "aircraft_pitch_rad",
            "aircraft_yaw_rad")


@dataclass(frozen=True)
class ViewRun:
    """One run as the viewer draws it.

    Parameters
    ----------
    label : str
        Name on the page (default: the scenario's name, or the folder's).
    columns : dict
        Time-series name -> (N,) array, SI units in the names (``t_s`` [s] and the names of
        :data:`SERIES` the run has).
    joint_count : numpy.ndarray
        (N,) joints at each output time [-].
    joints_m : numpy.ndarray
        (sum(joint_count), 3) joint positions in S_p [m], time after time
        (:meth:`hosedrogue.results.run.RunResult.hose_shapes`).
    document : dict
        The run's ``run.json`` content (what was run, how it ended, its outcome).
    source : str
        Where the run came from (a folder, or "memory").
    """

    label: str
    columns: dict
    joint_count: np.ndarray
    joints_m: np.ndarray
    document: dict = field(default_factory=dict)
    source: str = "memory"

    def __post_init__(self):
        t = np.asarray(self.columns.get("t_s", ()))
        if t.ndim != 1 or t.size < 1 or self.joint_count.shape != t.shape:
            raise ParameterError(f"run {self.label!r}: {t.size} output times but hose shapes at "
                                 f"{self.joint_count.size}: the time series and the hose must have one row per time")
        if not np.all(np.diff(t) > 0):
            raise ParameterError(f"run {self.label!r}: t_s must increase strictly")

    @property
    def t_s(self) -> np.ndarray:
        """(N,) output times [s]."""
        return np.asarray(self.columns["t_s"], dtype=np.float64)

    def between(self, start_s: float | None = None, end_s: float | None = None) -> "ViewRun":
        """The run's output times in [start_s, end_s] only.

        Parameters
        ----------
        start_s, end_s : float, optional
            The window [s] (default: the run's first and last output time).

        Returns
        -------
        ViewRun

        Raises
        ------
        ParameterError
            If no output time of the run lies in the window.
        """
        t = self.t_s
        lo = t[0] if start_s is None else float(start_s)
        hi = t[-1] if end_s is None else float(end_s)
        keep = (t >= lo) & (t <= hi)
        if not keep.any():
            raise ParameterError(f"window [{lo:g}, {hi:g}] s: holds no output time of run {self.label!r} "
                                 f"(it runs from {t[0]:g} to {t[-1]:g} s)")
        shapes = split_joints(self.joint_count, self.joints_m)
        return ViewRun(label=self.label, columns={k: v[keep] for k, v in self.columns.items()},
                       joint_count=self.joint_count[keep],
                       joints_m=np.concatenate([shapes[i] for i in np.flatnonzero(keep)]), document=self.document,
                       source=self.source)

    @classmethod
    def from_result(cls, result: RunResult, label: str | None = None) -> "ViewRun":
        """The view of a run in memory (either hose model).

        Parameters
        ----------
        result : hosedrogue.results.run.RunResult
            The run.
        label : str, optional
            Name on the page (default: the scenario's name in ``result.meta``, else "run").

        Returns
        -------
        ViewRun
        """
        counts, joints = result.hose_shapes()
        doc = json.loads(json.dumps(result.run_document(), default=float))  # what run.json would hold
        return cls(label=label or str(doc.get("scenario") or "run"), columns=_series(result.columns()),
                   joint_count=counts, joints_m=joints, document=doc)


def _series(columns) -> dict:
    """``t_s``, the charted columns and the aircraft's the run has, as float64 arrays."""
    return {name: np.asarray(columns[name], dtype=np.float64) for name in ("t_s", *SERIES, *AIRCRAFT)
            if name in columns}


def _check_digests(folder, path: Path, doc: dict, t_s, counts, joints) -> None:
    """Refuse a ``run.json`` whose digests of the run's data (:func:`hosedrogue.results.hose_file.run_digests`)
    are not those of the folder's ``timeseries.csv`` and ``hose.npz``: a run.json of another run (one
    written before run.json held them is read on the times' check alone)."""
    recorded = doc.get(DIGEST_KEY)
    if recorded is None:
        return
    found = run_digests(path / "timeseries.csv", t_s, counts, joints)
    differ = [name for name in found if not isinstance(recorded, dict) or recorded.get(name) != found[name]]
    if differ:
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: run.json is of another run (its {DIGEST_KEY} of "
                             f"{' and '.join(differ)} is not this folder's): files of different runs")


def read_run(folder: str | Path, label: str | None = None) -> ViewRun:
    """Read a run's folder for the viewer.

    Parameters
    ----------
    folder : str or pathlib.Path
        A folder written by ``hosedrogue simulate --out DIR`` or :func:`hosedrogue.write`.
    label : str, optional
        Name on the page (default: the scenario's name in ``run.json``, else the folder's name).

    Returns
    -------
    ViewRun

    Raises
    ------
    ParameterError
        One line naming the folder: not a folder, not a run's folder (a file of :data:`RUN_FILES`
        missing), or files that cannot be read or do not agree.
    """
    import pandas as pd

    path = Path(folder)
    if not path.is_dir():
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: not a folder (give the --out folder of hosedrogue simulate)")
    missing = [name for name in RUN_FILES if not (path / name).is_file()]
    if missing:
        hint = ("written before hosedrogue wrote the hose's shape: run the scenario again"
                if missing == [HOSE_FILE] else "give the --out folder of hosedrogue simulate")
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: not a run folder (no {', '.join(missing)}; {hint})")
    try:
        doc = json.loads((path / "run.json").read_text())
        table = pd.read_csv(path / "timeseries.csv")
    except (OSError, ValueError, pd.errors.ParserError) as exc:
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: unreadable run files: {str(exc).splitlines()[0]}") from None
    if not isinstance(doc, dict) or "t_s" not in table.columns:
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: not a run folder (run.json is not an object or "
                             "timeseries.csv has no t_s column)")
    t_hose, counts, joints = read_hose_npz(path / HOSE_FILE)
    columns = _series({c: table[c].to_numpy() for c in table.columns})
    # timeseries.csv has 10 significant digits: 1e-9 relative is the rounding of its times
    if t_hose.shape != columns["t_s"].shape or not np.allclose(t_hose, columns["t_s"], rtol=1e-9, atol=1e-12):
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: hose.npz has {t_hose.size} output times and "
                             f"timeseries.csv {columns['t_s'].size}, or their times differ: files of different runs")
    t_end = doc.get("t_end_s")
    if not isinstance(t_end, (int, float)) or not t_hose.size or not np.isclose(t_end, t_hose[-1], rtol=1e-9, atol=1e-12):
        raise ParameterError(f"RUN_DIR = {str(folder)!r}: run.json ends at t_end_s = {t_end!r} and timeseries.csv at "
                             f"{float(t_hose[-1]) if t_hose.size else None!r} s: files of different runs")
    _check_digests(folder, path, doc, t_hose, counts, joints)
    columns["t_s"] = t_hose  # the full-precision times
    return ViewRun(label=label or str(doc.get("scenario") or path.resolve().name), columns=columns,
                   joint_count=counts, joints_m=joints, document=doc, source=str(path))
