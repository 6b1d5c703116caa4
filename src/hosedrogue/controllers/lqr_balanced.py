"""The paper's LQR (Sec. 3.2.2, Eqs. 35-37) read as a regulator of the balanced states.

This is the reading that reproduces the paper's Table 3 lateral LQR row (see
docs/paper-differences.md); the integral-action reading of Eq. 34 is in :mod:`.lqr`.

Design model
    Each channel's reduced model (lateral u_hor [N] -> P_ny [m], vertical u_ver [N] -> P_nz [m];
    the paper's Table 2 2nd-order models or this project's balanced truncation) is brought to its
    *balanced realization* (`balanced_realization`): controllability and observability Gramians
    equal and diagonal, diag(sigma_1, ..., sigma_n), the Hankel singular values [m/N]. A balanced
    state has the unit sqrt(m N), so a weight on it is in 1/(m N).

Weights
    The paper's Q = diag(12000, 8000, 8000, 10000) and R = diag(0.4, 0.5) (`PAPER_LQR_Q`,
    `PAPER_LQR_R`) are split per channel: lateral Q = diag(12000, 8000) on its two balanced
    states and R = 0.4 [1/N^2]; vertical Q = diag(8000, 10000), R = 0.5. For a design model of
    order n per channel, Q is a 2n diagonal: the lateral states, then the vertical ones.

Regulator
    u = -K x_b per channel, K = R^-1 B_b^T P from the algebraic Riccati equation (Eq. 37 with the
    state weight Q, `control.lqr`).

Sign of the balanced states
    A balanced realization is unique only up to the sign of each state (for distinct Hankel
    singular values): x_b -> S x_b with S = diag(+-1) is balanced too. A diagonal Q is invariant,
    S Q S = Q, so the Riccati solution becomes S P S, the gain K S, and the control law
    u = -K S (S x_b) = -K x_b is unchanged; the same holds for the observer below. The gain in
    any fixed coordinates (`BalancedLQRChannel.gain_original`, the controller's y -> u transfer
    function) therefore does not depend on the sign choice; a test flips the signs to check it.
    A non-diagonal Q would not have this property. `balanced_realization` fixes the signs so that
    every entry of B_b is >= 0, to make printed gains reproducible.

Reference steps (Table 3, Fig. 10)
    A static prefilter N = 1 / (C_b (B_b K - A_b)^-1 B_b) per channel gives the reference loop
    u = -K x_b + N r unit DC gain (`lqr_balanced_reference_loop`). The reference enters through u,
    which the observer also sees, so the estimation error is not excited by r: on the design model
    the step response equals that of full state feedback.

Observer (a documented choice; the paper only writes x-hat in Eq. 36)
    The balanced state is not measured. It is estimated per channel by the steady-state Kalman
    filter of the balanced design model,

        x_hat' = A_b x_hat + B_b u + L (y - C_b x_hat),

    with process noise entering where the control force does (turbulence and model error act
    on the drogue like a force) of intensity `TURBULENCE_FORCE_PSD` = 1e4 N^2 s, and measurement
    noise of intensity `POSITION_NOISE_PSD` = 1e-6 m^2 s (1 cm rms sampled at 100 Hz). The
    process intensity is the order of the gust force: at 150 m/s a 1.5 m/s rms gust changes the
    drogue's 1230 N drag by about 2 x 1230 x 1.5 / 150 = 25 N rms, correlated over
    L/V = 530 m / 150 m/s = 3.5 s, i.e. a white-noise intensity of about
    2 x 25^2 x 3.5 = 4.4e3 N^2 s; 1e4 allows for the gust load on the hose itself. The observer
    poles this gives (recorded by the tests):

    * paper Table 2 models: lateral -90.6, -17.0, vertical -79.7, -18.1 rad/s, against the
      regulator's -11.8, -2.69 and -6.69, -4.44 rad/s;
    * this project's 2nd-order models at 150 m/s, 8000 m: lateral -34.3 +- 24.0j, vertical
      -39.1 +- 3.6j rad/s, against the regulator's -16.8, -1.57 and -11.2, -2.11 rad/s.

    A slower observer (intensity 100 N^2 s, poles near 12 rad/s) cuts the turbulence peak in the
    nonlinear closed loop only 10x / 7x (lateral / vertical); 1e4 gives 20x / 12x, and 1e5 no more
    than 24x / 14x, where the 2nd-order design model's own error dominates.

Controller for the nonlinear loop (`BalancedLQRDesign.controller`)
    One `LinearController` of 2n states [x_hat_lat; x_hat_ver], measured offset y [m] in, force
    u [N] out, reference 0 (regulation about the balance position, no prefilter):

        A_c = A_b - B_b K - L C_b,  B_c = L,  C_c = -K,  D_c = 0

    (block diagonal over the channels). Its anti-windup gain is B_b: when the actuator makes u_a
    instead of the command u (a drogue's surfaces saturated), the observer is driven by u_a,
    ``x_hat' = A_b x_hat + B_b u_a + L (y - C_b x_hat)``, so it keeps estimating the plant.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import control
from scipy.linalg import solve_continuous_are

from .linear import LinearController, N_FORCES, N_MEASUREMENTS
from .lqr import PAPER_LQR_Q, PAPER_LQR_R, POSITION_NOISE_PSD

__all__ = [
    "TURBULENCE_FORCE_PSD",
    "balanced_realization",
    "BalancedLQRChannel",
    "BalancedLQRDesign",
    "lqr_balanced_channel",
    "lqr_balanced_design",
    "lqr_balanced_reference_loop",
]

#: Observer design: intensity of the force-like process noise per channel [N^2 s] (gust load,
#: see the module docstring).
TURBULENCE_FORCE_PSD = 1e4


def _siso_ss(sys, name: str) -> control.StateSpace:
    if sys.ninputs != 1 or sys.noutputs != 1:
        raise ValueError(f"{name} must be SISO, got {sys.noutputs} outputs x {sys.ninputs} inputs")
    ss = control.ss(sys)
    if np.any(ss.D != 0.0):
        raise ValueError(f"{name} must be strictly proper (D = 0), got D = {ss.D.tolist()}")
    if ss.nstates == 0 or np.any(np.linalg.eigvals(ss.A).real >= 0.0):
        raise ValueError(f"{name} must be stable with at least one state for a balanced realization")
    return ss


def balanced_realization(sys, signs=None) -> tuple[control.StateSpace, np.ndarray, np.ndarray]:
    """Balanced realization of a stable SISO system (square-root method).

    Parameters
    ----------
    sys : control.StateSpace or control.TransferFunction
        Stable, strictly proper, force [N] -> offset [m], n states (any realization).
    signs : array_like of {+1, -1}, shape (n,), optional
        Extra sign of each balanced state, applied after the default convention (every entry of
        B_b >= 0). For testing that designs do not depend on the sign choice.

    Returns
    -------
    balanced : control.StateSpace
        (A_b, B_b, C_b, 0) with both Gramians equal to diag(hsv); states in sqrt(m N).
    T : numpy.ndarray, shape (n, n)
        Transformation x_b = T x from the states of ``control.ss(sys)``.
    hsv : numpy.ndarray, shape (n,)
        Hankel singular values [m/N], decreasing.

    Raises
    ------
    ValueError
        If the system is not SISO, not strictly proper, unstable, or has a zero Hankel singular
        value (not minimal).
    """
    ss = _siso_ss(sys, "sys")
    n = ss.nstates
    wc = control.gram(ss, "c")
    wo = control.gram(ss, "o")
    lc = np.linalg.cholesky(0.5 * (wc + wc.T))
    lo = np.linalg.cholesky(0.5 * (wo + wo.T))
    u, hsv, vt = np.linalg.svd(lo.T @ lc)
    if hsv[-1] <= 1e-12 * hsv[0]:
        raise ValueError(f"sys is not minimal: Hankel singular values {hsv}")
    s_half = np.diag(hsv**-0.5)
    T = s_half @ u.T @ lo.T
    T_inv = lc @ vt.T @ s_half
    b = T @ ss.B
    sign = np.where(b[:, 0] < 0.0, -1.0, 1.0)
    if signs is not None:
        extra = np.asarray(signs, dtype=float).reshape(-1)
        if extra.shape != (n,) or not np.all(np.abs(extra) == 1.0):
            raise ValueError(f"signs must be {n} values of +1 or -1, got {signs!r}")
        sign = sign * extra
    T = sign[:, None] * T
    T_inv = T_inv * sign[None, :]
    balanced = control.ss(T @ ss.A @ T_inv, T @ ss.B, ss.C @ T_inv, np.zeros((1, 1)))
    return balanced, T, hsv


@dataclass(frozen=True, eq=False)
class BalancedLQRChannel:
    """One channel of the balanced-state LQR.

    Attributes
    ----------
    balanced : control.StateSpace
        Balanced design model (A_b, B_b, C_b), force [N] -> offset [m].
    transform : numpy.ndarray, shape (n, n)
        x_b = T x from the states of the given realization.
    hsv : numpy.ndarray, shape (n,)
        Hankel singular values [m/N].
    Q : numpy.ndarray, shape (n, n)
        Weight on the balanced states [1/(m N)].
    R : float
        Weight on the force [1/N^2].
    gain : numpy.ndarray, shape (1, n)
        K on the balanced states [sqrt(N/m)].
    gain_original : numpy.ndarray, shape (1, n)
        K T, the same law on the given realization's states (sign-choice independent).
    prefilter : float
        N [N/m], unit DC gain from the reference r [m] to the offset.
    observer_gain : numpy.ndarray, shape (n, 1)
        Kalman gain L [sqrt(m N)/(m s)].
    regulator_poles : numpy.ndarray
        Eigenvalues of A_b - B_b K [rad/s].
    observer_poles : numpy.ndarray
        Eigenvalues of A_b - L C_b [rad/s].
    """

    balanced: control.StateSpace
    transform: np.ndarray
    hsv: np.ndarray
    Q: np.ndarray
    R: float
    gain: np.ndarray
    gain_original: np.ndarray
    prefilter: float
    observer_gain: np.ndarray
    regulator_poles: np.ndarray
    observer_poles: np.ndarray


def lqr_balanced_channel(
    plant_siso,
    q_diag,
    r: float,
    *,
    force_noise_psd: float = TURBULENCE_FORCE_PSD,
    position_noise_psd: float = POSITION_NOISE_PSD,
    signs=None,
) -> BalancedLQRChannel:
    """Balanced-state LQR and Kalman observer for one channel.

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        Stable strictly proper design model, force [N] -> offset [m], n states.
    q_diag : array_like, shape (n,)
        Diagonal of Q on the balanced states [1/(m N)], each >= 0 (all zero: K = 0, the
        stable plant left alone).
    r : float
        Weight on the force [1/N^2], > 0.
    force_noise_psd : float, optional
        Observer process-noise intensity entering through B [N^2 s], > 0.
    position_noise_psd : float, optional
        Observer measurement-noise intensity [m^2 s], > 0.
    signs : array_like of {+1, -1}, optional
        Passed to `balanced_realization` (tests of sign independence).

    Returns
    -------
    BalancedLQRChannel

    Raises
    ------
    ValueError
        For a plant `balanced_realization` rejects, weights of the wrong size or sign, or
        non-positive noise intensities.
    """
    balanced, T, hsv = balanced_realization(plant_siso, signs)
    n = balanced.nstates
    q = np.asarray(q_diag, dtype=float).reshape(-1)
    if q.shape != (n,) or not np.all(np.isfinite(q)) or np.any(q < 0.0):
        raise ValueError(f"q_diag must be {n} finite values >= 0, got {q_diag!r}")
    r = float(r)
    if not (np.isfinite(r) and r > 0.0):
        raise ValueError(f"r must be finite and > 0 [1/N^2], got {r}")
    if not force_noise_psd > 0.0:
        raise ValueError(f"force_noise_psd must be > 0 [N^2 s], got {force_noise_psd}")
    if not position_noise_psd > 0.0:
        raise ValueError(f"position_noise_psd must be > 0 [m^2 s], got {position_noise_psd}")
    A, B, C = balanced.A, balanced.B, balanced.C
    Q = np.diag(q)
    K, _, reg_poles = control.lqr(A, B, Q, np.array([[r]]))
    K = np.asarray(K)
    A_cl = A - B @ K
    prefilter = float(1.0 / (C @ np.linalg.solve(-A_cl, B))[0, 0])
    # Steady-state Kalman filter, the dual Riccati equation (scipy; G W G^T symmetrized exactly).
    W = force_noise_psd * (B @ B.T)
    W = 0.5 * (W + W.T)
    V = np.array([[float(position_noise_psd)]])
    P = solve_continuous_are(A.T, C.T, W, V)
    L = P @ C.T / V[0, 0]
    return BalancedLQRChannel(
        balanced=balanced,
        transform=T,
        hsv=hsv,
        Q=Q,
        R=r,
        gain=K,
        gain_original=K @ T,
        prefilter=prefilter,
        observer_gain=L,
        regulator_poles=np.asarray(reg_poles),
        observer_poles=np.linalg.eigvals(A - L @ C),
    )


@dataclass(frozen=True, eq=False)
class BalancedLQRDesign:
    """Two-channel balanced-state LQR with observers.

    Attributes
    ----------
    lateral, vertical : BalancedLQRChannel
        The channel designs (u_hor -> P_ny, u_ver -> P_nz).
    plant : control.StateSpace
        Block-diagonal balanced design model, [u_hor, u_ver] [N] -> [P_ny, P_nz] [m], states
        lateral then vertical.
    gain : numpy.ndarray, shape (2, 2n)
        Block-diagonal K on the balanced states.
    observer_gain : numpy.ndarray, shape (2n, 2)
        Block-diagonal L.
    prefilter : numpy.ndarray, shape (2, 2)
        diag(N_lat, N_ver) [N/m].
    controller : LinearController
        Observer-based regulator y [m] -> u [N] for the closed loop (reference 0).
    """

    lateral: BalancedLQRChannel
    vertical: BalancedLQRChannel
    plant: control.StateSpace
    gain: np.ndarray
    observer_gain: np.ndarray
    prefilter: np.ndarray
    controller: LinearController

    @property
    def regulator_poles(self) -> np.ndarray:
        """Regulator poles of both channels [rad/s]."""
        return np.concatenate([self.lateral.regulator_poles, self.vertical.regulator_poles])

    @property
    def observer_poles(self) -> np.ndarray:
        """Observer poles of both channels [rad/s]."""
        return np.concatenate([self.lateral.observer_poles, self.vertical.observer_poles])


def _block_diag(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0] + b.shape[0], a.shape[1] + b.shape[1]))
    out[: a.shape[0], : a.shape[1]] = a
    out[a.shape[0]:, a.shape[1]:] = b
    return out


def lqr_balanced_design(
    lateral_siso,
    vertical_siso,
    Q=PAPER_LQR_Q,
    R=PAPER_LQR_R,
    *,
    force_noise_psd: float = TURBULENCE_FORCE_PSD,
    position_noise_psd: float = POSITION_NOISE_PSD,
    signs=None,
) -> BalancedLQRDesign:
    """The paper's LQR on the balanced states of each channel, with Kalman observers.

    Parameters
    ----------
    lateral_siso, vertical_siso : control.TransferFunction or control.StateSpace
        Stable strictly proper design models, u_hor [N] -> P_ny [m] and u_ver [N] -> P_nz [m],
        n_lat and n_ver states (2 and 2 for the paper's design model).
    Q : array_like, shape (n_lat + n_ver, n_lat + n_ver)
        Diagonal weight on [lateral balanced states, vertical balanced states] [1/(m N)].
        Default: the paper's diag(12000, 8000, 8000, 10000). Off-diagonal entries are rejected
        (the design would depend on the balanced states' signs).
    R : array_like, shape (2, 2)
        Diagonal weight on [u_hor, u_ver] [1/N^2]. Default: the paper's diag(0.4, 0.5).
    force_noise_psd, position_noise_psd : float, optional
        Observer noise intensities [N^2 s], [m^2 s] (see the module docstring).
    signs : tuple of two array_like, optional
        Extra signs of the lateral and vertical balanced states (tests).

    Returns
    -------
    BalancedLQRDesign

    Raises
    ------
    ValueError
        For non-diagonal or mis-sized weights, or channels `balanced_realization` rejects.
    """
    lat = control.ss(lateral_siso)
    ver = control.ss(vertical_siso)
    n_lat, n_ver = lat.nstates, ver.nstates
    Q = np.array(Q, dtype=float)
    R = np.array(R, dtype=float)
    nq = n_lat + n_ver
    if Q.shape != (nq, nq):
        raise ValueError(f"Q must have shape ({nq}, {nq}) for design models of {n_lat} + {n_ver} states, got {Q.shape}")
    if R.shape != (N_FORCES, N_FORCES):
        raise ValueError(f"R must have shape (2, 2), got {R.shape}")
    for name, w in (("Q", Q), ("R", R)):
        if np.any(w != np.diag(np.diag(w))):
            raise ValueError(f"{name} must be diagonal (a balanced state's sign is arbitrary)")
    signs = (None, None) if signs is None else signs
    kw = dict(force_noise_psd=force_noise_psd, position_noise_psd=position_noise_psd)
    ch_lat = lqr_balanced_channel(lat, np.diag(Q)[:n_lat], R[0, 0], signs=signs[0], **kw)
    ch_ver = lqr_balanced_channel(ver, np.diag(Q)[n_lat:], R[1, 1], signs=signs[1], **kw)
    A = _block_diag(ch_lat.balanced.A, ch_ver.balanced.A)
    B = _block_diag(ch_lat.balanced.B, ch_ver.balanced.B)
    C = _block_diag(ch_lat.balanced.C, ch_ver.balanced.C)
    K = _block_diag(ch_lat.gain, ch_ver.gain)
    L = _block_diag(ch_lat.observer_gain, ch_ver.observer_gain)
    plant = control.ss(A, B, C, np.zeros((N_MEASUREMENTS, N_FORCES)),
                       inputs=["u_hor", "u_ver"], outputs=["P_ny", "P_nz"])
    # anti-windup: the observer sees the force the actuator makes (x_hat' gains B (u_a - u))
    controller = LinearController(A=A - B @ K - L @ C, B=L, C=-K, D=np.zeros((N_FORCES, N_MEASUREMENTS)),
                                  anti_windup=B)
    return BalancedLQRDesign(
        lateral=ch_lat,
        vertical=ch_ver,
        plant=plant,
        gain=K,
        observer_gain=L,
        prefilter=np.diag([ch_lat.prefilter, ch_ver.prefilter]),
        controller=controller,
    )


def lqr_balanced_reference_loop(design: BalancedLQRDesign, plant=None) -> control.StateSpace:
    """Closed loop for reference steps: u = -K x_hat + N r, observer driven by y and u.

    Parameters
    ----------
    design : BalancedLQRDesign
        The controller.
    plant : control.StateSpace or control.TransferFunction, optional
        Strictly proper plant, [u_hor, u_ver] [N] -> [P_ny, P_nz] [m], any order (e.g. the
        6th-order or full linear model); default the balanced design model.

    Returns
    -------
    control.StateSpace
        Inputs [r_ny, r_nz] [m]; outputs [P_ny, P_nz] [m] and [u_hor, u_ver] [N]; states
        [plant x; observer x_hat].
    """
    g = design.plant if plant is None else control.ss(plant)
    if g.ninputs != N_FORCES or g.noutputs != N_MEASUREMENTS or np.any(g.D != 0.0):
        raise ValueError("plant must be strictly proper with inputs [u_hor, u_ver] and outputs [P_ny, P_nz]")
    A, B, C = design.plant.A, design.plant.B, design.plant.C
    K, L, N = design.gain, design.observer_gain, design.prefilter
    ng, n, p = g.nstates, A.shape[0], N_MEASUREMENTS
    A_cl = np.block([
        [g.A, -g.B @ K],
        [L @ g.C, A - B @ K - L @ C],
    ])
    B_cl = np.vstack([g.B @ N, B @ N])
    C_cl = np.vstack([
        np.hstack([g.C, np.zeros((p, n))]),
        np.hstack([np.zeros((N_FORCES, ng)), -K]),
    ])
    D_cl = np.vstack([np.zeros((p, p)), N])
    return control.ss(A_cl, B_cl, C_cl, D_cl,
                      inputs=["r_ny", "r_nz"], outputs=["P_ny", "P_nz", "u_hor", "u_ver"])
