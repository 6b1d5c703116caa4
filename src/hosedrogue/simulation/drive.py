"""Run sampled-data controllers on a stepper: the one loop of a run with the user's controllers
(fixed-length or engagement), :func:`drive`.

Every control step of the stepper (the greatest common divisor of the controllers' sample
times, :func:`control_step`), each controller whose sample is due is called with the
measurement and its command is held by the stepper until its next call. A controller that
raises (any exception, ``sys.exit`` and a ``KeyboardInterrupt`` of its own included: only the
user's Ctrl-C interrupts, :class:`~hosedrogue.controllers.sampled.CtrlC`), in ``reset`` or any call,
or returns a bad command stops the run there with a one-line message naming it, the time and the
problem; the stepper keeps what was computed (``completed`` False). A controller that
holds the stepper may end the run itself in its call (``stepper.stop(reason)``, e.g. the pilot
of a live flight ending it): nothing is integrated after that.
"""

from __future__ import annotations

import math
from typing import Mapping

from ..controllers.sampled import CtrlC, SampledController, one_line
from .budget import whole_multiple
from .stepper import StepperBase


def control_step(controllers: Mapping[str, SampledController], step_s: float) -> float:
    """The control step [s] that serves every controller: the greatest common divisor of their
    sample times, each a whole multiple of the RK4 step.

    Parameters
    ----------
    controllers : mapping
        Role -> :class:`~hosedrogue.controllers.sampled.SampledController`.
    step_s : float
        The RK4 step [s].

    Returns
    -------
    float
        [s]

    Raises
    ------
    ParameterError
        A sample time that is not a whole multiple of the RK4 step.
    """
    counts = [whole_multiple(c.sample_time_s, step_s, f"{c.table}.sample_time_s", "numerics.step_s")
              for c in controllers.values()]
    return math.gcd(*counts) * step_s


def drive(stepper: StepperBase, controllers: Mapping[str, SampledController], built: Mapping | None = None):
    """Run ``controllers`` on ``stepper`` from its reset state to the end; return its result.

    Parameters
    ----------
    stepper : StepperBase
        A reset stepper whose control step divides every controller's sample time.
    controllers : mapping
        Role -> :class:`~hosedrogue.controllers.sampled.SampledController`.
    built : mapping, optional
        Role -> controller objects already built from ``controllers`` (default: built here).

    Returns
    -------
    RunResult
        ``stepper.result()``: completed, or stopped with the reason (a controller's failure, a
        failed state, a miss).
    """
    built = dict(built) if built is not None else {role: spec.build() for role, spec in controllers.items()}
    plan = [(role, built[role], round(spec.sample_time_s / stepper.control_step_s), spec.name)
            for role, spec in controllers.items()]
    with CtrlC() as ctrl_c:
        _loop(stepper, plan, ctrl_c)
    return stepper.result()


def _loop(stepper: StepperBase, plan: list, ctrl_c: CtrlC) -> None:
    """Reset the controllers and run them on the stepper until it is done or one of them fails."""
    m = stepper.measurement
    for role, ctrl, _, name in plan:
        try:
            ctrl.reset(m)
        except BaseException as exc:
            if ctrl_c.is_ctrl_c(exc):
                raise
            stepper.stop(_failure(role, name, 0.0, "reset", f"raised {type(exc).__name__}: {one_line(exc)}"))
            return
    k = 0
    dt_steps, h, advance = stepper.spc, stepper.h, stepper._advance
    plan = [(role, ctrl, every, name, stepper.holder(role)) for role, ctrl, every, name in plan]
    while not stepper.done:
        t = (k * dt_steps) * h  # the stepper's time, to the bit
        for role, ctrl, every, name, hold in plan:
            if k % every:
                continue
            try:
                value = ctrl(t, m)
                problem = hold(value)  # a command's own __float__ or __iter__ is user code too
            except BaseException as exc:
                if ctrl_c.is_ctrl_c(exc):
                    raise
                problem = f"raised {type(exc).__name__}: {one_line(exc)}"
            if problem is not None:
                stepper.stop(_failure(role, name, t, "call", problem))
                break
        else:
            if stepper.done:  # a controller that ended the run itself (stepper.stop in its call)
                break
            advance()
            k += 1


def _failure(role: str, name: str, t: float, when: str, problem: str) -> str:
    """Why a controller stopped the run, and when (the stepper's message adds the last time kept)."""
    what = "reset" if when == "reset" else f"call at t = {t:.4f} s"
    return f"the {role} controller {name!r} {problem} (in its {what})"
