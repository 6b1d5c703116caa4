"""The hose equations in a manoeuvring tanker's frame, derived a second time in an inertial frame.

The package writes the hose equations in the tanker's body axes B at the tow point with the
apparent forces of B's motion (``model/frame.py``: ``-a_0 - alpha x r - Omega x (Omega x r) -
2 Omega x v`` on every joint, the link inertia's moment, the air's rotation relative to B). Here
``sympy.physics.mechanics`` derives them from docs/model.md §9 alone, in an inertial frame N:
B is N rotated by the 3-2-1 angles (heading psi, flight path gamma, bank phi), all prescribed
functions of time; the tow point moves at ``V(t) B.x``; the links are oriented relative to B as
in docs/model.md §1; the air is at rest in N, so every drag sees the point's velocity in N; the
heading rate comes from the coordination condition (no lateral specific force at the tow point,
``(a_O - g N.z) . B.y = 0``) solved here by sympy. KanesMethod then takes the inertial
accelerations and the links' inertial angular velocities itself, so none of the package's frame
terms are used. The two agree at random states and at times inside the roll, pitch and speed
ramps of a segment that changes all three at once (from the package's flight state, whose
profile is checked against its own derivatives in tests/spec/test_manoeuvres.py).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
import sympy as sm
from sympy.physics import mechanics as me

from hosedrogue.constants import G0
from hosedrogue.spec.params import PAPER

# Relative tolerance on qdd: both sides solve H qdd = f in double precision with cond(H) ~ 10-35
# at these states (tests/model/test_independent_derivation.py), so rounding is ~1e-14. The smallest frame
# term exercised (the link inertia's gyroscopic moment J Omega^2 ~ 0.1 N m against gravity moments
# ~30 N m) changes qdd by ~1e-3, the Coriolis and Euler forces by 1e-2-1, so 1e-9 resolves each to
# 1e-6 of itself: a wrong sign, factor or axis fails.
RTOL_QDD = 1e-9
FLIGHT = ("phi", "phid", "phidd", "gam", "gamd", "gamdd", "V", "Vd")


@functools.lru_cache(maxsize=None)
def derive(n: int):
    """qdd(q, qd, flight, params) of the n-link hose behind a manoeuvring tanker (lambdified)."""
    t = me.dynamicsymbols._t
    psi, gam, phi, V = me.dynamicsymbols("psi gam phi V")
    q = me.dynamicsymbols(f"q0:{2 * n}")
    u = me.dynamicsymbols(f"u0:{2 * n}")
    g, rho, d_o, c_t, c_n, cda, J_d, u_y, u_z = sm.symbols("g rho d_o c_t c_n CdA J_d u_y u_z", real=True)
    lk = sm.symbols(f"l1:{n + 1}", positive=True)
    Mk = sm.symbols(f"M1:{n + 1}", positive=True)
    Jk = sm.symbols(f"J1:{n + 1}", nonnegative=True)

    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", (psi, gam, phi), "321")
    origin = me.Point("N0")
    origin.set_vel(N, 0)
    tow = origin.locatenew("O", 0)
    tow.set_vel(N, V * B.x)

    frames, joints = [], [tow]
    for k in range(n):
        A = B.orientnew(f"A{k + 1}", "Axis", (q[2 * k], B.y))
        L = A.orientnew(f"L{k + 1}", "Axis", (q[2 * k + 1], A.z))
        frames.append(L)
        P = joints[-1].locatenew(f"P{k + 1}", lk[k] * (-L.x))
        P.v2pt_theory(joints[-1], N, L)
        joints.append(P)

    bodies = []
    for k in range(n):
        bodies.append(me.Particle(f"m{k + 1}", joints[k + 1], Mk[k]))
        bodies.append(me.RigidBody(f"R{k + 1}", joints[k + 1], frames[k], 0,
                                   (me.inertia(frames[k], 0, Jk[k], Jk[k]), joints[k + 1])))
    bodies.append(me.RigidBody("D", joints[n], frames[-1], 0, (me.inertia(frames[-1], 0, J_d, J_d), joints[n])))

    def mat(vec):
        return vec.to_matrix(B)

    loads = [(joints[k + 1], Mk[k] * g * N.z) for k in range(n)]
    for k in range(n):  # midpoint drag, half on each end joint; the air is at rest in N
        e = mat(-frames[k].x)
        vt_vec = (mat(joints[k].vel(N)) + mat(joints[k + 1].vel(N))) / 2
        nk = -e
        vt = vt_vec.dot(nk)
        vn = vt_vec - vt * nk
        D = (-sm.Rational(1, 2) * rho * sm.pi * d_o * lk[k] * (c_t * vt * sm.Abs(vt) * nk
                                                               + c_n * sm.sqrt(vn.dot(vn)) * vn))
        Dv = D[0] * B.x + D[1] * B.y + D[2] * B.z
        loads += [(joints[k], Dv / 2), (joints[k + 1], Dv / 2)]
    vr = mat(joints[n].vel(N))
    Dd = -sm.Rational(1, 2) * rho * cda * sm.sqrt(vr.dot(vr)) * vr
    loads.append((joints[n], Dd[0] * B.x + (Dd[1] + u_y) * B.y + (Dd[2] + u_z) * B.z))
    loads = [(pt, f) for pt, f in loads if pt is not tow]  # the tow point is driven

    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
    kane.kanes_equations(bodies, loads)

    # the coordinated turn: no lateral specific force at the tow point fixes psi'
    psid_s = sm.Symbol("psid")
    lateral = (tow.acc(N) - g * N.z).dot(B.y).subs(psi.diff(t), psid_s)
    psid_expr = sm.solve(sm.Eq(lateral, 0), psid_s)[0]
    fl = {name: sm.Symbol(name, real=True) for name in FLIGHT}
    plain_flight = {phi.diff(t, 2): fl["phidd"], gam.diff(t, 2): fl["gamdd"], V.diff(t): fl["Vd"],
                    phi.diff(t): fl["phid"], gam.diff(t): fl["gamd"], phi: fl["phi"], gam: fl["gam"], V: fl["V"]}
    psid_num = me.msubs(psid_expr, plain_flight)
    psidd = psid_expr.diff(t)  # d/dt of psi'(phi, gamma, gamma', V)
    psidd_num = me.msubs(psidd, plain_flight)

    qs = sm.symbols(f"qs0:{2 * n}", real=True)
    us = sm.symbols(f"us0:{2 * n}", real=True)
    subs = {qi.diff(): ui for qi, ui in zip(q, us)}
    subs.update(dict(zip(u, us)))
    subs.update(dict(zip(q, qs)))
    subs.update({psi.diff(t, 2): psidd_num, psi.diff(t): psid_num, psi: sm.Rational(3, 10)})
    subs.update(plain_flight)
    H = me.msubs(kane.mass_matrix, subs)
    f = me.msubs(kane.forcing, subs)
    args = (qs, us, [fl[name] for name in FLIGHT], [g, rho, d_o, c_t, c_n, cda, J_d, u_y, u_z, *lk, *Mk, *Jk])
    Hf = sm.lambdify(args, H, modules="numpy", cse=True)
    ff = sm.lambdify(args, f, modules="numpy", cse=True)
    psid_f = sm.lambdify([[fl[name] for name in FLIGHT], [g]], psid_num, modules="numpy")

    def accelerations(qv, qdv, flight, p):
        return np.linalg.solve(np.asarray(Hf(qv, qdv, flight, p), float), np.asarray(ff(qv, qdv, flight, p), float).ravel())

    return accelerations, psid_f


def _package(n, air, lumping):
    from hosedrogue.model.system import HoseModel

    motion = {"roll_acceleration_deg_s2": 600.0, "pitch_acceleration_deg_s2": 60.0, "jerk_m_s3": 40.0,
              "bank_deg": -10.0, "flight_path_deg": 5.0,
              "segments": [{"start_s": 0.0, "bank_deg": 50.0, "roll_rate_deg_s": 30.0, "flight_path_deg": -20.0,
                            "pitch_rate_deg_s": 10.0, "airspeed_m_s": 60.0, "acceleration_m_s2": 15.0}]}
    p = PAPER.replace(hose={"links": n, "bending": "off", "mass_lumping": lumping},
                      flight={"airspeed_m_s": 25.0, "density_scale": 1.0 if air else 0.0},
                      wake={"enabled": False}, tanker_motion=motion)
    return HoseModel(p)


def _param_vector(model):
    hose, drogue = model.params.hose, model.params.drogue
    n = model.n
    J_links = model.J - np.r_[np.zeros(n - 1), drogue.inertia_kg_m2]
    return [G0, model.rho, hose.outer_diameter_m, hose.tangential_drag_coefficient, hose.normal_drag_coefficient,
            math.pi * drogue.diameter_m**2 / 4 * drogue.drag_coefficient, drogue.inertia_kg_m2, 0.0, 0.0,
            *model.l, *model.M, *J_links]


# times in the pitch and speed ramp-ups (the roll cruising at 30 deg/s), in the speed's ramp-up
# with roll and pitch cruising, and in the roll's ramp-down
TIMES_S = (0.1, 0.5, 2.05)


@pytest.mark.parametrize("air", [False, True], ids=["no-air", "air"])
@pytest.mark.parametrize("lumping", ["aft", "split"])
def test_frame_terms_agree_with_an_inertial_derivation(air, lumping, rng):
    from hosedrogue.model.frame import flight_state

    n = 2
    accelerations, psid_f = derive(n)
    model = _package(n, air, lumping)
    p = _param_vector(model)
    for t in TIMES_S:
        fs = flight_state(t, model.env, len(model.env) - model.motion_table.size)
        flight = list(fs[:8])
        assert abs(flight[1]) > 0.05 and abs(flight[4]) > 0.01 and abs(flight[7]) > 0.5  # all three changing
        for _ in range(3):
            q = np.empty(2 * n)
            q[0::2] = rng.uniform(-0.8, 0.8, n)
            q[1::2] = rng.uniform(-0.6, 0.6, n)
            qd = rng.uniform(-1.0, 1.0, 2 * n)
            u = rng.uniform(-100.0, 100.0, 2)
            p[7], p[8] = u
            ref = accelerations(q, qd, flight, p)
            got = model.outputs(np.concatenate([q, qd]), t=t, u=u).qdd
            assert np.linalg.norm(got - ref) <= RTOL_QDD * np.linalg.norm(ref), (t, got, ref)


def test_the_frames_rotation_matters_at_this_tolerance(rng):
    """The check above can fail: the same states with the frame terms of straight flight (the
    package's level model at the same airspeed) differ from the inertial derivation by far more
    than RTOL_QDD."""
    from hosedrogue.model.frame import flight_state
    from hosedrogue.model.system import HoseModel

    n = 2
    accelerations, _ = derive(n)
    model = _package(n, True, "aft")
    level = HoseModel(model.params.replace(tanker_motion={"bank_deg": 0.0, "flight_path_deg": 0.0, "segments": []}))
    p = _param_vector(model)
    t = TIMES_S[0]
    flight = list(flight_state(t, model.env, len(model.env) - model.motion_table.size)[:8])
    q = rng.uniform(-0.5, 0.5, 2 * n)
    qd = rng.uniform(-1.0, 1.0, 2 * n)
    ref = accelerations(q, qd, flight, p)
    got = level.outputs(np.concatenate([q, qd]), t=t).qdd
    assert np.linalg.norm(got - ref) > 1e3 * RTOL_QDD * np.linalg.norm(ref)


def test_coordination_gives_the_issues_turn_rate():
    """The sympy coordination condition gives psi' = g tan(phi) / V in a level turn
    (docs/model.md §9), and the package's Omega is that rate about the inertial vertical."""
    from hosedrogue.model.frame import ENV_M_W
    from hosedrogue.model.system import HoseModel
    from hosedrogue.model import chain_loads as CL, layout as LY

    _, psid_f = derive(2)
    phi, V = math.radians(30.0), 150.0
    assert psid_f([phi, 0, 0, 0, 0, 0, V, 0], [G0]) == pytest.approx(G0 * math.tan(phi) / V, rel=1e-14)
    model = HoseModel(PAPER.replace(tanker_motion={"bank_deg": 30.0}))
    scratch = np.empty(LY.ENV_SIZE)
    CL.fill_env(0.0, model.env, model.gust_values, scratch)
    omega = scratch[ENV_M_W:ENV_M_W + 3]
    vertical = np.array([0.0, math.sin(phi), math.cos(phi)])  # the inertial down direction in B
    np.testing.assert_allclose(omega, G0 * math.tan(phi) / V * vertical, rtol=1e-14, atol=1e-17)
