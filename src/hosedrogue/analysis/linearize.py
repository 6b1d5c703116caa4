"""Numerical linearization about the balance position (paper Eqs. 31-32; docs/model.md §5).

States are the deviations of ``x = [q, qd]`` (4n) from the equilibrium, inputs the control force
``u = [u_hor, u_ver]`` [N] at the drogue, outputs the drogue's lateral and vertical offset
``[P_ny, P_nz]`` [m] from its balance position. Jacobians are central differences of the
compiled right-hand side in steady air (wake as configured, no gusts): with a perturbation of
1e-6 (rad, rad/s, N) the truncation error is ~1e-12 of the derivative's scale, far below any
effect a controller designer can see.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import chain_dynamics as CD
from ..errors import ParameterError
from ..model.system import HoseModel
from ..spec.params import PAPER, Params
from .equilibrium import Equilibrium, solve_equilibrium

#: Central-difference perturbation for states [rad, rad/s] and inputs [N].
FD_STEP = 1e-6


@dataclass(frozen=True)
class LinearModel:
    """x' = A x + B u, y = C x + D u about ``equilibrium``; SI units."""

    A: np.ndarray  #: (4n, 4n) state matrix [1/s and 1/s^2]; states [rad, rad/s]
    B: np.ndarray  #: (4n, 2) input matrix; inputs u_hor, u_ver [N]
    C: np.ndarray  #: (2, 4n) output matrix; outputs P_ny, P_nz [m]
    D: np.ndarray  #: (2, 2) feedthrough (zero)
    equilibrium: Equilibrium  #: the balance position linearized about
    params: Params  #: the parameter set

    @property
    def ss(self):
        """python-control StateSpace with named inputs and outputs."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, inputs=["u_hor", "u_ver"],
                          outputs=["P_ny", "P_nz"], name="hose_drogue")

    @property
    def poles(self) -> np.ndarray:
        return np.linalg.eigvals(self.A)


def _steady_derivative(model: HoseModel):
    args = model.kernel_args(steady=True)

    def f(x, u):
        dx = np.empty_like(x)
        CD.rhs(0.0, x, u, *args, dx)
        return dx

    return f


def _drogue_yz(model: HoseModel, x: np.ndarray) -> np.ndarray:
    """Drogue lateral and vertical position [m] at state x: the last row of
    :meth:`HoseModel.joint_positions` (the kernels' one definition)."""
    return model.joint_positions(x[: 2 * model.n])[-1, 1:]


def linearize(params: Params = PAPER, equilibrium: Equilibrium | None = None,
              model: HoseModel | None = None) -> LinearModel:
    """Linear model about the balance position of ``params`` (wake on or off as configured), in
    the tanker's initial steady flight (level, or a steady turn or climb: ``params.tanker_motion``).

    Parameters
    ----------
    params : Params
        Parameter set (turbulence is ignored: steady air).
    equilibrium : Equilibrium, optional
        The balance position (solved if not given).
    model : HoseModel, optional
        A model of ``params`` to reuse.

    Returns
    -------
    LinearModel
        Central-difference Jacobians (step :data:`FD_STEP`) in SI units.
    """
    model = model if model is not None else HoseModel(params)
    if model.elastic:
        raise ParameterError(f"hose.axial_stiffness_n = {model.params.hose.axial_stiffness_n!r}: the linearization is "
                             "of the rigid chain (axial_stiffness_n = inf); a drogue controller for an elastic hose "
                             "is designed on its rigid twin (controllers.design.rigid_twin)")
    eq = equilibrium if equilibrium is not None else solve_equilibrium(params, model=model)
    f = _steady_derivative(model)
    x0 = eq.state
    u0 = np.zeros(2)
    nx = x0.size
    A = np.empty((nx, nx))
    C = np.empty((2, nx))
    for i in range(nx):
        xp, xm = x0.copy(), x0.copy()
        xp[i] += FD_STEP
        xm[i] -= FD_STEP
        A[:, i] = (f(xp, u0) - f(xm, u0)) / (2 * FD_STEP)
        C[:, i] = (_drogue_yz(model, xp) - _drogue_yz(model, xm)) / (2 * FD_STEP)
    B = np.empty((nx, 2))
    for j in range(2):
        up, um = u0.copy(), u0.copy()
        up[j] += FD_STEP
        um[j] -= FD_STEP
        B[:, j] = (f(x0, up) - f(x0, um)) / (2 * FD_STEP)
    return LinearModel(A, B, C, np.zeros((2, 2)), eq, model.params)
