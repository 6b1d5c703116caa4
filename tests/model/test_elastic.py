"""The elastic link chain (docs/model.md §11): the O(n) recursion against Lagrange's equations of
its own energy, energy conservation and its order in the step for RK4 and the stiff SDIRK, the
snap of a straight hose against the exact wave-equation solution, the balance position's stretch
against the elastic continuum, and the rigid link as the limit of a stiff one."""

import math

import numpy as np
import pytest
from scipy.integrate import simpson

from hosedrogue.analysis.continuum import solve_continuum
from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.engagement import Reel, simulate_engagement
from hosedrogue.errors import ParameterError
from hosedrogue.model import layout as LY
from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER
from hosedrogue.simulation.simulate import simulate

MU = PAPER.hose.mass_per_length_kg_m


def elastic_params(n=6, EA=1e4, ca=0.0, **numerics):
    return PAPER.replace(hose={"links": n, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split",
                               "axial_stiffness_n": EA, "axial_damping_n_s": ca},
                         flight={"density_scale": 0.0}, numerics=numerics or {})


def swinging_state(model, rng, stretch=0.01, rate=0.1):
    """A swinging, stretched chain: angles about the trail, random rates, lengths within 1 %."""
    n = model.n
    x = np.zeros(6 * n)
    x[: 2 * n: 2] = np.pi / 2 + rng.uniform(-0.5, 0.5, n)
    x[1: 2 * n: 2] = rng.uniform(-0.3, 0.3, n)
    x[2 * n: 4 * n] = rng.uniform(-0.5, 0.5, 2 * n)
    x[4 * n: 5 * n] = model.l * (1.0 + rng.uniform(-stretch, stretch, n))
    x[5 * n:] = rng.uniform(-rate, rate, n)
    return x


def test_recursion_solves_lagranges_equations_of_the_energy(rng):
    """The three-coordinate articulated-body recursion (angles and length per link) against
    Lagrange's equations formed by central differences of the chain's own kinetic and potential
    energy (gravity, bending, strain): ``M a = -d(M u)/dq u + dT/dq - dV/dq``, M the Hessian of T in
    the velocities (T is quadratic in them, so a 1e-3 step is exact but for round-off). The
    differences' error: round-off 1e-16 x 1e3 J over steps of 1e-3 and 1e-6, about 1e-7 of the
    accelerations (measured 6e-8); bound 1e-5 of the largest acceleration."""
    model = HoseModel(elastic_params(n=6, EA=1e4))
    n = model.n
    x = swinging_state(model, rng)

    def split(x):
        return np.r_[x[: 2 * n], x[4 * n: 5 * n]], np.r_[x[2 * n: 4 * n], x[5 * n:]]

    def join(q, u):
        return np.r_[q[: 2 * n], u[: 2 * n], q[2 * n:], u[2 * n:]]

    def T(q, u):
        return model.energy(join(q, u))[0]

    def V(q):
        return model.energy(join(q, np.zeros(3 * n)))[1]

    q, u = split(x)
    m = 3 * n
    eye = np.eye(m)
    h, e = 1e-3, 1e-6
    H = np.array([[(T(q, u + h * (eye[i] + eye[j])) - T(q, u + h * (eye[i] - eye[j])) - T(q, u - h * (eye[i] - eye[j]))
                    + T(q, u - h * (eye[i] + eye[j]))) / (4 * h * h) for j in range(m)] for i in range(m)])

    def momentum(q, u):
        return np.array([(T(q, u + h * eye[i]) - T(q, u - h * eye[i])) / (2 * h) for i in range(m)])

    dp = (momentum(q + e * u, u) - momentum(q - e * u, u)) / (2 * e)
    dTdq = np.array([(T(q + e * eye[i], u) - T(q - e * eye[i], u)) / (2 * e) for i in range(m)])
    dVdq = np.array([(V(q + e * eye[i]) - V(q - e * eye[i])) / (2 * e) for i in range(m)])
    a_lagrange = np.linalg.solve(H, -dp + dTdq - dVdq)
    a = model.outputs(x).qdd
    assert np.max(np.abs(a - a_lagrange)) < 1e-5 * np.max(np.abs(a))


@pytest.mark.parametrize("integrator,steps,order", [("rk4", (4e-4, 2e-4, 1e-4), 4), ("sdirk2", (2e-3, 1e-3, 5e-4), 2)])
def test_energy_is_conserved_to_the_schemes_order(integrator, steps, order):
    """No air, no damping: the energy (kinetic, gravity, bending, strain) of a swinging, stretching
    chain is conserved to the integrator's error over 5 s, which must shrink by 2^order per halving
    of the step (a factor 0.7 of it allowed for the error constant's drift: > 11 for RK4, > 2.8 for
    the SDIRK). Measured drift: RK4 1e-9, 3e-11 J at 2e-4, 1e-4 s; SDIRK 1.1e-2, 2.8e-3, 7e-4 J at
    2, 1, 0.5 ms, of a 9 kJ energy."""
    drift = []
    for h in steps:
        p = elastic_params(n=8, EA=1e5, integrator=integrator, step_s=h, output_every=int(round(0.01 / h)))
        model = HoseModel(p)
        x0 = swinging_state(model, np.random.default_rng(1), stretch=0.0, rate=0.0)
        r = simulate(p, 5.0, x0=x0, model=model)
        assert r.completed, r.message
        E = np.array([sum(model.energy(x)) for x in r.states])
        drift.append(np.max(np.abs(E - E[0])))
    assert drift[0] / drift[1] > 0.7 * 2**order and drift[1] / drift[2] > 0.7 * 2**order, drift
    assert drift[-1] < 1e-6 * abs(E[0]) if integrator == "rk4" else True


def snap_run(integrator, h, n=200, EA=1e6, ca=20.0, v=2.0, duration=0.03):
    """A straight hose of 16 m along the trail, air and gravity off, the exit held (the locked reel),
    the drogue end jerked aft to v [m/s] and kept there by a drogue of 1e7 kg (it slows by 1e-5 m/s
    over the run): the engagement driver's elastic chain."""
    p = PAPER.replace(hose={"links": n, "link_inertia": "rod", "bending": "off", "mass_lumping": "split",
                            "axial_stiffness_n": EA, "axial_damping_n_s": ca},
                      drogue={"mass_kg": 1e7, "inertia_kg_m2": 0.0}, flight={"density_scale": 0.0},
                      numerics={"integrator": integrator, "step_s": h, "output_every": 1})
    l = p.hose.link_length_m
    x0 = np.zeros(6 * n)  # pitch and yaw 0: every link along -x, straight aft of the exit
    x0[4 * n: 5 * n] = l
    x0[6 * n - 1] = v
    r = simulate_engagement(p, duration, reel=Reel(law="locked"), probe=None, x0=x0, gravity_m_s2=0.0)
    assert r.completed, r.message
    return r, p


@pytest.mark.parametrize("integrator,h", [("rk4", 2e-5), ("sdirk2", 1e-4)])
def test_snap_wave_speed_and_tension(integrator, h):
    """The exact solution of the wave equation for a taut-free string jerked at one end to v: a
    front at c = sqrt(EA / mu) (477 m/s for 1e6 N and 4.4 kg/m) behind which the tension is
    v sqrt(EA mu) (4195 N at 2 m/s). The front is located by the time the tension of each link
    crosses half the plateau (a fit over 12 links between 4 and 12 m from the jerked end); the
    plateau is the mean tension 2 to 10 m behind the front at 25 ms (before the reflection at the
    exit). The brief's bound: 2 % each. A little axial damping (20 N s; the front's width
    sqrt(c_a t / mu) = 1 cm after 25 ms) smooths the lattice's ringing. Measured: speed -0.07 %
    (RK4 at 20 us) and -0.08 % (SDIRK at 0.1 ms), plateau below 1e-5."""
    EA, v, n = 1e6, 2.0, 200
    r, p = snap_run(integrator, h)
    # every link's tension EA eps + c_a deps/dt from the joints' positions and velocities
    l = p.hose.link_length_m
    d = np.diff(np.array(r.joints_m), axis=1)
    lam = np.linalg.norm(d, axis=2)
    lamd = np.einsum("tki,tki->tk", np.diff(np.array(r.joint_velocities_m_s), axis=1), d) / lam
    T = EA * (lam / l - 1.0) + p.hose.axial_damping_n_s * lamd / l
    c, plateau = math.sqrt(EA / MU), v * math.sqrt(EA * MU)
    links = np.arange(40, 160, 10)
    arrival = np.array([r.t_s[np.argmax(T[:, k] > 0.5 * plateau)] for k in links])
    distance = 16.0 - (links + 0.5) * l
    speed = np.polyfit(arrival, distance, 1)[0]
    i = int(np.argmin(np.abs(r.t_s - 0.025)))
    s = (np.arange(n) + 0.5) * l
    behind = (s > 6.0) & (s < 14.0)
    assert abs(speed / c - 1.0) < 0.02
    assert abs(np.mean(T[i, behind]) / plateau - 1.0) < 0.02
    # the drogue end's tension (the per-step record) is the plateau too, before the reflection
    rec = r.step_loads
    assert abs(np.median(rec[(rec[:, 0] > 0.005) & (rec[:, 0] < 0.03), 2]) / plateau - 1.0) < 0.02


def test_static_stretch_is_the_integral_of_the_continuum_tension():
    """The trailed elastic hose (1e6 N, wake on, 150 m/s at 8000 m, no bending) at its balance
    position: its stretch (the sum of the links' actual lengths minus 16 m, 22.3 mm) equals the
    integral of T / EA along the hose, T the tension of the independent continuum solution
    (analysis.continuum with the stretch in its kinematics; Simpson's rule on 20001 samples, error
    far below 1e-12 m), to 1e-6 m (the brief's bound). The link model converges to it at second
    order: measured 8.6e-9, 2.1e-9, 5.4e-10 m at 20, 40, 80 links."""
    EA = 1e6
    diffs = []
    for n in (20, 40):
        p = PAPER.replace(hose={"links": n, "link_inertia": "rod", "bending": "off", "mass_lumping": "split",
                                "axial_stiffness_n": EA})
        eq = solve_equilibrium(p)
        shape = solve_continuum(p, samples=20001)
        integral = simpson(np.linalg.norm(shape.tension_n, axis=1), x=shape.s_m) / EA
        diffs.append(eq.stretch_m - integral)
        assert abs(eq.stretch_m - integral) < 1e-6
    assert 0.02 < eq.stretch_m < 0.025
    assert abs(diffs[1]) < abs(diffs[0]) / 3  # second order in 1/links


def test_elastic_balance_position_is_at_rest():
    """The elastic chain's balance position is a rest state of its dynamics: every acceleration
    (angles and lengths) below 1e-7 of g over the link length (the solver's 1e-10 residual of the
    weight moment, through the smallest joint mass)."""
    p = PAPER.replace(hose={"links": 20, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split",
                            "axial_stiffness_n": 1e6, "axial_damping_n_s": 3000.0})
    eq = solve_equilibrium(p)
    model = HoseModel(p)
    acc = model.outputs(eq.state, steady=True).qdd
    assert np.max(np.abs(acc)) < 1e-7 * 9.81 / 0.8
    assert eq.lengths_m is not None and np.all(eq.lengths_m > model.l)


def test_stiff_links_approach_the_rigid_chain():
    """The rigid link is the limit of a stiff one: the paper's 20-link hose released from its
    balance position displaced by the wake-free swing of swing-release's kind (0.5 rad/s on every
    pitch), integrated 2 s with air on; the elastic chain (SDIRK at 1 ms) started with its links at
    their material length approaches the rigid one (RK4 at 1 ms) as EA grows - the drogue's
    distance falls about tenfold per decade of EA (1e6 -> 1e7 -> 1e8 N: measured ratios > 5)."""
    base = PAPER.replace(hose={"links": 20, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split"},
                         numerics={"step_s": 1e-3, "output_every": 10})
    eq = solve_equilibrium(base)
    x0 = eq.state.copy()
    x0[40::2] = 0.5
    rigid = simulate(base, 2.0, x0=x0, equilibrium=eq)
    gaps = []
    for EA in (1e6, 1e7, 1e8):
        p = base.replace(hose={"axial_stiffness_n": EA}, numerics={"integrator": "sdirk2"})
        xe = np.concatenate([x0, p.hose.link_length_m * np.ones(20), np.zeros(20)])
        r = simulate(p, 2.0, x0=xe, equilibrium=eq)
        assert r.completed, r.message
        gaps.append(np.max(np.linalg.norm(r.drogue_position_m - rigid.drogue_position_m, axis=1)))
    assert gaps[0] / gaps[1] > 5 and gaps[1] / gaps[2] > 5, gaps


def test_integrator_and_links_must_match():
    with pytest.raises(ParameterError, match=r"'sdirk2': the fixed-length run of rigid links .* integrates with 'rk4' or 'adaptive'$"):
        simulate(PAPER.replace(numerics={"integrator": "sdirk2"}), 0.1)
    with pytest.raises(ParameterError, match=r"'adaptive': the fixed-length run of an elastic hose .* integrates with 'rk4' or 'sdirk2'$"):
        simulate(elastic_params(integrator="adaptive"), 0.1)
    with pytest.raises(ParameterError, match="hose.axial_damping_n_s = 5.0: an inextensible hose"):
        PAPER.replace(hose={"axial_damping_n_s": 5.0})


def test_rigid_hose_keeps_its_arrays():
    """EA = inf is the paper's rigid chain: the model's state stays [q, qd] (4n)."""
    model = HoseModel(PAPER)
    assert not model.elastic and model.state_size == 4 * model.n and math.isinf(model.ps[LY.PS_EA])


def test_solve_without_accelerations_leaves_the_loads_and_skips_the_accelerations(rng):
    """The output kernels' solve (``without_accelerations``: the recursion's backward sweep only)
    gives the full solve's tow-point force, exit tension, link tensions and joints bit for bit
    (the forward pass writes only the accelerations, after the sweep: equality is exact, not to a
    tolerance) and leaves the accelerations' array as it was (here NaN)."""
    from hosedrogue.model import chain_dynamics as CD
    from hosedrogue.model import elastic as E

    model = HoseModel(elastic_params(n=6, EA=1e4, ca=30.0))
    n = model.n
    x = swinging_state(model, rng)
    got = []
    for skip in (False, True):
        ws = CD.make_workspace(n)
        ews = E.make_elastic_workspace(n)
        if skip:
            ews = E.without_accelerations(ews)
        ws[CD.WS_QDD][:] = np.nan
        E.elastic_evaluate_ws(0.3, x, np.zeros(2), model.l, model.M, model.J, model.ps, model.env,
                              model.gust_values, ws, ews, 0.0, x)
        got.append((ws[CD.WS_TOW].copy(), ws[CD.WS_T0].copy(), ews[E.EWS_T].copy(), ws[CD.WS_R].copy(),
                    ws[CD.WS_QDD].copy()))
    full, skipped = got
    for a, b in zip(full[:4], skipped[:4]):
        np.testing.assert_array_equal(a, b)
    assert np.all(np.isfinite(full[4])) and np.all(np.isnan(skipped[4]))
    assert len(E.without_accelerations(E.make_elastic_workspace(n))[E.EWS_LAMDD]) == 0
