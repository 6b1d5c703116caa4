"""The balance position (Sec. 2.3.2; docs/model.md §5): the rest state in steady air.

Method (no hand-tuned starting guesses):

1. *Towed-cable guess.* In a uniform free stream, with bending ignored, every link of a chain
   of two-force members lies along the resultant of the forces on everything aft of it. Marching
   from the drogue to the tow point, each link's direction is found by a short fixed-point
   iteration (its own drag depends on its direction). This is exact without wake and bending.
2. *Newton polish.* ``scipy.optimize.root`` (MINPACK ``hybr``) on the full static generalized
   forces ``Q(q) = 0`` (wake, bending, everything), with a central-difference Jacobian.
3. *Continuation.* If the direct solve fails (strong wake at low dynamic pressure), the wake's
   circulation is raised from 0 to its full value in steps, each solve starting from the last.
4. *Elastic links.* From the rigid balance position, each link stretched by its tension, chord
   iterations with the rigid solve's Jacobian for the angles and the axial spring for the lengths
   (no Jacobian of the 3n elastic unknowns); MINPACK's Newton where they do not converge.

The solver's own result is returned with the answer so a failure can be diagnosed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from ..constants import G0
from ..errors import EquilibriumError
from ..model import chain_dynamics as CD, elastic as E, layout as LY
from ..model.system import HoseModel
from ..spec.params import PAPER, Params

#: Converged when every generalized force is below this fraction of the hose's weight moment
#: S_1 g l_1: 1e-10 of it moves the drogue by far less than a micrometre.
RESIDUAL_TOLERANCE = 1e-10


@dataclass(frozen=True)
class Equilibrium:
    """The balance position, in S_p (x forward, y right, z down), SI units."""

    q: np.ndarray  #: generalized coordinates (2n,) [rad]
    joints_m: np.ndarray  #: joint positions (n+1, 3) [m]
    drogue_position_m: np.ndarray  #: (3,) [m]
    drogue_drag_n: np.ndarray  #: aerodynamic force on the drogue (3,) [N]
    tow_force_n: np.ndarray  #: force the hose exerts on the tow point (3,) [N]
    #: exit tension T_0: the hose's pull along it at the exit, the force a hose drum holds [N]
    exit_tension_n: float
    balance_ratio: float  #: D = V_D / L_H: drogue drop below the tow point over hose length
    residual: float  #: max |Q| over S_1 g l_1 (dimensionless)
    solver: object = field(repr=False)  #: scipy OptimizeResult of the last Newton solve
    #: elastic links: their actual lengths (n,) [m] under the steady tension; None for rigid links
    lengths_m: np.ndarray | None = None
    #: elastic links: the hose's stretch, actual minus material length [m] (0 for rigid links)
    stretch_m: float = 0.0

    @property
    def link_angles_rad(self) -> np.ndarray:
        """(n, 2): [pitch, yaw] of every link [rad]."""
        return self.q.reshape(-1, 2)

    @property
    def drogue_drag_magnitude_n(self) -> float:
        return float(np.linalg.norm(self.drogue_drag_n))

    @property
    def state(self) -> np.ndarray:
        """The full state [q, 0] (4n,); for elastic links [q, 0, lam, 0] (6n,)."""
        rest = np.concatenate([self.q, np.zeros_like(self.q)])
        if self.lengths_m is None:
            return rest
        return np.concatenate([rest, self.lengths_m, np.zeros_like(self.lengths_m)])

    def to_dict(self) -> dict:
        return {
            "drogue_position_m": self.drogue_position_m.tolist(),
            "drogue_drag_n": self.drogue_drag_magnitude_n,
            "drogue_drag_vector_n": self.drogue_drag_n.tolist(),
            "tow_force_n": self.tow_force_n.tolist(),
            "exit_tension_n": self.exit_tension_n,
            "balance_ratio": self.balance_ratio,
            "link_angles_rad": self.link_angles_rad.tolist(),
            "residual": self.residual,
            "solver_success": bool(self.solver.success),
            "solver_message": str(self.solver.message),
        }


def towed_cable_guess(model: HoseModel) -> np.ndarray:
    """Link angles of the chain in a uniform free stream without bending (step 1 above).

    Parameters
    ----------
    model : HoseModel
        The model (link lengths and masses, density, airspeed, drag coefficients).

    Returns
    -------
    numpy.ndarray
        q (2n,) [rad]: pitch and yaw of every link.
    """
    n, l, M = model.n, [float(x) for x in model.l], [float(x) for x in model.M]
    V, rho = model.params.flight.airspeed_m_s, model.rho
    hose, drogue = model.params.hose, model.params.drogue
    q_cn = 0.5 * rho * math.pi * hose.outer_diameter_m * hose.normal_drag_coefficient
    q_ct = 0.5 * rho * math.pi * hose.outer_diameter_m * hose.tangential_drag_coefficient
    wind = np.array([-V, 0.0, 0.0])
    drogue_drag = 0.5 * rho * V * V * math.pi * drogue.diameter_m**2 / 4 * drogue.drag_coefficient
    # the same operations on the same numbers as numpy's on 3-vectors, bit for bit, at a fraction
    # of their call overhead: -(-wind) is wind; np.linalg.norm(x) of a vector is sqrt(x.dot(x))
    vrel, dot, sqrt = -wind, np.ndarray.dot, math.sqrt

    def link_drag(k: int, e: np.ndarray) -> np.ndarray:
        vt = dot(wind, e)
        vn = vrel + vt * e
        return -q_ct * l[k] * vt * abs(vt) * (-e) - q_cn * l[k] * sqrt(dot(vn, vn)) * vn

    carried = np.array([-drogue_drag, 0.0, 0.0])  # forces aft of the current link's aft joint
    q = np.zeros(2 * n)
    drag_aft = None  # the last link's drag at its direction, computed once for both of its joints
    for k in range(n - 1, -1, -1):
        base = carried + np.array([0.0, 0.0, M[k] * G0])
        if drag_aft is not None:
            base = base + 0.5 * drag_aft
        e = base / sqrt(dot(base, base))
        for _ in range(100):
            total = base + 0.5 * link_drag(k, e)
            e_new = total / sqrt(dot(total, total))
            d = e_new - e
            if sqrt(dot(d, d)) < 1e-14:
                e = e_new
                break
            e = e_new
        # the link pulls its aft joint forward along -e; the joint's load points along +e
        drag_aft = link_drag(k, e)
        carried = base + 0.5 * drag_aft
        q[2 * k + 1] = math.asin(max(-1.0, min(1.0, -e[1])))
        q[2 * k] = math.atan2(e[2], -e[0])
    return q


class ChainStatics:
    """The statics of the fixed-length chain of ``model`` by its own evaluation: the rigid links'
    generalized forces at rest, the elastic links', and the outputs of a rest state.
    :func:`solve_equilibrium` takes another chain's statics with the same three methods (the
    engagement's, by the engagement's own evaluation: ``hosedrogue.engagement.balance``).

    Parameters
    ----------
    model : HoseModel
        The chain.
    narrow : bool
        Evaluate rigid links by the entry compiled for level flight in still air where the flight
        is that (:func:`hosedrogue.model.chain_dynamics.point_kernel`; the same numbers).
    """

    def __init__(self, model: HoseModel, narrow: bool = False):
        self.model, self.narrow = model, narrow

    def residual(self, env: np.ndarray):
        """The rigid links' generalized forces at rest Q(q) (2n,) [N m] in the air ``env``."""
        model, n = self.model, self.model.n
        gust = model.gust_values
        Q = np.empty(2 * n)
        x = np.zeros(4 * n)  # [q, qd = 0]: the statics
        kernel = CD.point_kernel(env, x, 0.0, self.narrow)
        u = np.zeros(2)
        ws = CD.make_workspace(n)
        xi, G = CD.static_scratch(n)

        def fun(q):
            x[: 2 * n] = q
            kernel(True, 0.0, x, u, model.l, model.M, model.J, model.ps, env, gust, ws, xi, G, Q)
            return Q.copy()

        return fun

    def elastic_residual(self, env: np.ndarray):
        """The elastic links' generalized forces at rest Q(y) (3n,) [N m] of y = [q, lam] in the air
        ``env`` (:func:`hosedrogue.model.elastic.elastic_static_residual`)."""
        model = self.model
        Q = np.empty(3 * model.n)

        def fun(y):
            E.elastic_static_residual(np.ascontiguousarray(y), model.l, model.M, model.J, model.ps, env,
                                      model.gust_values, 0.0, Q)
            return Q.copy()

        return fun

    def outputs(self, rest: np.ndarray):
        """Joint positions [m], drogue drag and tow-point force [N] and exit tension [N] of the rest
        state ``rest`` in steady air (:meth:`HoseModel.outputs`)."""
        return self.model.outputs(rest, steady=True, narrow=self.narrow)


def _central_jacobian(fun):
    """The central-difference Jacobian of ``fun`` (steps of 1e-7 rad)."""

    def jac(q, h=1e-7):
        m = q.size
        Jm = np.empty((m, m))
        qp = q.copy()
        for i in range(m):
            qp[i] = q[i] + h
            fp = fun(qp)
            qp[i] = q[i] - h
            fm = fun(qp)
            qp[i] = q[i]
            Jm[:, i] = (fp - fm) / (2 * h)
        return Jm

    return jac


def _newton(statics, env: np.ndarray, q0: np.ndarray, scale: float):
    fun = statics.residual(env)
    sol = scipy.optimize.root(fun, q0, jac=_central_jacobian(fun), method="hybr", options={"xtol": 1e-13})
    res = float(np.max(np.abs(fun(sol.x)))) / scale
    return sol, res


#: The banded chord (:func:`_banded_chord`): half-bandwidth of its Jacobian [-] (the bending
#: couples neighbouring links, the drag of a joint the links on either side; what lies beyond,
#: the drag and the wake of the joints further aft, is 4 % of the Jacobian's norm at 160 links and
#: slows the iteration only), its refresh interval and its most iterations [-] (measured: 37 at
#: 160 links, each cutting the residual about 2.3 times).
BAND, BAND_REFRESH, BAND_ITERATIONS = 5, 10, 200


def _band_jacobian(fun, q: np.ndarray, w: int, h: float = 1e-7) -> np.ndarray:
    """The Jacobian's band (half-width w) in LAPACK's banded storage, by central differences of
    2 w + 1 groups of columns (every (2 w + 1)-th column perturbed together)."""
    m, g = q.size, 2 * w + 1
    ab = np.zeros((g, m))
    for c in range(g):
        d = np.zeros(m)
        d[c::g] = h
        col = (fun(q + d) - fun(q - d)) / (2 * h)
        for j in range(c, m, g):
            lo, hi = max(0, j - w), min(m, j + w + 1)
            ab[w + lo - j: w + hi - j, j] = col[lo:hi]
    return ab


def _band_lu(ab: np.ndarray):
    """The band's LU factors (LAPACK's gbtrf on ``ab`` in scipy.linalg.solve_banded's storage, with
    its rows for the fill-in): factorized once per Jacobian, each chord step then one gbtrs
    (:func:`_band_solve`), the very solve that solve_banded's gbsv (gbtrf, then gbtrs) does, bit
    for bit, without refactorizing the same band at every step."""
    from scipy.linalg import lapack

    if not np.all(np.isfinite(ab)):
        raise ValueError("array must not contain infs or NaNs")
    a2 = np.zeros((3 * BAND + 1, ab.shape[1]))
    a2[BAND:, :] = ab
    lu, piv, info = lapack.dgbtrf(a2, BAND, BAND, overwrite_ab=True)
    return lu, piv, info


def _band_solve(factors, r: np.ndarray) -> np.ndarray:
    """The solution of the band's system (:func:`_band_lu`) for the right-hand side ``r``."""
    from scipy.linalg import lapack

    lu, piv, info = factors
    if info > 0:
        raise np.linalg.LinAlgError("singular matrix")
    return lapack.dgbtrs(lu, BAND, BAND, r, piv)[0]


def _banded_chord(fun, q0: np.ndarray, scale: float):
    """The rigid balance position by chord iterations on the banded part of the Jacobian
    (:data:`BAND`), refreshed every :data:`BAND_REFRESH` iterations: 22 residual evaluations per
    Jacobian instead of MINPACK's 4n. Returns a scipy ``OptimizeResult`` (``x``, ``residual``,
    ``band``: the last banded Jacobian) once the residual is below 1e-2 of
    :data:`RESIDUAL_TOLERANCE`, or None (diverged, or not converged in :data:`BAND_ITERATIONS`)."""
    q = q0.copy()
    for it in range(BAND_ITERATIONS):
        if it % BAND_REFRESH == 0:
            ab = _band_jacobian(fun, q, BAND)
            factors = None
        r = fun(q)
        res = float(np.max(np.abs(r))) / scale
        if not np.isfinite(res):
            return None
        if res < 1e-2 * RESIDUAL_TOLERANCE:
            return scipy.optimize.OptimizeResult(x=q, success=True, nit=it, residual=res, band=ab,
                                                 message=f"chord iterations on a banded Jacobian converged in {it}")
        factors = factors or _band_lu(ab)  # factorized at the band's first use
        q = q - _band_solve(factors, r)
    return None


def solve_equilibrium(params: Params = PAPER, model: HoseModel | None = None, banded: bool = False,
                      narrow: bool = False, statics=None) -> Equilibrium:
    """Balance position for steady air (free stream and, if enabled, the tanker wake), in the
    tanker's initial steady flight: level, or a steady coordinated turn or climb
    (``params.tanker_motion``, docs/model.md §9; the frame's apparent forces are loads of the
    statics, the towed-cable guess is level flight's and Newton takes it from there).

    Parameters
    ----------
    params : Params
        Parameter set (the paper's case by default); turbulence is ignored.
    model : HoseModel, optional
        A model of ``params`` to reuse (built if not given).
    banded : bool, optional
        Solve the angles first by chord iterations on a banded Jacobian (:func:`_banded_chord`;
        MINPACK's Newton as before where they do not converge): the engagement's, about ten times
        faster; the balance position moves within the residual tolerance.
    narrow : bool, optional
        Evaluate the rigid chain by the entry compiled for level flight in still air
        (:func:`hosedrogue.model.chain_dynamics.point_kernel`) when the flight is that: the same
        numbers, a first run compiles a third as much; for a process that evaluates nothing else of
        the chain (``hosedrogue steady``), since one that goes on to simulate compiles both.
    statics : ChainStatics or alike, optional
        The chain's statics (residuals and outputs at rest; default :class:`ChainStatics` of
        ``model``): the engagement passes its own, evaluated by its own compiled evaluation.

    Returns
    -------
    Equilibrium
        Link angles, joint and drogue positions [m], drogue drag and tow-point force [N].

    Raises
    ------
    EquilibriumError
        If no converged rest state is found; its ``result`` is the last solver result.
    """
    model = model if model is not None else HoseModel(params)
    statics = statics if statics is not None else ChainStatics(model, narrow)
    scale = model.S[0] * G0 * model.l[0]
    q = towed_cable_guess(model)
    env_full = model.steady_env
    sol = _banded_chord(statics.residual(env_full), q, scale) if banded else None
    if sol is not None:
        res = sol.residual
    else:
        sol, res = _newton(statics, env_full, q, scale)
    if not (res < RESIDUAL_TOLERANCE):
        # continuation in the wake's circulation
        q_c = q
        for frac in np.linspace(0.0, 1.0, 11):
            env = env_full.copy()
            env[LY.ENV_WAKE + 1] *= frac
            sol, res = _newton(statics, env, q_c, scale)
            if not np.all(np.isfinite(sol.x)):
                break
            q_c = sol.x
        if not (res < RESIDUAL_TOLERANCE):
            raise EquilibriumError(
                f"equilibrium not found: residual {res:.3g} of the weight moment after wake "
                f"continuation (solver: {sol.message})",
                sol,
            )
    q = sol.x.copy()
    lengths = None
    if model.elastic:
        sol, res, q, lengths = _elastic_newton(model, env_full, q, scale, sol, statics)
    # angles are only defined modulo 2 pi; report the principal values
    q = (q + np.pi) % (2 * np.pi) - np.pi
    rest = np.concatenate([q, np.zeros_like(q)])
    if lengths is not None:
        rest = np.concatenate([rest, lengths, np.zeros_like(lengths)])
    out = statics.outputs(rest)
    drogue = out.joints_m[-1].copy()
    return Equilibrium(
        q=q,
        joints_m=out.joints_m.copy(),
        drogue_position_m=drogue,
        drogue_drag_n=out.drogue_drag_n.copy(),
        tow_force_n=out.tow_force_n.copy(),
        exit_tension_n=out.exit_tension_n,
        balance_ratio=float(drogue[2] / model.params.hose.length_m),
        residual=res,
        solver=sol,
        lengths_m=lengths,
        stretch_m=0.0 if lengths is None else float(np.sum(lengths) - np.sum(model.l)),
    )


#: The elastic chord iteration stops when its last correction moved no angle [rad] and no length
#: [m, over the link length] by more than this (MINPACK's xtol of the Newton it replaces), at most
#: CHORD_ITERATIONS times (measured: 7 for the shipped engagements' 160 links with the rigid
#: solve's full Jacobian, each reducing the residual by 25-50 times; 26 with its band, 67-83 for
#: the 22.9 m hose of benchmarks/scenarios/wing-pod-response.toml).
CHORD_XTOL, CHORD_ITERATIONS = 1e-13, 200


def _elastic_chord(fun, n: int, y0: np.ndarray, rigid, EA: float, scale: float):
    """The elastic balance position by chord iterations (no Jacobian of its own): the angles'
    correction from the rigid balance position's Jacobian (MINPACK's factorization ``Q R`` at its
    solution, ``rigid.fjac`` and ``rigid.r``: the elastic angles' Jacobian but for the links'
    stretch, T / EA ~ 1e-3), the lengths' from their spring ``-EA`` (the length entry is ``l (e.G -
    T)`` with ``T = EA (lam - l) / l``). The neglected couplings are of the order of the stretch and
    the drag's share, so each iteration cuts the residual by a constant factor. Returns (y, residual,
    iterations) or None if it did not converge. It stops when the last correction is below
    :data:`CHORD_XTOL` or the residual below 1e-2 of :data:`RESIDUAL_TOLERANCE`. With the rigid
    solve's band (``rigid.band``, :func:`_banded_chord`) instead of its factorization the angles'
    correction leaves out the couplings beyond the band too, and the iteration converges slower."""
    import scipy.linalg

    m = 2 * n
    band = getattr(rigid, "band", None)
    if band is None:
        R = np.zeros((m, m))
        R[np.triu_indices(m)] = rigid.r
    factors = None
    y = y0.copy()
    for it in range(1, CHORD_ITERATIONS + 1):
        r = fun(y)
        if not np.all(np.isfinite(r)):
            return None
        if band is None:
            dq = -scipy.linalg.solve_triangular(R, rigid.fjac @ r[:m])
        else:
            factors = factors or _band_lu(band)
            dq = -_band_solve(factors, r[:m])
        dlam = r[m:] / EA
        y = y + np.concatenate([dq, dlam])
        small = max(np.max(np.abs(dq)), np.max(np.abs(dlam / y0[m:]))) <= CHORD_XTOL
        if small or float(np.max(np.abs(r))) / scale < 1e-2 * RESIDUAL_TOLERANCE:
            res = float(np.max(np.abs(fun(y)))) / scale
            return (y, res, it) if res < RESIDUAL_TOLERANCE else None
    return None


def _elastic_newton(model: HoseModel, env: np.ndarray, q_rigid: np.ndarray, scale: float, rigid=None, statics=None):
    """The elastic chain's balance position from the rigid one: each link stretched by its rigid
    tension (``lam = l (1 + T / EA)``), then chord iterations on the rigid solve's Jacobian
    (:func:`_elastic_chord`), or where they do not converge (or without ``rigid``, the rigid
    solver's result) MINPACK's hybrid Newton with a central-difference Jacobian, on the elastic
    static generalized forces of angles and lengths (``statics.elastic_residual``, default
    :class:`ChainStatics` of ``model``: :func:`hosedrogue.model.elastic.elastic_static_residual`).
    Returns the solver result, the scaled residual, the angles [rad] and the lengths [m]."""
    n, l = model.n, model.l
    fun = (statics if statics is not None else ChainStatics(model)).elastic_residual(env)

    tension = fun(np.concatenate([q_rigid, l]))[2 * n:] / l  # at lam = l the residual is l T_rigid
    y0 = np.concatenate([q_rigid, l * (1.0 + tension / model.ps[LY.PS_EA])])
    if rigid is not None and (getattr(rigid, "r", None) is not None or getattr(rigid, "band", None) is not None):
        chord = _elastic_chord(fun, n, y0, rigid, float(model.ps[LY.PS_EA]), scale)
        if chord is not None:
            y, res, it = chord
            how = "its band" if getattr(rigid, "band", None) is not None else "its factorization"
            sol = scipy.optimize.OptimizeResult(x=y, success=True, nit=it, nfev=it + 1, message=(
                f"chord iterations on the rigid balance position's Jacobian ({how}) converged in {it}"))
            return sol, res, y[: 2 * n].copy(), y[2 * n:].copy()
    return _elastic_minpack(fun, y0, n, scale)


def _elastic_minpack(fun, y0: np.ndarray, n: int, scale: float):
    """MINPACK's hybrid Newton with a central-difference Jacobian on the elastic residual ``fun``
    from ``y0`` (the fallback of :func:`_elastic_newton`)."""

    def jac(y, h=1e-9):
        m = y.size
        Jm = np.empty((m, m))
        yp = y.copy()
        for i in range(m):
            step = h * max(1.0, abs(y[i]))
            yp[i] = y[i] + step
            fp = fun(yp)
            yp[i] = y[i] - step
            fm = fun(yp)
            yp[i] = y[i]
            Jm[:, i] = (fp - fm) / (2 * step)
        return Jm

    sol = scipy.optimize.root(fun, y0, jac=jac, method="hybr", options={"xtol": 1e-14})
    res = float(np.max(np.abs(fun(sol.x)))) / scale
    if not (res < RESIDUAL_TOLERANCE):
        raise EquilibriumError(f"elastic equilibrium not found: residual {res:.3g} of the weight moment "
                               f"(solver: {sol.message})", sol)
    return sol, res, sol.x[: 2 * n].copy(), sol.x[2 * n:].copy()
