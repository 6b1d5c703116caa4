"""The frame a live flight streams to its page: the state at a receiver sample as JSON (the
hose's joints as base64 float32, the probe, the head-up display's figures, the pace), and the
HUD's straight-on miss distance.
"""

from __future__ import annotations

import base64
import json
import math

import numpy as np

from ..jsonio import plain

__all__ = ["frame_document", "straight_on_miss", "plain"]


def frame_document(outputs: dict, command, source: str, pace) -> str:
    """The frame of the state ``outputs`` as the page draws it (JSON text).

    Parameters
    ----------
    outputs : dict
        :meth:`hosedrogue.engagement.EngagementStepper.outputs` at the sample, plus
        ``"outcome"`` (the run's outcome so far).
    command : sequence of 3 float
        The command in effect (v_x, v_y, v_z) [m/s].
    source : str
        What gave it ("keyboard", "gamepad", "none").
    pace : hosedrogue.fly.clock.Pace
        How the flight keeps to real time.

    Returns
    -------
    str
        ``t`` [s], ``joints`` (base64 little-endian float32, (count, 3) [m] in S_p), ``count``,
        ``probe`` [m], ``coupled``, ``range_m``, ``offset_m`` (drogue minus tip [m]),
        ``closure_m_s``, ``miss_m`` (:func:`straight_on_miss`), ``axis_miss_m``, ``plane_m``,
        ``tension_n``, ``probe_load_n``, ``links``, ``length_m``, ``command``, ``source``,
        ``ratio``, ``capacity``, ``late_samples``, ``lost_s``, ``outcome``.
    """
    o = outputs
    joints, probe = o["joints_m"], o["probe_position_m"]
    frame = {"t": o["t_s"], "joints": _b64(joints, "<f4"), "count": int(joints.shape[0]),
             "probe": probe.tolist(), "coupled": o["coupled"], "range_m": float(joints[-1, 0] - probe[0]),
             "offset_m": (joints[-1] - probe).tolist(), "closure_m_s": o["closure_speed_m_s"],
             "miss_m": straight_on_miss(joints, probe), "axis_miss_m": o["miss_distance_m"],
             "plane_m": o["plane_distance_m"], "tension_n": o["exit_tension_n"],
             "probe_load_n": float(np.linalg.norm(o["probe_force_n"])), "links": o["links"],
             "length_m": o["hose_length_m"], "command": list(command), "source": source,
             "ratio": pace.ratio, "capacity": pace.capacity if math.isfinite(pace.capacity) else None,
             "late_samples": pace.late_samples, "lost_s": pace.lost_s, "outcome": plain(o["outcome"])}
    return json.dumps(frame, separators=(",", ":"), allow_nan=False)


def straight_on_miss(joints: np.ndarray, tip: np.ndarray) -> float:
    """The miss distance the probe is heading for: where the tip, flying straight forward (+x),
    meets the coupler plane (through the drogue, normal to the last link), its distance from the
    drogue [m]. The HUD's figure: before contact the radial distance from the drogue's axis
    (the run's ``miss_distance_m``) also counts the axis's tilt times the range (0.8 m at 3 m for
    a hose hanging 15 degrees), which flying straight on does not miss by.

    Parameters
    ----------
    joints : array (n+1, 3)
        The hose's joints, the last the drogue [m] in S_p.
    tip : array (3,)
        The probe tip [m] in S_p.

    Returns
    -------
    float
        [m]; the radial distance from the axis when the plane is within 6 degrees of containing x
        (a straight-on path would not cross it).
    """
    n = joints[-1] - joints[-2]
    n = n / np.linalg.norm(n)
    rel = tip - joints[-1]
    if abs(n[0]) < 0.1:
        return float(np.linalg.norm(rel - (rel @ n) * n))
    crossing = rel.copy()
    crossing[0] -= (rel @ n) / n[0]
    return float(np.linalg.norm(crossing))


def _b64(array: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")
