"""The elastic hose of varying length (docs/model.md §11): agreement with the fixed-length elastic
chain at L' = 0 and with simulate for the locked reel, the energy balance with the strain energy
and the axial damping through remeshes and chart switches (RK4 and the stiff SDIRK), and the
remesh of stretched links."""

import numpy as np
import pytest

from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.engagement import Reel, simulate_engagement
from hosedrogue.engagement.chain import chain_arrays
from hosedrogue.engagement.parameters import engagement_parameters
from hosedrogue.engagement.loop import no_loop
from hosedrogue.model import chain_dynamics as CD, elastic as E, layout as LY
from hosedrogue.model.engagement import evaluation as EV, outputs as EO
from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER
from hosedrogue.simulation.budget import on_step_grid
from hosedrogue.simulation.simulate import simulate

MU = PAPER.hose.mass_per_length_kg_m


@pytest.mark.parametrize("lumping", ["split", "aft"])
@pytest.mark.parametrize("exit_link", [1.0, 0.9], ids=["equal-links", "short-exit-link"])
def test_engagement_at_rest_length_is_the_elastic_hose_model(rng, lumping, exit_link):
    """At L' = 0 the elastic chain of varying length is the fixed-length elastic chain: the same
    accelerations of angles and lengths, tow-point force, exit tension, link tensions and energy
    (kinetic; bending plus strain) at a random stretched, moving state. Round-off of one O(n)
    solve: 1e-9 relative, 1e-9 N, 1e-9 J (measured ~1e-14 relative)."""
    p = PAPER.replace(hose={"links": 12, "link_inertia": "rod", "bending": "moment", "mass_lumping": lumping,
                            "axial_stiffness_n": 2e5, "axial_damping_n_s": 400.0})
    n = 12
    l_nom = p.hose.length_m / n
    lengths = np.r_[exit_link * l_nom, np.full(n - 1, l_nom)]
    model = HoseModel(p, lengths=lengths)
    chain = chain_arrays(p, lengths, l_nom)
    q = np.pi / 2 * 0.3 + rng.uniform(-0.2, 0.2, 2 * n)
    qd = rng.uniform(-0.5, 0.5, 2 * n)
    lam = lengths * (1.0 + rng.uniform(-0.01, 0.01, n))
    lamd = rng.uniform(-0.2, 0.2, n)
    x = np.concatenate([q, qd, lam, lamd])
    ref = model.outputs(x)
    ep = engagement_parameters(p, Reel(law="locked"), None, chain, np.zeros(3))
    z = np.concatenate([x, [float(np.sum(lengths)), 0.0], np.zeros(LY.Z_TAIL - 2)])
    args = (n, chain.l.copy(), chain.M.copy(), chain.J.copy(), model.ps, model.env, model.gust_values, ep,
            chain.chart, no_loop())
    ws, ews = CD.make_workspace(n), E.make_elastic_workspace(n)
    out = np.empty(LY.O_SIZE)
    EV.eng_evaluate_elastic(0.0, z, *args, ws, ews, np.empty(2), out, 0.0, np.zeros(n))
    acc = np.concatenate([ws[CD.WS_QDD], ews[E.EWS_LAMDD]])
    assert np.max(np.abs(acc - ref.qdd)) < 1e-9 * np.max(np.abs(ref.qdd))
    assert abs(out[LY.O_T0] - ref.exit_tension_n) < 1e-9
    N = 1
    joints, jvel, scal, tow, tdrog, drag, links_t = (np.empty((N, n + 1, 3)), np.empty((N, n + 1, 3)),
                                                     np.empty((N, LY.O_SIZE)), np.empty((N, 3)), np.empty(N),
                                                     np.empty((N, 3)), np.empty((N, n)))
    EO.eng_outputs(np.zeros(1), z[None, :], *args, joints, jvel, scal, tow, tdrog, drag, links_t, np.empty((N, 4)))
    assert np.max(np.abs(tow[0] - ref.tow_force_n)) < 1e-9
    eps = lam / lengths - 1.0
    np.testing.assert_allclose(links_t[0], 2e5 * eps + 400.0 * lamd / lengths, rtol=0, atol=1e-9)
    kinetic, potential = model.energy(x)
    kin_r, kin_v = np.empty_like(joints[0]), np.empty_like(jvel[0])
    T, U, T_reel = EO.eng_energy(z, *args[:5], ep, chain.chart, kin_r, kin_v)
    # the events' kinematic pass gives the evaluation's joints bit for bit (the same operations)
    assert np.array_equal(kin_r, joints[0]) and np.array_equal(kin_v, jvel[0])
    gravity = -float(np.sum(model.M * model.ps[LY.PS_G] * model.joint_positions(q, lam)[1:, 2]))
    assert abs(T - kinetic) < 1e-9 and T_reel == 0.0
    assert abs(U - (potential - gravity)) < 1e-9


def test_locked_reel_is_simulate_for_elastic_links():
    """The locked reel without probe is the fixed-length elastic chain: the engagement driver and
    simulate (both the SDIRK at 2 ms, from the same elastic balance position) give the same drogue
    path over 3 s of moderate turbulence to 1e-9 m (the two compiled loops do the same arithmetic
    but for the engagement's extra terms that vanish at L' = 0; measured 0)."""
    p = PAPER.replace(hose={"links": 20, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split",
                            "axial_stiffness_n": 1e6, "axial_damping_n_s": 3000.0},
                      turbulence={"enabled": True, "intensity": "moderate", "seed": 7},
                      numerics={"integrator": "sdirk2", "step_s": 0.002, "output_every": 5})
    fixed = simulate(p, 3.0)
    eng = simulate_engagement(p, 3.0, reel=Reel(law="locked"), probe=None)
    assert fixed.completed and eng.completed
    assert np.max(np.abs(fixed.drogue_position_m - eng.drogue_position_m)) < 1e-9
    assert np.max(np.abs(fixed.exit_tension_n - eng.exit_tension_n)) < 1e-6


def swinging_start(n, rng, yaw_scale=0.2):
    x0 = np.zeros(6 * n)
    x0[0: 2 * n: 2] = np.pi / 2 + np.linspace(0.7, -0.3, n)
    x0[1: 2 * n: 2] = np.linspace(0.2, -0.1, n)
    x0[2 * n: 4 * n] = rng.uniform(-0.5, 0.5, 2 * n)
    x0[2 * n + 1: 4 * n: 2] *= yaw_scale
    x0[4 * n: 5 * n] = 2.0 * (1.0 + rng.uniform(-0.005, 0.005, n))  # 16 m in 8 links, stretched by up to 0.5 %
    x0[5 * n:] = rng.uniform(-0.2, 0.2, n)
    return x0


def free_reel_run(integrator, step, yaw_scale=0.2, n=8):
    """The rigid chain's free-reel run (tests/engagement/test_engagement_chain.py) with elastic links: no air,
    no gravity, conservative bending, EA = 1e5 N (axial waves at 151 m/s, so RK4 is stable at these
    steps) and 50 N s of axial damping; the reel pays out at 1.5 m/s and a constant-tension motor
    brakes it and reels back in, splitting and merging the exit link (``yaw_scale`` 3: links swing
    sideways and change chart)."""
    p = PAPER.replace(hose={"links": n, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split",
                            "axial_stiffness_n": 1e5, "axial_damping_n_s": 50.0},
                      flight={"density_scale": 0.0},
                      numerics={"integrator": integrator, "step_s": step, "output_every": int(round(0.05 / step))})
    reel = Reel(law="constant-tension", tension_set_n=100.0, max_torque_n_m=1e5, max_takeup_speed_m_s=50.0,
                max_payout_speed_m_s=50.0)
    # 10 s to the nearest output time (9.984 s at 4 ms: 208 outputs of 12 steps), as every run must be
    duration = on_step_grid(10.0, step, p.numerics.output_every)
    return simulate_engagement(p, duration, reel=reel, probe=None, x0=swinging_start(n, np.random.default_rng(1), yaw_scale),
                               length_rate_m_s=1.5, gravity_m_s2=0.0, energy=True)


def balance_residual(r):
    """E(t) - E(0) - (motor work - friction heat + carried kinetic energy - axial damping heat)
    - (the energy changes recorded at the remeshes)."""
    E_ = r.energy
    total = E_["kinetic"] + E_["elastic"] + E_["reel"]
    jumps = np.zeros_like(total)
    for ev in r.events:
        if ev["kind"] in ("split", "merge", "chart"):
            jumps[r.t_s > ev["t_s"] + 1e-12] += ev["energy_jump_j"]
    return total - total[0] - (E_["motor"] - E_["friction"] + E_["flux"] - E_["axial"]) - jumps


@pytest.fixture(scope="module")
def free_runs():
    runs = {("rk4", h): free_reel_run("rk4", h) for h in (4e-3, 2e-3, 1e-3)}
    runs.update({("sdirk2", h): free_reel_run("sdirk2", h) for h in (2e-3, 1e-3, 5e-4)})
    runs[("charts", 1e-3)] = free_reel_run("rk4", 1e-3, yaw_scale=3.0)
    return runs


def test_elastic_free_run_exercises_split_merge_and_charts(free_runs):
    kinds = [e["kind"] for e in free_runs[("rk4", 1e-3)].events]
    assert kinds.count("split") >= 1 and kinds.count("merge") >= 2, kinds
    assert sum(e["kind"] == "chart" for e in free_runs[("charts", 1e-3)].events) >= 3


@pytest.mark.parametrize("integrator,steps,factor", [("rk4", (4e-3, 2e-3, 1e-3), 8.0),
                                                     ("sdirk2", (2e-3, 1e-3, 5e-4), 2.5)])
def test_elastic_energy_balance_with_moving_reel(free_runs, integrator, steps, factor):
    """Kinetic + bending + strain + reel energy changes by the motor's work, minus the drum
    friction and the links' axial damping heat, plus the kinetic energy carried by hose joining
    or leaving the moving masses, through splits and merges (docs/model.md §11). The residual must
    shrink with the step at the scheme's order (RK4: > 8 per halving, h^4 with room for the
    remesh instants moving with the step; the SDIRK: > 2.5 per halving, h^2 reached from above:
    measured ratios 2.8 and 3.5) and close below 1e-6 of the initial kinetic energy at RK4's finest
    step (the brief's bound). Measured residuals over the initial kinetic energy: RK4 at 4, 2, 1
    ms 1.4e-3, 3.4e-5, 4.3e-7; SDIRK at 2, 1, 0.5, 0.25, 0.125 ms 7.1e-4, 2.6e-4, 7.5e-5,
    2.0e-5, 5.1e-6. The axial damping's heat (39 J, of 17 J initial kinetic energy) is far
    above the residual."""
    res = {h: np.max(np.abs(balance_residual(free_runs[(integrator, h)]))) / free_runs[(integrator, h)].energy["kinetic"][0]
           for h in steps}
    assert res[steps[0]] > factor * res[steps[1]] and res[steps[1]] > factor * res[steps[2]], res
    r = free_runs[(integrator, steps[-1])]
    if integrator == "rk4":
        assert res[steps[-1]] < 1e-6, res
    assert r.energy["axial"][-1] > 1e-3 * r.energy["kinetic"][0]  # the damping's heat counts


def test_elastic_energy_balance_through_chart_switches(free_runs):
    """The same balance through chart switches (links swinging sideways): below 1e-6 of the
    kinetic energy with RK4 at 1 ms."""
    r = free_runs[("charts", 1e-3)]
    assert np.max(np.abs(balance_residual(r))) < 1e-6 * r.energy["kinetic"][0]


def test_elastic_remesh_keeps_positions_velocities_and_material(free_runs):
    """A split inserts a material point of the exit link (same strain on both sides), a merge
    joins links 0 and 1 straight to old joint 2 with their mean strain: every surviving joint keeps
    its position and velocity (round-off: 1e-12 m, m/s), the hose mass in the air stays mu L
    (1e-10 kg), a merge leaves the reel's speed alone (it is a state of its own) and loses the
    material of the kink only (about l gamma^2 / 4: below 1 cm for the up to 0.15 rad between these
    2 m links; measured up to 3.7 mm)."""
    r = free_runs[("rk4", 1e-3)]
    for ev in r.events:
        if ev["kind"] in ("split", "merge", "chart"):
            assert ev["position_jump_m"] < 1e-12 and ev["velocity_jump_m_s"] < 1e-12, ev
        if ev["kind"] == "merge":
            assert 0.0 <= ev["length_lost_m"] < 1e-2 and ev["reel_speed_jump_m_s"] == 0.0, ev
    assert np.max(np.abs(r.hose_mass_kg - MU * r.hose_length_m)) < 1e-10


def test_split_of_a_stretched_exit_link_keeps_the_strain():
    """A split of the paying-out exit link: the two new links carry the old strain and strain rate
    (the tensions and the exit tension unchanged to round-off, 1e-9 N of ~1 kN)."""
    from hosedrogue.engagement.chain import initial_chain, split

    p = PAPER.replace(hose={"links": 8, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split",
                            "axial_stiffness_n": 1e5, "axial_damping_n_s": 50.0})
    chain = initial_chain(p)
    eq = solve_equilibrium(p)
    n = chain.n
    z = np.concatenate([eq.state, [16.0 + 1.0, 0.8], np.zeros(LY.Z_TAIL - 2)])  # exit link holds 3 m of material
    z[5 * n] = 0.05
    z2, ch2 = split(z, chain, p)
    l1 = z[6 * n + LY.Z_L] - np.sum(chain.l[1:])
    lam, lamd = z[4 * n], z[5 * n]
    eps_d = lamd / l1 - lam * 0.8 / l1**2
    m = ch2.n
    la, lb = z2[4 * m], z2[4 * m + 1]
    lad, lbd = z2[5 * m], z2[5 * m + 1]
    la0 = l1 - chain.l_nom
    assert abs(la / la0 - lam / l1) < 1e-14 and abs(lb / chain.l_nom - lam / l1) < 1e-14
    assert abs((lad / la0 - la * 0.8 / la0**2) - eps_d) < 1e-14
    assert abs(lbd / chain.l_nom - eps_d) < 1e-14


@pytest.mark.parametrize("law", ["constant-tension", "response"])
def test_elastic_engagement_rests_at_the_balance_position_of_a_steady_turn(law):
    """The elastic chains in the tanker's steady frame (docs/model.md §9): a descending 30-degree
    turn, the engagement of an elastic hose (1e6 N, 3000 N s, the SDIRK at 2 ms) on a free reel
    without probe, started at the elastic balance position in that turn (solved with the frame's
    loads at rest, the stretch included): nothing moves - the drogue within 1e-8 m for 2 s, the
    free length constant to 1e-9 m (measured 8e-12 and 9e-12 m, constant tension; 5e-15 m and 0,
    response: the balance position's 1e-10 residual). A frame load missing from the elastic chain's evaluation, its
    static residual or the reel's equation would set the hose moving (the turn shifts the drogue
    by decimetres)."""
    from hosedrogue.scenarios import scenario_from_dict
    import hosedrogue as hd

    sc = scenario_from_dict({"scenario": {"name": "rest", "duration_s": 2.0}, "model": {"preset": "converged"},
                             "hose": {"axial_stiffness_n": 1e6, "axial_damping_n_s": 3000.0},
                             "numerics": {"integrator": "sdirk2", "step_s": 0.002, "output_every": 5},
                             "reel": {"law": law}, "tanker_motion": {"bank_deg": 30.0, "flight_path_deg": -5.0}})
    res = hd.run(sc)
    eq = solve_equilibrium(sc.params)
    level = solve_equilibrium(sc.params.replace(tanker_motion={"bank_deg": 0.0, "flight_path_deg": 0.0}))
    assert res.completed and eq.lengths_m is not None
    assert np.max(np.abs(res.drogue_position_m - eq.drogue_position_m)) < 1e-8
    assert np.ptp(res.hose_length_m) < 1e-9
    assert np.linalg.norm(eq.drogue_position_m - level.drogue_position_m) > 0.1


def test_zero_takeup_user_reel_is_the_locked_reel_for_elastic_links():
    """The commanded reel (a user law, here zero take-up at 100 Hz, on a drive strong enough for
    the whip: 1e5 N m) with an elastic hose: the speed servo asks for L'' = 0, which the elastic
    chain takes as a prescribed length (as the locked reel's), so the run is the locked reel's -
    engage-locked on 40 elastic links (the SDIRK at 2 ms), the drogue within 1e-9 m, the length
    constant (measured: the same bits)."""
    import dataclasses

    from hosedrogue import load_scenario, run
    from hosedrogue.studies.convergence import with_links

    sc = with_links(load_scenario("engage-locked"), 40)
    sc = dataclasses.replace(sc, params=sc.params.replace(numerics={"step_s": 0.002, "output_every": 5}))
    locked = run(sc)
    zero = Reel(law="python", entry="hosedrogue.examples.controllers:constant_takeup", sample_time_s=0.01,
                max_torque_n_m=1e5)
    got = run(dataclasses.replace(sc, engagement=dataclasses.replace(sc.engagement, reel=zero)))
    assert got.completed and got.outcome["result"] == "captured"
    assert np.all(got.hose_length_m == got.hose_length_m[0])
    assert np.max(np.abs(got.drogue_position_m - locked.drogue_position_m)) < 1e-9


def test_drogue_surfaces_refuse_an_elastic_hose(tmp_path, capsys):
    """The drogue's control surfaces (main's [drogue_actuator]) run the rigid links' state layout:
    an elastic hose with them is refused in one line naming hose.axial_stiffness_n - in a scenario
    file (exit 2, nothing written), in simulate and in simulate_engagement."""
    from hosedrogue.cli import main
    from hosedrogue.spec.drogue_surfaces import DrogueActuator
    from hosedrogue.errors import ParameterError

    f = tmp_path / "elastic-surfaces.toml"
    f.write_text('[scenario]\nextends = "engage-response"\n\n[controller]\ntype = "pid"\n\n[drogue_actuator]\n')
    out = tmp_path / "out"
    assert main(["simulate", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "hose.axial_stiffness_n = 1000000.0" in err[0] and "rigid links" in err[0], err
    assert not out.exists()
    p = PAPER.replace(hose={"axial_stiffness_n": 1e6, "axial_damping_n_s": 3000.0},
                      numerics={"integrator": "sdirk2", "step_s": 0.001})
    with pytest.raises(ParameterError, match="hose.axial_stiffness_n"):
        simulate(p, 0.1, drogue_actuator=DrogueActuator())
    with pytest.raises(ParameterError, match="hose.axial_stiffness_n"):
        simulate_engagement(p, 0.1, reel=Reel(law="locked"), probe=None, drogue_actuator=DrogueActuator())


def test_sampled_fixed_length_paths_refuse_an_elastic_hose():
    """The fixed-length stepper (the sampled-data controllers' driver) runs the rigid chain: an
    elastic hose is refused in one line naming hose.axial_stiffness_n, there and in simulate with a
    sampled built-in controller."""
    from hosedrogue.errors import ParameterError
    from hosedrogue.simulation.stepper import FixedLengthStepper

    p = PAPER.replace(hose={"axial_stiffness_n": 1e6, "axial_damping_n_s": 3000.0},
                      numerics={"integrator": "rk4", "step_s": 0.0001})  # RK4: the stepper's integrator
    with pytest.raises(ParameterError, match=r"hose.axial_stiffness_n = 1000000.0: the fixed-length stepper"):
        FixedLengthStepper(p, 0.1, control_step_s=0.01)
    with pytest.raises(ParameterError, match="a sampled-data controller runs the rigid fixed-length chain"):
        simulate(p, 0.1, sample_time_s=0.01)


def test_more_least_corrections_than_the_most_still_converge():
    """``numerics.sdirk_corrections`` above the SDIRK's usual most (6) raises the most with it:
    8 corrections per stage on the shipped responsive reel for 0.5 s run to the end, and the hose
    is where the default 2 put it to within the 1 mm/s tolerance's effect over 0.5 s (a joint
    moved by less than 1 mm)."""
    import dataclasses

    from hosedrogue import load_scenario, run

    sc = load_scenario("engage-response")
    runs = [run(dataclasses.replace(sc, duration_s=0.5, params=sc.params.replace(
        numerics={"sdirk_corrections": k}))) for k in (2, 8)]
    assert all(r.completed for r in runs), [r.message for r in runs]
    assert np.max(np.abs(runs[0].drogue_position_m - runs[1].drogue_position_m)) < 1e-3


def test_saved_steps_loads_from_the_outputs_are_the_time_loops(monkeypatch):
    """The per-step record's rows at the saved steps, which the driver takes from the saved states'
    outputs (``derived_outputs``: the full evaluation), are the rows the time loop writes itself
    (``state_loads``: the kinematics alone) to the bit, through the capture (the probe load) and the
    remeshes of the responsive reel's take-up."""
    import dataclasses

    from hosedrogue.engagement import driver as DR
    from hosedrogue.model.engagement import steps as ES
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run

    scenario = dataclasses.replace(load_scenario("engage-response"), duration_s=4.0)
    fused = run(scenario)
    segment, assemble = ES.eng_segment, DR.assemble_result
    monkeypatch.setattr(ES, "eng_segment", lambda *a: segment(*a, saved_loads=False))
    monkeypatch.setattr(DR, "assemble_result", lambda *a, **k: assemble(*a, **{**k, "loads_from_outputs": False}))
    own = run(scenario)
    assert fused.outcome["result"] == "captured" and fused.outcome["remesh_events"] > 0
    assert np.max(fused.step_loads[:, 3]) > 100.0  # the probe load after the capture [N]
    assert np.array_equal(fused.step_loads, own.step_loads)
