"""Frequency and step responses of single-input single-output LTI models (python-control), as
plain arrays: the Bode and step figures of the linearized model and its reductions (paper Figs.
5-8) and the reduction errors on a frequency grid."""

from __future__ import annotations

import numpy as np

__all__ = ["freq_response", "step_response"]


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
    """Response of a SISO system to a unit step.

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

    return np.squeeze(np.asarray(control.step_response(sys, T=t).outputs, dtype=float))
