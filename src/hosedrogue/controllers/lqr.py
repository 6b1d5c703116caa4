"""LQR with integral action and a Kalman-filter observer (paper Sec. 3.2.2, Eqs. 34-37).

This is the *integral-action reading* of the paper's LQR, kept as a sensitivity: with the
paper's Q and R it is far slower than Table 3. The reading that reproduces Table 3's lateral
LQR row weighs the balanced states instead, see :mod:`.lqr_balanced` (the default design of
scenarios and of ``hosedrogue design lqr``). The paper's weights `PAPER_LQR_Q`, `PAPER_LQR_R`
are defined here for both readings.

Design model
    The reduced two-channel model x' = A x + B u, y = C x (D = 0): by default the block
    diagonal of the lateral (u_hor [N] -> P_ny [m]) and vertical (u_ver [N] -> P_nz [m])
    2nd-order channels, 4 states (`two_channel_plant`). Any strictly proper two-input
    two-output model can be used.

Integral augmentation (Eq. 34)
    z' = y (z = integral of the offset [m s]); augmented state x_a = [x; z],

        A_a = [[A, 0], [C, 0]],  B_a = [[B], [0]],  C_a = [[C, 0], [0, I]],

    so the augmented outputs are [y; z] = [P_ny, P_nz, z_ny, z_nz].

Regulator (Eqs. 35-37)
    u = -K x_a = -K_x x - K_z z, K from `control.lqr` with state weight Q_x = C_a^T Q C_a and
    input weight R. The paper's weights are `PAPER_LQR_Q` = diag(12000, 8000, 8000, 10000) on
    [P_ny, P_nz, z_ny, z_nz] (units 1/m^2 and 1/(m s)^2) and `PAPER_LQR_R` = diag(0.4, 0.5)
    on [u_hor, u_ver] (1/N^2). The cost depends on y and z only, so K applied to the true state
    does not depend on the realization chosen for the design model.

Observer (documented choice; the paper does not describe one)
    The reduced state x is not measured. It is estimated by the steady-state Kalman filter
    (`control.lqe`) of the design model with
    process noise entering where the control force does (G = B: turbulence and model error
    act on the drogue like a force) of intensity `FORCE_NOISE_PSD` = 100 N^2 s per channel, and
    measurement noise on [P_ny, P_nz] of intensity `POSITION_NOISE_PSD` = 1e-6 m^2 s per
    channel (1 cm rms position noise sampled at 100 Hz: (0.01 m)^2 x 0.01 s). On the paper's
    Table 2 models this puts the observer poles near -9.5 +/- 7.7j rad/s (|s| ~ 12 rad/s),
    about 4 times faster than the fastest regulator pole with the paper's weights.

        x_hat' = A x_hat + B u + L (y - C x_hat),   u = -K_x x_hat - K_z z.

    The controller is driven only by the measured y and by its own force u.

Controller (`LQRDesign.controller`)
    A `LinearController` with state x_c = [x_hat; z] (n + 2), measured offset y [m] in
    (reference 0), force u [N] out:

        A_c = [[A - B K_x - L C, -B K_z], [0, 0]],  B_c = [[L], [I]],
        C_c = [-K_x, -K_z],  D_c = 0.

    Anti-windup gain ``[B; -K_z^+ / T_t]``: when the actuator makes u_a instead of u, the observer
    is driven by u_a and the integrator is conditioned back toward u_a with the tracking time
    T_t = 1 / |Re p|, p the slowest regulator pole (the loop's own time scale).

Reference tracking (`lqr_tracking_closed_loop`)
    For step-response figures the reference r [m] enters only the integrator, z' = y - r.
    Since r does not enter the observer, the estimation error is not excited by r and the
    step response from r equals that of full state feedback on the design model.

What this gives on the paper's Table 2 models with the paper's Q and R (tests record it):
K_x is small (~1 N per unit of the companion-form state) and K_z ~ 141.4 N/(m s) in both
channels (sqrt(q_z / r) to 9 digits: the integral weight dominates), the regulator poles are
-0.209, -0.315, -0.455 +/- 3.088j and -0.609 +/- 2.555j rad/s, and the unit reference steps
have rise / 2 % settling / overshoot of about 6.66 s / 12.5 s / 0 % (lateral) and
10.3 s / 18.7 s / 0 % (vertical), against the paper's 0.839 / 1.49 / 2.24 and
0.671 / 1.45 / 5.07 (Table 3). The paper's numbers are not reproduced. Likely reasons, none
checkable from the text: the paper's reference injection (here r enters only the integrator,
so the y-weighted state feedback pulls y back towards 0 during the step; a servo form with
steady-state feedforward is much faster and overshoots), the output units of the paper's
design model (Q in 1/m^2 here; with the plant gain ~2.5e-3 m/N a 1 m error weighs like a
~170 N force, so control is expensive; scaling Q by 10..1000 still leaves rise times of
2-4 s in this structure), its realization/observer, or a slip in the printed weights.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import control

from ..analysis.reduction import require_siso
from .linear import LinearController, N_FORCES, N_MEASUREMENTS

__all__ = [
    "PAPER_LQR_Q",
    "PAPER_LQR_R",
    "FORCE_NOISE_PSD",
    "POSITION_NOISE_PSD",
    "LQRDesign",
    "two_channel_plant",
    "augment_with_integrator",
    "lqr_integral_design",
    "lqr_tracking_closed_loop",
]

#: Paper Eq. 37: Q = diag(12000, 8000, 8000, 10000). Integral reading: weight on the augmented
#: outputs [P_ny, P_nz, z_ny, z_nz] (1/m^2, 1/(m s)^2); balanced reading (`lqr_balanced`): on the
#: lateral then vertical balanced states (1/(m N)).
PAPER_LQR_Q = np.diag([12000.0, 8000.0, 8000.0, 10000.0])
PAPER_LQR_Q.setflags(write=False)

#: Paper Eq. 37: weight on the forces [u_hor, u_ver] (1/N^2).
PAPER_LQR_R = np.diag([0.4, 0.5])
PAPER_LQR_R.setflags(write=False)

#: Observer design: intensity of the force-like process noise per channel [N^2 s].
FORCE_NOISE_PSD = 100.0

#: Observer design: intensity of the position measurement noise per channel [m^2 s]
#: (1 cm rms sampled at 100 Hz).
POSITION_NOISE_PSD = 1e-6


def two_channel_plant(lateral_siso, vertical_siso) -> control.StateSpace:
    """Block-diagonal two-channel model from the lateral and vertical SISO channels.

    Parameters
    ----------
    lateral_siso : control.TransferFunction or control.StateSpace
        u_hor [N] -> P_ny [m].
    vertical_siso : control.TransferFunction or control.StateSpace
        u_ver [N] -> P_nz [m].

    Returns
    -------
    control.StateSpace
        Inputs [u_hor, u_ver], outputs [P_ny, P_nz]; states: lateral then vertical.
    """
    for name, sys in (("lateral_siso", lateral_siso), ("vertical_siso", vertical_siso)):
        require_siso(name, sys)
    lat = control.ss(lateral_siso)
    ver = control.ss(vertical_siso)
    plant = control.append(lat, ver)
    return control.ss(plant.A, plant.B, plant.C, plant.D,
                      inputs=["u_hor", "u_ver"], outputs=["P_ny", "P_nz"])


def _strictly_proper_2x2(plant, name: str = "plant") -> control.StateSpace:
    ss = control.ss(plant)
    if ss.ninputs != N_FORCES or ss.noutputs != N_MEASUREMENTS:
        raise ValueError(
            f"{name} must have inputs [u_hor, u_ver] and outputs [P_ny, P_nz], got "
            f"{ss.ninputs} inputs and {ss.noutputs} outputs"
        )
    if np.any(ss.D != 0.0):
        raise ValueError(f"{name} must be strictly proper (D = 0) for Eq. 34, got D = {ss.D.tolist()}")
    return ss


def augment_with_integrator(plant) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 34: the design model augmented with the output integrator z' = y.

    Parameters
    ----------
    plant : control.StateSpace or control.TransferFunction
        Strictly proper, inputs [u_hor, u_ver] [N], outputs [P_ny, P_nz] [m], n states.

    Returns
    -------
    A_aug : numpy.ndarray, shape (n + 2, n + 2)
    B_aug : numpy.ndarray, shape (n + 2, 2)
    C_aug : numpy.ndarray, shape (4, n + 2)
        Maps [x; z] to the augmented outputs [P_ny, P_nz, z_ny, z_nz].
    """
    ss = _strictly_proper_2x2(plant)
    n, p, m = ss.nstates, ss.noutputs, ss.ninputs
    A_aug = np.block([[ss.A, np.zeros((n, p))], [ss.C, np.zeros((p, p))]])
    B_aug = np.vstack([ss.B, np.zeros((p, m))])
    C_aug = np.block([[ss.C, np.zeros((p, p))], [np.zeros((p, n)), np.eye(p)]])
    return A_aug, B_aug, C_aug


@dataclass(frozen=True, eq=False)
class LQRDesign:
    """Result of `lqr_integral_design`.

    Attributes
    ----------
    plant : control.StateSpace
        Design model, n states, [u_hor, u_ver] [N] -> [P_ny, P_nz] [m].
    gain_state : numpy.ndarray, shape (2, n)
        K_x, force per design-model state.
    gain_integral : numpy.ndarray, shape (2, 2)
        K_z [N/(m s)], force per integrated offset.
    observer_gain : numpy.ndarray, shape (n, 2)
        Kalman gain L.
    regulator_poles : numpy.ndarray
        Eigenvalues of A_aug - B_aug K [rad/s].
    observer_poles : numpy.ndarray
        Eigenvalues of A - L C [rad/s].
    riccati_solution : numpy.ndarray
        P of Eq. 37 (returned for diagnosis).
    Q, R : numpy.ndarray
        Output and input weights used.
    controller : LinearController
        Observer-based controller y [m] -> u [N], state [x_hat; z].
    """

    plant: control.StateSpace
    gain_state: np.ndarray
    gain_integral: np.ndarray
    observer_gain: np.ndarray
    regulator_poles: np.ndarray
    observer_poles: np.ndarray
    riccati_solution: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    controller: LinearController


def _check_weight(name: str, w, size: int, positive_definite: bool) -> np.ndarray:
    w = np.array(w, dtype=float)
    if w.shape != (size, size):
        raise ValueError(f"{name} must have shape ({size}, {size}), got {w.shape}")
    if not np.allclose(w, w.T, rtol=1e-12, atol=0.0):
        raise ValueError(f"{name} must be symmetric")
    eig = np.linalg.eigvalsh(w)
    if positive_definite and eig.min() <= 0.0:
        raise ValueError(f"{name} must be positive definite, smallest eigenvalue {eig.min()}")
    if not positive_definite and eig.min() < -1e-12 * max(1.0, eig.max()):
        raise ValueError(f"{name} must be positive semi-definite, smallest eigenvalue {eig.min()}")
    return w


def lqr_integral_design(
    plant,
    Q=PAPER_LQR_Q,
    R=PAPER_LQR_R,
    *,
    force_noise_psd: float = FORCE_NOISE_PSD,
    position_noise_psd: float = POSITION_NOISE_PSD,
) -> LQRDesign:
    """LQR with integral action (Eqs. 34-37) and a steady-state Kalman observer.

    Parameters
    ----------
    plant : control.StateSpace or control.TransferFunction
        Strictly proper design model, inputs [u_hor, u_ver] [N], outputs [P_ny, P_nz] [m]
        (e.g. `two_channel_plant` of the 2nd-order channels).
    Q : array_like, shape (4, 4)
        Weight on [P_ny, P_nz, z_ny, z_nz], symmetric positive semi-definite. Default: paper.
    R : array_like, shape (2, 2)
        Weight on [u_hor, u_ver], symmetric positive definite. Default: paper.
    force_noise_psd : float, optional
        Observer process-noise intensity per channel, entering through B [N^2 s], > 0.
    position_noise_psd : float, optional
        Observer measurement-noise intensity per channel [m^2 s], > 0.

    Returns
    -------
    LQRDesign

    Raises
    ------
    ValueError
        For wrong shapes, non-definite weights, non-positive noise intensities, or a plant
        that is not strictly proper two-input two-output.
    """
    ss = _strictly_proper_2x2(plant)
    Q = _check_weight("Q", Q, 2 * N_MEASUREMENTS, positive_definite=False)
    R = _check_weight("R", R, N_FORCES, positive_definite=True)
    if not force_noise_psd > 0.0:
        raise ValueError(f"force_noise_psd must be > 0 [N^2 s], got {force_noise_psd}")
    if not position_noise_psd > 0.0:
        raise ValueError(f"position_noise_psd must be > 0 [m^2 s], got {position_noise_psd}")

    n = ss.nstates
    A_aug, B_aug, C_aug = augment_with_integrator(ss)
    Q_x = C_aug.T @ Q @ C_aug
    Q_x = 0.5 * (Q_x + Q_x.T)  # exact symmetry, required by the Riccati solver
    K, P, reg_poles = control.lqr(A_aug, B_aug, Q_x, R)
    K = np.asarray(K)
    K_x, K_z = K[:, :n], K[:, n:]

    L, _, obs_poles = control.lqe(
        ss.A, ss.B, ss.C,
        force_noise_psd * np.eye(N_FORCES),
        position_noise_psd * np.eye(N_MEASUREMENTS),
    )
    L = np.asarray(L)

    p = N_MEASUREMENTS
    A_c = np.block([
        [ss.A - ss.B @ K_x - L @ ss.C, -ss.B @ K_z],
        [np.zeros((p, n)), np.zeros((p, p))],
    ])
    B_c = np.vstack([L, np.eye(p)])
    C_c = np.hstack([-K_x, -K_z])
    # anti-windup: the observer sees the force made, u_a; the integrator is conditioned back toward
    # it within the closed loop's slowest time constant (docstring, "Controller")
    t_track = 1.0 / float(np.min(np.abs(np.real(np.asarray(reg_poles)))))
    aw = np.vstack([ss.B, -np.linalg.pinv(K_z) / t_track])
    controller = LinearController(A=A_c, B=B_c, C=C_c, D=np.zeros((N_FORCES, p)), anti_windup=aw)
    return LQRDesign(
        plant=ss,
        gain_state=K_x,
        gain_integral=K_z,
        observer_gain=L,
        regulator_poles=np.asarray(reg_poles),
        observer_poles=np.asarray(obs_poles),
        riccati_solution=np.asarray(P),
        Q=Q,
        R=R,
        controller=controller,
    )


def lqr_tracking_closed_loop(design: LQRDesign, plant=None) -> control.StateSpace:
    """Closed loop for reference steps: the reference enters the integrator, z' = y - r.

    Parameters
    ----------
    design : LQRDesign
        The controller design.
    plant : control.StateSpace or control.TransferFunction, optional
        Strictly proper plant to close the loop around (e.g. a higher-order model);
        default: the design model.

    Returns
    -------
    control.StateSpace
        Inputs [r_ny, r_nz] [m]; outputs [P_ny, P_nz] [m] and [u_hor, u_ver] [N];
        states [plant x; observer x_hat; integrator z].
    """
    g = design.plant if plant is None else _strictly_proper_2x2(plant)
    A, B, C = design.plant.A, design.plant.B, design.plant.C
    K_x, K_z, L = design.gain_state, design.gain_integral, design.observer_gain
    ng, n, p = g.nstates, A.shape[0], N_MEASUREMENTS
    # u = -K_x x_hat - K_z z
    A_cl = np.block([
        [g.A, -g.B @ K_x, -g.B @ K_z],
        [L @ g.C, A - B @ K_x - L @ C, -B @ K_z],
        [g.C, np.zeros((p, n)), np.zeros((p, p))],
    ])
    B_cl = np.vstack([np.zeros((ng, p)), np.zeros((n, p)), -np.eye(p)])
    C_cl = np.vstack([
        np.hstack([g.C, np.zeros((p, n)), np.zeros((p, p))]),
        np.hstack([np.zeros((N_FORCES, ng)), -K_x, -K_z]),
    ])
    D_cl = np.zeros((p + N_FORCES, p))
    return control.ss(A_cl, B_cl, C_cl, D_cl,
                      inputs=["r_ny", "r_nz"], outputs=["P_ny", "P_nz", "u_hor", "u_ver"])
