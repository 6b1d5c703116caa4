"""The hose-drogue model: validated parameters turned into the arrays the numba core works on.

:class:`HoseModel` is the Python-facing object: ``accelerations``, ``mass_matrix``, ``energy``,
``joint_positions`` and ``outputs`` at a state, plus everything the integrators and the
equilibrium solver need. The air environment (free stream, tanker wake, gust record) is part of
the model so that every force evaluation asks the same air-velocity function.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from ..constants import G0
from ..environment.atmosphere import density
from ..environment.turbulence import GustRecord, generate_gusts
from ..environment.wake import wake_scalars
from ..spec.params import PAPER, ParameterError, Params
from . import elastic as E
from . import frame
from . import chain_dynamics as CD, chain_loads as CL, layout as LY


@dataclass(frozen=True)
class StateOutputs:
    """Quantities derived from one state, all in S_p (x forward, y right, z down), SI units."""

    qdd: np.ndarray  #: generalized accelerations (2n,) [rad/s^2]
    joints_m: np.ndarray  #: joint positions (n+1, 3) [m], row 0 is the tow point
    joint_velocities_m_s: np.ndarray  #: joint velocities (n+1, 3) [m/s]
    drogue_drag_n: np.ndarray  #: aerodynamic force on the drogue (3,) [N]
    tow_force_n: np.ndarray  #: force the hose exerts on the tow point (3,) [N]
    exit_tension_n: float  #: exit tension T_0, the hose's pull along it at the exit [N]


def lumped_masses(params: Params, lengths: np.ndarray) -> tuple[np.ndarray, float]:
    """Joint masses of links of the given lengths (docs/model.md §2; ``params.hose.mass_lumping``).

    Parameters
    ----------
    params : Params
        Hose (mass per length, ``mass_lumping``) and drogue (mass).
    lengths : array (n,)
        Link lengths [m], from the tow point aft (they need not be equal: the engagement's chain
        has an exit link of its own length, ``engagement/chain.py``).

    Returns
    -------
    M : array (n,)
        ``M[k]`` [kg] sits at joint k+1; the drogue's mass is in ``M[n-1]``. ``aft``: each link's
        mass at its aft joint; ``split``: half of each link's mass at each end joint.
    M_tow : float
        The mass lumped at the tow point (joint 0) [kg]: half of link 0 for ``split``, else 0.
    """
    link_mass = params.hose.mass_per_length_kg_m * np.asarray(lengths, dtype=np.float64)
    if params.hose.mass_lumping == "aft":
        M = link_mass.copy()
        M_tow = 0.0
    else:  # "split": half of link k at joint k-1, half at joint k
        M = 0.5 * link_mass
        M[:-1] += 0.5 * link_mass[1:]
        M_tow = 0.5 * float(link_mass[0])
    M[-1] += params.drogue.mass_kg
    return M, M_tow


def link_inertias(params: Params, lengths: np.ndarray, drogue: bool = True) -> np.ndarray:
    """Link rotational inertias J [kg m^2] (n,): Table 1's fixed value (``link_inertia = "paper"``)
    or the rod's m l^2 / 12 (``"rod"``) of links of the given lengths [m], the drogue's inertia
    added to the last link's (docs/model.md §2).

    The drogue is a body on the last link's axis without a roll degree of freedom: its inertia
    about its pitch and yaw axes is transverse inertia of that link, kinetic energy
    ``J_d |omega|^2 / 2`` with the link's angular velocity ``|omega|^2 = c2^2 thd1^2 + thd2^2``,
    the same in either angle chart (the paper's form ``J_d (thd1^2 + thd2^2) / 2`` also counts
    the frames' twist ``s2 thd1`` about the link, which is no motion of the drogue).

    Parameters
    ----------
    params : Params
        ``hose.link_inertia``, ``hose.link_inertia_kg_m2`` [kg m^2], ``hose.mass_per_length_kg_m``
        [kg/m] and ``drogue.inertia_kg_m2`` [kg m^2].
    lengths : array_like (n,)
        Link lengths [m].
    drogue : bool
        Add the drogue's inertia to the last link (default; False: the links alone).

    Returns
    -------
    numpy.ndarray (n,)
        Link inertias [kg m^2].
    """
    lengths = np.asarray(lengths, dtype=np.float64)
    if params.hose.link_inertia == "paper":
        J = np.full(lengths.size, params.hose.link_inertia_kg_m2)
    else:
        J = params.hose.mass_per_length_kg_m * lengths**3 / 12.0
    if drogue:
        J[-1] += params.drogue.inertia_kg_m2
    return J


class HoseModel:
    """Arrays and entry points of one parameter set.

    Parameters
    ----------
    params : Params
        Validated parameters (default: the paper's case).
    gusts : GustRecord, optional
        Turbulence record; by default generated from ``params.turbulence`` (its window and seed).
    duration_s : float, optional
        Length of the run [s] the gust record must cover when the turbulence window has no end
        (``turbulence.duration_s = inf``, the default); without it such a model has steady air
        only (enough for balance positions and linearizations) and :meth:`gusts_cover` says so.
    lengths : array_like (n,), optional
        Link lengths [m], exit link first, instead of ``hose.links`` equal links of
        ``hose.length_m`` (the engagement's chain at a given mesh and free length); the model's
        ``params`` then carry ``hose.length_m = sum(lengths)`` and ``hose.links = n``. Masses and
        inertias follow from the lengths (:func:`lumped_masses`, :func:`link_inertias`).

    Notes
    -----
    The tanker's motion (``params.tanker_motion``, docs/model.md §9) is part of the environment:
    ``env`` carries its table (the kernels evaluate the frame terms at every time),
    ``steady_env`` its initial steady flight (level, or a steady coordinated turn or climb).
    """

    def __init__(self, params: Params = PAPER, gusts: GustRecord | None = None, duration_s: float | None = None,
                 lengths=None):
        if lengths is not None:
            lengths = np.array(lengths, dtype=np.float64).ravel()
            if lengths.size < 1 or not np.all(np.isfinite(lengths) & (lengths > 0)):
                raise ParameterError(f"lengths = {lengths!r}: must be one or more finite link lengths > 0 m")
            params = params.replace(hose={"length_m": float(np.sum(lengths)), "links": int(lengths.size)})
        self.params = params
        hose, drogue, flight = params.hose, params.drogue, params.flight
        n = hose.links
        self.n = n
        self.rho = density(flight.altitude_m) * flight.density_scale
        self.l = np.full(n, hose.link_length_m) if lengths is None else lengths
        #: joint masses [kg]: M[k] sits at joint k+1 (docs/model.md §2); M_tow at the tow point (joint 0)
        self.M, self.M_tow = lumped_masses(params, self.l)
        self.S = np.cumsum(self.M[::-1])[::-1].copy()
        self.J = link_inertias(params, self.l)
        inertia_area = math.pi * (hose.outer_diameter_m**4 - hose.inner_diameter_m**4) / 64.0
        bending = {"off": LY.BENDING_OFF, "paper": LY.BENDING_PAPER, "moment": LY.BENDING_MOMENT}
        ps = np.zeros(LY.PS_SIZE)
        ps[LY.PS_G] = G0
        ps[LY.PS_RHO] = self.rho
        ps[LY.PS_V] = flight.airspeed_m_s
        ps[LY.PS_DO] = hose.outer_diameter_m
        ps[LY.PS_CT] = hose.tangential_drag_coefficient
        ps[LY.PS_CN] = hose.normal_drag_coefficient
        ps[LY.PS_DROGUE_CDA] = math.pi * drogue.diameter_m**2 / 4.0 * drogue.drag_coefficient
        ps[LY.PS_EI] = hose.elastic_modulus_pa * inertia_area
        ps[LY.PS_BENDING] = bending[hose.bending]
        ps[LY.PS_DRAG_QUAD] = {"midpoint": LY.DRAG_MIDPOINT, "gauss2": LY.DRAG_GAUSS2}[hose.drag_quadrature]
        ps[LY.PS_BEND_DAMP] = hose.bending_damping_n_m2_s
        ps[LY.PS_M_TOW] = self.M_tow
        ps[LY.PS_EA] = hose.axial_stiffness_n
        ps[LY.PS_CA] = hose.axial_damping_n_s
        self.ps = ps
        #: elastic links (finite axial stiffness): the hose state is [q, qd, lam, lamd] (6n), lam
        #: the links' actual lengths [m] (:mod:`hosedrogue.model.elastic`)
        self.elastic = hose.elastic
        if gusts is None:
            turb = params.turbulence
            if turb.enabled and math.isinf(turb.duration_s) and duration_s is None:
                # no run length: steady air only (the window is empty), see gusts_cover
                gusts = generate_gusts(turb, flight.airspeed_m_s, duration_s=0.0)
            else:
                gusts = generate_gusts(turb, flight.airspeed_m_s, run_duration_s=duration_s)
        self.gusts = gusts
        #: the tanker's motion (docs/model.md §9) as the compiled core reads it after env's
        #: scalars (None in straight and level flight); ``steady_env`` holds the initial steady
        #: flight only, the frame of the balance position and the linearization
        V0 = flight.airspeed_m_s
        self.motion_table = frame.motion_table(params.tanker_motion, V0)
        self.env = frame.with_motion(self._environment(gusts), self.motion_table, V0)
        self.steady_env = frame.with_motion(self._environment(None),
                                            frame.motion_table(params.tanker_motion, V0, steady=True), V0)

    def _environment(self, gusts: GustRecord | None) -> np.ndarray:
        """The env array without the tanker's motion; ``gusts=None`` gives steady air (no turbulence)."""
        p = self.params
        env = np.zeros(LY.ENV_SIZE)
        env[LY.ENV_V] = p.flight.airspeed_m_s
        if self.rho > 0.0:  # without air there are no air forces, and the wake's circulation W/(rho V b0) is undefined
            env[LY.ENV_WAKE:LY.ENV_WAKE + 6] = wake_scalars(p.tanker, p.wake, p.flight.airspeed_m_s, self.rho)
        if gusts is None or not p.turbulence.enabled:
            env[LY.ENV_T_ON] = math.inf
            env[LY.ENV_T_OFF] = math.inf
            env[LY.ENV_G_DT] = 1.0
        else:
            env[LY.ENV_FROZEN] = 1.0 if p.turbulence.distribution == "frozen" else 0.0
            env[LY.ENV_T_ON] = gusts.t_on_s
            env[LY.ENV_T_OFF] = gusts.t_off_s
            env[LY.ENV_G_T0] = gusts.t0_s
            env[LY.ENV_G_DT] = gusts.dt_s
            env[LY.ENV_G_CUBIC] = 1.0 if gusts.interpolation == "cubic" else 0.0
        return env

    def gusts_cover(self, duration_s: float) -> bool:
        """Whether the gust record covers a run of ``duration_s`` [s]: turbulence off, or its
        window ends before the run does, or the record reaches the run's end.

        Parameters
        ----------
        duration_s : float
            Length of the run [s].

        Returns
        -------
        bool
        """
        turb = self.params.turbulence
        if not turb.enabled:
            return True
        needed = min(turb.start_s + turb.duration_s, duration_s)
        return needed <= turb.start_s or self.gusts.t_off_s >= needed

    @property
    def gust_values(self) -> np.ndarray:
        return np.ascontiguousarray(self.gusts.values, dtype=np.float64)

    def kernel_args(self, steady: bool = False) -> tuple:
        """The model's arrays in the order every kernel takes them: ``(l, M, S, J, ps, env, gust)``.

        Parameters
        ----------
        steady : bool
            Steady air (no gusts; the wake as configured) instead of the model's turbulence.

        Returns
        -------
        tuple
            Link lengths ``l`` [m], joint masses ``M`` [kg], suffix masses ``S`` [kg], link
            inertias ``J`` [kg m^2], the ``ps`` and ``env`` scalar arrays and the gust record
            values [m/s]; e.g. ``chain_dynamics.rhs(t, x, u, *model.kernel_args(), dx)``.
        """
        env = self.steady_env if steady else self.env
        return (self.l, self.M, self.S, self.J, self.ps, env, self.gust_values)

    # --- state-level entry points -------------------------------------------------------------
    @property
    def state_size(self) -> int:
        """Length of the hose state: 4n ``[q, qd]``, or 6n ``[q, qd, lam, lamd]`` for elastic links."""
        return (6 if self.elastic else 4) * self.n

    def rigid_only(self, what: str) -> "HoseModel":
        """This model, if its links are rigid; for a path that runs the rigid chain only.

        Parameters
        ----------
        what : str
            The path, for the message (e.g. "the fixed-length stepper").

        Returns
        -------
        HoseModel
            ``self``.

        Raises
        ------
        ParameterError
            One line naming ``hose.axial_stiffness_n`` when the links are elastic.
        """
        if self.elastic:
            raise ParameterError(f"hose.axial_stiffness_n = {self.params.hose.axial_stiffness_n!r}: {what} runs rigid "
                                 "links (axial_stiffness_n = inf); simulate an elastic hose with a continuous controller")
        return self

    def _check_state(self, x: np.ndarray) -> np.ndarray:
        x = np.ascontiguousarray(x, dtype=np.float64)
        if x.shape != (self.state_size,):
            layout = "[q, qd, lam, lamd]" if self.elastic else "[q, qd]"
            raise ValueError(f"state has shape {x.shape}; expected ({self.state_size},) = {layout} for n = {self.n}")
        return x

    def outputs(self, x, t: float = 0.0, u=(0.0, 0.0), steady: bool = False, narrow: bool = False) -> StateOutputs:
        """Accelerations and derived outputs at state ``x`` = [q, qd] (elastic: [q, qd, lam,
        lamd], and ``qdd`` then holds the angles' and the lengths' accelerations, 3n), time t [s],
        force u [N]; ``narrow``: rigid links evaluated by the entry compiled for level flight in
        still air at rest where that is the case (:func:`chain_dynamics.point_kernel`; the same
        numbers)."""
        x = self._check_state(x)
        ws = CD.make_workspace(self.n)
        env = self.steady_env if steady else self.env
        if self.elastic:
            ews = E.make_elastic_workspace(self.n)
            E.elastic_evaluate_ws(float(t), x, np.asarray(u, dtype=np.float64), self.l, self.M, self.J, self.ps,
                                  env, self.gust_values, ws, ews, 0.0, x)
            qdd = np.concatenate([ws[CD.WS_QDD], ews[E.EWS_LAMDD]])
        else:
            kernel = CD.point_kernel(env, x, float(t), narrow)
            kernel(False, float(t), x, np.asarray(u, dtype=np.float64), self.l, self.M, self.J, self.ps, env,
                   self.gust_values, ws, *CD.static_scratch(self.n), np.empty(2 * self.n))
            qdd = ws[CD.WS_QDD]
        r, v, dd, tf = ws[CD.WS_R], ws[CD.WS_V], ws[CD.WS_DRAG], ws[CD.WS_TOW]
        return StateOutputs(qdd, r, v, dd, tf, float(ws[CD.WS_T0][0]))

    def accelerations(self, q, qd, t: float = 0.0, u=(0.0, 0.0)) -> np.ndarray:
        """Generalized accelerations [rad/s^2] (2n,)."""
        return self.outputs(np.concatenate([q, qd]), t, u).qdd

    def derivative(self, t: float, x, u=(0.0, 0.0)) -> np.ndarray:
        """dx/dt of the state x = [q, qd] (4n,), or of [q, qd, lam, lamd] (6n,) for elastic links."""
        x = self._check_state(x)
        if self.elastic:
            n = self.n
            acc = self.outputs(x, t, u).qdd
            return np.concatenate([x[2 * n: 4 * n], acc[: 2 * n], x[5 * n:], acc[2 * n:]])
        dx = np.empty_like(x)
        CD.rhs(float(t), x, np.asarray(u, dtype=np.float64), self.l, self.M, self.S, self.J,
               self.ps, self.env, self.gust_values, dx, self._point_work())
        return dx

    def _point_work(self) -> tuple:
        """This thread's scratch of :func:`chain_dynamics.rhs` (made at its first use)."""
        works = self.__dict__.setdefault("_works", {})
        key = threading.get_ident()
        work = works.get(key)
        if work is None:
            work = works[key] = CD.point_work(self.n)
        return work

    def accelerations_dense(self, q, qd, t: float = 0.0, u=(0.0, 0.0)) -> np.ndarray:
        """qdd from the dense mass matrix (O(n^3) reference for the O(n) recursion)."""
        x = self._check_state(np.concatenate([q, qd]))
        return CD.accelerations_dense(float(t), x, np.asarray(u, dtype=np.float64), self.l, self.M,
                                     self.S, self.J, self.ps, self.env, self.gust_values)

    def mass_matrix(self, q) -> np.ndarray:
        """H(q) (2n, 2n) [kg m^2]."""
        return CD.mass_matrix_at(np.ascontiguousarray(q, dtype=np.float64), self.l, self.S, self.J, self.ps)

    def energy(self, x) -> tuple[float, float]:
        """(kinetic, potential) energy [J]; potential includes the ``moment`` bending energy
        (and, for elastic links, their strain energy)."""
        x = self._check_state(x)
        if self.elastic:
            return E.elastic_energy(x, self.l, self.M, self.J, self.ps)
        return CD.energy(x, self.l, self.M, self.J, self.ps)

    def static_residual(self, q, steady: bool = True) -> np.ndarray:
        """Generalized forces at rest [N m] (2n,); zero at an equilibrium."""
        Q = np.empty(2 * self.n)
        env = self.steady_env if steady else self.env
        x = np.zeros(4 * self.n)
        x[: 2 * self.n] = q
        CD.evaluate_point(True, 0.0, x, np.zeros(2), self.l, self.M, self.J, self.ps, env, self.gust_values,
                          CD.make_workspace(self.n), *CD.static_scratch(self.n), Q)
        return Q

    def joint_positions(self, q, lengths=None) -> np.ndarray:
        """Joint positions (n+1, 3) [m] in S_p; row 0 is the tow point (the compiled kernels'
        definition: :func:`chain_loads.link_frames` then :func:`chain_loads.chain_positions`).

        ``lengths`` (n,) [m]: the links' actual lengths (an elastic chain's); default the model's
        link lengths."""
        q = np.ascontiguousarray(q, dtype=np.float64)
        ws = CD.make_workspace(self.n)
        CL.link_frames(q, self.n, ws[CD.WS_E], ws[CD.WS_A], ws[CD.WS_B], ws[CD.WS_CS])
        r = np.empty((self.n + 1, 3))
        lengths = self.l if lengths is None else np.ascontiguousarray(lengths, dtype=np.float64)
        CL.chain_positions(lengths, ws[CD.WS_E], r)
        return r
