"""PID control of the drogue position, one loop per channel (paper Sec. 3.2.1, Eq. 33).

Each channel uses the parallel PID with a first-order filter on the derivative term,

    C(s) = K_P + K_I / s + K_D N s / (s + N),

acting on the error e = r - y, r = 0 (the equilibrium) in closed loop, so the applied force is
u = -C(s) y. `pid_controller` returns the diagonal two-channel controller as a
`LinearController` (lateral: P_ny -> u_hor, vertical: P_nz -> u_ver) with the sign inside.

Realization used by `pid_controller`, per channel (state order [integrator, filter]):
C(s) = (K_P + K_D N) + K_I / s - K_D N^2 / (s + N), i.e. x_i' = y, x_f' = -N x_f + y,
u = -(K_I x_i - K_D N^2 x_f + (K_P + K_D N) y). A state is omitted when its gain is zero
(K_I = 0 or K_D = 0), so the realization is minimal.

`tune_pid` is a loop-shaping design (see its docstring): it places the gain crossover of
L(s) = C(s) G(s) at a requested frequency with a requested phase margin, solving for the
gains from the plant's frequency response at that frequency.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import control
from scipy.optimize import brentq, minimize_scalar

from ..analysis.reduction import require_siso
from .linear import LinearController

__all__ = ["PIDGains", "PAPER_PID", "pid_controller", "tune_pid", "tracking_time_s"]


def _check_gain(name: str, value: float, positive: bool) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0.0 or (positive and value == 0.0):
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"PIDGains.{name} must be finite and {bound}, got {value}")
    return value


@dataclass(frozen=True)
class PIDGains:
    """Gains of one channel's PID, Eq. 33: K_P + K_I/s + K_D N s/(s + N).

    Parameters
    ----------
    kp : float
        Proportional gain K_P [N/m], >= 0.
    ki : float
        Integral gain K_I [N/(m s)], >= 0.
    kd : float
        Derivative gain K_D [N s/m], >= 0.
    n_filter : float
        Derivative filter bandwidth N [rad/s], > 0.
    """

    kp: float
    ki: float
    kd: float
    n_filter: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "kp", _check_gain("kp", self.kp, positive=False))
        object.__setattr__(self, "ki", _check_gain("ki", self.ki, positive=False))
        object.__setattr__(self, "kd", _check_gain("kd", self.kd, positive=False))
        object.__setattr__(self, "n_filter", _check_gain("n_filter", self.n_filter, positive=True))

    def transfer_function(self) -> control.TransferFunction:
        """C(s) as one rational function, error [m] -> force [N].

        Returns
        -------
        control.TransferFunction
            ((K_P + K_D N) s^2 + (K_P N + K_I) s + K_I N) / (s^2 + N s).
        """
        kp, ki, kd, n = self.kp, self.ki, self.kd, self.n_filter
        return control.tf([kp + kd * n, kp * n + ki, ki * n], [1.0, n, 0.0])

    def frequency_response(self, omega_rad_s) -> np.ndarray:
        """C(j omega) [N/m] at angular frequencies `omega_rad_s` [rad/s]."""
        s = 1j * np.asarray(omega_rad_s, dtype=float)
        return self.kp + self.ki / s + self.kd * self.n_filter * s / (s + self.n_filter)


#: The paper's PID gains (Sec. 3.2.1, below Eq. 33), designed on the Table 2 2nd-order models.
PAPER_PID: dict[str, PIDGains] = {
    "lateral": PIDGains(kp=10787.14, ki=10476.72, kd=1854.79, n_filter=105.76),
    "vertical": PIDGains(kp=10603.98, ki=10671.05, kd=1509.66, n_filter=79.37),
}


def _channel_blocks(g: PIDGains) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, np.ndarray]:
    """Positive-form realization (A, B, C, D) of C(s) for one channel, and its anti-windup gain
    (:func:`tracking_time_s`) on the integrator."""
    a, b, c, aw = [], [], [], []
    if g.ki > 0.0:
        a.append(0.0)
        b.append(1.0)
        c.append(g.ki)
        aw.append(-1.0 / (g.ki * tracking_time_s(g)))
    if g.kd > 0.0:
        a.append(-g.n_filter)
        b.append(1.0)
        c.append(-g.kd * g.n_filter**2)
        aw.append(0.0)
    d = g.kp + g.kd * g.n_filter
    return np.diag(a), np.array(b), np.array(c), d, np.array(aw)


def tracking_time_s(g: PIDGains) -> float:
    """Tracking time T_t [s] of the PID's back-calculation anti-windup: ``sqrt(T_i T_d) =
    sqrt(K_D / K_I)``, or ``T_i = K_P / K_I`` without derivative action (Astrom and Hagglund's rule;
    0.42 s lateral and 0.38 s vertical for the paper's gains).

    While the actuator makes u_a instead of the command u, the integrator state gains
    ``-(u_a - u) / (K_I T_t)``, so the command returns toward u_a with time constant T_t.

    Parameters
    ----------
    g : PIDGains
        The channel's gains (``ki > 0``).

    Returns
    -------
    float
    """
    if g.kd > 0.0:
        return math.sqrt(g.kd / g.ki)
    return g.kp / g.ki if g.kp > 0.0 else 1.0 / g.ki


def pid_controller(lateral: PIDGains, vertical: PIDGains) -> LinearController:
    """Diagonal two-channel PID acting on the measured offset: u = -diag(C_lat, C_ver) y.

    Parameters
    ----------
    lateral : PIDGains
        P_ny [m] -> u_hor [N].
    vertical : PIDGains
        P_nz [m] -> u_ver [N].

    Returns
    -------
    LinearController
        States [lateral integrator, lateral filter, vertical integrator, vertical filter]
        (a state is left out when its gain is zero); integrator states in m s, filter states
        in m s. Its ``anti_windup`` is the back-calculation on each integrator
        (:func:`tracking_time_s`).
    """
    blocks = [_channel_blocks(lateral), _channel_blocks(vertical)]
    sizes = [blk[0].shape[0] for blk in blocks]
    nc = sum(sizes)
    A = np.zeros((nc, nc))
    B = np.zeros((nc, 2))
    C = np.zeros((2, nc))
    D = np.zeros((2, 2))
    AW = np.zeros((nc, 2))
    start = 0
    for k, (a, b, c, d, aw) in enumerate(blocks):
        sl = slice(start, start + sizes[k])
        A[sl, sl] = a
        B[sl, k] = b
        C[k, sl] = -c
        D[k, k] = -d
        AW[sl, k] = aw
        start += sizes[k]
    return LinearController(A=A, B=B, C=C, D=D, anti_windup=AW)


def _pid_shape(x: np.ndarray | float, ti_over_td: float, n_td: float) -> np.ndarray:
    """C(j w) / K_P as a function of x = w T_d, for T_i = ti_over_td T_d and N = n_td / T_d."""
    jx = 1j * np.asarray(x, dtype=float)
    return 1.0 + 1.0 / (ti_over_td * jx) + n_td * jx / (jx + n_td)


def tune_pid(
    plant_siso,
    crossover_rad_s: float,
    phase_margin_deg: float,
    *,
    ti_over_td: float = 4.0,
    n_td: float = 10.0,
    branch: str = "high",
) -> PIDGains:
    """PID gains that put the loop's gain crossover and phase margin where requested.

    Method (loop shaping at one frequency). Write C(s) = K_P (1 + 1/(T_i s) + T_d s N/(s + N))
    (so K_I = K_P / T_i, K_D = K_P T_d) with the two shape ratios fixed: T_i = `ti_over_td` T_d
    and N = `n_td` / T_d. Then C(j w_c) / K_P depends on x = w_c T_d only. Its phase rises from
    -90 deg (x -> 0, integral action dominates) to a maximum lead phi_max at some x_peak and
    falls back towards 0 deg as x -> infinity (derivative action, limited by the filter,
    dominates). The required controller phase at the crossover is

        phi_C = -180 deg + phase_margin - arg G(j w_c)   (wrapped to [-180, 180) deg),

    solved for x by bisection (`scipy.optimize.brentq`) on one branch:

    - ``branch="high"`` (default): x > x_peak, possible when 0 < phi_C < phi_max. The
      derivative term supplies the phase and the integral action is weak at w_c. The paper's
      PID gains lie on this branch (their x = w_c T_d is about 27.5 lateral and 10.8 vertical,
      beyond the phase peak of their shape), and the designs are well damped.
    - ``branch="low"``: x < x_peak, possible when -90 deg < phi_C < phi_max. Less
      high-frequency gain, but the integral action is strong at w_c; on the hose channels this
      typically gives conditionally stable loops (gain margin below 1) with large overshoot.

    Then K_P = 1 / |G(j w_c) C(j w_c)/K_P| makes |L(j w_c)| = 1. Finally the closed loop is
    checked for stability.

    The result has |L(j w_c)| = 1 and arg L(j w_c) = -180 deg + phase margin exactly; whether
    w_c is the only gain crossover depends on the plant (a lightly damped resonance above w_c
    can create others), so check the design with `control.stability_margins`.

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        G(s), force [N] -> offset [m].
    crossover_rad_s : float
        Requested gain-crossover frequency w_c [rad/s], > 0.
    phase_margin_deg : float
        Requested phase margin [deg], in (0, 180).
    ti_over_td : float, optional
        Ratio T_i / T_d (default 4, the classical Ziegler-Nichols ratio), > 0.
    n_td : float, optional
        N T_d, the derivative filter pole relative to 1/T_d (default 10), > 0.
    branch : {"high", "low"}, optional
        Which solution for x = w_c T_d to take (see above). Default "high".

    Returns
    -------
    PIDGains

    Raises
    ------
    ValueError
        If an argument is out of range, the plant is not SISO, the required controller phase
        is outside what this PID shape can give on the chosen branch at w_c (the message
        states the achievable range), or the resulting closed loop is unstable.
    """
    require_siso("plant_siso", plant_siso)
    if not (math.isfinite(crossover_rad_s) and crossover_rad_s > 0.0):
        raise ValueError(f"crossover_rad_s must be finite and > 0, got {crossover_rad_s}")
    if not 0.0 < phase_margin_deg < 180.0:
        raise ValueError(f"phase_margin_deg must be in (0, 180), got {phase_margin_deg}")
    if not ti_over_td > 0.0:
        raise ValueError(f"ti_over_td must be > 0, got {ti_over_td}")
    if not n_td > 0.0:
        raise ValueError(f"n_td must be > 0, got {n_td}")

    w = float(crossover_rad_s)
    g_jw = complex(np.squeeze(plant_siso(1j * w)))
    if g_jw == 0.0:
        raise ValueError(f"plant gain is zero at crossover_rad_s={w}")
    phi_c = -math.pi + math.radians(phase_margin_deg) - np.angle(g_jw)
    phi_c = (phi_c + math.pi) % (2.0 * math.pi) - math.pi  # wrap to [-pi, pi)

    def phase(x: float) -> float:
        return float(np.angle(_pid_shape(x, ti_over_td, n_td)))

    # Phase peak of the shape, searched on a log scale of x.
    res = minimize_scalar(lambda lx: -phase(10.0**lx), bounds=(-6.0, 6.0), method="bounded")
    x_peak, phi_max = 10.0**res.x, -res.fun
    if branch == "low":
        x_lo, x_hi = 1e-9, x_peak
    elif branch == "high":
        x_lo, x_hi = x_peak, 1e9
    else:
        raise ValueError(f"branch must be 'high' or 'low', got {branch!r}")
    phi_lo, phi_hi = sorted((phase(x_lo), phase(x_hi)))
    if not phi_lo < phi_c < phi_hi:
        raise ValueError(
            f"the PID shape (Ti/Td={ti_over_td}, N Td={n_td}) gives a phase between "
            f"{math.degrees(phi_lo):.1f} and {math.degrees(phi_hi):.1f} deg on the {branch!r} branch, "
            f"but {math.degrees(phi_c):.1f} deg is needed at {w} rad/s for a {phase_margin_deg} deg "
            f"phase margin; change the crossover, margin, shape ratios or branch"
        )
    x = brentq(lambda xx: phase(xx) - phi_c, x_lo, x_hi, xtol=1e-14, rtol=1e-13)
    kp = 1.0 / (abs(g_jw) * abs(complex(_pid_shape(x, ti_over_td, n_td))))
    td = x / w
    gains = PIDGains(kp=kp, ki=kp / (ti_over_td * td), kd=kp * td, n_filter=n_td / td)

    loop = control.feedback(control.series(gains.transfer_function(), plant_siso), 1)
    poles = loop.poles()
    if np.any(np.real(poles) >= 0.0):
        raise ValueError(
            f"the design for crossover {w} rad/s and phase margin {phase_margin_deg} deg gives an "
            f"unstable closed loop (poles {np.round(poles, 4)}); choose other specifications"
        )
    return gains
