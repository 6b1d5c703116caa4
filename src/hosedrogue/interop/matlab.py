"""MATLAB ``.mat`` files (version 5, :func:`scipy.io.savemat`) of simulations and linear models.

Every array keeps full double precision (the CSV files round to 10 significant digits), every
signal has its name and unit next to it, and names follow the project's SI suffixes
(``_m``, ``_m_s``, ``_n``, ``_s``; :func:`hosedrogue.units.unit_of`). In MATLAB::

    r = load('timeseries.mat');  plot(r.t_s, r.signals.drogue_dy_m)
    m = load('linear_model.mat');  sys = ss(m.A, m.B, m.C, m.D, 'InputName', cellstr(m.input_names))
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..units import unit_of  # also importable from here, where it was defined before hosedrogue.units


def _save(data: dict, path: str | Path) -> Path:
    """Write ``data`` as a compressed version-5 .mat file, 1-D arrays as columns (MATLAB's time series)."""
    from scipy.io import savemat

    path = Path(path)
    savemat(path, data, do_compression=True, oned_as="column")
    return path


def _cellstr(items) -> np.ndarray:
    """A MATLAB cell array of strings (a 1 x n object array)."""
    cell = np.empty((1, len(items)), dtype=object)
    for i, s in enumerate(items):
        cell[0, i] = str(s)
    return cell


def state_names(links: int) -> list[str]:
    """Names of the state ``x = [q, qd]``: ``theta_1_1_rad`` (pitch), ``theta_1_2_rad`` (yaw), ...,
    then the rates ``theta_1_1_rad_s``, ...

    Parameters
    ----------
    links : int
        Number of links n.

    Returns
    -------
    list of str
        4 n names in state order.
    """
    q = [f"theta_{k}_{j}_rad" for k in range(1, links + 1) for j in (1, 2)]
    return q + [f"{name}_s" for name in q]


def simulation_mat_dict(result) -> dict:
    """The content of a simulation's ``.mat`` file.

    Parameters
    ----------
    result : hosedrogue.results.SimulationResult
        A finished (or stopped) simulation.

    Returns
    -------
    dict
        ``t_s`` (N x 1) [s]; ``signals``, a struct of the columns of
        :meth:`~hosedrogue.results.SimulationResult.to_dataframe` (each N x 1, SI units);
        ``signal_names`` and ``signal_units`` (cell arrays, same order); ``data`` (N x m, those
        columns side by side); ``states`` (N x 4n) [rad, rad/s] with ``state_names``;
        ``completed``, ``message``, ``equilibrium_drogue_position_m`` (1 x 3) [m] and ``meta_json``
        (the run's settings as JSON text).
    """
    df = result.to_dataframe()
    names = list(df.columns)
    data = df.to_numpy(dtype=np.float64)
    n = result.states.shape[1] // 4
    eq = result.equilibrium_m if result.equilibrium_m is not None else np.full(3, np.nan)
    return {
        "t_s": np.asarray(result.t_s, dtype=np.float64).reshape(-1, 1),
        "signals": {c: data[:, i].reshape(-1, 1) for i, c in enumerate(names)},
        "signal_names": _cellstr(names),
        "signal_units": _cellstr([unit_of(c) for c in names]),
        "data": data,
        "states": np.asarray(result.states, dtype=np.float64),
        "state_names": _cellstr(state_names(n)),
        "completed": bool(result.completed),
        "message": str(result.message),
        "equilibrium_drogue_position_m": np.asarray(eq, dtype=np.float64).reshape(1, 3),
        "meta_json": json.dumps(result.meta, default=str),
    }


def write_simulation_mat(result, path: str | Path) -> Path:
    """Write a simulation to a MATLAB file (see :func:`simulation_mat_dict` for the variables).

    Parameters
    ----------
    result : hosedrogue.results.SimulationResult
        The simulation.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return _save(simulation_mat_dict(result), path)


def linear_mat_dict(lm, channels, table2: dict) -> dict:
    """The content of a linear model's ``.mat`` file.

    Parameters
    ----------
    lm : hosedrogue.analysis.linearize.LinearModel
        Full-order model ``x' = A x + B u, y = C x + D u`` about the balance position.
    channels : hosedrogue.controllers.design.ReducedChannels
        The lateral and vertical channels at the requested order.
    table2 : dict
        ``{"lateral": (num, den), "vertical": (num, den)}``: each channel's transfer function,
        descending powers of s, monic denominator (:func:`hosedrogue.analysis.reduction.table2_form`).

    Returns
    -------
    dict
        ``A, B, C, D`` (SI: states [rad, rad/s], inputs [N], outputs [m]); ``state_names``,
        ``input_names`` (``u_hor_n``, ``u_ver_n``), ``input_units``, ``output_names``
        (``P_ny_m``, ``P_nz_m``), ``output_units``; ``x_eq`` (4n x 1, the balance state);
        per channel ``lateral`` / ``vertical`` structs with ``num``, ``den`` (1 x k),
        ``A, B, C, D`` of the reduced realization, ``poles`` [rad/s], ``input_name`` and
        ``output_name``; ``order`` (0 for full); ``flight`` struct (altitude_m, airspeed_m_s,
        wake, links).
    """
    params = lm.params
    n = params.hose.links
    out = {
        "A": np.asarray(lm.A, dtype=np.float64), "B": np.asarray(lm.B, dtype=np.float64),
        "C": np.asarray(lm.C, dtype=np.float64), "D": np.asarray(lm.D, dtype=np.float64),
        "state_names": _cellstr(state_names(n)),
        "input_names": _cellstr(["u_hor_n", "u_ver_n"]), "input_units": _cellstr(["N", "N"]),
        "output_names": _cellstr(["P_ny_m", "P_nz_m"]), "output_units": _cellstr(["m", "m"]),
        "x_eq": lm.equilibrium.state.reshape(-1, 1),
        "order": 0 if channels.order is None else int(channels.order),
        "flight": {"altitude_m": float(params.flight.altitude_m), "airspeed_m_s": float(params.flight.airspeed_m_s),
                   "wake": bool(params.wake.enabled), "links": int(n)},
    }
    for name, sys_, u, y in (("lateral", channels.lateral, "u_hor_n", "P_ny_m"),
                             ("vertical", channels.vertical, "u_ver_n", "P_nz_m")):
        num, den = table2[name]
        poles = np.sort_complex(np.asarray(sys_.poles()))
        out[name] = {
            "num": np.asarray(num, dtype=np.float64).reshape(1, -1),
            "den": np.asarray(den, dtype=np.float64).reshape(1, -1),
            "A": np.atleast_2d(np.asarray(sys_.A, dtype=np.float64)),
            "B": np.atleast_2d(np.asarray(sys_.B, dtype=np.float64)),
            "C": np.atleast_2d(np.asarray(sys_.C, dtype=np.float64)),
            "D": np.atleast_2d(np.asarray(sys_.D, dtype=np.float64)),
            "poles": poles.reshape(-1, 1),
            "input_name": u, "output_name": y,
        }
    return out


def write_linear_mat(lm, channels, table2: dict, path: str | Path) -> Path:
    """Write a linear model to a MATLAB file (see :func:`linear_mat_dict` for the variables).

    Parameters
    ----------
    lm : hosedrogue.analysis.linearize.LinearModel
        Full-order linear model.
    channels : hosedrogue.controllers.design.ReducedChannels
        Reduced lateral and vertical channels.
    table2 : dict
        Transfer functions per channel, ``{"lateral": (num, den), "vertical": (num, den)}``.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return _save(linear_mat_dict(lm, channels, table2), path)
