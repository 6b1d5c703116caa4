"""PID gains tuned to step-response targets (rise time, settling time, overshoot) on a channel model.

The loop is the paper's (Sec. 3.2.1, Eq. 33): unity feedback, ``C(s) = K_P + K_I/s + K_D N s/(s + N)``
on the error, plant ``G(s)`` force [N] -> offset [m]; the figures of merit are Table 3's
(:mod:`.stepinfo`: 10-90 % rise, 2 % settling from the step instant, overshoot in % of the step).

**Why the gains form a family.** The closed loop's characteristic polynomial
``s (s + N) den_G(s) + num_G(s) ((K_P + K_D N) s^2 + (K_P N + K_I) s + K_I N)`` has degree n + 2;
on the 2nd-order design model its four poles fix the four parameters (K_P, K_I, K_D, N) by a
linear solve (:func:`pid_for_poles`). Three step targets therefore leave one degree of freedom:
the gains that meet them form curves in the four-parameter space, and a rule must pick one.

**Method** (:func:`tune_pid_to_step`; docs/tuning.md):

1. Parameters scaled by the plant's DC gain g = |G(0)| [m/N] and the targets:
   ``theta = ln(K_P g, K_I g t_s, K_D g / t_r, N t_r)``, inside :data:`BOUNDS`.
2. Residuals ``F = (ln(t_r / t_r*), ln(t_s / t_s*), (OS - OS*) / 10 pp)``: a 10 % error in a time
   weighs as much as one percentage point of overshoot (the acceptance check's tolerances).
3. Global search: differential evolution (:func:`scipy.optimize.differential_evolution`, seeded,
   so the result is reproducible; first population the best of a Sobol sample of the box)
   minimizing ``|F|^2 +`` :data:`DAMPING_WEIGHT` ``(1 - zeta_min)^2`` (zeta_min the smallest
   damping ratio of the closed-loop poles: of several branches of solutions, the better damped
   one), the population's steps on one time grid set by the targets
   (:func:`.pid_loop.population_step_figures`).
4. Refinement: :func:`scipy.optimize.least_squares` on F from the exact step response
   (:class:`.pid_loop.ModalStep`: modal form, crossings and peak by root finding), to
   ``max |F| <`` :data:`MET`.
5. Continuation: the solution curve F = 0 through that point is followed in both directions
   (pseudo-arclength, Newton corrector) until a bound, the end of the branch (the settling time
   jumps where an extremum of the response touches the 2 % band), or :data:`MAX_POINTS`.
6. Repeated search: while the best damped point found has zeta_min below 1 - :data:`DAMPING_TIE`,
   steps 3-5 are repeated with a new seed and the penalty :data:`FLOOR_WEIGHT`
   ``max(0, floor - zeta_min)^2``, floor = that damping + :data:`DAMPING_GAIN`, up to
   :data:`MAX_SEARCHES` searches; every branch found joins the family.
7. Choice: the member whose least damped closed-loop pole is best damped (largest zeta_min, ties
   within :data:`DAMPING_TIE`); among those, the least high-frequency gain ``K_P + K_D N`` (the
   force per metre at the step instant, and the gain from position noise to force).
   ``min_damping`` excludes members whose zeta_min is lower.

The three targets are met to :data:`MET` (relative in the times, x10 pp in the overshoot) on
the model the gains are tuned on; the chosen member is only as unique as the rule of step 7.
If no point of the search box meets them, :class:`TargetsNotMet` carries the closest design
found.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import differential_evolution, least_squares

from .pid import PIDGains
from .pid_loop import ModalStep, plant_polynomials, population_step_figures
from .stepinfo import StepMetrics

__all__ = ["StepTargets", "PIDTuning", "TargetsNotMet", "tune_pid_to_step", "pid_for_poles", "BOUNDS", "MET",
           "DAMPING_TIE", "DAMPING_WEIGHT", "FLOOR_WEIGHT", "DAMPING_GAIN", "MAX_SEARCHES",
           "MAX_POINTS", "SEED"]

#: Bounds of the scaled parameters (K_P g, K_I g t_s, K_D g / t_r, N t_r) [-]: four to six decades
#: around the paper's design (26.5, 26.3, 67, 7.2 lateral on its Table 2 model); N t_r <= 100
#: keeps the derivative filter within two decades of the loop's speed.
BOUNDS = ((1e-2, 1e4), (1e-3, 1e5), (1e-3, 1e5), (0.1, 100.0))
#: Targets count as met when every residual of F is below this [-]: 1e-6 of a time target,
#: 1e-5 percentage points of overshoot (far below the 1e-4 to which Table 3's interpolated
#: time grid reads a step).
MET = 1e-6
#: Smallest damping ratios closer than this [-] count as equal in the choice (step 7): 0.01 of
#: damping changes a pole pair's own overshoot by at most 0.4 percentage points above damping 0.7
#: and by less than 0.06 above 0.9.
DAMPING_TIE = 0.01
#: Most points followed in each direction of the solution curve [-].
MAX_POINTS = 80
#: Seed of the global search [-] (a fixed seed: the same plant and targets give the same bits).
SEED = 2018
#: Weight of the overshoot residual: one percentage point counts as a 10 % time error [pp].
OVERSHOOT_SCALE_PCT = 10.0
#: Weight [-] of (1 - smallest damping ratio)^2 in the global search's cost: where several branches
#: of solutions exist the search lands on the better damped one (the whole range of damping
#: weighs as a 3 % error in the targets, so an exact solution wins over any larger miss).
DAMPING_WEIGHT = 1e-3
#: Weight [-] of the shortfall of the smallest damping ratio below the floor of a repeated search
#: (step 6): 0.1 short costs as much as a 10 % error in a target.
FLOOR_WEIGHT = 1.0
#: Least gain in the smallest damping ratio [-] a repeated search must find to be repeated again.
DAMPING_GAIN = 0.05
#: Most global searches [-] (the first, and the repeats asking for better damping).
MAX_SEARCHES = 3
_GRID = (200, 600)  # samples of the global search's grid on [0, 4 t_r] and [4 t_r, 4 t_s] [-]
# global search: Sobol sample size, population per parameter, generations, relative tolerance [-]
_SAMPLE, _POPSIZE, _MAXITER, _DE_TOL = 1024, 15, 300, 0.01
_STEP0, _STEP_MAX, _STEP_MIN = 0.05, 0.3, 1e-3  # continuation steps in scaled log-parameters [-]
_SAME_BRANCH = 0.2  # a refined point this close to a followed one [-] lies on its branch
_FD = 1e-7  # forward-difference step of the Jacobian in log-parameters [-]


class TargetsNotMet(ValueError):
    """No gains in the search box meet the targets.

    Parameters
    ----------
    message : str
        What was asked and the closest figures reached.
    closest : PIDTuning
        The best design found (``met`` is False).
    """

    def __init__(self, message: str, closest: "PIDTuning"):
        super().__init__(message)
        self.closest = closest


@dataclass(frozen=True)
class StepTargets:
    """Unit-step targets of one channel, with Table 3's definitions (:mod:`.stepinfo`).

    Parameters
    ----------
    rise_time_s : float
        10-90 % rise time [s], > 0.
    settling_time_s : float
        2 % settling time from the step instant [s], > rise time.
    overshoot_pct : float
        Peak overshoot [% of the step], in (0, 100) (a step-matching design cannot aim at
        exactly zero: every non-overshooting response would match).
    """

    rise_time_s: float
    settling_time_s: float
    overshoot_pct: float

    def __post_init__(self) -> None:
        for name in ("rise_time_s", "settling_time_s", "overshoot_pct"):
            v = float(getattr(self, name))
            if not math.isfinite(v):
                raise ValueError(f"StepTargets.{name} must be finite, got {v}")
            object.__setattr__(self, name, v)
        if not self.rise_time_s > 0.0:
            raise ValueError(f"StepTargets.rise_time_s must be > 0 s, got {self.rise_time_s}")
        if not self.settling_time_s > self.rise_time_s:
            raise ValueError(f"StepTargets.settling_time_s must exceed the rise time {self.rise_time_s:g} s, "
                             f"got {self.settling_time_s}")
        if not 0.0 < self.overshoot_pct < 100.0:
            raise ValueError(f"StepTargets.overshoot_pct must be in (0, 100) %, got {self.overshoot_pct}")

    def as_dict(self) -> dict[str, float]:
        """``{"rise_time_s", "settling_time_s", "overshoot_pct"}`` (Table 3's keys).

        Returns
        -------
        dict
        """
        return {"rise_time_s": self.rise_time_s, "settling_time_s": self.settling_time_s,
                "overshoot_pct": self.overshoot_pct}


@dataclass(frozen=True)
class PIDTuning:
    """A PID tuned to step targets (:func:`tune_pid_to_step`).

    Attributes
    ----------
    gains : PIDGains
        K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s].
    targets : StepTargets
        What was asked.
    metrics : StepMetrics
        The step's figures on the tuning model (exact modal response, crossings by root finding).
    residual : float
        max |F| [-] (see the module docstring); below :data:`MET` when the targets are met.
    poles_rad_s : numpy.ndarray
        Closed-loop poles [rad/s].
    min_damping : float
        Smallest damping ratio of the closed-loop poles [-] (1 for a real pole).
    high_frequency_gain_n_per_m : float
        K_P + K_D N [N/m], the controller's gain at high frequency.
    family : numpy.ndarray, shape (k, 6)
        The designs found that meet the targets: K_P, K_I, K_D, N, smallest damping ratio,
        K_P + K_D N per row, each branch followed ordered along its curve (one row, the closest
        design, when the targets are not met).
    """

    gains: PIDGains
    targets: StepTargets
    metrics: StepMetrics
    residual: float
    poles_rad_s: np.ndarray
    min_damping: float
    high_frequency_gain_n_per_m: float
    family: np.ndarray

    @property
    def met(self) -> bool:
        """Whether every residual is below :data:`MET`."""
        return self.residual < MET


def _unscale(theta: np.ndarray, g0: float, targets: StepTargets) -> np.ndarray:
    """Gains (K_P, K_I, K_D, N) from scaled log-parameters; ``theta`` (4,) or (4, S)."""
    e = np.exp(theta)
    tr, ts = targets.rise_time_s, targets.settling_time_s
    return np.array([e[0] / g0, e[1] / (g0 * ts), e[2] * tr / g0, e[3] / tr])


def _scale(gains, g0: float, targets: StepTargets) -> np.ndarray:
    """Scaled log-parameters of gains (K_P, K_I, K_D, N)."""
    kp, ki, kd, n = gains
    tr, ts = targets.rise_time_s, targets.settling_time_s
    return np.log([kp * g0, ki * g0 * ts, kd * g0 / tr, n * tr])


def _population_cost(num_g, den_g, targets: StepTargets, t: np.ndarray, floor: float):
    """The global search's cost of a population of scaled parameters (4, S): |F|^2, the damping
    preference, and the penalty for a smallest damping ratio below ``floor``."""
    g0 = abs(num_g[-1] / den_g[-1])

    def cost(theta: np.ndarray) -> np.ndarray:
        with np.errstate(over="ignore", invalid="ignore"):
            fig = population_step_figures(num_g, den_g, _unscale(np.atleast_2d(theta), g0, targets), t)
        with np.errstate(invalid="ignore", divide="ignore"):
            f = (np.log(fig["rise_time_s"] / targets.rise_time_s) ** 2
                 + np.log(fig["settling_time_s"] / targets.settling_time_s) ** 2
                 + ((fig["overshoot_pct"] - targets.overshoot_pct) / OVERSHOOT_SCALE_PCT) ** 2)
        zeta = fig["min_damping"]
        f = f + DAMPING_WEIGHT * (1.0 - zeta) ** 2 + FLOOR_WEIGHT * np.maximum(0.0, floor - zeta) ** 2
        return np.where(fig["stable"] & np.isfinite(f), f, 1e3)

    return cost


# --------------------------------------------------------------------------------------------
# The search


class _Problem:
    """The residuals F of one plant and set of targets, in scaled log-parameters."""

    def __init__(self, plant_siso, targets: StepTargets):
        self.num_g, self.den_g = plant_polynomials(plant_siso)
        self.g0 = abs(self.num_g[-1] / self.den_g[-1])
        self.targets = targets
        self.lo = np.log([b[0] for b in BOUNDS])
        self.hi = np.log([b[1] for b in BOUNDS])

    def step(self, theta) -> ModalStep:
        return ModalStep(self.num_g, self.den_g, _unscale(np.asarray(theta, dtype=float), self.g0, self.targets))

    def residuals(self, theta) -> np.ndarray:
        """F(theta) (3,); 1e3 each outside the box, or where the loop is unstable or the step does not
        rise or settle."""
        theta = np.asarray(theta, dtype=float)
        if not np.all((theta >= self.lo - 1e-6) & (theta <= self.hi + 1e-6)):
            return np.full(3, 1e3)
        st = self.step(theta)
        if not st.stable:
            return np.full(3, 1e3)
        m = st.metrics()
        tg = self.targets
        f = np.array([math.log(m.rise_time_s / tg.rise_time_s) if m.rise_time_s > 0 else np.nan,
                      math.log(m.settling_time_s / tg.settling_time_s) if m.settling_time_s > 0 else np.nan,
                      (m.overshoot_pct - tg.overshoot_pct) / OVERSHOOT_SCALE_PCT])
        return np.where(np.isfinite(f), f, 1e3)

    def jacobian(self, theta, f0) -> np.ndarray:
        cols = []
        for k in range(4):
            d = np.zeros(4)
            d[k] = _FD
            cols.append((self.residuals(theta + d) - f0) / _FD)
        return np.stack(cols, axis=1)

    def global_search(self, floor: float, seed: int) -> np.ndarray:
        """Differential evolution over the box, penalizing a smallest damping ratio below ``floor``;
        the population's steps on one target-scaled grid."""
        tg = self.targets
        t = np.concatenate([np.linspace(0.0, 4.0 * tg.rise_time_s, _GRID[0] + 1)[:-1],
                            np.linspace(4.0 * tg.rise_time_s, 4.0 * tg.settling_time_s, _GRID[1])])
        cost = _population_cost(self.num_g, self.den_g, tg, t, floor)
        from scipy.stats import qmc

        sample = qmc.scale(qmc.Sobol(4, seed=seed).random(_SAMPLE), self.lo, self.hi)
        init = sample[np.argsort(cost(sample.T), kind="stable")[: 4 * _POPSIZE]]
        res = differential_evolution(cost, list(zip(self.lo, self.hi)), vectorized=True, updating="deferred", seed=seed,
                                     init=init, maxiter=_MAXITER, tol=_DE_TOL, polish=False)
        return res.x

    def refine(self, theta) -> np.ndarray:
        """Gauss-Newton on the exact residuals, inside the box."""
        theta = np.clip(theta, self.lo + 1e-9, self.hi - 1e-9)
        r = least_squares(self.residuals, theta, bounds=(self.lo, self.hi), method="trf", diff_step=_FD,
                          xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=200)
        return r.x if np.max(np.abs(r.fun)) <= np.max(np.abs(self.residuals(theta))) else theta

    def correct(self, theta_pred, tangent):
        """Newton on [F; tangent . (theta - theta_pred)] = 0: (theta, F's Jacobian at the last
        iterate), or None if it does not converge."""
        theta, jac = theta_pred.copy(), None
        for _ in range(8):
            f = self.residuals(theta)
            if np.max(np.abs(f)) >= 1e3:
                return None
            if np.max(np.abs(f)) < 0.1 * MET:
                return theta, (self.jacobian(theta, f) if jac is None else jac)
            jac = self.jacobian(theta, f)
            rhs = -np.concatenate([f, [tangent @ (theta - theta_pred)]])
            try:
                theta = theta + np.linalg.solve(np.vstack([jac, tangent]), rhs)
            except np.linalg.LinAlgError:
                return None
        return (theta, jac) if np.max(np.abs(self.residuals(theta))) < MET else None

    @staticmethod
    def null_direction(jac, previous=None) -> np.ndarray:
        """Unit null vector of F's Jacobian (the curve's tangent), oriented along ``previous``."""
        v = np.linalg.svd(jac)[2][-1]
        return -v if previous is not None and v @ previous < 0.0 else v

    def trace(self, theta0, direction: float) -> list[np.ndarray]:
        """Points of the solution curve from theta0 (excluded) in one direction."""
        points = []
        tau = direction * self.null_direction(self.jacobian(theta0, self.residuals(theta0)))
        theta, h = theta0, _STEP0
        while len(points) < MAX_POINTS and h >= _STEP_MIN:
            pred = theta + h * tau
            if np.any(pred < self.lo) or np.any(pred > self.hi):
                break
            out = self.correct(pred, tau)
            if out is None or np.linalg.norm(out[0] - theta) > 3.0 * h:
                h *= 0.5
                continue
            theta, tau = out[0], self.null_direction(out[1], tau)
            points.append(theta)
            h = min(1.5 * h, _STEP_MAX)
        return points


def _tuning(problem: _Problem, theta, family) -> PIDTuning:
    st = problem.step(theta)
    gains = _unscale(theta, problem.g0, problem.targets)
    return PIDTuning(gains=PIDGains(*gains), targets=problem.targets, metrics=st.metrics(),
                     residual=float(np.max(np.abs(problem.residuals(theta)))), poles_rad_s=np.sort_complex(st.poles),
                     min_damping=st.min_damping(), high_frequency_gain_n_per_m=float(gains[0] + gains[2] * gains[3]),
                     family=np.asarray(family, dtype=float).reshape(-1, 6))


def _family_row(problem: _Problem, theta) -> list[float]:
    kp, ki, kd, n = _unscale(theta, problem.g0, problem.targets)
    return [kp, ki, kd, n, problem.step(theta).min_damping(), kp + kd * n]


def tune_pid_to_step(plant_siso, targets: StepTargets, *, min_damping: float = 0.0) -> PIDTuning:
    """PID gains whose unit-step response on ``plant_siso`` meets ``targets`` (method: module docstring).

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        G(s), force [N] -> offset [m], strictly proper, stable or not, no zero at s = 0 (e.g. a
        2nd-order channel of :func:`hosedrogue.controllers.design.reduced_channels`).
    targets : StepTargets
        Rise time [s], settling time [s] and overshoot [%] of the unit reference step.
    min_damping : float, optional
        Smallest damping ratio [-] every closed-loop pole must have, in [0, 1] (default 0: any
        stable loop).

    Returns
    -------
    PIDTuning
        The chosen gains, the achieved figures (targets met to :data:`MET`), the closed-loop
        poles and the traced family.

    Raises
    ------
    TargetsNotMet
        If no gains inside :data:`BOUNDS` meet the targets, or none of those found has every
        pole damped by ``min_damping``; ``closest`` holds the best design found.
    ValueError
        If the plant is not SISO, not strictly proper, has a zero at s = 0, or ``min_damping``
        is outside [0, 1].
    """
    if not 0.0 <= min_damping <= 1.0:
        raise ValueError(f"min_damping must be in [0, 1], got {min_damping}")
    problem = _Problem(plant_siso, targets)
    thetas, floor, closest = [], min_damping, None
    for k in range(MAX_SEARCHES):
        theta0 = problem.refine(problem.global_search(floor, SEED + k))
        miss = float(np.max(np.abs(problem.residuals(theta0))))
        if miss >= MET:
            closest = theta0 if closest is None or miss < np.max(np.abs(problem.residuals(closest))) else closest
            continue
        if thetas and np.min(np.linalg.norm(np.array(thetas) - theta0, axis=1)) < _SAME_BRANCH:
            continue  # a branch already followed
        branch = problem.trace(theta0, -1.0)[::-1] + [theta0] + problem.trace(theta0, +1.0)
        thetas += branch
        best = max(problem.step(th).min_damping() for th in thetas)
        if best >= 1.0 - DAMPING_TIE:
            break
        floor = max(floor, best + DAMPING_GAIN)
    if not thetas:
        closest = _tuning(problem, closest, [_family_row(problem, closest)])
        m = closest.metrics
        damped = f" and every closed-loop pole damped >= {min_damping:g}" if min_damping > 0.0 else ""
        raise TargetsNotMet(
            f"no PID within the search bounds{damped} meets rise {targets.rise_time_s:g} s, settling "
            f"{targets.settling_time_s:g} s, overshoot {targets.overshoot_pct:g} %; closest: rise "
            f"{m.rise_time_s:.4g} s, settling {m.settling_time_s:.4g} s, overshoot {m.overshoot_pct:.3g} %", closest)
    family = np.array([_family_row(problem, th) for th in thetas])
    damping, hf_gain = family[:, 4], family[:, 5]
    allowed = damping >= min_damping
    if not np.any(allowed):
        best = int(np.argmax(damping))
        raise TargetsNotMet(
            f"the gains meeting the targets found have a smallest closed-loop damping ratio of at most "
            f"{damping[best]:.3f}, below min_damping {min_damping:g}", _tuning(problem, thetas[best], family))
    top = np.max(damping[allowed])
    candidates = np.nonzero(allowed & (damping >= top - DAMPING_TIE))[0]
    pick = int(candidates[np.argmin(hf_gain[candidates])])
    return _tuning(problem, thetas[pick], family)


def pid_for_poles(plant_siso, poles) -> PIDGains:
    """The PID whose unity-feedback loop around a 2nd-order plant has the given four poles.

    With G(s) = (b1 s + b0) / (s^2 + a1 s + a0) the characteristic polynomial
    ``s^4 + (N + a1 + b1 c2) s^3 + (a0 + N a1 + b0 c2 + b1 c1) s^2 + (N a0 + b0 c1 + b1 c0) s + b0 c0``
    (c2 = K_P + K_D N, c1 = K_P N + K_I, c0 = K_I N) is matched coefficient by coefficient: c0
    from the constant term, c2 and c1 linear in N from the next two, and N from the s^1 term.

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        2nd-order SISO plant, force [N] -> offset [m].
    poles : array_like, shape (4,)
        Closed-loop poles [rad/s], complex ones in conjugate pairs.

    Returns
    -------
    PIDGains

    Raises
    ------
    ValueError
        If the plant is not 2nd order with a nonzero s^1 numerator coefficient, or a resulting
        gain is negative (these poles need a PID with a negative gain) or N is not > 0.
    """
    num, den = plant_polynomials(plant_siso)
    if den.size != 3 or num.size != 2:
        raise ValueError(f"plant_siso must be (b1 s + b0) / (s^2 + a1 s + a0), got degrees {num.size - 1}/{den.size - 1}")
    (b1, b0), (_, a1, a0) = num, den
    coeffs = np.real(np.poly(np.asarray(poles, dtype=complex)))
    if coeffs.size != 5:
        raise ValueError(f"poles must hold 4 values, got {coeffs.size - 1}")
    _, d3, d2, d1, d0 = coeffs
    c0 = d0 / b0
    p2, q2 = (d3 - a1) / b1, -1.0 / b1  # c2 = p2 + q2 N
    p1, q1 = (d2 - a0 - b0 * p2) / b1, (-a1 - b0 * q2) / b1  # c1 = p1 + q1 N
    n = (d1 - b0 * p1 - b1 * c0) / (a0 + b0 * q1)
    c2, c1 = p2 + q2 * n, p1 + q1 * n
    ki = c0 / n
    kp = (c1 - ki) / n
    kd = (c2 - kp) / n
    try:
        return PIDGains(kp=kp, ki=ki, kd=kd, n_filter=n)
    except ValueError as exc:
        raise ValueError(f"no PID with nonnegative gains places these poles ({exc})") from None
