"""Linear time-invariant controller in state-space form, the common output of every design.

A `LinearController` reads the measured drogue offset from its equilibrium position,
y = [P_ny, P_nz] [m] (lateral along S_p y, vertical along S_p z), and returns the control force
on the drogue, u = [u_hor, u_ver] [N]:

    xc' = A xc + B y
    u   = C xc + D y

The negative-feedback sign is inside the controller (a proportional controller has D = -K_P),
so a closed loop is formed by applying u directly: no further sign change.

A design may carry an anti-windup gain ``K_aw`` (nc x 2): when the force the actuator can make,
u_a, differs from the command u (a drogue's control surfaces at their deflection limit), the loop
adds ``K_aw (u_a - u)`` to xc' (:mod:`hosedrogue.model.drogue_actuator`). The reference is the
equilibrium (y = 0); reference tracking for step-response figures is handled by the designs
(`pid`, `lqr`) themselves.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import control

__all__ = ["LinearController", "N_MEASUREMENTS", "N_FORCES"]

#: Number of measured outputs fed to a controller: [P_ny, P_nz] [m].
N_MEASUREMENTS = 2
#: Number of control forces produced by a controller: [u_hor, u_ver] [N].
N_FORCES = 2


def _as_matrix(name: str, value, shape: tuple[int, int]) -> np.ndarray:
    arr = np.array(value, dtype=float, copy=True)
    if arr.size == 0:
        arr = arr.reshape(shape)
    if arr.ndim != 2 or arr.shape != shape:
        raise ValueError(f"LinearController.{name} must have shape {shape}, got {np.shape(value)}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"LinearController.{name} must be finite, got non-finite entries")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class LinearController:
    """Continuous-time LTI controller: measured offset y [m] -> drogue force u [N].

    Parameters
    ----------
    A : array_like, shape (nc, nc)
        Controller state matrix [1/s].
    B : array_like, shape (nc, 2)
        Input matrix; its units make A xc + B y consistent with the state units.
    C : array_like, shape (2, nc)
        Output matrix, force per controller state.
    D : array_like, shape (2, 2)
        Feedthrough [N/m]; includes the feedback sign (negative for a stabilizing gain).
    anti_windup : array_like, shape (nc, 2), optional
        Anti-windup gain K_aw [state units / N]: xc' gains ``K_aw (u_a - u)`` when the actuator
        makes u_a instead of the commanded u. Default zeros (none).

    Notes
    -----
    The arrays are copied and made read-only at construction. A controller with no states
    (nc = 0) is a static gain u = D y.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    anti_windup: np.ndarray | None = None

    def __post_init__(self) -> None:
        a = np.asarray(self.A, dtype=float)
        nc = a.shape[0] if a.ndim == 2 else (0 if a.size == 0 else -1)
        if nc < 0:
            raise ValueError(f"LinearController.A must be a square 2-D array, got shape {np.shape(self.A)}")
        object.__setattr__(self, "A", _as_matrix("A", self.A, (nc, nc)))
        object.__setattr__(self, "B", _as_matrix("B", self.B, (nc, N_MEASUREMENTS)))
        object.__setattr__(self, "C", _as_matrix("C", self.C, (N_FORCES, nc)))
        object.__setattr__(self, "D", _as_matrix("D", self.D, (N_FORCES, N_MEASUREMENTS)))
        aw = np.zeros((nc, N_FORCES)) if self.anti_windup is None else self.anti_windup
        object.__setattr__(self, "anti_windup", _as_matrix("anti_windup", aw, (nc, N_FORCES)))

    @property
    def n_states(self) -> int:
        """Number of controller states nc."""
        return self.A.shape[0]

    @classmethod
    def static_zero(cls) -> "LinearController":
        """The "no controller" case: no states and u = 0 for every y."""
        return cls(
            A=np.zeros((0, 0)),
            B=np.zeros((0, N_MEASUREMENTS)),
            C=np.zeros((N_FORCES, 0)),
            D=np.zeros((N_FORCES, N_MEASUREMENTS)),
        )

    @classmethod
    def static_gain(cls, gain_n_per_m) -> "LinearController":
        """Memoryless controller u = D y with D = `gain_n_per_m` [N/m], shape (2, 2)."""
        return cls(
            A=np.zeros((0, 0)),
            B=np.zeros((0, N_MEASUREMENTS)),
            C=np.zeros((N_FORCES, 0)),
            D=gain_n_per_m,
        )

    def as_statespace(self) -> control.StateSpace:
        """The controller as a `control.StateSpace`, inputs [P_ny, P_nz], outputs [u_hor, u_ver]."""
        import control  # python-control only where a design or an analysis needs it (package docstring)

        return control.ss(
            self.A, self.B, self.C, self.D, 0,
            inputs=["P_ny", "P_nz"], outputs=["u_hor", "u_ver"],
        )

    def output(self, xc, y) -> np.ndarray:
        """Force u = C xc + D y [N] for controller state `xc` (nc,) and offset `y` (2,) [m]."""
        return self.C @ np.asarray(xc, dtype=float) + self.D @ np.asarray(y, dtype=float)

    def state_derivative(self, xc, y) -> np.ndarray:
        """Controller state rate xc' = A xc + B y for state `xc` (nc,) and offset `y` (2,) [m]."""
        return self.A @ np.asarray(xc, dtype=float) + self.B @ np.asarray(y, dtype=float)

    def closed_loop(self, plant) -> control.StateSpace:
        """Closed loop with a linear plant, u applied directly (sign already inside).

        Parameters
        ----------
        plant : control.StateSpace or control.TransferFunction
            Inputs [u_hor, u_ver] [N], outputs [P_ny, P_nz] [m].

        Returns
        -------
        control.StateSpace
            Autonomous closed loop with an external force disturbance d [N] added to u as
            input and the offset y [m] as output; its poles are the closed-loop poles.
        """
        import control

        plant_ss = plant if isinstance(plant, control.StateSpace) else control.tf2ss(plant)
        if plant_ss.ninputs != N_FORCES or plant_ss.noutputs != N_MEASUREMENTS:
            raise ValueError(
                f"plant must have {N_FORCES} inputs and {N_MEASUREMENTS} outputs, got "
                f"{plant_ss.ninputs} inputs and {plant_ss.noutputs} outputs"
            )
        return control.feedback(plant_ss, self.as_statespace(), sign=+1)
