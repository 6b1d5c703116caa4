"""Your own controllers in the loop, measured and printed next to their targets (never asserted).

Sections (all by default, or name some on the command line):

* ``pid`` - the paper's turbulence case (paper-turbulence-pid, 60 s, RK4 at 5 ms) with the user's
  discretized PID in Python at 100 Hz (hosedrogue.examples.controllers:discrete_pid) against the
  built-in PID compiled in the same sampled-data mode and against the continuous built-in PID:
  wall time (target: the user's at most 1.3 times the built-in compiled one), and the drogue
  trajectories' largest differences (the check: user vs built-in sampled within 1e-6 m);
* ``stepping`` - the stepping API: environment steps per second of EngagementStepper at 20 links
  and a 0.02 s control step on one core (approach-moderate: converged preset, moderate
  turbulence, bow wave; a PD command computed in Python each step; resets included; target
  >= 5,000), at RK4 steps of 5, 10 and 20 ms; and of FixedLengthStepper;
* ``reel`` - engage-locked's set-up at its 160 links: the locked reel, the built-in response law,
  the user's zero take-up and slack-feedback laws (engage-slack-law): length taken up [m] (target
  >= 1 m) and peak slack [m] (target: at most a fifth of the locked reel's);
* ``docking`` - 200-run Monte Carlo campaigns of approach-moderate with the straight-line probe,
  the pilot model and the PD docking controller (approach-moderate-docking) on 2 Dask workers:
  capture rates with their Wilson 95 % intervals (target: PD above the straight line), and the
  PD campaign's rows for 1 and 2 workers compared.

Run:  .venv/bin/python benchmarks/user_controllers.py [pid] [stepping] [reel] [docking]
(one core per process: NUMBA_NUM_THREADS=1 is set here). CPU seconds are the process's own
(time.process_time), the fairest figure on a shared machine; wall seconds are printed too.
"""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import dataclasses  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from hosedrogue import load_scenario, run  # noqa: E402
from hosedrogue.spec.sections import Controller, Receiver, Reel  # noqa: E402


def best_of(fn, repeats=3):
    """(best wall [s], best CPU [s], last result) over ``repeats`` calls."""
    wall = cpu = math.inf
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        out = fn()
        wall, cpu = min(wall, time.perf_counter() - w), min(cpu, time.process_time() - c)
    return wall, cpu, out


def pid():
    sc = load_scenario("paper-turbulence-pid")

    def with_ctrl(**table):
        return dataclasses.replace(sc, loop=dataclasses.replace(sc.loop, controller=Controller(**table)))

    cases = {
        "built-in PID, continuous (compiled)": sc,
        "built-in PID, sampled at 100 Hz (compiled)": with_ctrl(type="pid", sample_time_s=0.01),
        "user PID in Python at 100 Hz": with_ctrl(type="python", entry="hosedrogue.examples.controllers:discrete_pid",
                                                 sample_time_s=0.01, options={"sample_time_s": 0.01}),
    }
    results = {}
    for name, case in cases.items():
        run(case)  # compile
        wall, cpu, results[name] = best_of(lambda c=case: run(c), 5)
        print(f"  {name:45s} {wall:6.3f} s wall, {cpu:6.3f} s CPU (best of 5)")
        results[name + " cpu"] = cpu
    names = list(cases)
    ratio = results[names[2] + " cpu"] / results[names[1] + " cpu"]
    print(f"  user / built-in sampled: {ratio:.2f} x CPU time (target <= 1.3); user / built-in continuous: "
          f"{results[names[2] + ' cpu'] / results[names[0] + ' cpu']:.2f} x")
    c, s, u = (results[n].drogue_position_m for n in names)
    print(f"  drogue: user vs built-in sampled {np.max(np.abs(u - s)):.2e} m (check <= 1e-6 m); sampled vs "
          f"continuous {np.max(np.abs(s - c)) * 1e3:.3f} mm, peak offset of the continuous PID "
          f"{np.max(np.abs(results[names[0]].drogue_offset_m[:, 1:])) * 1e3:.2f} mm")


def stepping():
    from hosedrogue.engagement import EngagementStepper
    from hosedrogue.simulation.stepper import FixedLengthStepper

    base = load_scenario("approach-moderate")
    for step in (0.005, 0.01, 0.02):
        sc = dataclasses.replace(base, params=base.params.replace(
            numerics={"step_s": step, "output_every": max(1, int(round(0.01 / step)))}))
        e = sc.engagement
        st = EngagementStepper(sc.params, sc.duration_s, control_step_s=0.02, reel=e.reel, probe=e.probe,
                               bow_wave=e.bow_wave, receiver=Receiver(), record=False)

        def episodes(count=20):
            steps = 0
            for seed in range(count):
                m = st.reset(seed=seed)
                while not st.done:
                    rp, rv, dv = m.relative_position_m, m.relative_velocity_m_s, m.drogue_velocity_m_s
                    m = st.step(receiver=(1.0, dv[1] + 2.0 * rp[1] + 0.2 * rv[1], dv[2] + 2.0 * rp[2] + 0.2 * rv[2]))
                    steps += 1
            return steps

        episodes(1)
        wall, cpu, steps = best_of(episodes, 3)
        print(f"  EngagementStepper, {sc.params.hose.links} links, RK4 {step * 1e3:g} ms, control 20 ms: "
              f"{steps / cpu:8.0f} steps per CPU s ({steps / wall:8.0f} per wall s; {steps} steps, 20 resets; "
              f"target >= 5000)")
    p = load_scenario("paper-turbulence").params.replace(turbulence={"start_s": 0.0})
    st = FixedLengthStepper(p, 20.0, control_step_s=0.02, record=False)

    def fixed():
        steps = 0
        m = st.reset(seed=1)
        while not st.done:
            m = st.step(drogue=(-5000.0 * (m.drogue_position_m[1] - m.drogue_balance_m[1]),
                                -5000.0 * (m.drogue_position_m[2] - m.drogue_balance_m[2])))
            steps += 1
        return steps

    fixed()
    wall, cpu, steps = best_of(fixed, 3)
    print(f"  FixedLengthStepper, {p.hose.links} links, RK4 {p.numerics.step_s * 1e3:g} ms, control 20 ms: "
          f"{steps / cpu:8.0f} steps per CPU s ({steps / wall:8.0f} per wall s)")


def reel():
    sc = load_scenario("engage-locked")
    zero = Reel(law="python", entry="hosedrogue.examples.controllers:constant_takeup", sample_time_s=0.01)
    cases = {
        "locked": sc,
        "built-in response law": dataclasses.replace(sc, engagement=dataclasses.replace(
            sc.engagement, reel=Reel(law="response"))),
        "user zero take-up, 2000 N m motor": dataclasses.replace(sc, engagement=dataclasses.replace(
            sc.engagement, reel=zero)),
        "user zero take-up, 1e5 N m drive": dataclasses.replace(sc, engagement=dataclasses.replace(
            sc.engagement, reel=dataclasses.replace(zero, max_torque_n_m=1e5))),
        "user slack law, 4 /s (the built-in gain)": dataclasses.replace(
            load_scenario("engage-slack-law"), engagement=dataclasses.replace(
                load_scenario("engage-slack-law").engagement, reel=dataclasses.replace(
                    load_scenario("engage-slack-law").engagement.reel, options={"gain_1_s": 4.0}))),
        "user slack law, 8 /s (engage-slack-law)": load_scenario("engage-slack-law"),
    }
    out = {}
    for name, case in cases.items():
        t = time.perf_counter()
        r = run(case)
        o = out[name] = r.outcome
        print(f"  {name:42s} taken up {o['length_taken_up_m']:.3f} m, peak slack {o['peak_slack_m']:.3f} m, "
              f"peak exit tension {o['peak_exit_tension_n']:.0f} N, L range "
              f"[{np.min(r.hose_length_m):.4f}, {np.max(r.hose_length_m):.4f}] m, {o['result']}, "
              f"{time.perf_counter() - t:.0f} s")
    locked = out["locked"]["peak_slack_m"]
    for name in ("built-in response law", "user slack law, 4 /s (the built-in gain)",
                 "user slack law, 8 /s (engage-slack-law)"):
        print(f"  {name}: slack cut x{locked / out[name]['peak_slack_m']:.2f} (target >= 5), taken up "
              f"{out[name]['length_taken_up_m']:.2f} m (target >= 1 m)")


def docking():
    from hosedrogue.studies import executor
    from hosedrogue.studies.campaign import run_campaign

    root = Path(tempfile.mkdtemp(prefix="hosedrogue-docking-"))
    cluster, client = executor.local_cluster(2)
    try:
        for name in ("approach-moderate", "approach-moderate-pilot", "approach-moderate-docking"):
            t = time.perf_counter()
            cap = run_campaign(name, 200, root / name, client=client, progress=False).capture
            print(f"  {name:28s} captured {cap['rate'] * 100:5.1f} % of {cap['runs']}, Wilson 95 % "
                  f"[{cap['ci95'][0] * 100:.1f}, {cap['ci95'][1] * 100:.1f}] %, {time.perf_counter() - t:.0f} s")
    finally:
        client.close()
        cluster.close()
    one = root / "docking-1-worker"
    run_campaign("approach-moderate-docking", 200, one, scheduler="synchronous", progress=False)
    same = (one / "runs.csv").read_text().splitlines()
    two = (root / "approach-moderate-docking" / "runs.csv").read_text().splitlines()
    print(f"  approach-moderate-docking rows: 1 worker vs 2 workers identical after sorting: "
          f"{sorted(same) == sorted(two)}")


SECTIONS = {"pid": pid, "stepping": stepping, "reel": reel, "docking": docking}

if __name__ == "__main__":
    chosen = sys.argv[1:] or list(SECTIONS)
    for name in chosen:
        print(f"{name}:")
        SECTIONS[name]()
