"""The MATLAB files of a run (``timeseries.mat``) and of the linear models and controllers
(:mod:`hosedrogue.interop.matlab`): a version-5 ``.mat`` writer, MATLAB's cell array of strings
and the names of the hose's state."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["save_mat", "cellstr", "state_names"]


def save_mat(data: dict, path: str | Path) -> Path:
    """Write ``data`` as a compressed version-5 .mat file, 1-D arrays as columns (MATLAB's time series).

    Parameters
    ----------
    data : dict
        Variable name -> array, string, bool or struct (dict).
    path : str or pathlib.Path
        File to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from scipy.io import savemat

    path = Path(path)
    savemat(path, data, do_compression=True, oned_as="column")
    return path


def cellstr(items) -> np.ndarray:
    """A MATLAB cell array of strings (a 1 x n object array).

    Parameters
    ----------
    items : iterable of str
        The strings.

    Returns
    -------
    numpy.ndarray
    """
    items = list(items)
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


def hose_state_matrices(pieces: list) -> dict:
    """The MATLAB file's ``states`` and ``charts`` of an engagement from its segments' (hose states,
    charts): ``states`` (N, 4 n_max) [q, qd] [rad, rad/s] named by :func:`state_names` with n_max the
    most links of the run, a row of fewer links NaN beyond them (its q in columns 0..2n, its rates
    from 2 n_max); ``charts`` (N, n_max) each link's chart (0 standard angles, 1 the alternative
    chart, NaN beyond the row's links).

    Parameters
    ----------
    pieces : list of (numpy.ndarray, numpy.ndarray)
        Per segment its hose states (k, 4n) and its links' charts (n,).

    Returns
    -------
    dict
        name -> (array, column names).
    """
    n_max = max(z.shape[1] // 4 for z, _ in pieces)
    rows = sum(z.shape[0] for z, _ in pieces)
    x, chart = np.full((rows, 4 * n_max), np.nan), np.full((rows, n_max), np.nan)
    i = 0
    for z, ch in pieces:
        n, k = z.shape[1] // 4, z.shape[0]
        x[i:i + k, :2 * n] = z[:, :2 * n]
        x[i:i + k, 2 * n_max:2 * n_max + 2 * n] = z[:, 2 * n:]
        chart[i:i + k, :n] = ch
        i += k
    return {"states": (x, state_names(n_max)), "charts": (chart, [f"chart_{k}" for k in range(1, n_max + 1)])}
