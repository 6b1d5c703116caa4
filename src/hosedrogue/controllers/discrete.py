"""The built-in linear drogue controllers in sampled-data mode: the zero-order-hold
discretization of a design and its law as a controller of the sampled-data interface
(:mod:`hosedrogue.controllers.sampled`, docs/controllers.md), with the anti-windup of a drogue
steered by control surfaces (docs/model.md §10). The compiled loop runs the same law
(:func:`hosedrogue.model.sampled.fl_linear_sampled_run`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .linear import LinearController

__all__ = ["DiscreteLinearController", "discretize", "discretize_anti_windup", "linear_controller_factory"]


def discretize(controller: LinearController, sample_time_s: float):
    """The zero-order-hold discretization of a linear controller: with its input sampled every
    T and its state updated as ``xd[k+1] = Ad xd[k] + Bd y[k]``, ``u[k] = Cd xd[k] + Dd y[k]``,
    where ``[[Ad, Bd], [0, I]] = expm([[A, B], [0, 0]] T)``, ``Cd = C``, ``Dd = D``.

    Parameters
    ----------
    controller : LinearController
        Continuous controller, measured offset [m] -> force [N].
    sample_time_s : float
        T [s], > 0.

    Returns
    -------
    Ad, Bd, Cd, Dd : numpy.ndarray
        (nc, nc), (nc, 2), (2, nc), (2, 2).
    """
    from scipy.linalg import expm

    nc = controller.n_states
    block = np.zeros((nc + 2, nc + 2))
    block[:nc, :nc] = controller.A
    block[:nc, nc:] = controller.B
    e = expm(block * float(sample_time_s))
    return (np.ascontiguousarray(e[:nc, :nc]), np.ascontiguousarray(e[:nc, nc:]),
            np.ascontiguousarray(controller.C, dtype=np.float64), np.ascontiguousarray(controller.D, dtype=np.float64))


def discretize_anti_windup(controller: LinearController, sample_time_s: float) -> np.ndarray:
    """The zero-order-hold discretization of a controller's anti-windup input: ``Bw`` of
    ``xd[k+1] = Ad xd[k] + Bd y[k] + Bw e[k]`` for ``xc' = A xc + B y + K_aw e``, e held over
    the sample: ``[[Ad, Bw], [0, I]] = expm([[A, K_aw], [0, 0]] T)``.

    Parameters
    ----------
    controller : LinearController
        Its ``A`` and ``anti_windup`` K_aw (nc, 2) [state units / N].
    sample_time_s : float
        T [s], > 0.

    Returns
    -------
    numpy.ndarray (nc, 2)
    """
    from scipy.linalg import expm

    nc = controller.n_states
    block = np.zeros((nc + 2, nc + 2))
    block[:nc, :nc] = controller.A
    block[:nc, nc:] = controller.anti_windup
    return np.ascontiguousarray(expm(block * float(sample_time_s))[:nc, nc:])


class DiscreteLinearController:
    """A built-in linear drogue controller as a sampled-data controller of this interface: its
    zero-order-hold discretization (:func:`discretize`) acting on the measured drogue offset from
    its balance position, ``y = drogue_position_m[1:] - drogue_balance_m[1:]`` [m]. The compiled
    loop runs the same law when a built-in controller has ``sample_time_s`` > 0.

    With the drogue's control surfaces commanded by force, its anti-windup acts as the continuous
    one's, sampled: the error e [N] is the force the clipped mixing makes at the measured dynamic
    pressure ``m.drogue_q_pa`` minus the command, and ``xd`` gains ``Bw e``
    (:func:`discretize_anti_windup`; docs/model.md §10).

    Parameters
    ----------
    controller : LinearController
        The continuous design.
    sample_time_s : float
        T [s].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (their mixing and deflection limit give the anti-windup error).
    """

    def __init__(self, controller: LinearController, sample_time_s: float, drogue_actuator=None):
        from ..model import drogue_actuator as DA

        self.Ad, self.Bd, self.Cd, self.Dd = discretize(controller, sample_time_s)
        self.x = np.zeros(self.Ad.shape[0])
        self.act = None
        if drogue_actuator is not None and drogue_actuator.command == "force":
            self.act = DA.actuator_array(np.zeros(DA.ACT_IDEAL), drogue_actuator, None, controller.n_states)
            self.Bw = discretize_anti_windup(controller, sample_time_s)
            self._mixing_error = DA.mixing_error

    def reset(self, m: Measurement) -> None:
        """Zero the controller's state.

        Parameters
        ----------
        m : Measurement
            The first measurement (unused).
        """
        self.x[:] = 0.0

    def __call__(self, t: float, m: Measurement) -> np.ndarray:
        """The force (u_y, u_z) [N] for the measurement m at time t [s]; advances the state.

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        numpy.ndarray (2,)
        """
        y = m.drogue_position_m[1:] - m.drogue_balance_m[1:]
        u = self.Cd @ self.x + self.Dd @ y
        self.x = self.Ad @ self.x + self.Bd @ y
        if self.act is not None:
            self.x += self.Bw @ np.array(self._mixing_error(u[0], u[1], m.drogue_q_pa, self.act))
        return u


def linear_controller_factory(controller: LinearController, sample_time_s: float, drogue_actuator=None) -> Callable:
    """A factory of :class:`DiscreteLinearController` (for :class:`SampledController`).

    Parameters
    ----------
    controller : LinearController
        The continuous design.
    sample_time_s : float
        T [s].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (the anti-windup's error).

    Returns
    -------
    callable
        ``factory() -> DiscreteLinearController``.
    """
    return _LinearFactory(controller, float(sample_time_s), drogue_actuator)


@dataclass(frozen=True)
class _LinearFactory:
    """A picklable factory of a :class:`DiscreteLinearController` (Dask workers receive it by value)."""

    controller: LinearController
    sample_time_s: float
    drogue_actuator: Any = None

    def __call__(self) -> DiscreteLinearController:
        return DiscreteLinearController(self.controller, self.sample_time_s, self.drogue_actuator)
