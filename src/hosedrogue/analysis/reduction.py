"""Model reduction of the linearized hose-drogue model (paper Sec. 3.1, Table 2).

Balanced truncation (Moore 1981; Glover 1984) of a stable LTI system keeps the states with the
largest Hankel singular values (HSVs). For a stable system G of order n with HSVs
sigma_1 >= ... >= sigma_n, the truncation G_r of order r satisfies the a-priori bound

    ||G - G_r||_inf <= 2 * (sigma_{r+1} + ... + sigma_n),

which `truncation_error_bound` evaluates and the tests check on a dense frequency grid.

The plant convention is two inputs u = [u_hor, u_ver] [N] and two outputs y = [P_ny, P_nz] [m]
(drogue lateral and vertical offset from its equilibrium); the lateral channel is u_hor -> P_ny
and the vertical channel u_ver -> P_nz.

Numerical thresholds used here, each a documented module constant:

- `MINREAL_TOL`: rank tolerance for removing uncontrollable/unobservable states in
  `split_channels`;
- `NUMERATOR_ZERO_RTOL`: leading numerator coefficients below this fraction of the largest
  one are treated as round-off zeros in `table2_form`.
"""

from __future__ import annotations

import math

import numpy as np
import control

__all__ = [
    "MINREAL_TOL",
    "NUMERATOR_ZERO_RTOL",
    "hankel_singular_values",
    "balanced_truncation",
    "truncation_error_bound",
    "table2_form",
    "second_order_characteristics",
    "format_tf",
    "split_channels",
]

#: Rank tolerance passed to SLICOT TB01PD (through `control.StateSpace.minreal`) when a channel
#: is extracted from the two-input two-output model: TB01PD uses it as the lower bound on the
#: reciprocal condition number in the rank decisions of its controllability/observability
#: staircase reduction, so it is relative. 1e-9 drops the states of the other channel when the
#: two are decoupled to round-off, yet keeps couplings at the level of finite-difference errors
#: of a numerical linearization (~1e-7 relative), which balanced truncation then handles.
MINREAL_TOL = 1e-9

#: Leading numerator coefficients whose magnitude is at most this fraction of the largest
#: numerator coefficient are dropped by `table2_form`. A state-space to transfer-function
#: conversion of a strictly proper system leaves such coefficients at ~1e-16 relative; the
#: smallest genuine coefficient in the paper's Table 2 is ~3e-6 of the largest, so 1e-10
#: separates the two with margin on both sides.
NUMERATOR_ZERO_RTOL = 1e-10


def _as_statespace(sys, name: str = "sys") -> control.StateSpace:
    if isinstance(sys, control.StateSpace):
        return sys
    if isinstance(sys, control.TransferFunction):
        return control.tf2ss(sys)
    raise TypeError(f"{name} must be a control.StateSpace or control.TransferFunction, got {type(sys).__name__}")


def _require_continuous(sys, name: str = "sys") -> None:
    if control.isdtime(sys, strict=True):
        raise ValueError(f"{name} must be a continuous-time system (dt=0), got dt={sys.dt}")


def hankel_singular_values(sys) -> np.ndarray:
    """Hankel singular values of a stable continuous-time LTI system.

    Computed by the square-root method: with Cholesky factors of the Gramians,
    Wc = Rc^T Rc and Wo = Ro^T Ro (SLICOT SB03OD via `control.gram`), the HSVs are the
    singular values of Ro Rc^T. This is more accurate than the square roots of the eigenvalues
    of Wo Wc for systems whose HSVs span many decades, and gives non-negative real values by
    construction.

    Parameters
    ----------
    sys : control.StateSpace or control.TransferFunction
        Stable continuous-time system. For the hose model: inputs force [N], outputs
        offset [m], so the HSVs are in m/N.

    Returns
    -------
    numpy.ndarray
        Hankel singular values, sorted in decreasing order, in the units of the system's gain.

    Raises
    ------
    ValueError
        If the system is discrete-time or has a pole with non-negative real part.
    """
    ss = _as_statespace(sys)
    _require_continuous(ss)
    if ss.nstates == 0:
        return np.zeros(0)
    poles = np.linalg.eigvals(ss.A)
    if np.any(poles.real >= 0.0):
        worst = poles[np.argmax(poles.real)]
        raise ValueError(
            f"Hankel singular values need a stable system; pole {worst:.6g} has real part >= 0"
        )
    rc = control.gram(ss, "cf")
    ro = control.gram(ss, "of")
    hsv = np.linalg.svd(ro @ rc.T, compute_uv=False)
    return np.sort(hsv)[::-1]


def balanced_truncation(sys, order: int) -> control.StateSpace:
    """Balanced truncation of an LTI system to a given order.

    Uses `control.balred(sys, order, method="truncate")` (SLICOT AB09AD, square-root balance
    and truncate; for a system with unstable poles AB09MD reduces the stable part only and
    keeps the unstable part). The feedthrough D is kept unchanged.

    Parameters
    ----------
    sys : control.StateSpace or control.TransferFunction
        Continuous-time system to reduce.
    order : int
        Requested number of states, >= 1. If the system already has at most this many states
        it is returned unchanged (converted to state space if it was a transfer function).

    Returns
    -------
    control.StateSpace
        Reduced model. Its order may be lower than `order` if the system has fewer than
        `order` Hankel singular values above SLICOT's round-off threshold (a minimal
        realization of lower order exists).

    Raises
    ------
    ValueError
        If `order` is not an integer >= 1, or the system is discrete-time.
    """
    if isinstance(order, (bool, np.bool_)) or not isinstance(order, (int, np.integer)):
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    if order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order}")
    ss = _as_statespace(sys)
    _require_continuous(ss)
    if ss.nstates <= order:
        return ss
    return control.balred(ss, int(order), method="truncate")


def truncation_error_bound(hsv, order: int) -> float:
    """A-priori H-infinity error bound of balanced truncation: twice the discarded HSVs.

    Parameters
    ----------
    hsv : array_like
        Hankel singular values in decreasing order (as from `hankel_singular_values`),
        in the system's gain units (m/N for the hose model).
    order : int
        Order of the truncated model, 0 <= order <= len(hsv).

    Returns
    -------
    float
        2 * sum(hsv[order:]), an upper bound on max over frequency of the largest singular
        value of G(jw) - G_r(jw), same units as `hsv`.

    Raises
    ------
    ValueError
        If `order` is outside [0, len(hsv)] or `hsv` is not a 1-D array.
    """
    hsv = np.asarray(hsv, dtype=float)
    if hsv.ndim != 1:
        raise ValueError(f"hsv must be a 1-D array, got shape {hsv.shape}")
    if not 0 <= order <= hsv.size:
        raise ValueError(f"order must be in [0, {hsv.size}], got {order}")
    return float(2.0 * np.sum(hsv[order:]))


def require_siso(name: str, sys) -> None:
    """Raise ValueError unless ``sys`` has one input and one output (the one SISO check).

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    sys : control.StateSpace or control.TransferFunction
        The system.
    """
    if sys.ninputs != 1 or sys.noutputs != 1:
        raise ValueError(f"{name} must be SISO, got {sys.noutputs} outputs x {sys.ninputs} inputs")


def table2_form(sys_siso) -> tuple[np.ndarray, np.ndarray]:
    """Numerator and monic denominator of a SISO system, as printed in the paper's Table 2.

    Parameters
    ----------
    sys_siso : control.StateSpace or control.TransferFunction
        Single-input single-output system.

    Returns
    -------
    num : numpy.ndarray
        Numerator coefficients, descending powers of s, with leading coefficients of magnitude
        <= `NUMERATOR_ZERO_RTOL` times the largest one removed (round-off from the
        state-space conversion). An all-zero numerator is returned as ``[0.0]``.
    den : numpy.ndarray
        Denominator coefficients, descending powers of s, scaled so that ``den[0] == 1``.

    Raises
    ------
    ValueError
        If the system is not SISO or its denominator's leading coefficient is zero.
    """
    require_siso("sys_siso", sys_siso)
    tf = control.ss2tf(sys_siso) if isinstance(sys_siso, control.StateSpace) else sys_siso
    num = np.atleast_1d(np.asarray(tf.num[0][0], dtype=float))
    den = np.atleast_1d(np.asarray(tf.den[0][0], dtype=float))
    den = np.trim_zeros(den, "f")
    if den.size == 0:
        raise ValueError("denominator is identically zero")
    lead = den[0]
    num = num / lead
    den = den / lead
    scale = np.max(np.abs(num)) if num.size else 0.0
    if scale == 0.0:
        return np.array([0.0]), den
    keep = np.nonzero(np.abs(num) > NUMERATOR_ZERO_RTOL * scale)[0][0]
    return num[keep:], den


def second_order_characteristics(num, den) -> dict:
    """DC gain, natural frequency, damping ratio and zero of a 2nd-order transfer function.

    Parameters
    ----------
    num, den : array_like
        Coefficients in descending powers of s (Table 2's form, :func:`table2_form`); force [N]
        to offset [m].

    Returns
    -------
    dict
        ``dc_gain_m_n`` [m/N], ``natural_frequency_rad_s`` [rad/s], ``damping_ratio`` [-],
        ``zero_1_s`` [1/s] (NaN without a finite zero).
    """
    num = np.asarray(num, float)
    den = np.asarray(den, float)
    wn = math.sqrt(den[-1] / den[0])
    return {"dc_gain_m_n": num[-1] / den[-1], "natural_frequency_rad_s": wn,
            "damping_ratio": den[1] / den[0] / (2.0 * wn),
            "zero_1_s": -num[-1] / num[-2] if num.size >= 2 and num[-2] != 0 else float("nan")}


def _format_coefficient(value: float, digits: int) -> str:
    """Positional notation rounded to `digits` significant digits (as Table 2 prints them),
    scientific notation outside 1e-6 <= |value| < 1e7 where positional would be unreadable."""
    if 1e-6 <= value < 1e7:
        return np.format_float_positional(value, precision=digits, unique=False, fractional=False, trim="-")
    return f"{value:.{digits}g}"


def _format_poly(coeffs: np.ndarray, digits: int, monic_lead: bool) -> str:
    degree = coeffs.size - 1
    terms: list[str] = []
    for i, c in enumerate(coeffs):
        power = degree - i
        if c == 0.0:
            continue
        sign = "-" if c < 0 else "+"
        mag = abs(c)
        if power == 0:
            body = _format_coefficient(mag, digits)
        else:
            s_pow = "s" if power == 1 else f"s^{power}"
            body = s_pow if (monic_lead and i == 0 and mag == 1.0) else f"{_format_coefficient(mag, digits)} {s_pow}"
        if not terms:
            terms.append(body if sign == "+" else f"-{body}")
        else:
            terms.append(f"{sign} {body}")
    return " ".join(terms) if terms else "0"


def format_tf(num, den, digits: int = 4) -> str:
    """Readable one-line transfer function, in the style of the paper's Table 2.

    Parameters
    ----------
    num, den : array_like
        Coefficients in descending powers of s (as from `table2_form`).
    digits : int, optional
        Significant digits per coefficient (default 4, as in Table 2).

    Returns
    -------
    str
        For example ``"(0.000922 s + 0.01539) / (s^2 + 0.5367 s + 6.265)"``. A leading
        denominator coefficient of exactly 1 is not printed.

    Raises
    ------
    ValueError
        If `digits` < 1.
    """
    if digits < 1:
        raise ValueError(f"digits must be >= 1, got {digits}")
    num = np.atleast_1d(np.asarray(num, dtype=float))
    den = np.atleast_1d(np.asarray(den, dtype=float))
    return f"({_format_poly(num, digits, False)}) / ({_format_poly(den, digits, True)})"


def split_channels(sys2x2) -> tuple[control.StateSpace, control.StateSpace]:
    """Lateral and vertical SISO channels of the two-input two-output hose model.

    Parameters
    ----------
    sys2x2 : control.StateSpace or control.TransferFunction
        Inputs [u_hor, u_ver] [N], outputs [P_ny, P_nz] [m].

    Returns
    -------
    lateral : control.StateSpace
        u_hor [N] -> P_ny [m], a minimal realization (`MINREAL_TOL`).
    vertical : control.StateSpace
        u_ver [N] -> P_nz [m], a minimal realization (`MINREAL_TOL`).

    Raises
    ------
    ValueError
        If the system does not have two inputs and two outputs.
    """
    ss = _as_statespace(sys2x2, "sys2x2")
    if ss.ninputs != 2 or ss.noutputs != 2:
        raise ValueError(
            f"split_channels needs inputs [u_hor, u_ver] and outputs [P_ny, P_nz], got "
            f"{ss.noutputs} outputs x {ss.ninputs} inputs"
        )
    channels = []
    for k in range(2):
        sub = control.ss(ss.A, ss.B[:, [k]], ss.C[[k], :], ss.D[[k]][:, [k]])
        channels.append(sub.minreal(MINREAL_TOL))
    return channels[0], channels[1]
