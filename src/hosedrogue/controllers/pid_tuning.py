"""PID gains tuned to step-response bounds (rise time, settling time and overshoot at most, damping
at least) on a channel model, the least high-frequency gain among those that meet them.

The loop is the paper's (Sec. 3.2.1, Eq. 33): unity feedback, ``C(s) = K_P + K_I/s + K_D N s/(s + N)``
on the error, plant ``G(s)`` force [N] -> offset [m]; the figures of merit are Table 3's
(:mod:`.stepinfo`: 10-90 % rise, 2 % settling from the step instant, overshoot in % of the step).

**The targets are bounds.** A design meets them when its unit step rises in at most ``t_r*``,
settles in at most ``t_s*``, overshoots at most ``OS*`` and every closed-loop pole is damped at least
``zeta*`` (optional, default 0: any stable loop). A design that beats a target meets it.

**The cost: the least high-frequency gain** ``K_P + K_D N`` [N/m] among the designs that meet the
bounds. It is the force per metre of reference step at the step instant (the step's peak force on
these loops) and the gain from position-sensor noise to force at high frequency: the least
actuator effort and noise for the performance asked. (The integral of the squared step error
would instead pick the fastest loop the search box allows: a property of the box, not of the
loop.)

**Method** (:func:`tune_pid_to_step`; docs/tuning.md):

1. Parameters scaled by the plant's DC gain g = |G(0)| [m/N] and the targets:
   ``theta = ln(K_P g, K_I g t_s, K_D g / t_r, N t_r)``, inside :data:`BOUNDS`; the cost is
   ``ln(g (K_P + K_D N))``.
2. Slacks ``c = (ln(t_r* / t_r), ln(t_s* / t_s), (OS* - OS) / 10 pp, (zeta_min - zeta*) / 0.1)``, each
   >= 0 when its bound is met; a 10 % miss of a time weighs as one percentage point of overshoot
   (:data:`OVERSHOOT_SCALE_PCT`) and as 0.01 of damping (:data:`DAMPING_SCALE`).
3. Global search: differential evolution (:func:`scipy.optimize.differential_evolution`, seeded,
   first population the best of a Sobol sample of the box) on the cost where every slack is at
   least :data:`SEARCH_MARGIN` (the population's steps on one grid set by the targets,
   :func:`.pid_loop.population_step_figures`), and above every such design the total shortfall:
   a design meeting the bounds always beats one that does not, and among those that do not the
   smaller shortfall wins.
4. The choice: the first member of the final population, in the order of that cost, that meets
   the bounds on the exact step (:class:`.pid_loop.ModalStep`: modal form, crossings, extrema and
   band entry by root finding). Its cost is the least the search found, within the search's
   tolerance (:data:`_DE_TOL`, 1 % of the population's mean cost) and the margin; a local
   constrained refinement (SLSQP, COBYQA) was tried and left out: the settling time jumps where
   an extremum touches the band, and SLSQP's steps left the region of stable loops, COBYQA took
   minutes.
5. When no member meets them: the closest design, the least sum of squared shortfalls
   (:func:`scipy.optimize.least_squares` from the search's best), is returned in
   :class:`TargetsNotMet`.

Every figure of the result is measured on the exact step of the returned gains; ``met`` is the
comparison of those figures with the bounds, without tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import differential_evolution, least_squares

from .pid import PIDGains
from .pid_loop import ModalStep, plant_polynomials, population_step_figures
from .stepinfo import StepMetrics

__all__ = ["StepTargets", "PIDTuning", "TargetsNotMet", "tune_pid_to_step", "pid_for_poles", "BOUNDS",
           "SEARCH_MARGIN", "OVERSHOOT_SCALE_PCT", "DAMPING_SCALE", "SEED", "SLACK_NAMES"]

#: Bounds of the scaled parameters (K_P g, K_I g t_s, K_D g / t_r, N t_r) [-]: four to six decades
#: around the paper's design (26.5, 26.3, 67, 7.2 lateral on its Table 2 model); N t_r <= 100
#: keeps the derivative filter within two decades of the loop's speed.
BOUNDS = ((1e-2, 1e4), (1e-3, 1e5), (1e-3, 1e5), (0.1, 100.0))
#: Seed of the global search [-] (a fixed seed: the same plant and targets give the same bits).
SEED = 2018
#: One percentage point of overshoot weighs as a 10 % miss of a time [pp].
OVERSHOOT_SCALE_PCT = 10.0
#: 0.1 of damping ratio weighs as a 10 % miss of a time [-].
DAMPING_SCALE = 0.1
#: The global search aims this far inside every bound [-] (2e-3 of a time, 0.02 pp of overshoot):
#: four times the error of its grid's interpolated crossings (5e-4 of a time measured on the paper's
#: models, tests/controllers/test_pid_tuning.py), so its best design meets the bounds on the exact step.
SEARCH_MARGIN = 2e-3
#: Names of the slacks, in order [-].
SLACK_NAMES = ("rise_time_s", "settling_time_s", "overshoot_pct", "min_damping")
_GRID = (200, 600)  # samples of the global search's grid on [0, 4 t_r] and [4 t_r, 4 t_s] [-]
# global search: Sobol sample size, population per parameter, generations, relative tolerance [-]
_SAMPLE, _POPSIZE, _MAXITER, _DE_TOL = 1024, 15, 300, 0.01
_FD = 1e-7  # finite-difference step of the exact slacks in log-parameters [-]
_MISSING = 1e3  # the slack of a figure not reached (no rise, no settling, unstable loop) [-]
_TRIED = 20  # members of the final population tried, best first, on the exact step [-]


class TargetsNotMet(ValueError):
    """No gains in the search box meet the bounds.

    Parameters
    ----------
    message : str
        What was asked and the closest figures reached.
    closest : PIDTuning
        The closest design found (``met`` is False).
    """

    def __init__(self, message: str, closest: "PIDTuning"):
        super().__init__(message)
        self.closest = closest


@dataclass(frozen=True)
class StepTargets:
    """Unit-step bounds of one channel, with Table 3's definitions (:mod:`.stepinfo`).

    Parameters
    ----------
    rise_time_s : float
        Largest 10-90 % rise time [s], > 0.
    settling_time_s : float
        Largest 2 % settling time from the step instant [s], > rise time.
    overshoot_pct : float
        Largest peak overshoot [% of the step], in [0, 100).
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
        if not 0.0 <= self.overshoot_pct < 100.0:
            raise ValueError(f"StepTargets.overshoot_pct must be in [0, 100) %, got {self.overshoot_pct}")

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
    """A PID tuned to step bounds (:func:`tune_pid_to_step`).

    Attributes
    ----------
    gains : PIDGains
        K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s].
    targets : StepTargets
        The bounds asked.
    min_damping_required : float
        The damping bound asked [-] (0: any stable loop).
    metrics : StepMetrics
        The step's figures on the tuning model (exact modal response, crossings, extrema and band
        entry by root finding).
    slack : numpy.ndarray, shape (4,)
        Scaled slacks of :data:`SLACK_NAMES` [-] (module docstring, step 2): >= 0 where the bound is
        met; -1000 for a figure not reached.
    met : bool
        Every slack >= 0: the figures of ``metrics`` and ``min_damping`` within the bounds.
    poles_rad_s : numpy.ndarray
        Closed-loop poles [rad/s].
    min_damping : float
        Smallest damping ratio of the closed-loop poles [-] (1 for a real pole).
    high_frequency_gain_n_per_m : float
        K_P + K_D N [N/m], the cost minimized among the designs that meet the bounds.
    """

    gains: PIDGains
    targets: StepTargets
    min_damping_required: float
    metrics: StepMetrics
    slack: np.ndarray
    met: bool
    poles_rad_s: np.ndarray
    min_damping: float
    high_frequency_gain_n_per_m: float

    def shortfalls(self) -> list[str]:
        """What misses its bound, e.g. ``"settling 3.786 s > 2.5 s"`` (empty when met).

        Returns
        -------
        list of str
        """
        m, tg = self.metrics, self.targets
        text = {"rise_time_s": f"rise {m.rise_time_s:.4g} s > {tg.rise_time_s:g} s",
                "settling_time_s": f"settling {m.settling_time_s:.4g} s > {tg.settling_time_s:g} s",
                "overshoot_pct": f"overshoot {m.overshoot_pct:.4g} % > {tg.overshoot_pct:g} %",
                "min_damping": f"damping {self.min_damping:.3f} < {self.min_damping_required:g}"}
        return [text[k].replace("nan s >", "not reached, bound") for k, c in zip(SLACK_NAMES, self.slack) if not c >= 0.0]


def _unscale(theta: np.ndarray, g0: float, targets: StepTargets) -> np.ndarray:
    """Gains (K_P, K_I, K_D, N) from scaled log-parameters; ``theta`` (4,) or (4, S)."""
    e = np.exp(theta)
    tr, ts = targets.rise_time_s, targets.settling_time_s
    return np.array([e[0] / g0, e[1] / (g0 * ts), e[2] * tr / g0, e[3] / tr])


def _cost(theta) -> np.ndarray:
    """ln(g (K_P + K_D N)) of scaled log-parameters (4,) or (4, S): K_P g = e^theta_0 and
    K_D N g = e^(theta_2 + theta_3)."""
    return np.logaddexp(theta[0], theta[2] + theta[3])


def _slacks(targets: StepTargets, min_damping: float, rise, settle, over, zeta) -> np.ndarray:
    """The scaled slacks (module docstring, step 2) of figures (scalars or arrays), stacked on the
    first axis; a figure not reached (NaN) gives -:data:`_MISSING`."""
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.array([np.log(targets.rise_time_s / np.asarray(rise, dtype=float)),
                      np.log(targets.settling_time_s / np.asarray(settle, dtype=float)),
                      (targets.overshoot_pct - np.asarray(over, dtype=float)) / OVERSHOOT_SCALE_PCT,
                      (np.asarray(zeta, dtype=float) - min_damping) / DAMPING_SCALE])
    return np.where(np.isnan(c), -_MISSING, np.minimum(c, _MISSING))


# --------------------------------------------------------------------------------------------
# The search


class _Problem:
    """The cost and the slacks of one plant and set of bounds, in scaled log-parameters."""

    def __init__(self, plant_siso, targets: StepTargets, min_damping: float):
        self.num_g, self.den_g = plant_polynomials(plant_siso)
        self.g0 = abs(self.num_g[-1] / self.den_g[-1])
        self.targets, self.min_damping = targets, min_damping
        self.lo = np.log([b[0] for b in BOUNDS])
        self.hi = np.log([b[1] for b in BOUNDS])
        self.ceiling = float(_cost(self.hi)) + 1.0  # above the cost of every design in the box

    def step(self, theta) -> ModalStep:
        return ModalStep(self.num_g, self.den_g, _unscale(np.asarray(theta, dtype=float), self.g0, self.targets))

    def slack(self, theta) -> np.ndarray:
        """The exact slacks (4,); -:data:`_MISSING` each for an unstable loop."""
        st = self.step(theta)
        if not st.stable:
            return np.full(4, -_MISSING)
        m = st.metrics()
        return _slacks(self.targets, self.min_damping, m.rise_time_s, m.settling_time_s, m.overshoot_pct,
                       st.min_damping())

    def population_cost(self, t: np.ndarray):
        """The global search's cost of a population (4, S): the cost where every slack on the grid
        ``t`` is at least :data:`SEARCH_MARGIN`, else the ceiling plus the total shortfall."""

        def cost(theta: np.ndarray) -> np.ndarray:
            theta = np.atleast_2d(theta)
            with np.errstate(over="ignore", invalid="ignore"):
                fig = population_step_figures(self.num_g, self.den_g, _unscale(theta, self.g0, self.targets), t)
            c = _slacks(self.targets, self.min_damping, fig["rise_time_s"], fig["settling_time_s"],
                        fig["overshoot_pct"], fig["min_damping"]) - SEARCH_MARGIN
            c = np.where(fig["stable"], c, -_MISSING)
            short = np.sum(np.maximum(0.0, -c), axis=0)
            return np.where(short > 0.0, self.ceiling + short, _cost(theta))

        return cost

    def global_search(self):
        """Differential evolution over the box: its final population and their costs, best first."""
        tg = self.targets
        t = np.concatenate([np.linspace(0.0, 4.0 * tg.rise_time_s, _GRID[0] + 1)[:-1],
                            np.linspace(4.0 * tg.rise_time_s, 4.0 * tg.settling_time_s, _GRID[1])])
        cost = self.population_cost(t)
        from scipy.stats import qmc

        sample = qmc.scale(qmc.Sobol(4, seed=SEED).random(_SAMPLE), self.lo, self.hi)
        init = sample[np.argsort(cost(sample.T), kind="stable")[: 4 * _POPSIZE]]
        res = differential_evolution(cost, list(zip(self.lo, self.hi)), vectorized=True, updating="deferred",
                                     seed=SEED, init=init, maxiter=_MAXITER, tol=_DE_TOL, polish=False)
        order = np.argsort(res.population_energies, kind="stable")
        return res.population[order], res.population_energies[order]

    def closest(self, theta0) -> np.ndarray:
        """The least sum of squared shortfalls near ``theta0`` (Gauss-Newton on the exact slacks)."""

        def short(th):
            return np.maximum(0.0, -self.slack(th))

        theta0 = np.clip(theta0, self.lo + 1e-9, self.hi - 1e-9)
        r = least_squares(short, theta0, bounds=(self.lo, self.hi), method="trf", diff_step=_FD,
                          xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=200)
        return r.x if np.sum(r.fun ** 2) < np.sum(short(theta0) ** 2) else theta0


def _tuning(problem: _Problem, theta) -> PIDTuning:
    st = problem.step(theta)
    gains = _unscale(theta, problem.g0, problem.targets)
    slack = problem.slack(theta)
    return PIDTuning(gains=PIDGains(*gains), targets=problem.targets, min_damping_required=problem.min_damping,
                     metrics=st.metrics(), slack=slack, met=bool(np.all(slack >= 0.0)),
                     poles_rad_s=np.sort_complex(st.poles), min_damping=st.min_damping(),
                     high_frequency_gain_n_per_m=float(gains[0] + gains[2] * gains[3]))


def tune_pid_to_step(plant_siso, targets: StepTargets, *, min_damping: float = 0.0) -> PIDTuning:
    """The PID of least high-frequency gain whose unit step on ``plant_siso`` meets the bounds
    ``targets`` (method: module docstring).

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        G(s), force [N] -> offset [m], strictly proper, stable or not, no zero at s = 0 (e.g. a
        2nd-order channel of :func:`hosedrogue.controllers.design.reduced_channels`).
    targets : StepTargets
        Largest rise time [s], settling time [s] and overshoot [%] of the unit reference step.
    min_damping : float, optional
        Smallest damping ratio [-] every closed-loop pole must have, in [0, 1] (default 0: any
        stable loop).

    Returns
    -------
    PIDTuning
        The chosen gains, their exact step figures (``met`` True), the closed-loop poles.

    Raises
    ------
    TargetsNotMet
        If no design found inside :data:`BOUNDS` meets the bounds; ``closest`` holds the closest
        design found (``met`` False), the message what it misses.
    ValueError
        If the plant is not SISO, not strictly proper, has a zero at s = 0, or ``min_damping``
        is outside [0, 1].
    """
    if not 0.0 <= min_damping <= 1.0:
        raise ValueError(f"min_damping must be in [0, 1], got {min_damping}")
    problem = _Problem(plant_siso, targets, float(min_damping))
    population, energies = problem.global_search()
    for theta in population[:_TRIED]:
        if np.all(problem.slack(theta) >= 0.0):
            return _tuning(problem, theta)
    closest = _tuning(problem, problem.closest(population[0]))
    damped = f" and every closed-loop pole damped >= {min_damping:g}" if min_damping > 0.0 else ""
    raise TargetsNotMet(
        f"no PID within the search bounds has rise <= {targets.rise_time_s:g} s, settling <= "
        f"{targets.settling_time_s:g} s, overshoot <= {targets.overshoot_pct:g} %{damped}; closest: "
        + ", ".join(closest.shortfalls()), closest)


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
