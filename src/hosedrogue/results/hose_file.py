"""The hose's shape over time, as a run's folder holds it: ``hose.npz`` (docs/viewer.md).

One NumPy file of three arrays: ``t_s`` (N,) output times [s], ``joint_count`` (N,) joints at
each time [-] and ``joints_m`` (sum of joint_count, 3) joint positions in S_p [m], time after
time, each from the tow point (its row 0) to the drogue. The joints of every time are stacked
with their own count because the engagement's link count changes where the hose is remeshed; the
fixed-length hose has n+1 at every time. Stored as computed (float64, not resampled).

* :func:`stack_joints` - per-time joint arrays -> (joint_count, joints_m)
  (:meth:`hosedrogue.results.run.RunResult.hose_shapes`);
* :func:`split_joints` - the inverse;
* :func:`write_hose_npz`, :func:`read_hose_npz` - the file (the reader checks that its arrays agree);
* :func:`run_digests` - the SHA-256 of a run's ``timeseries.csv`` (:func:`file_digest`) and of its
  hose's arrays (:func:`hose_digest`), which ``run.json`` records (:data:`DIGEST_KEY`,
  :func:`digest_record`) so that the viewer knows a ``run.json`` of another run.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from ..errors import ParameterError

__all__ = ["DIGEST_KEY", "FILE", "stack_joints", "split_joints", "write_hose_npz", "read_hose_npz", "hose_digest",
           "file_digest", "run_digests", "digest_record"]

#: File name of the hose's shape in a run's folder.
FILE = "hose.npz"
#: The key of ``run.json`` that holds :func:`run_digests` of the run's other files.
DIGEST_KEY = "data_sha256"


def stack_joints(joints_per_time) -> tuple[np.ndarray, np.ndarray]:
    """Stack the joint positions of every output time in one array.

    Parameters
    ----------
    joints_per_time : iterable of array_like
        Per output time, the (n+1, 3) joint positions [m] (an (N, n+1, 3) array, or a list of
        arrays whose n changes).

    Returns
    -------
    joint_count : numpy.ndarray
        (N,) int64: joints at each output time [-].
    joints_m : numpy.ndarray
        (sum(joint_count), 3) the joint positions [m], time after time.
    """
    if isinstance(joints_per_time, np.ndarray) and joints_per_time.ndim == 3:  # one n at every time
        n_out, joints, _ = joints_per_time.shape
        return (np.full(n_out, joints, dtype=np.int64),
                np.ascontiguousarray(joints_per_time, dtype=np.float64).reshape(n_out * joints, 3))
    shapes = [np.asarray(joints, dtype=np.float64) for joints in joints_per_time]
    counts = np.array([j.shape[0] for j in shapes], dtype=np.int64)
    return counts, (np.concatenate(shapes) if shapes else np.empty((0, 3)))


def split_joints(joint_count: np.ndarray, joints_m: np.ndarray) -> list[np.ndarray]:
    """The joints of each output time (the inverse of :func:`stack_joints`).

    Parameters
    ----------
    joint_count : numpy.ndarray
        (N,) joints at each output time [-].
    joints_m : numpy.ndarray
        (sum(joint_count), 3) joint positions [m].

    Returns
    -------
    list of numpy.ndarray
        N views, each (joint_count[i], 3) [m].
    """
    return np.split(joints_m, np.cumsum(joint_count)[:-1]) if len(joint_count) else []


def write_hose_npz(path: str | Path, t_s: np.ndarray, joint_count: np.ndarray, joints_m: np.ndarray) -> Path:
    """Write the hose's shape over time (uncompressed, full precision).

    Parameters
    ----------
    path : str or pathlib.Path
        File to write (``hose.npz`` in a run's folder).
    t_s : numpy.ndarray
        (N,) output times [s].
    joint_count : numpy.ndarray
        (N,) joints at each output time [-].
    joints_m : numpy.ndarray
        (sum(joint_count), 3) joint positions in S_p [m].

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    with path.open("wb") as fh:  # a file object: numpy adds no ".npz" to the name
        np.savez(fh, t_s=np.asarray(t_s, dtype=np.float64), joint_count=np.asarray(joint_count, dtype=np.int64),
                 joints_m=np.asarray(joints_m, dtype=np.float64))
    return path


def read_hose_npz(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a run's ``hose.npz``, checking that its arrays agree.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (:func:`write_hose_npz`).

    Returns
    -------
    t_s : numpy.ndarray
        (N,) output times [s].
    joint_count : numpy.ndarray
        (N,) joints at each output time [-].
    joints_m : numpy.ndarray
        (sum(joint_count), 3) joint positions in S_p [m].

    Raises
    ------
    ParameterError
        If it is not such a file (unreadable, arrays missing, shapes that disagree).
    """
    try:
        with np.load(Path(path), allow_pickle=False) as data:
            t, counts, joints = (np.asarray(data[k]) for k in ("t_s", "joint_count", "joints_m"))
    except (OSError, ValueError, KeyError, EOFError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ParameterError(f"{str(path)!r}: not a run's hose file (arrays t_s, joint_count, joints_m): {first}") from None
    if (t.ndim != 1 or counts.shape != t.shape or joints.ndim != 2 or joints.shape[1:] != (3,)
            or (counts.size and counts.min() < 2) or int(counts.sum()) != joints.shape[0]):
        raise ParameterError(f"{str(path)!r}: t_s {t.shape}, joint_count {counts.shape} and joints_m {joints.shape} "
                             "disagree: must be (N,), (N,) each >= 2, and (sum of joint_count, 3)")
    return t.astype(np.float64), counts.astype(np.int64), joints.astype(np.float64)


def hose_digest(t_s: np.ndarray, joint_count: np.ndarray, joints_m: np.ndarray) -> str:
    """The SHA-256 of a hose's arrays as :func:`write_hose_npz` stores them (float64, int64,
    float64; not the zip's bytes, which carry a time stamp), each preceded by its dtype and shape.

    Parameters
    ----------
    t_s, joint_count, joints_m : numpy.ndarray
        The hose's shape over time (:func:`write_hose_npz`).

    Returns
    -------
    str
        Hex digest.
    """
    h = hashlib.sha256()
    for a, dtype in ((t_s, np.float64), (joint_count, np.int64), (joints_m, np.float64)):
        a = np.ascontiguousarray(a, dtype=dtype)
        h.update(f"{a.dtype.str} {a.shape}".encode())
        h.update(a)  # the array's bytes through the buffer protocol (a.tobytes() copied them first)
    return h.hexdigest()


def file_digest(path: str | Path) -> str:
    """The SHA-256 of a file's bytes (a run's ``timeseries.csv``).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    str
        Hex digest.
    """
    with Path(path).open("rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def run_digests(csv_path: str | Path, t_s: np.ndarray, joint_count: np.ndarray, joints_m: np.ndarray) -> dict:
    """What identifies a run's data: the SHA-256 of its ``timeseries.csv`` (the file's bytes,
    :func:`file_digest`) and of its hose's arrays (:func:`hose_digest`), the same in every process.

    Parameters
    ----------
    csv_path : str or pathlib.Path
        The run's ``timeseries.csv``.
    t_s, joint_count, joints_m : numpy.ndarray
        The hose's shape over time (:func:`write_hose_npz`).

    Returns
    -------
    dict
        ``{"timeseries.csv": hex digest, "hose.npz": hex digest}``.
    """
    return digest_record(file_digest(csv_path), hose_digest(t_s, joint_count, joints_m))


def digest_record(csv_sha256: str, hose_sha256: str) -> dict:
    """The digests as ``run.json`` records them (:data:`DIGEST_KEY`) and :func:`run_digests`
    returns them, from digests taken elsewhere (``scenarios.runner.write`` hashes on a thread).

    Parameters
    ----------
    csv_sha256 : str
        :func:`file_digest` of the run's ``timeseries.csv``.
    hose_sha256 : str
        :func:`hose_digest` of its hose's arrays.

    Returns
    -------
    dict
        ``{"timeseries.csv": csv_sha256, "hose.npz": hose_sha256}``.
    """
    return {"timeseries.csv": csv_sha256, FILE: hose_sha256}
