"""Frequency and step responses of LTI models (python-control), as plain arrays: the Bode and step
figures of the linearized model and its reductions (paper Figs. 5-8), the reduction errors on a
frequency grid, and the unit steps of closed loops (Table 3, Figs. 10-11, the PID tuning).

:func:`step_outputs` is python-control's ``step_response`` of a continuous state-space model
with its floating-point operations unchanged and its Python loop over the time points compiled:
``forced_response`` (python-control 0.10) discretizes the model for a first-order hold on the
input, ``[[A dt, B dt, 0], [0, 0, I], [0, 0, 0]]`` through ``scipy.linalg.expm``, and steps
``x[i] = (Ad @ x[i-1] + Bd0 @ u[i-1]) + Bd1 @ u[i]``, one interpreted iteration (3 to 7 us) per
time point. Here the same matrix exponential gives the same ``Ad``, ``Bd0``, ``Bd1``; a unit step
on input k makes ``Bd0 @ u`` and ``Bd1 @ u`` the same two vectors at every step (products by 1
and 0 and sums with zeros, exact), computed once by the same numpy calls; the compiled loop
calls BLAS's ``dgemv`` for ``Ad @ x`` (numba's ``np.dot``, as numpy's ``@``) and adds the two
vectors in the same order; the outputs are the same ``C @ x + D @ u``. The responses are bit
for bit python-control's: checked on every call of the report's controllers and PID-tuning
sections (benchmarks/step_responses.py) and in tests/analysis/test_responses.py.

A response is a function of the model's four matrices, the input, the first and last time and
the number of points alone (the time step is ``(t[-1] - t[0]) / (N - 1)``): :func:`step_outputs`
keeps the last ones it computed (:data:`MEMO_BYTES` of them at most) under exactly these, so a
loop stepped again on the same grid (Table 3's paper PID in the PID-tuning section, the LQR's
design grid that is also Fig. 10's) costs a copy and gives the same bits.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np
from numba import njit

from ..jit import JIT

__all__ = ["freq_response", "step_response", "step_outputs", "MEMO_BYTES"]

#: Most bytes of responses :func:`step_outputs` keeps for a repeated call (the least recently used
#: leave first); the report's two controller sections compute about 40 MB.
MEMO_BYTES = 64 * 2**20
_memo: OrderedDict = OrderedDict()


def freq_response(sys, w) -> np.ndarray:
    """Complex frequency response of a SISO system.

    Parameters
    ----------
    sys : control.LTI
        Force [N] to offset [m].
    w : array_like
        Angular frequencies [rad/s].

    Returns
    -------
    numpy.ndarray
        G(j w) [m/N], complex.
    """
    return np.squeeze(np.asarray(sys(1j * w), dtype=complex))


def step_response(sys, t) -> np.ndarray:
    """Response of a SISO system to a unit step (a continuous state-space model through
    :func:`step_outputs`, any other as python-control computes it: the same bits).

    Parameters
    ----------
    sys : control.LTI
        Force [N] to offset [m].
    t : array_like
        Times [s].

    Returns
    -------
    numpy.ndarray
        Offset [m] after a 1 N step.
    """
    import control

    if isinstance(sys, control.StateSpace) and control.isctime(sys, strict=True):
        return np.squeeze(step_outputs(sys, t))
    return np.squeeze(np.asarray(control.step_response(sys, T=t).outputs, dtype=float))


@njit(**JIT)
def _hold_steps(ad, b0, b1, n_steps):
    """States x[:, i] = (ad @ x[:, i-1] + b0) + b1 from x[:, 0] = 0, shape (n, n_steps)."""
    n = ad.shape[0]
    xout = np.zeros((n, n_steps))
    prev = np.zeros(n)
    nxt = np.empty(n)
    for i in range(1, n_steps):
        np.dot(ad, prev, nxt)
        for j in range(n):
            v = (nxt[j] + b0[j]) + b1[j]
            xout[j, i] = v
            prev[j] = v
    return xout


def step_outputs(sys, t, input_index: int = 0) -> np.ndarray:
    """Outputs of a continuous state-space model after a unit step on one input, from rest.

    The same numbers as ``control.step_response(sys, t, input=input_index).outputs`` (see the
    module docstring), at a fraction of its cost.

    Parameters
    ----------
    sys : control.StateSpace
        Continuous-time model, any number of inputs and outputs.
    t : array_like, shape (N,)
        Evenly spaced times [s], N >= 2.
    input_index : int, optional
        The input that steps from 0 to 1 at t[0] (default 0).

    Returns
    -------
    numpy.ndarray, shape (outputs, N)
        Every output at every time, per unit of the input.

    Raises
    ------
    ValueError
        If ``sys`` is not a continuous state-space model, ``input_index`` is not one of its
        inputs, or ``t`` is not evenly spaced with at least two points.
    """
    import control

    if not isinstance(sys, control.StateSpace) or not control.isctime(sys, strict=True):
        raise ValueError(f"sys must be a continuous-time control.StateSpace, got {sys!r:.80}")
    m = sys.ninputs
    if not 0 <= input_index < m:
        raise ValueError(f"input_index = {input_index}: the model has {m} inputs")
    t = np.atleast_1d(np.asarray(t, dtype=float)).reshape(-1)
    n_steps = t.shape[0]
    if n_steps < 2:
        raise ValueError(f"t has {n_steps} point: need at least two")
    # python-control's own test and time step (forced_response)
    dt = (t[-1] - t[0]) / (n_steps - 1)
    if not np.allclose(np.diff(t), dt):
        raise ValueError("t must be evenly spaced")
    A, B, C, D = (np.asarray(x, dtype=float) for x in (sys.A, sys.B, sys.C, sys.D))
    key = (A.shape, C.shape, A.tobytes(), B.tobytes(), C.tobytes(), D.tobytes(), t[0], t[-1], n_steps, input_index)
    if key in _memo:
        _memo.move_to_end(key)
        return _memo[key].copy()
    y = _step(A, B, C, D, t, input_index)
    if y.nbytes <= MEMO_BYTES:
        _memo[key] = y.copy()
        while sum(v.nbytes for v in _memo.values()) > MEMO_BYTES:
            _memo.popitem(last=False)
    return y


def _step(A, B, C, D, t, input_index):
    """:func:`step_outputs` computed: python-control's discretization, the compiled loop."""
    import scipy.linalg

    n, m, n_steps = A.shape[0], B.shape[1], t.shape[0]
    dt = (t[-1] - t[0]) / (n_steps - 1)
    u = np.zeros((m, n_steps))
    u[input_index, :] = np.ones_like(t)
    big = np.block([[A * dt, B * dt, np.zeros((n, m))],
                    [np.zeros((m, n + m)), np.identity(m)],
                    [np.zeros((m, n + 2 * m))]])
    e = scipy.linalg.expm(big)
    ad = e[:n, :n]
    bd1 = e[:n, n + m:]
    bd0 = e[:n, n:n + m] - bd1
    xout = _hold_steps(np.ascontiguousarray(ad), bd0 @ u[:, 0], bd1 @ u[:, 1], n_steps)
    return C @ xout + D @ u
