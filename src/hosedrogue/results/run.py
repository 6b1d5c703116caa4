"""Result objects of a run: named signals with units, ``to_dataframe()``, ``to_csv()``, ``plot()``.

One interface for both hose models (:class:`RunResult`): the fixed-length hose (:class:`SimulationResult`)
and the hose of varying length in an engagement (:class:`EngagementResult`) give the same quantities under
the same names, so writers, campaigns and user code take either without a branch; a drogue with control
surfaces adds theirs (:class:`hosedrogue.results.surfaces.WithSurfaces`). Frames: S_p, the tanker trajectory frame
(x forward, y right, z down), origin at the tow point.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import math

import numpy as np

from .matlab_file import cellstr, hose_state_matrices, save_mat, state_names
from .convergence import PEAK_KEYS, UNVERIFIED_NOTE, unverified, verification_document, went_slack
from .statistics import DEFAULT_CAPTURE_RADII_M, window_statistics
from .surfaces import WithSurfaces
from ..version import __version__

#: The time-series columns of every run, in file order (SI units in the names; the engagement
#: adds its own after them, :meth:`EngagementResult.extra_columns`).
COLUMNS = ("t_s", "drogue_x_m", "drogue_y_m", "drogue_z_m", "drogue_dx_m", "drogue_dy_m", "drogue_dz_m",
           "drogue_vx_m_s", "drogue_vy_m_s", "drogue_vz_m_s", "drogue_drag_x_n", "drogue_drag_y_n",
           "drogue_drag_z_n", "tow_force_x_n", "tow_force_y_n", "tow_force_z_n", "exit_tension_n", "u_y_n", "u_z_n")


def stop_message(t_kept_s: float, reason: str, t_event_s: float | None = None) -> str:
    """The one-line message of a run that stopped early: ``"stopped at t = T s: reason"``, T the
    time of the last state the run kept (its result's ``t_s[-1]``), and when the cause came
    after it (a state that failed in the next step, a controller's call between output times) that
    time too.

    Parameters
    ----------
    t_kept_s : float
        The time of the last state kept [s].
    reason : str
        Why (one line).
    t_event_s : float, optional
        When the cause happened [s], if not at ``t_kept_s``.

    Returns
    -------
    str
    """
    # 5e-5 s: half the last digit the message shows, below which the two times read the same
    after = "" if t_event_s is None or abs(t_event_s - t_kept_s) < 5e-5 else f" (at t = {t_event_s:.4f} s)"
    return f"stopped at t = {t_kept_s:.4f} s: {reason}{after}"


@dataclass(frozen=True, kw_only=True)
class RunResult:
    """What every run gives: the drogue's motion, the loads at the tow point, the control force.

    ``completed`` is False when the run stopped early (divergence, a failed state); everything
    up to ``t_s[-1]`` is still valid and ``message`` says when and why it stopped. Every array has
    one row per output time (N rows); vectors are in the tanker frame S_p.
    """

    t_s: np.ndarray  #: (N,) output times [s]
    drogue_position_m: np.ndarray  #: (N, 3) drogue (last joint) position [m]
    drogue_velocity_m_s: np.ndarray  #: (N, 3) drogue velocity [m/s]
    drogue_drag_n: np.ndarray  #: (N, 3) aerodynamic force on the drogue [N]
    tow_force_n: np.ndarray  #: (N, 3) force the hose exerts on the tow point (the hose exit) [N]
    #: (N,) exit tension T_0: the hose's pull along the hose at the exit, the force a hose drum holds [N]
    exit_tension_n: np.ndarray
    control_force_n: np.ndarray  #: (N, 2) control force at the drogue, lateral y and vertical z [N]
    joints_m: Any  #: per output time, (n+1, 3) joint positions [m] (row 0 the tow point)
    completed: bool  #: True if the run reached its end time
    message: str  #: "completed", or when and why the run stopped
    equilibrium_m: np.ndarray | None = None  #: (3,) drogue balance position at the start [m]
    meta: dict[str, Any] = field(default_factory=dict)  #: what was run (scenario, seed, parameters)
    #: window [start, end) [s] of :meth:`statistics`: the turbulence window, or the whole run without turbulence
    statistics_window_s: tuple = (0.0, math.inf)
    #: the run's figures against the same run on a finer mesh (:func:`hosedrogue.studies.verify.verify_run`,
    #: docs/convergence.md "Verifying a run"); None: not verified
    verification: dict | None = None

    @functools.cached_property
    def drogue_offset_m(self) -> np.ndarray:
        """(N, 3) drogue position relative to the balance position at the start [m], read-only.

        Computed on first use and kept: the file writers, the statistics and the figures each
        read it (eight times in a ``simulate``: 0.04 s of CPU for 5000 s of the paper's case)."""
        ref = self.equilibrium_m if self.equilibrium_m is not None else self.drogue_position_m[0]
        off = self.drogue_position_m - ref
        off.flags.writeable = False
        return off

    def to_dataframe(self):
        """The time series as a table, one row per output time, SI units in the column names.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        return pd.DataFrame(self.columns())

    def columns(self) -> dict[str, np.ndarray]:
        """The time series' columns, name -> (N,) array, in file order (SI units in the names):
        :data:`COLUMNS` for every run, then the hose model's own (:meth:`extra_columns`)."""
        pos, off, vel = self.drogue_position_m, self.drogue_offset_m, self.drogue_velocity_m_s
        drag, tow, u = self.drogue_drag_n, self.tow_force_n, self.control_force_n
        cols = {
            "t_s": self.t_s,
            "drogue_x_m": pos[:, 0], "drogue_y_m": pos[:, 1], "drogue_z_m": pos[:, 2],
            "drogue_dx_m": off[:, 0], "drogue_dy_m": off[:, 1], "drogue_dz_m": off[:, 2],
            "drogue_vx_m_s": vel[:, 0], "drogue_vy_m_s": vel[:, 1], "drogue_vz_m_s": vel[:, 2],
            "drogue_drag_x_n": drag[:, 0], "drogue_drag_y_n": drag[:, 1], "drogue_drag_z_n": drag[:, 2],
            "tow_force_x_n": tow[:, 0], "tow_force_y_n": tow[:, 1], "tow_force_z_n": tow[:, 2],
            "exit_tension_n": self.exit_tension_n,
            "u_y_n": u[:, 0], "u_z_n": u[:, 1],
        }
        cols.update(self.extra_columns())
        return cols

    def extra_columns(self) -> dict[str, np.ndarray]:
        """The hose model's own columns after :data:`COLUMNS` (none for the fixed-length hose)."""
        return {}

    def outcome_columns(self) -> dict[str, Any]:
        """The hose model's own columns of a campaign's ``runs.csv`` row (none here; the
        engagement's capture test and peaks, :meth:`EngagementResult.outcome_columns`)."""
        return {}

    def row_message(self) -> str:
        """The ``message`` column of a campaign's ``runs.csv`` row."""
        return self.message

    def headline(self) -> str:
        """The run's headline statistics in a line, as ``hosedrogue simulate`` prints them: over
        the statistics window, the peak and RMS radial drogue offset [m] and the peak control force [N]."""
        st = self.statistics()
        start, end = self.statistics_window_s
        window = "the whole run" if math.isinf(end) else f"{start:g}-{end:g} s"
        return (f"drogue offset over {window}: peak {st['peak_radial_m']:.4g} m, RMS {st['rms_radial_m']:.4g} m; "
                f"peak control force {st['peak_u_n']:.4g} N")

    def statistics(self, capture_radii_m=None) -> dict[str, float]:
        """The run's window statistics (:func:`hosedrogue.results.statistics.window_statistics`: peak and RMS
        drogue offsets [m], peak control forces [N], the time fraction inside each capture radius)
        over :attr:`statistics_window_s`.

        Parameters
        ----------
        capture_radii_m : sequence of float, optional
            Capture radii [m] (default :data:`hosedrogue.results.statistics.DEFAULT_CAPTURE_RADII_M`).

        Returns
        -------
        dict
            Statistic name (unit in the name) -> value; NaN where the window holds no sample.
        """
        radii = DEFAULT_CAPTURE_RADII_M if capture_radii_m is None else capture_radii_m
        return window_statistics(self.t_s, self.drogue_offset_m, self.control_force_n,
                                 self.statistics_window_s, radii)

    #: File name of the run's figure (:meth:`plot`) in its output folder.
    FIGURE = "displacement.png"

    def run_document(self) -> dict[str, Any]:
        """The content of the run's ``run.json``: :func:`run_header`, the ``statistics``, the ``spectrum``
        (:func:`hosedrogue.results.spectra.displacement_spectrum`), then what was run (``meta``).

        Returns
        -------
        dict
        """
        from .spectra import PREDICTION_KEY, displacement_spectrum

        meta = {k: v for k, v in self.meta.items() if k != PREDICTION_KEY}
        return {**run_header(self), "statistics": _statistics_document(self), "spectrum": displacement_spectrum(
            self, self.meta.get(PREDICTION_KEY)), "verification": verification_document(self), **meta}

    def plot(self, **kwargs):
        """The run's figure (see hosedrogue.plotting); returns a matplotlib Figure."""
        raise NotImplementedError

    def hose_shapes(self) -> tuple[np.ndarray, np.ndarray]:
        """(joint_count (N,) [-], joints_m (sum of joint_count, 3) [m] in S_p): the joints at every
        output time, stacked alike for both hose models (:func:`hosedrogue.results.hose_file.stack_joints`)."""
        from .hose_file import stack_joints
        return stack_joints(self.joints_m)

    def matrices(self) -> dict[str, tuple[np.ndarray, list[str]]]:
        """Arrays a MATLAB file carries besides the time series: name -> (array (N, k), column names)."""
        return {}

    def mat_dict(self) -> dict[str, Any]:
        """The content of the run's ``.mat`` file (MATLAB version 5).

        Returns
        -------
        dict
            ``t_s`` (N x 1) [s]; ``signals``, a struct of the time series' columns (each N x 1, SI
            units); ``signal_names`` and ``signal_units`` (cell arrays, same order); ``data`` (N x m,
            those columns side by side); the run's :meth:`matrices` with their ``<name>_names``
            (``states`` [rad, rad/s]; an engagement's also ``charts``); ``completed``, ``message``,
            ``equilibrium_drogue_position_m`` (1 x 3) [m], ``meta_json`` (the run's settings).
        """
        from ..jsonio import dumps, fallback
        from ..units import unit_of

        cols = self.columns()
        names = list(cols)
        data = np.column_stack([np.asarray(cols[c], dtype=np.float64) for c in names])
        eq = self.equilibrium_m if self.equilibrium_m is not None else np.full(3, np.nan)
        out = {
            "t_s": np.asarray(self.t_s, dtype=np.float64).reshape(-1, 1),
            "signals": {c: data[:, i].reshape(-1, 1) for i, c in enumerate(names)},
            "signal_names": cellstr(names),
            "signal_units": cellstr([unit_of(c) for c in names]),
            "data": data,
        }
        for name, (array, columns) in self.matrices().items():
            out[name] = np.asarray(array, dtype=np.float64)
            out[f"{name[:-1] if name.endswith('s') else name}_names"] = cellstr(columns)
        out.update({
            "completed": bool(self.completed),
            "message": str(self.message),
            "equilibrium_drogue_position_m": np.asarray(eq, dtype=np.float64).reshape(1, 3),
            "meta_json": dumps(self.meta, default=fallback),  # strict JSON, as run.json
        })
        return out

    def to_mat(self, path: str | Path) -> Path:
        """Write the run to a MATLAB file (see :meth:`mat_dict` for the variables).

        Parameters
        ----------
        path : str or pathlib.Path
            File to write (``.mat``).

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        return save_mat(self.mat_dict(), path)

    def to_csv(self, path: str | Path) -> Path:
        """Write the time series to CSV (see :meth:`columns`), 10 significant digits.

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        path = Path(path)
        cols = self.columns()
        names = list(cols)
        data = np.column_stack([np.asarray(cols[c], dtype=np.float64) for c in names]) if names else np.empty((0, 0))
        if not np.isfinite(data).all():  # pandas writes non-finite values its own way
            self.to_dataframe().to_csv(path, index=False, float_format="%.10g")
            return path
        # the same text as pandas' to_csv(float_format="%.10g"), about 5x faster: one format
        # operation per block of rows instead of pandas' per-column formatter
        row = ",".join(["%.10g"] * data.shape[1]) + "\n"
        block = 4096  # rows per format operation (bounds the temporary tuple)
        with path.open("w", newline="") as fh:
            fh.write(",".join(names) + "\n")
            for i in range(0, data.shape[0], block):
                rows = data[i:i + block]
                fh.write((row * rows.shape[0]) % tuple(rows.ravel().tolist()))
        return path


@dataclass(frozen=True, kw_only=True)
class SimulationResult(WithSurfaces, RunResult):
    """A run of the fixed-length hose (:func:`hosedrogue.simulate`)."""

    states: np.ndarray  #: (N, 4n) x = [q, qd] [rad, rad/s]

    def matrices(self) -> dict[str, tuple[np.ndarray, list[str]]]:
        """The state (N, 4n) [rad, rad/s] with :func:`state_names`, for the MATLAB file."""
        return {"states": (self.states, state_names(self.states.shape[1] // 4))}

    def plot(self, **kwargs):
        """Lateral and vertical drogue displacement against time (see hosedrogue.plotting)."""
        from ..plotting.figures import plot_displacement

        return plot_displacement(self, **kwargs)


#: Keys of run.json's "engagement" object (docs/engagement.md, "What a run reports").
SUMMARY_KEYS = ("result", "miss_distance_m", "closure_speed_m_s", "peak_probe_load_n", "peak_exit_tension_n",
                "peak_slack_m", "peak_drogue_excursion_m", "peak_control_force_n")

@dataclass(frozen=True, kw_only=True)
class EngagementResult(WithSurfaces, RunResult):
    """Time histories (S_p, SI units) and the outcome of one engagement run.

    Every array has one row per output time (N rows); vectors are in the tanker frame S_p.
    """

    hose_length_m: np.ndarray  #: (N,) free hose length L [m]
    reel_speed_m_s: np.ndarray  #: (N,) take-up speed r_d w [m/s], positive reeling in
    drogue_tension_n: np.ndarray  #: (N,) tension in the last link (at the drogue) [N]
    probe_force_n: np.ndarray  #: (N, 3) force of the probe on the drogue [N]
    probe_position_m: np.ndarray  #: (N, 3) probe tip position [m]
    coupled: np.ndarray  #: (N,) bool: probe and drogue coupled
    slack_m: np.ndarray  #: (N,) hose length minus the straight exit-to-drogue distance [m]
    motor_torque_n_m: np.ndarray  #: (N,) reel motor torque tau_m [N m]
    miss_distance_series_m: np.ndarray  #: (N,) radial probe-to-coupler distance in the coupler plane [m]
    plane_distance_m: np.ndarray  #: (N,) probe tip aft of the coupler plane [m] (positive before contact)
    closure_speed_series_m_s: np.ndarray  #: (N,) probe speed toward the coupler plane relative to the drogue [m/s]
    links: np.ndarray  #: (N,) number of links
    hose_mass_kg: np.ndarray  #: (N,) hose mass in the air from the lumped masses [kg]
    joint_velocities_m_s: list  #: per output time, (n+1, 3) joint velocities [m/s]
    energy: dict  #: "kinetic", "elastic", "reel", "motor", "friction", "exit", "flux", "probe", "axial" (N,) [J]
    events: list  #: remesh, chart and contact events (dicts, times [s], jumps [m], [m/s], [J])
    outcome: dict  #: result, contact figures and peaks (keys carry their units, e.g. ``peak_slack_m``)
    #: elastic links: (steps + 1, 5) the loads after every integration step: time [s], exit
    #: tension [N], drogue-end tension [N], probe load [N], slack [m] (None for rigid links)
    step_loads: np.ndarray | None = None
    #: elastic links: per output time, every link's tension [N] (n,), exit link first (None for rigid links)
    link_tensions_n: list | None = None
    #: per segment its hose states (k, 4n) [rad, rad/s] and its links' charts (n,): the MATLAB
    #: file's ``states`` and ``charts`` (:meth:`matrices`), built only when it is written
    hose_states: list | None = None

    def matrices(self) -> dict[str, tuple[np.ndarray, list[str]]]:
        """The hose's states and charts (:func:`hosedrogue.results.matlab_file.hose_state_matrices`)."""
        return hose_state_matrices(self.hose_states) if self.hose_states else {}

    def extra_columns(self) -> dict[str, np.ndarray]:
        """The engagement's columns after :data:`COLUMNS`: reel, tensions, probe, coupler-plane
        geometry, slack, motor torque, links and the coupled flag."""
        return {
            "hose_length_m": self.hose_length_m,
            "reel_speed_m_s": self.reel_speed_m_s,
            "drogue_tension_n": self.drogue_tension_n,
            "probe_load_n": np.linalg.norm(self.probe_force_n, axis=1),
            "probe_x_m": self.probe_position_m[:, 0], "probe_y_m": self.probe_position_m[:, 1],
            "probe_z_m": self.probe_position_m[:, 2],
            "miss_distance_m": self.miss_distance_series_m,
            "probe_plane_distance_m": self.plane_distance_m,
            "closure_speed_m_s": self.closure_speed_series_m_s,
            "slack_m": self.slack_m,
            "motor_torque_n_m": self.motor_torque_n_m,
            "links": self.links,
            "coupled": self.coupled.astype(int),
        }

    FIGURE = "engagement.png"

    def run_document(self) -> dict[str, Any]:
        """The content of the run's ``run.json``: :func:`run_header`, the ``"engagement"`` summary
        (:meth:`summary`), the remesh, chart and contact ``"events"``, then what was run.

        Returns
        -------
        dict
        """
        meta = dict(self.meta)
        events = meta.pop("events", [])
        return {**run_header(self), "statistics": _statistics_document(self), "engagement": self.summary(),
                "verification": verification_document(self), "events": events, **meta}

    def capture_category(self) -> str:
        """The capture test's result in a word: "captured", "miss", "failed latch", "no contact"
        (the probe never reached the coupler plane) or "stopped" (a failed state)."""
        head = str(self.outcome.get("result", "")).split(":", 1)[0]
        if head in ("captured", "miss", "failed latch"):
            return head
        return "no contact" if self.completed else "stopped"

    def outcome_columns(self) -> dict[str, Any]:
        """The engagement's columns of a campaign's ``runs.csv`` row: the capture test's
        ``result`` (:meth:`capture_category`), the radial miss [m] and the closure speed [m/s] at
        the coupler plane (NaN without contact), and the run's peak probe load [N], peak exit
        tension [N] and peak slack [m] (``hosedrogue.studies.store.ENGAGEMENT_COLUMNS``)."""
        out = self.outcome

        def number(key):
            return math.nan if out.get(key) is None else float(out[key])

        return {"result": self.capture_category(), "miss_distance_m": number("miss_distance_m"),
                "closure_speed_m_s": number("closure_speed_m_s"), "peak_probe_load_n": number("peak_probe_load_n"),
                "peak_exit_tension_n": number("peak_exit_tension_n"), "peak_slack_m": number("peak_slack_m")}

    def row_message(self) -> str:
        """The ``message`` column of a campaign's row: the capture test's result, then the run's message."""
        return f"{self.outcome.get('result')}; {self.message}"

    def headline(self) -> str:
        """:meth:`RunResult.headline`, then the outcome, the miss [m], the peak probe load [N] and the
        peak exit tension [N]."""
        s = self.summary()
        miss = "none" if s["miss_distance_m"] is None else f"{s['miss_distance_m']:.3f} m"
        return (super().headline() + f"\nengagement: {s['result']}; miss {miss}; peak probe load "
                f"{s['peak_probe_load_n']:.4g} N; peak exit tension {s['peak_exit_tension_n']:.4g} N")

    def went_slack(self) -> bool:
        """Whether the hose went (nearly) slack: the exit tension fell below
        :data:`~hosedrogue.results.convergence.SLACK_TENSION_FRACTION` of the steady trail tension
        (:func:`hosedrogue.results.convergence.went_slack`).

        Returns
        -------
        bool
        """
        return went_slack(self.exit_tension_n)

    def summary(self) -> dict[str, Any]:
        """The run's ``"engagement"`` object: :data:`SUMMARY_KEYS` first, then the supporting
        figures, ``peak_tension_converged`` and ``converged`` (each peak of
        :data:`~hosedrogue.results.convergence.PEAK_KEYS`: True or False as measured by the run's
        :attr:`verification`, ``"unverified"`` without one) and ``notes``.

        Returns
        -------
        dict
            Outcome keys with their units in the names (``miss_distance_m``, ``peak_probe_load_n``, ...).
        """
        o = self.outcome
        out = {k: o.get(k) for k in SUMMARY_KEYS}
        out.update({k: v for k, v in o.items() if k not in out})
        if self.verification is None:
            converged, notes = unverified(), [UNVERIFIED_NOTE]
        else:
            figures = self.verification["figures"]
            converged, notes = {k: figures[k]["converged"] for k in PEAK_KEYS}, list(self.verification["notes"])
        out["peak_tension_converged"] = converged["peak_exit_tension_n"]
        out["converged"] = converged
        out["notes"] = notes
        return out

    def plot(self, **kwargs):
        """The engagement's time histories (drogue, tensions, probe load, slack, reel; see hosedrogue.plotting)."""
        from ..plotting.engagement import plot_engagement_history

        return plot_engagement_history({self.meta.get("scenario", "run"): self}, **kwargs)


def run_header(result) -> dict:
    """The first entries of a run's ``run.json``, common to every driver: package, version,
    completed, message, end time [s] and the drogue's balance position [m].

    Parameters
    ----------
    result : SimulationResult or hosedrogue.engagement.result.EngagementResult
        The run (its ``completed``, ``message``, ``t_s`` [s] and ``equilibrium_m`` [m]).

    Returns
    -------
    dict
    """
    return {
        "package": "hosedrogue",
        "version": __version__,
        "completed": result.completed,
        "message": result.message,
        "t_end_s": float(result.t_s[-1]) if result.t_s.size else 0.0,
        "equilibrium_drogue_position_m": np.asarray(result.equilibrium_m).tolist(),
    }


def _statistics_document(result: RunResult) -> dict:
    """run.json's ``"statistics"``: the window [s] (null end: the whole run) and the statistics."""
    start, end = result.statistics_window_s
    stats = {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in result.statistics().items()}
    return {"window_s": [start, None if math.isinf(end) else end], **stats}
