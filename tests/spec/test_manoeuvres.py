"""The tanker's manoeuvres (docs/model.md §9): checks by independent routes and invariants.

* a steady climb is level flight with gravity tilted: the link model's balance position in a
  climb (the kernel's frame terms), Richardson-extrapolated in the link count, equals the
  continuous hose's with a gravity vector rotated here by scipy;
* a steady coordinated turn: the split-lumped link model converges at second order to the
  continuous hose in the same turn; what the turn does besides the apparent gravity g / cos(phi);
* with the air off in a steady turn, the rotating frame's Jacobi integral is conserved, its drift
  shrinking as h^4 with the RK4 step;
* a speed change settles to the balance position of the new speed, a turn entry and exit back to
  the level one, within 1 mm;
* the locked-reel engagement in a turn entry is the fixed-length run;
* the smooth ramps, the wake at the load factor, the gust record read along the path flown.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import hosedrogue as hd
from hosedrogue.analysis.continuum import solve_continuum
from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.analysis.steady_flight import TURN_TERMS, steady_params, turn_breakdown
from hosedrogue.constants import G0
from hosedrogue.model.frame import SteadyFrame, ramp_profile
from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER
from hosedrogue.scenarios import scenario_from_dict

#: The link model that converges to the continuous hose: split lumping, no bending (the continuum
#: neglects it), rod link inertia (its moments are O(l^3) per link, so they vanish at second
#: order) and no drogue rotational inertia (its gyroscopic moment in a turn, carried by the last
#: link, is a force ~ J_d Omega^2 / l that a hose without bending stiffness cannot carry).
CONTINUUM_LIKE = {"hose": {"bending": "off", "mass_lumping": "split", "link_inertia": "rod"},
                  "drogue": {"inertia_kg_m2": 0.0}}


def test_ramp_profile_integrates_consistently():
    """One ramp's change is the integral of its rate, the rate that of its rate of change, the
    integral that of the change (trapezoids on 2e5 points, dt = 1.9e-5 s: error ~ dt^2 |f'| / 8
    at each kink of an integrand between grid points, |f'| <= 2 here, so 1e-9 bounds it), all
    continuous, ending at the full change ``rate (ramp_s + cruise_s)``."""
    rate, ta, tc = 0.2, 0.7, 1.3
    t = np.linspace(-0.5, 2 * ta + tc + 1.0, 200001)
    out = np.array([ramp_profile(ti, rate, ta, tc) for ti in t])
    integral, change, r, acc = out.T
    dt = t[1] - t[0]
    cumtrapz = (lambda f: np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dt)]))
    np.testing.assert_allclose(cumtrapz(r), change, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cumtrapz(acc), r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cumtrapz(change), integral, rtol=0, atol=1e-9)
    assert change[-1] == pytest.approx(rate * (ta + tc), rel=1e-14)
    assert np.max(np.abs(np.diff(acc))) < 1e-4  # the rate's rate is continuous (no step)
    assert np.max(r) == pytest.approx(rate, rel=1e-12) and acc.max() == pytest.approx(0.5 * rate * math.pi / ta)


@pytest.mark.parametrize("gamma_deg", [5.0, -10.0])
def test_steady_climb_is_level_flight_with_gravity_rotated(gamma_deg):
    """The balance position in a steady climb (the kernel's frame terms) equals that of level
    flight with gravity rotated by gamma in the tanker frame, computed by the continuous hose with
    the gravity vector rotated by scipy, to 1e-6 m (the issue's bound). The link model is
    Richardson-extrapolated from 40 and 80 links (second order, next term O(n^-4): ~1e-9 m). The
    wake's circulation carries the lift W cos(gamma) in both."""
    base = PAPER.replace(**CONTINUUM_LIKE)
    climb = steady_params(base, flight_path_deg=gamma_deg)
    pos = {n: solve_equilibrium(climb.replace(hose={"links": n})).drogue_position_m for n in (40, 80)}
    richardson = (4.0 * pos[80] - pos[40]) / 3.0
    gravity = Rotation.from_euler("y", math.radians(gamma_deg)).inv().apply([0.0, 0.0, G0])
    tilted = SteadyFrame(tuple(gravity), (0.0, 0.0, 0.0), math.cos(math.radians(gamma_deg)))
    reference = solve_continuum(base, frame=tilted).drogue_position_m
    assert np.linalg.norm(richardson - reference) < 1e-6
    level = solve_equilibrium(base.replace(hose={"links": 80})).drogue_position_m
    assert np.linalg.norm(pos[80] - level) > 0.05  # the climb really moves the drogue (cm)


def test_steady_turn_converges_at_second_order_to_the_continuum():
    """A 30-degree coordinated level turn: the drogue error of the split-lumped link model against
    the continuous hose in the same turn falls by 4 per doubling of the links (second order; the
    O(n^-4) term makes it 4.0003 at 10 -> 20 links, so [3.96, 4.04] is 1 %), and the Richardson
    limit of 40 and 80 links is within 1e-8 m of it (measured 4e-10 m)."""
    turn = steady_params(PAPER.replace(**CONTINUUM_LIKE), bank_deg=30.0)
    reference = solve_continuum(turn).drogue_position_m
    pos = {n: solve_equilibrium(turn.replace(hose={"links": n})).drogue_position_m for n in (10, 20, 40, 80)}
    errors = [np.linalg.norm(pos[n] - reference) for n in (10, 20, 40, 80)]
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.96) & (ratios < 4.04)), ratios
    assert np.linalg.norm((4.0 * pos[80] - pos[40]) / 3.0 - reference) < 1e-8
    # the turn matters at this tolerance: the level balance position is decimetres away
    assert np.linalg.norm(solve_continuum(PAPER.replace(**CONTINUUM_LIKE)).drogue_position_m - reference) > 0.1


def test_what_a_turn_does_besides_the_apparent_gravity():
    """A 25-degree turn of the paper's hose, term by term (docs/model.md §9): the apparent gravity
    g / cos(phi) lowers the drogue by 29 cm; besides it, the wake at the load factor (4.4 cm right,
    5.8 cm down), the air's rotation (3.7 cm toward the inside of the turn, 1.5 cm up) and the
    centrifugal field (about 1 mm). The terms add up to the turn computed in one go, the inside
    of the turn is to the right in a right turn and to the left in a left one (the wake, the same
    in both, aside), and the first term is the level model with g / cos(phi) along z (0.5 mm bounds
    each figure, the rounding above)."""
    right = turn_breakdown(PAPER, 25.0)
    whole = solve_continuum(steady_params(PAPER, bank_deg=25.0)).drogue_position_m
    left = solve_continuum(steady_params(PAPER, bank_deg=-25.0)).drogue_position_m
    np.testing.assert_allclose(right.steps_m[-1], whole, atol=1e-12)
    np.testing.assert_allclose(right.contributions_m.sum(axis=0), right.turn_m, atol=1e-12)
    c = dict(zip(TURN_TERMS, right.contributions_m))
    expected_mm = {"apparent gravity g/cos(phi)": (None, -7.1, 287.6), "wake at the load factor": (None, 44.0, 57.7),
                   "air's rotation": (None, 37.4, -15.2)}
    for term, (_, dy, dz) in expected_mm.items():
        assert c[term][1] * 1e3 == pytest.approx(dy, abs=0.5) and c[term][2] * 1e3 == pytest.approx(dz, abs=0.5)
    assert np.linalg.norm(c["centrifugal field"]) < 2e-3
    # right minus left: twice the air's rotation term, to the 5 % its interaction with the others makes
    assert whole[1] - left[1] == pytest.approx(2.0 * c["air's rotation"][1], rel=0.05)


def _jacobi(model: HoseModel, x: np.ndarray, accel: np.ndarray, omega: np.ndarray) -> float:
    """The rotating frame's Jacobi integral [J] of state x: relative kinetic energy, bending energy,
    the potential of the uniform apparent gravity ``accel`` and of the centrifugal field, and the
    links' rotational T0 ``-J |P Omega|^2 / 2`` (from docs/model.md §9, computed here)."""
    n = model.n
    kinetic, potential = model.energy(x)
    r = model.joint_positions(x[: 2 * n])
    gravity_z = -np.sum(model.M * G0 * r[1:, 2])
    bending = potential - gravity_z
    e = np.diff(r, axis=0) / model.l[:, None]
    p_omega = omega[None, :] - (e @ omega)[:, None] * e
    return (kinetic + bending - np.sum(model.M * (r[1:] @ accel))
            - 0.5 * np.sum(model.M * np.sum(np.cross(omega, r[1:]) ** 2, axis=1))
            - 0.5 * np.sum(model.J * np.sum(p_omega**2, axis=1)))


def test_jacobi_integral_is_conserved_in_a_steady_turn_without_air():
    """Air off, a 45-degree coordinated turn at 50 m/s (turn rate 0.196 rad/s): the hose released
    from its shape in the air swings under the apparent gravity g / cos(phi) along z, the
    centrifugal field and the Coriolis force. The Jacobi integral's drift over 10 s shrinks by
    at least 14 per halving of the RK4 step (fourth order is 16; measured 30-33: RK4's energy
    error of a near-linear oscillation is O(h^6) per step, its amplification 1 - (h w)^6 / 72, so
    O(h^5) over the run; 40 bounds that) and is below 1e-6 of the energy exchanged at 2.5 ms,
    while the energy of the level-flight formula changes by far more: the frame terms are what
    conserve it."""
    phi = math.radians(45.0)
    V = 50.0
    omega = G0 * math.tan(phi) / V * np.array([0.0, math.sin(phi), math.cos(phi)])
    accel = np.array([0.0, 0.0, G0 / math.cos(phi)])
    base = PAPER.replace(hose={"links": 10, "bending": "moment"}, flight={"airspeed_m_s": V})
    x0 = solve_equilibrium(base).state
    drifts, exchanged = [], None
    for h in (0.01, 0.005, 0.0025):
        p = steady_params(base.replace(flight={"density_scale": 0.0}, numerics={"step_s": h, "output_every": 1}),
                          bank_deg=45.0)
        res = hd.simulate(p, 10.0, x0=x0)
        assert res.completed
        model = HoseModel(p)
        jac = np.array([_jacobi(model, x, accel, omega) for x in res.states[:: int(0.05 / h)]])
        drifts.append(np.max(np.abs(jac - jac[0])))
        kin = np.array([model.energy(x)[0] for x in res.states[:: int(0.05 / h)]])
        exchanged = np.ptp(kin)
        level_energy = np.array([sum(model.energy(x)) for x in res.states[:: int(0.05 / h)]])
    ratios = np.array(drifts[:-1]) / np.array(drifts[1:])
    assert np.all((ratios > 14) & (ratios < 40)), (drifts, ratios)
    assert drifts[-1] < 1e-6 * exchanged
    assert np.ptp(level_energy) > 1e4 * drifts[-1]


def _run(tables: dict):
    sc = scenario_from_dict({"model": {"preset": "converged"}, "numerics": {"output_every": 20}, **tables})
    return sc, hd.run(sc)


def test_speed_change_settles_at_the_new_balance_position():
    """150 -> 170 m/s at 2 m/s^2 from t = 1 s (the speed-change scenario's manoeuvre, converged
    preset): over the last 5 s of 80 s the drogue is within 1 mm of the balance position at
    170 m/s (the wake's circulation at the new speed), after moving decimetres."""
    sc, res = _run({"scenario": {"name": "speed", "duration_s": 80.0},
                    "tanker_motion": {"segments": [{"start_s": 1.0, "airspeed_m_s": 170.0, "acceleration_m_s2": 2.0}]}})
    assert res.completed
    new = solve_equilibrium(sc.params.replace(flight={"airspeed_m_s": 170.0}, tanker_motion={"segments": []}))
    err = np.linalg.norm(res.drogue_position_m - new.drogue_position_m, axis=1)
    assert np.max(err[res.t_s > 75.0]) < 1e-3
    assert np.max(err) > 0.1


def test_turn_entry_and_exit_return_to_the_level_balance_position():
    """Roll into 30 degrees at 5 deg/s from t = 1 s, roll out from 21 s (converged preset): the
    drogue swings by decimetres and is back within 1 mm of the level balance position over the
    last 10 s of 140 s (its slowest modes decay in 9-13 s)."""
    sc, res = _run({"scenario": {"name": "turn", "duration_s": 140.0},
                    "tanker_motion": {"segments": [{"start_s": 1.0, "bank_deg": 30.0}, {"start_s": 21.0, "bank_deg": 0.0}]}})
    assert res.completed
    level = solve_equilibrium(sc.params.replace(tanker_motion={"segments": []}))
    err = np.linalg.norm(res.drogue_position_m - level.drogue_position_m, axis=1)
    assert np.max(err[res.t_s > 130.0]) < 1e-3
    assert np.max(err) > 0.3


def test_locked_reel_engagement_is_the_fixed_length_run_in_a_turn_entry():
    """The converged hose in moderate turbulence rolling into 30 degrees at 5 deg/s from 0.5 s,
    as a fixed-length scenario and as an engagement with the reel locked: the drogue within
    1e-6 m, the tow force and exit tension within 1e-3 N (the bounds of the level-flight check,
    tests/scenarios/test_one_run.py); both chains evaluate the one frame kernel (measured 5e-15 m)."""
    fixed = scenario_from_dict({
        "scenario": {"name": "fixed", "duration_s": 3.0}, "model": {"preset": "converged"},
        "turbulence": {"enabled": True, "intensity": "moderate", "seed": 7},
        "tanker_motion": {"segments": [{"start_s": 0.5, "bank_deg": 30.0, "roll_rate_deg_s": 5.0}]}})
    locked = scenario_from_dict({**fixed.to_dict(), "reel": {"law": "locked"}})
    a, b = hd.run(fixed), hd.run(locked)
    assert a.completed and b.completed
    np.testing.assert_array_equal(a.t_s, b.t_s)
    assert np.max(np.abs(a.drogue_position_m - b.drogue_position_m)) < 1e-6
    assert np.max(np.abs(a.tow_force_n - b.tow_force_n)) < 1e-3
    assert np.max(np.abs(a.exit_tension_n - b.exit_tension_n)) < 1e-3
    assert np.ptp(a.drogue_position_m[:, 1]) > 0.1  # the roll really moves the drogue


def test_the_wake_carries_the_lift_and_the_gusts_follow_the_path():
    """The evaluation's wake circulation in a 30-degree turn is the lift's, W / (cos(phi) rho V
    b0); during a speed change it is W / (rho V(t) b0), and the gust record is read at the path
    flown over the record's airspeed, V_0 t + the speed ramp's integral (here by quadrature)."""
    from hosedrogue.environment.wake import circulation
    from hosedrogue.model import chain_loads as CL, layout as LY
    from hosedrogue.model.frame import ENV_M_T

    turn = HoseModel(steady_params(PAPER, bank_deg=30.0))
    scratch = np.empty(LY.ENV_SIZE)
    CL.fill_env(0.0, turn.env, turn.gust_values, scratch)
    gamma = circulation(PAPER.tanker, PAPER.wake, 150.0, turn.rho)
    assert scratch[LY.ENV_WAKE + 1] == pytest.approx(gamma / math.cos(math.radians(30.0)), rel=1e-13)
    p = PAPER.replace(tanker_motion={"segments": [{"start_s": 1.0, "airspeed_m_s": 170.0, "acceleration_m_s2": 2.0}]})
    model = HoseModel(p)
    t = np.linspace(0.0, 8.0, 80001)
    V = []
    for ti in t:
        CL.fill_env(ti, model.env, model.gust_values, scratch)
        V.append(scratch[LY.ENV_V])
    V = np.array(V)
    assert V[0] == 150.0 and V[-1] == pytest.approx(150.0 + 2.0 * (8.0 - 1.0 - math.pi / 4.0), rel=1e-12)
    path = np.sum(0.5 * (V[1:] + V[:-1]) * np.diff(t))
    assert scratch[ENV_M_T] == pytest.approx(path / 150.0, rel=1e-10)
    assert scratch[LY.ENV_WAKE + 1] == pytest.approx(circulation(PAPER.tanker, PAPER.wake, V[-1], model.rho), rel=1e-12)


def test_linearization_about_a_steady_turn_matches_the_nonlinear_model():
    """In a 25-degree turn a 1 N lateral step at the drogue: the linear model about the turn's
    balance position and the nonlinear model agree within 2 % of the linear response's peak over
    5 s (the level-flight check's bound, tests/analysis/test_linear.py), while the level-flight linear
    model, differing by the turn, misses by more."""
    import control

    from hosedrogue.analysis.linearize import linearize

    turn = steady_params(PAPER.replace(numerics={"step_s": 0.0025, "output_every": 4}), bank_deg=25.0)
    lm = linearize(turn)
    u = np.array([1.0, 0.0])
    res = hd.simulate(turn, 5.0, control=lambda t, x: u, equilibrium=lm.equilibrium)
    y_lin = control.forced_response(lm.ss, res.t_s, np.outer(u, np.ones_like(res.t_s))).outputs[0]
    y_nl = res.drogue_offset_m[:, 1]
    assert np.max(np.abs(y_nl - y_lin)) < 0.02 * np.max(np.abs(y_lin))
    y_level = control.forced_response(linearize(PAPER).ss, res.t_s, np.outer(u, np.ones_like(res.t_s))).outputs[0]
    assert np.max(np.abs(y_nl - y_level)) > np.max(np.abs(y_nl - y_lin))


SEG = "[[tanker_motion.segments]]\n"


@pytest.mark.parametrize("motion, field", [
    ("[tanker_motion]\nbank_deg = 70.0\n", "tanker_motion.bank_deg = 70.0"),
    ("[tanker_motion]\nbank_deg = nan\n", "tanker_motion.bank_deg = nan"),
    ("[tanker_motion]\nflight_path_deg = -35.0\n", "tanker_motion.flight_path_deg"),
    (SEG + "start_s = 1.0\nbank_deg = 30.0\n" + SEG + "start_s = 3.0\nbank_deg = 0.0\n",
     "tanker_motion.segments[1].start_s = 3.0: starts before segments[0] ends"),
    (SEG + "start_s = 5.0\nbank_deg = 30.0\n" + SEG + "start_s = 1.0\nbank_deg = 0.0\n",
     "tanker_motion.segments[1].start_s = 1.0: before segments[0].start_s"),
    (SEG + "start_s = nan\nbank_deg = 30.0\n", "tanker_motion.segments[0].start_s = nan"),
    (SEG + "start_s = 1.0\nbank_deg = -61.0\n", "tanker_motion.segments[0].bank_deg = -61.0"),
    (SEG + "start_s = 1.0\nroll_rate_deg_s = 5.0\n", "tanker_motion.segments[0]: names none"),
    (SEG + "start_s = 1.0\nairspeed_m_s = 500.0\n", "tanker_motion.segments[0].airspeed_m_s = 500.0"),
    (SEG + "start_s = 1.0\nbank = 30.0\n", "tanker_motion.segments[0].bank: unknown field"),
    ("[tanker_motion]\nsegments = 3\n", "tanker_motion.segments = 3"),
])
def test_bad_motion_is_one_line_exit_2_nothing_written(tmp_path, capsys, motion, field):
    """A bank or flight-path angle beyond the supported range, NaN, segments that overlap or are
    out of order, a segment that changes nothing, an unknown key: one line naming the field, exit
    status 2, nothing written."""
    from hosedrogue import cli

    path = tmp_path / "case.toml"
    path.write_text("[scenario]\nduration_s = 1.0\n\n" + motion)
    out = tmp_path / "out"
    code = cli.main(["simulate", str(path), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and field in err and "Traceback" not in err, err
    assert not out.exists()


@pytest.mark.parametrize("argv", [["steady", "--bank-deg", "61"], ["steady", "--climb-deg", "nan"],
                                  ["linearize", "--bank-deg", "inf"]])
def test_bad_steady_flight_options_are_one_line(capsys, argv):
    from hosedrogue import cli

    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and argv[1] in err


def test_steady_command_in_a_turn_and_a_climb(capsys):
    """``hosedrogue steady --bank-deg 25 --climb-deg -3 --json`` is the library's balance position
    in that steady flight, and ``--continuum`` the continuous hose's; the table names the turn."""
    import json

    from hosedrogue import cli

    p = steady_params(PAPER, bank_deg=25.0, flight_path_deg=-3.0)
    assert cli.main(["steady", "--bank-deg", "25", "--climb-deg", "-3", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["drogue_position_m"] == solve_equilibrium(p).drogue_position_m.tolist()
    assert doc["tanker_motion"] == {"bank_deg": 25.0, "flight_path_deg": -3.0}
    assert cli.main(["steady", "--bank-deg", "25", "--climb-deg", "-3", "--continuum", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["drogue_position_m"] == solve_continuum(p).drogue_position_m.tolist()
    assert cli.main(["steady", "--bank-deg", "-25"]) == 0
    assert "in a 25 deg coordinated turn to the left" in capsys.readouterr().out


def test_the_motion_slots_follow_the_kernels_env():
    """The frame's slots of env start right after the bow wave's and end at the kernels' ENV_SIZE,
    where a manoeuvring model's motion table begins (one layout for both modules)."""
    from hosedrogue.model import frame
    from hosedrogue.model import layout as LY

    assert frame.ENV_M_ON == LY.ENV_BW_LEN + 1 and LY.ENV_SIZE == frame.ENV_M_END
    assert frame.ENV_M_D + 3 == frame.ENV_M_END
    level = HoseModel(PAPER)
    assert level.env.size == LY.ENV_SIZE and level.motion_table is None
    turn = HoseModel(steady_params(PAPER, bank_deg=10.0))
    assert turn.env.size == LY.ENV_SIZE + turn.motion_table.size and turn.env[frame.ENV_M_ON] == 1.0


@pytest.mark.parametrize("law", ["constant-tension", "response"])
def test_engagement_with_a_free_reel_rests_at_the_balance_position_of_a_steady_turn(law):
    """A descending 30-degree turn, the engagement with a free reel and no probe, started at the
    fixed-length chain's balance position in that turn: the reel's tension set point is the
    exit tension there, so nothing moves - the drogue within 1e-9 m of the balance position for
    2 s and the free length constant (measured 5e-15 m and 0). A frame load missing from either
    chain, or from the engagement's length equation, would set the hose moving (the turn's loads
    shift the drogue by decimetres)."""
    sc = scenario_from_dict({"scenario": {"name": "rest", "duration_s": 2.0}, "model": {"preset": "converged"},
                             "reel": {"law": law}, "tanker_motion": {"bank_deg": 30.0, "flight_path_deg": -5.0}})
    res = hd.run(sc)
    eq = solve_equilibrium(sc.params)
    assert res.completed
    assert np.max(np.abs(res.drogue_position_m - eq.drogue_position_m)) < 1e-9
    assert np.ptp(res.hose_length_m) < 1e-9
