"""hosedrogue.analysis.responses.step_outputs: python-control's step response with its loop over the
time points compiled. It must give python-control's bits (the report's Table 3 and figures were
computed that way), the exact response of a first-order lag (the first-order hold is exact for a
step), and compute a repeated call once."""

import numpy as np
import pytest
import control

from hosedrogue.analysis import responses
from hosedrogue.analysis.responses import step_outputs


def _mimo():
    """Two decoupled channels (a lightly damped pair, a lag with a zero) and a coupled output:
    stepping one input leaves the other channel's states exactly zero (the sign of those zeros
    is part of the bits)."""
    A = np.array([[0.0, 1.0, 0.0], [-40.0, -1.3, 0.0], [0.0, 0.0, -7.0]])
    B = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, -3.0]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.5, -0.1, 2.0]])
    D = np.array([[0.0, 0.0], [0.0, 0.1], [0.0, 0.0]])
    return control.ss(A, B, C, D)


@pytest.mark.parametrize("t", [np.linspace(0.0, 5.0, 2001), np.linspace(0.3, 2.3, 7), np.array([0.0, 0.01])])
def test_the_bits_of_python_controls_step_response(t):
    """Every output for each input, on grids from 0 and from 0.3 s and of two points, byte for byte."""
    loops = [_mimo(), control.ss(control.feedback(control.tf([3.0, 1.0], [1.0, 2.0, 5.0, 0.0]), 1)),
             control.ss(control.tf([1.0], [1.0, 0.4, 9.0]))]
    for sys in loops:
        for k in range(sys.ninputs):
            ref = control.step_response(sys, t, input=k, squeeze=False).outputs[:, 0, :]
            got = step_outputs(sys, t, k)
            assert got.shape == ref.shape and got.tobytes() == ref.tobytes()


def test_a_first_order_lag_is_exact():
    """y = (1 - exp(-a t)) / a for 1/(s + a): the hold is exact for a step, so only round-off
    remains: 1e-13 relative to the final value 1/a (a few hundred rounding errors of 1.1e-16
    accumulated over 4000 steps of a contracting recursion)."""
    a = 2.5
    t = np.linspace(0.0, 4.0, 4001)
    y = step_outputs(control.ss([[-a]], [[1.0]], [[1.0]], [[0.0]]), t)[0]
    assert np.max(np.abs(y - (1.0 - np.exp(-a * t)) / a)) < 1e-13 / a


def test_a_repeated_call_is_computed_once_and_a_copy(monkeypatch):
    """The same model, input and grid ends: the first answer again, not recomputed, a copy the
    caller may change; another input or grid is computed."""
    calls = []
    step = responses._step
    monkeypatch.setattr(responses, "_memo", type(responses._memo)())
    monkeypatch.setattr(responses, "_step", lambda *a: calls.append(a[-1]) or step(*a))
    sys, t = _mimo(), np.linspace(0.0, 2.0, 501)
    first = step_outputs(sys, t, 1)
    first_bits = first.tobytes()
    first[:] = np.nan
    again = step_outputs(control.ss(sys.A.copy(), sys.B, sys.C, sys.D), t.copy(), 1)
    assert again.tobytes() == first_bits and len(calls) == 1
    step_outputs(sys, t, 0)
    step_outputs(sys, np.linspace(0.0, 2.0, 502), 1)
    assert calls == [1, 0, 1]


def test_the_memo_keeps_at_most_its_bytes(monkeypatch):
    """With room for two responses of 3 x 501 values, a third pushes out the least recently used."""
    monkeypatch.setattr(responses, "_memo", type(responses._memo)())
    monkeypatch.setattr(responses, "MEMO_BYTES", 2 * 3 * 501 * 8)
    sys = _mimo()
    for t_end in (1.0, 2.0, 3.0):
        step_outputs(sys, np.linspace(0.0, t_end, 501), 0)
    assert len(responses._memo) == 2 and {k[7] for k in responses._memo} == {2.0, 3.0}


@pytest.mark.parametrize("sys, t, k, says", [
    (control.tf([1.0], [1.0, 1.0]), np.linspace(0, 1, 11), 0, "StateSpace"),
    (control.ss([[0.5]], [[1.0]], [[1.0]], [[0.0]], 0.1), np.linspace(0, 1, 11), 0, "continuous-time"),
    (control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]), np.array([0.0, 0.1, 0.3]), 0, "evenly spaced"),
    (control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]), np.array([0.0]), 0, "at least two"),
    (control.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]]), np.linspace(0, 1, 11), 1, "1 inputs"),
])
def test_what_it_refuses(sys, t, k, says):
    with pytest.raises(ValueError, match=says):
        step_outputs(sys, t, k)
