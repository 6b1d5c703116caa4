"""MATLAB ``.mat`` files (version 5, :func:`scipy.io.savemat`) of simulations and linear models.

Every array keeps full double precision (the CSV files round to 10 significant digits), every
signal has its name and unit next to it, and names follow the project's SI suffixes
(``_m``, ``_m_s``, ``_n``, ``_s``; :func:`hosedrogue.units.unit_of`). In MATLAB::

    r = load('timeseries.mat');  plot(r.t_s, r.signals.drogue_dy_m)
    m = load('linear_model.mat');  sys = ss(m.A, m.B, m.C, m.D, 'InputName', cellstr(m.input_names))
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..results import cellstr as _cellstr, save_mat as _save, state_names  # noqa: F401 - re-exported
from ..units import unit_of  # noqa: F401 - re-exported (the names' units)


def simulation_mat_dict(result) -> dict:
    """The content of a run's ``.mat`` file (:meth:`hosedrogue.results.RunResult.mat_dict`).

    Parameters
    ----------
    result : hosedrogue.results.RunResult
        A finished (or stopped) run of either hose model.

    Returns
    -------
    dict
    """
    return result.mat_dict()


def write_simulation_mat(result, path: str | Path) -> Path:
    """Write a run to a MATLAB file (:meth:`hosedrogue.results.RunResult.to_mat`).

    Parameters
    ----------
    result : hosedrogue.results.RunResult
        The run.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return result.to_mat(path)


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
        ``input_names`` (``u_y_n``, ``u_z_n``: the control force at the drogue, lateral and vertical), ``input_units``, ``output_names``
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
        "input_names": _cellstr(["u_y_n", "u_z_n"]), "input_units": _cellstr(["N", "N"]),
        "output_names": _cellstr(["P_ny_m", "P_nz_m"]), "output_units": _cellstr(["m", "m"]),
        "x_eq": lm.equilibrium.state.reshape(-1, 1),
        "order": 0 if channels.order is None else int(channels.order),
        "flight": {"altitude_m": float(params.flight.altitude_m), "airspeed_m_s": float(params.flight.airspeed_m_s),
                   "wake": bool(params.wake.enabled), "links": int(n)},
    }
    for name, sys_, u, y in (("lateral", channels.lateral, "u_y_n", "P_ny_m"),
                             ("vertical", channels.vertical, "u_z_n", "P_nz_m")):
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
