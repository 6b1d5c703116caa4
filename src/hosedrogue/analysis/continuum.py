"""The continuum limit: the steady shape of the continuous hose (towed-cable problem).

The link model is a discretization of a perfectly flexible towed cable. With bending neglected
(``hose.bending`` is ignored here) its steady shape as the number of links grows is the solution
of the boundary-value problem below; the link-count error of the discrete model is measured
against it (:mod:`hosedrogue.studies.accuracy`, docs/convergence.md).

Formulation (docs/model.md, "Continuum limit"). Arc length s runs from the tow point (s = 0) to
the drogue (s = L). ``G(s)`` [N] is the resultant of every external load on the hose aft of s
plus the drogue's load; a cable carries it as tension along itself, so the unit tangent
(pointing aft) is ``e = G / |G|`` and

    dr/ds = G / |G|,                 r(0) = 0,
    dG/ds = -f(r, e),                G(L) = m_d g z + D_d(r(L)),

with the load per length ``f = mu g z + d(r, e)``: gravity and the same drag laws as the links
(docs/model.md §3) for a hose element at rest in the air velocity ``w(r) = [-V, 0, 0] + w_wake(y, z)``:
``V_t = -w``, ``n = -e``, ``v_t = V_t . n``, ``V_n = V_t - v_t n``,
``d = -1/2 rho pi d_o (c_t v_t |v_t| n + c_n |V_n| V_n)``; the drogue drag
``D_d = -1/2 rho |w| (-w) (pi d_d^2 / 4) c_d`` at the drogue.

An elastic hose (finite ``hose.axial_stiffness_n`` = EA) is stretched by its tension: with s
the material (unstretched) arc length and the loads per material length, ``dr/ds = (1 + |G| /
EA) G / |G|`` (docs/model.md §11); its actual length is ``L + int |G| / EA ds``.

Because the drogue end carries a known load once its position is known, the problem is solved by
shooting on the drogue position ``r_L`` (3 unknowns): integrate the six equations from s = L
back to s = 0 starting from ``r(L) = r_L``, ``G(L) = m_d g z + D_d(r_L)`` (DOP853, relative
tolerance 1e-13), and solve ``r(0; r_L) = 0`` by Newton's method (MINPACK ``hybr``). The
residual ``|r(0)|`` is the position error of the result; it is driven below 1e-11 m, far below
the 1e-9 m asked of it. The integration is uniquely defined as long as the tension never
vanishes (always true with the drogue's drag pulling aft).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.integrate
import scipy.optimize

from ..constants import G0
from ..environment.atmosphere import density
from ..environment.wake import wake_field
from ..errors import EquilibriumError
from ..model.frame import SteadyFrame, steady_frame
from ..spec.params import PAPER, Params

#: Position tolerance of the shooting solution [m]: the tow point must be reproduced this well.
POSITION_TOLERANCE_M = 1e-9
#: Integrator tolerances: relative 1e-13 on a 16 m hose gives ~1e-12 m of truncation error.
RTOL, ATOL = 1e-13, 1e-12


@dataclass(frozen=True)
class ContinuumShape:
    """Steady shape of the continuous hose, in S_p (x forward, y right, z down), SI units."""

    s_m: np.ndarray  #: arc length from the tow point (k,) [m] (material arc length for an elastic hose)
    position_m: np.ndarray  #: hose centreline (k, 3) [m]; row 0 is the tow point
    tension_n: np.ndarray  #: load carried along the hose, G(s) (k, 3) [N]
    drogue_position_m: np.ndarray  #: (3,) [m]
    drogue_drag_n: np.ndarray  #: aerodynamic force on the drogue (3,) [N]
    tow_force_n: np.ndarray  #: force the hose exerts on the tow point, G(0) (3,) [N]
    balance_ratio: float  #: D = V_D / L_H
    position_error_m: float  #: |r(0)| of the shooting solution [m]
    solver: object = field(repr=False)  #: scipy OptimizeResult of the shooting

    @property
    def exit_tension_n(self) -> float:
        """Exit tension [N]: the tension at the tow point, |G(0)| (the continuous hose carries its
        load along its tangent)."""
        return float(np.linalg.norm(self.tension_n[0]))

    def to_dict(self) -> dict:
        return {
            "model": "continuum",
            "drogue_position_m": self.drogue_position_m.tolist(),
            "drogue_drag_n": float(np.linalg.norm(self.drogue_drag_n)),
            "drogue_drag_vector_n": self.drogue_drag_n.tolist(),
            "tow_force_n": self.tow_force_n.tolist(),
            "exit_tension_n": self.exit_tension_n,
            "balance_ratio": self.balance_ratio,
            "position_error_m": self.position_error_m,
            # MINPACK may stop with "no further improvement" once at round-off; what counts is
            # that the tow point is reproduced (checked in solve_continuum)
            "solver_success": bool(self.position_error_m < POSITION_TOLERANCE_M),
            "solver_message": str(self.solver.message),
        }


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of two 3-vectors (numpy's cross costs ~10 us a call in the integrator's inner loop)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


class _Loads:
    """Air and load functions of the continuous hose for one parameter set, in a steady frame."""

    def __init__(self, params: Params, frame: SteadyFrame):
        hose, drogue, flight = params.hose, params.drogue, params.flight
        self.params = params
        self.level = frame.is_level
        self.acc = np.asarray(frame.acceleration_m_s2, dtype=float)
        self.omega = np.asarray(frame.omega_rad_s, dtype=float)
        self.air_omega = np.asarray(frame.air_omega, dtype=float)
        self.wake_factor = frame.wake_factor
        self.rho = density(flight.altitude_m) * flight.density_scale
        self.V = flight.airspeed_m_s
        self.mu = hose.mass_per_length_kg_m
        self.q_ct = 0.5 * self.rho * math.pi * hose.outer_diameter_m * hose.tangential_drag_coefficient
        self.q_cn = 0.5 * self.rho * math.pi * hose.outer_diameter_m * hose.normal_drag_coefficient
        self.cda_d = math.pi * drogue.diameter_m**2 / 4.0 * drogue.drag_coefficient
        self.m_d = drogue.mass_kg
        self.wake_on = params.wake.enabled and self.rho > 0.0
        self.EA = hose.axial_stiffness_n  # inf: inextensible

    def air(self, r: np.ndarray) -> np.ndarray:
        w = np.array([-self.V, 0.0, 0.0])
        if self.wake_on:
            p = self.params
            vy, vz = wake_field(r[1], r[2], p.tanker, p.wake, self.V, density(p.flight.altitude_m)
                                * p.flight.density_scale)
            if self.level:
                w[1] += float(vy)
                w[2] += float(vz)
            else:
                w[1] += self.wake_factor * float(vy)
                w[2] += self.wake_factor * float(vz)
        if not self.level:
            w -= _cross(self.air_omega, r)  # the air at rest far away, seen from the turning frame
        return w

    def gravity(self, r: np.ndarray) -> np.ndarray:
        """Apparent gravity [m/s^2] at r: g z, or in a steady turn or climb ``g b_g - a_0 - Omega x
        (Omega x r)``."""
        if self.level:
            return np.array([0.0, 0.0, G0])
        return self.acc - _cross(self.omega, _cross(self.omega, r))

    def per_length(self, r: np.ndarray, e: np.ndarray) -> np.ndarray:
        """Gravity and drag per length of hose [N/m] at r with aft tangent e."""
        f = self.mu * self.gravity(r)
        if self.rho > 0.0:
            vrel = -self.air(r)
            nk = -e
            vt = vrel @ nk
            vn = vrel - vt * nk
            f += -self.q_ct * vt * abs(vt) * nk - self.q_cn * np.linalg.norm(vn) * vn
        return f

    def drogue_drag(self, r: np.ndarray) -> np.ndarray:
        if self.rho == 0.0:
            return np.zeros(3)
        vr = -self.air(r)
        return -0.5 * self.rho * self.cda_d * np.linalg.norm(vr) * vr

    def rhs(self, s, y):
        r, G = y[:3], y[3:]
        T = np.linalg.norm(G)
        e = G / T
        # an elastic hose is stretched by its tension: a material element ds is (1 + T / EA) ds long
        return np.concatenate([(1.0 + T / self.EA) * e, -self.per_length(r, e)])


def _integrate(loads: _Loads, r_L: np.ndarray, L: float, dense: bool = False):
    G_L = loads.m_d * loads.gravity(r_L) + loads.drogue_drag(r_L)
    y0 = np.concatenate([r_L, G_L])
    return scipy.integrate.solve_ivp(loads.rhs, (L, 0.0), y0, method="DOP853", rtol=RTOL, atol=ATOL,
                                     dense_output=dense)


def _initial_guess(loads: _Loads, L: float) -> np.ndarray:
    """Drogue position of a straight hose along the tow force without wake (a cheap start)."""
    drag = loads.drogue_drag(np.zeros(3)) if loads.rho > 0 else np.zeros(3)
    G = drag + (loads.m_d + 0.5 * loads.mu * L) * loads.gravity(np.zeros(3))
    if loads.rho > 0:
        G += 0.5 * L * loads.per_length(np.zeros(3), G / np.linalg.norm(G))
    return L * G / np.linalg.norm(G)


def solve_continuum(params: Params = PAPER, samples: int = 201, frame: SteadyFrame | None = None) -> ContinuumShape:
    """Steady shape of the continuous hose (bending neglected) for steady air (wake as configured)
    in the tanker's initial steady flight (a coordinated turn or a climb: ``params.tanker_motion``,
    docs/model.md §9).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and wake (``hose.links``, ``bending``, ``mass_lumping`` and the
        link inertia are irrelevant here; so is the drogue's rotational inertia, whose gyroscopic
        moment in a turn the continuous hose without bending stiffness cannot carry).
    samples : int
        Number of points of the returned shape, evenly spaced in arc length.
    frame : SteadyFrame, optional
        The frame's apparent acceleration [m/s^2], rotation [rad/s] and wake factor, instead of
        those of ``params.tanker_motion``'s initial flight (:func:`hosedrogue.model.frame.steady_frame`),
        e.g. a gravity vector rotated by other means, or one term of a turn alone.

    Raises
    ------
    EquilibriumError
        If the shooting does not reproduce the tow point to :data:`POSITION_TOLERANCE_M`.
    """
    if frame is None:
        frame = steady_frame(params.tanker_motion, params.flight.airspeed_m_s)
    loads = _Loads(params, frame)
    L = params.hose.length_m

    def residual(r_L):
        sol = _integrate(loads, r_L, L)
        return sol.y[:3, -1]

    r_L0 = _initial_guess(loads, L)
    sol = scipy.optimize.root(residual, r_L0, method="hybr", options={"xtol": 1e-14})
    r_L = sol.x
    ivp = _integrate(loads, r_L, L, dense=True)
    err = float(np.linalg.norm(ivp.y[:3, -1]))
    if not (ivp.success and err < POSITION_TOLERANCE_M):
        raise EquilibriumError(
            f"continuum shape not found: tow point missed by {err:.3g} m (solver: {sol.message})", sol)
    s = np.linspace(0.0, L, samples)
    Y = ivp.sol(s)
    # shift by the remaining tow-point miss so that the returned shape starts at the origin exactly
    shift = ivp.y[:3, -1]
    pos = Y[:3].T - shift
    return ContinuumShape(
        s_m=s,
        position_m=pos,
        tension_n=Y[3:].T.copy(),
        drogue_position_m=r_L - shift,
        drogue_drag_n=loads.drogue_drag(r_L),
        tow_force_n=ivp.y[3:, -1].copy(),
        balance_ratio=float((r_L - shift)[2] / L),
        position_error_m=err,
        solver=sol,
    )
