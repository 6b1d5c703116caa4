"""What the tanker's manoeuvres cost, printed as figures (never asserted).

* real-time factor (simulated seconds per wall second) of the shipped ``turn-entry-30`` (the
  converged model, 20 links, RK4 at 5 ms, 60 s) against the same run in level flight (its
  ``[tanker_motion]`` removed: the kernels then skip every frame term), the simulation only
  (``hosedrogue.simulate`` with the model and balance position built before the clock starts),
  compile time excluded; the fastest and the median of interleaved repeats, so a change of the
  machine's load hits both;
* the same for the engagement chain: ``approach-turn-moderate`` against ``approach-moderate``
  (the whole run through ``hosedrogue.run``, 4.5 s simulated).

Run:  .venv/bin/python benchmarks/manoeuvres.py   (one core: NUMBA_NUM_THREADS=1 is set here)
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import dataclasses  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import hosedrogue as hd  # noqa: E402
from hosedrogue.analysis.equilibrium import solve_equilibrium  # noqa: E402
from hosedrogue.model.system import HoseModel  # noqa: E402

#: the level-flight twin of a scenario: no tanker motion
LEVEL = {"bank_deg": 0.0, "flight_path_deg": 0.0, "segments": []}
#: target: the frame terms may cost at most this fraction of the level run's time
TARGET_OVERHEAD = 0.25


def _fixed_length_wall(params, duration_s):
    model = HoseModel(params, duration_s=duration_s)
    eq = solve_equilibrium(params, model=model)
    t0 = time.perf_counter()
    res = hd.simulate(params, duration_s, equilibrium=eq, model=model)
    wall = time.perf_counter() - t0
    assert res.completed
    return wall


def _run_wall(scenario):
    t0 = time.perf_counter()
    res = hd.run(scenario)
    wall = time.perf_counter() - t0
    assert res.completed
    return wall


def _compare(label, turn_wall, level_wall, duration_s, repeats):
    turn, level = [], []
    for _ in range(repeats):  # interleaved
        turn.append(turn_wall())
        level.append(level_wall())
    for name, f in (("fastest", min), ("median", np.median)):
        t, lv = float(f(turn)), float(f(level))
        print(f"{label} ({name} of {repeats}): manoeuvring {duration_s / t:7.0f} x real time ({t * 1e3:7.1f} ms), "
              f"level {duration_s / lv:7.0f} x ({lv * 1e3:7.1f} ms): the frame terms cost {100 * (t / lv - 1):+5.1f} % "
              f"(target <= {100 * TARGET_OVERHEAD:.0f} %)")


def main(repeats: int = 7) -> None:
    entry = hd.load_scenario("turn-entry-30")
    level = entry.params.replace(tanker_motion=LEVEL)
    d = entry.duration_s
    _fixed_length_wall(entry.params, 1.0)  # compile
    _fixed_length_wall(level, 1.0)
    _compare("turn-entry-30, fixed-length hose, 60 s", lambda: _fixed_length_wall(entry.params, d),
             lambda: _fixed_length_wall(level, d), d, repeats)
    turn_app = hd.load_scenario("approach-turn-moderate")
    level_app = hd.load_scenario("approach-moderate")
    assert dataclasses.replace(turn_app, params=turn_app.params.replace(tanker_motion=LEVEL), name=level_app.name,
                               source=level_app.source, description=level_app.description) == level_app
    _run_wall(turn_app)  # compile
    _run_wall(level_app)
    _compare("approach-turn-moderate vs approach-moderate, engagement, 4.5 s, whole run",
             lambda: _run_wall(turn_app), lambda: _run_wall(level_app), turn_app.duration_s, repeats)


if __name__ == "__main__":
    main()
