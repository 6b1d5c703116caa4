"""Result objects: named signals with units, ``to_dataframe()``, ``to_csv()``.

Frames: S_p, the tanker trajectory frame (x forward, y right, z down), origin at the tow point.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .version import __version__


@dataclass(frozen=True)
class SimulationResult:
    """A time simulation of the hose-drogue system.

    ``completed`` is False when the run stopped early (divergence, step limit); everything up to
    ``t_s[-1]`` is still valid and ``message`` says when and why it stopped.
    """

    t_s: np.ndarray  #: (N,) time [s]
    states: np.ndarray  #: (N, 4n) x = [q, qd] [rad, rad/s]
    joints_m: np.ndarray  #: (N, n+1, 3) joint positions [m]
    drogue_velocity_m_s: np.ndarray  #: (N, 3) [m/s]
    drogue_drag_n: np.ndarray  #: (N, 3) aerodynamic force on the drogue [N]
    tow_force_n: np.ndarray  #: (N, 3) force the hose exerts on the tow point [N]
    control_n: np.ndarray  #: (N, 2) control force [u_hor, u_ver] [N]
    completed: bool  #: True if the run reached its end time
    message: str  #: "completed", or when and why the run stopped
    equilibrium_m: np.ndarray | None = None  #: (3,) drogue position at the balance position [m]
    meta: dict[str, Any] = field(default_factory=dict)  #: what was run (seed, parameters, scenario)

    @property
    def drogue_position_m(self) -> np.ndarray:
        """(N, 3) drogue position [m] in S_p."""
        return self.joints_m[:, -1, :]

    @property
    def drogue_offset_m(self) -> np.ndarray:
        """(N, 3) drogue position relative to the balance position [m] (zeros if unknown)."""
        ref = self.equilibrium_m if self.equilibrium_m is not None else self.drogue_position_m[0]
        return self.drogue_position_m - ref

    def to_dataframe(self):
        """A pandas DataFrame, one row per saved time, SI units in the column names."""
        import pandas as pd

        pos = self.drogue_position_m
        off = self.drogue_offset_m
        cols = {
            "t_s": self.t_s,
            "drogue_x_m": pos[:, 0],
            "drogue_y_m": pos[:, 1],
            "drogue_z_m": pos[:, 2],
            "drogue_dy_m": off[:, 1],
            "drogue_dz_m": off[:, 2],
            "drogue_vx_m_s": self.drogue_velocity_m_s[:, 0],
            "drogue_vy_m_s": self.drogue_velocity_m_s[:, 1],
            "drogue_vz_m_s": self.drogue_velocity_m_s[:, 2],
            "drogue_drag_x_n": self.drogue_drag_n[:, 0],
            "drogue_drag_y_n": self.drogue_drag_n[:, 1],
            "drogue_drag_z_n": self.drogue_drag_n[:, 2],
            "tow_force_x_n": self.tow_force_n[:, 0],
            "tow_force_y_n": self.tow_force_n[:, 1],
            "tow_force_z_n": self.tow_force_n[:, 2],
            "u_hor_n": self.control_n[:, 0],
            "u_ver_n": self.control_n[:, 1],
        }
        return pd.DataFrame(cols)

    def to_csv(self, path: str | Path) -> Path:
        """Write the time series to CSV (see :meth:`to_dataframe` for the columns)."""
        path = Path(path)
        df = self.to_dataframe()
        data = df.to_numpy(dtype=np.float64)
        if not np.isfinite(data).all():  # pandas writes non-finite values its own way
            df.to_csv(path, index=False, float_format="%.10g")
            return path
        # the same text as pandas' to_csv(float_format="%.10g"), about 5x faster: one format
        # operation per block of rows instead of pandas' per-column formatter
        row = ",".join(["%.10g"] * data.shape[1]) + "\n"
        block = 4096  # rows per format operation (bounds the temporary tuple)
        with path.open("w", newline="") as fh:
            fh.write(",".join(df.columns) + "\n")
            for i in range(0, data.shape[0], block):
                rows = data[i:i + block]
                fh.write((row * rows.shape[0]) % tuple(rows.ravel().tolist()))
        return path

    def plot(self, **kwargs):
        """Lateral and vertical drogue displacement against time (see hosedrogue.plotting)."""
        from .plotting.figures import plot_displacement

        return plot_displacement(self, **kwargs)


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
