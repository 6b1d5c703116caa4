"""Run cost of the drogue steered by its control surfaces against the ideal force, printed as
figures (never asserted).

* the compiled RK4 loop's time per step of the paper's PID in the paper's turbulence case
  (20 links, ``paper-turbulence-pid``'s settings at the 2.5 ms the default servo needs), ideal
  force against the ``[drogue_actuator]`` defaults (four surfaces, second-order servos: 8 more
  states, the local air at the drogue and the mixing per evaluation), and the first-order servo
  (4 more states);
* the shipped scenarios through ``hosedrogue.run`` (balance, design, simulation, outputs: what a
  user waits for): ``paper-turbulence-pid`` (5 ms) against ``paper-turbulence-pid-actuated``
  (2.5 ms), and one approach, ``approach-moderate-pid`` against ``approach-moderate-pid-actuated``
  (the engagement's kernels): the surfaces' own cost and the halved step together;
* a user's sampled-data PID (``discrete_pid`` at 200 Hz, Python, through the stepper) on
  ``paper-turbulence-pid`` at 2.5 ms, ideal force against the surfaces.

Compile time is excluded (every path runs once first). Times are the process's CPU time
(``time.process_time``: the machine is shared, so wall time measures the other users too). Run:
``.venv/bin/python benchmarks/drogue_actuator.py`` (one core: NUMBA_NUM_THREADS=1 is set here).
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import dataclasses  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from hosedrogue.controllers.design import design_controller  # noqa: E402
from hosedrogue.analysis.equilibrium import solve_equilibrium  # noqa: E402
from hosedrogue.model.integrate import loop_arrays, rk4_run  # noqa: E402
from hosedrogue.model.system import HoseModel  # noqa: E402
from hosedrogue.spec.params import Actuator  # noqa: E402
from hosedrogue.scenarios import load_scenario  # noqa: E402
from hosedrogue.scenarios.runner import run  # noqa: E402
from hosedrogue.spec.sections import DrogueActuator  # noqa: E402
from hosedrogue.simulation.simulate import closed_loop_state, output_arrays, output_width  # noqa: E402

REPEATS = 5
#: Simulated time of the loop benchmark [s] (turbulence on throughout).
LOOP_S = 60.0
#: RK4 step of the loop benchmark [s]: what the default servo needs (DrogueActuator().max_step_s = 4.7 ms).
STEP_S = 0.0025


def loop_cost(section, repeats=REPEATS):
    """CPU time per RK4 step [us] of the compiled loop (fastest and median of ``repeats``)."""
    sc = load_scenario("paper-turbulence-pid")
    p = sc.params.replace(turbulence={"start_s": 0.0, "duration_s": LOOP_S}, numerics={"step_s": STEP_S, "output_every": 4})
    model = HoseModel(p, duration_s=LOOP_S)
    eq = solve_equilibrium(p, model=model)
    ctrl = design_controller("pid", {}, p)
    loop = loop_arrays(ctrl, eq.drogue_position_m[1:].copy(), Actuator(), np.zeros((1, 2)), 1.0, section)
    z0 = closed_loop_state(eq.state, ctrl, Actuator(), section)
    h = p.numerics.step_s
    nsteps = int(round(LOOP_S / h))
    every = p.numerics.output_every
    nsave = nsteps // every + 1

    def once():
        ts, zs, us = np.empty(nsave), np.empty((nsave, z0.size)), np.empty((nsave, output_width(loop.act)))
        outs = output_arrays(nsave, model.n)
        t0 = time.process_time()
        rk4_run(z0, h, nsteps, every, *model.kernel_args(), *loop, math.radians(85.0), ts, zs, us, *outs)
        return (time.process_time() - t0) / nsteps * 1e6

    once()
    walls = [once() for _ in range(repeats)]
    return min(walls), float(np.median(walls)), z0.size


def run_cost(name, repeats=REPEATS):
    """CPU time [s] of ``hosedrogue.run`` of a shipped scenario (fastest and median)."""
    sc = load_scenario(name)
    run(sc)
    walls = []
    for _ in range(repeats):
        t0 = time.process_time()
        run(sc)
        walls.append(time.process_time() - t0)
    return min(walls), float(np.median(walls))


def sampled_cost(repeats=REPEATS):
    """CPU time [s] of ``hosedrogue.run`` of paper-turbulence-pid with the user's discretized
    PID (``discrete_pid``, Python, called every 5 ms through the stepper), RK4 at 2.5 ms, ideal
    force against the ``[drogue_actuator]`` defaults (fastest and median of each)."""
    from hosedrogue.spec.sections import Controller, Loop

    base = load_scenario("paper-turbulence-pid")
    base = dataclasses.replace(base, params=base.params.replace(numerics={"step_s": STEP_S, "output_every": 2}))
    user = Controller("python", {"sample_time_s": 0.005}, sample_time_s=0.005,
                      entry="hosedrogue.examples.controllers:discrete_pid")
    out = {}
    for label, section in (("ideal force", None), ("surfaces", DrogueActuator())):
        sc = dataclasses.replace(base, loop=Loop(controller=user, drogue_actuator=section))
        run(sc)
        walls = []
        for _ in range(repeats):
            t0 = time.process_time()
            run(sc)
            walls.append(time.process_time() - t0)
        out[label] = (min(walls), float(np.median(walls)))
    return out


def main():
    print(f"load average {os.getloadavg()[0]:.2f} (machine shared: figures vary with it)")
    cases = {"ideal force": None, "surfaces, 2nd-order servos": DrogueActuator(),
             "surfaces, 1st-order servos": DrogueActuator(servo_order=1)}
    base = None
    for label, section in cases.items():
        best, med, nz = loop_cost(section)
        base = best if base is None else base
        print(f"RK4 loop, paper PID, 20 links, {1000 * STEP_S:g} ms, {label}: {best:.2f} us/step best, {med:.2f} "
              f"median ({nz} states; x{best / base:.2f} of the ideal force)")
    for scen in ("paper-turbulence-pid", "approach-moderate-pid"):
        ideal = run_cost(scen)
        act = run_cost(scen + "-actuated")
        print(f"hosedrogue.run {scen}: {ideal[0]:.3f} s best / {ideal[1]:.3f} median; {scen}-actuated "
              f"{act[0]:.3f} / {act[1]:.3f} s (x{act[0] / ideal[0]:.2f})")
    cost = sampled_cost()
    ideal, act = cost["ideal force"], cost["surfaces"]
    print(f"hosedrogue.run paper-turbulence-pid, the user's discrete_pid at 200 Hz, RK4 {1000 * STEP_S:g} ms: ideal "
          f"force {ideal[0]:.3f} s best / {ideal[1]:.3f} median; surfaces {act[0]:.3f} / {act[1]:.3f} s "
          f"(x{act[0] / ideal[0]:.2f})")
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
