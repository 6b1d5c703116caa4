"""The engagement's pilot and receiver (numba): the rates of the states of the pilot, who flies
the probe toward the drogue seen one reaction time ago (the drogue history, read by cubic
Hermite interpolation), and of the receiver flown by a velocity command (docs/engagement.md,
"Pilot model"; docs/controllers.md).
"""

from __future__ import annotations

import math

from numba import njit

from ...jit import JIT_NO_ALLOC
from ..layout import (
    EP_COUPLED, EP_FEED, EP_H, EP_P0Y, EP_P0Z, EP_PIL_AMAX, EP_PIL_DELAY, EP_PIL_LAG, EP_PIL_TV, EP_PIL_VMAX,
    EP_RCV_AMAX, EP_RCV_TV, EP_RCV_VMAX, PIL_VY, PIL_Y, RCV_CX, RCV_VX, RCV_X, Z_TAIL,
)
from .chain import tail_start
from .probe import fed_tip


@njit(**JIT_NO_ALLOC)
def delayed_drogue(tq, hist, h):
    """Drogue lateral and vertical position [m] at time tq >= 0 from the history ``hist`` (rows:
    global RK4 steps; y, z, y', z' [m, m/s]) by cubic Hermite interpolation between the steps
    (O(h^4), below the RK4 error); a row not yet written (NaN) is never used."""
    x = tq / h
    k = int(math.floor(x))
    last = hist.shape[0] - 1
    if k < 0:
        k = 0
    if k >= last:
        return hist[last, 0], hist[last, 1]
    s = x - k
    if s < 1e-9 or not math.isfinite(hist[k + 1, 0]):
        return hist[k, 0], hist[k, 1]
    s2 = s * s
    s3 = s2 * s
    h00 = 2.0 * s3 - 3.0 * s2 + 1.0
    h10 = s3 - 2.0 * s2 + s
    h01 = -2.0 * s3 + 3.0 * s2
    h11 = s3 - s2
    y = h00 * hist[k, 0] + h10 * h * hist[k, 2] + h01 * hist[k + 1, 0] + h11 * h * hist[k + 1, 2]
    zz = h00 * hist[k, 1] + h10 * h * hist[k, 3] + h01 * hist[k + 1, 1] + h11 * h * hist[k + 1, 3]
    return y, zz


@njit(**JIT_NO_ALLOC)
def pilot_rates(t, z, n, ep, hist, dz):
    """dz/dt of the pilot's states (docs/engagement.md, "Pilot model"): per axis the aim is the
    drogue's position one reaction time ago (before t = 0 the start point: the pilot starts to
    chase the drogue at t = 0), the commanded speed ``(aim - p) / lag`` clipped to the speed
    bound, and the acceleration ``(v_cmd - v) / tau_v`` clipped to the acceleration bound. Once
    coupled the pilot holds station (v_cmd = 0): the drogue is on the probe."""
    b = tail_start(n, ep) + Z_TAIL
    tq = t - ep[EP_PIL_DELAY]
    if tq < 0.0:
        ay = ep[EP_P0Y]
        az = ep[EP_P0Z]
    else:
        ay, az = delayed_drogue(tq, hist, ep[EP_H])
    vmax = ep[EP_PIL_VMAX]
    amax = ep[EP_PIL_AMAX]
    for i in range(2):
        aim = ay if i == 0 else az
        p = z[b + PIL_Y + i]
        v = z[b + PIL_VY + i]
        vcmd = 0.0
        if ep[EP_COUPLED] == 0.0:
            vcmd = min(max((aim - p) / ep[EP_PIL_LAG], -vmax), vmax)
        dz[b + PIL_Y + i] = v
        dz[b + PIL_VY + i] = min(max((vcmd - v) / ep[EP_PIL_TV], -amax), amax)


@njit(**JIT_NO_ALLOC)
def receiver_rates(t, z, n, ep, dz):
    """dz/dt of the receiver's states (docs/controllers.md): per axis the held velocity command,
    clipped to the speed bound, is followed through the first-order lag tau_v with the
    acceleration clipped to its bound (the pilot model's response, :func:`pilot_rates`); the
    command itself is held (zero rate). A fed path (``EP_FEED``): the tip's velocity and
    acceleration at time t on it (:func:`~.probe.fed_tip`; the states follow it, the tip is the path)."""
    b = tail_start(n, ep) + Z_TAIL
    if ep[EP_FEED] != 0.0:
        _, v, a = fed_tip(t, ep)
        for i in range(3):
            dz[b + RCV_X + i] = v[i]
            dz[b + RCV_VX + i] = a[i]
            dz[b + RCV_CX + i] = 0.0
        return
    tv = ep[EP_RCV_TV]
    for i in range(3):
        vmax = ep[EP_RCV_VMAX + i]
        amax = ep[EP_RCV_AMAX + i]
        v = z[b + RCV_VX + i]
        vcmd = min(max(z[b + RCV_CX + i], -vmax), vmax)
        dz[b + RCV_X + i] = v
        dz[b + RCV_VX + i] = min(max((vcmd - v) / tv, -amax), amax)
        dz[b + RCV_CX + i] = 0.0
