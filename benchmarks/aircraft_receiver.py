"""Cost of the receiver flown as an aircraft in the engagement, printed (never asserted):

* CPU seconds per simulated second of the aircraft alone (``AircraftReceiver.fly``: RK4 at 10 ms,
  four evaluations of the Python derivative per step, the wind at each, the inner loop at every
  step), in moderate turbulence;
* one whole run of ``approach-f16-moderate`` against ``approach-moderate-docking`` (the point
  receiver with its PD docking controller; the same 4.5 s, the same hose), compile time excluded.

Each figure is the best of ``--repeats`` CPU times of this process (``time.process_time``).

Run:  .venv/bin/python benchmarks/aircraft_receiver.py
"""

from __future__ import annotations

import argparse
import time

import hosedrogue as hd
from hosedrogue.engagement.aircraft_receiver import AircraftEngagementStepper, AircraftReceiver
from hosedrogue.model import layout as LY


def best(f, repeats: int) -> float:
    """Best CPU time [s] of ``f()`` over ``repeats`` calls (one call first to compile and warm)."""
    f()
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        f()
        times.append(time.process_time() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    sc = hd.load_scenario("approach-f16-moderate")
    ac = AircraftReceiver(sc.engagement.receiver, sc.params)
    e = sc.engagement
    st = AircraftEngagementStepper(sc.params, 4.5, control_step_s=0.02, reel=e.reel, probe=e.probe,
                                   bow_wave=e.bow_wave, receiver=e.receiver)  # the air the aircraft flies in
    env, gust, g = st.model.env, st.model.gust_values, float(st.model.ps[LY.PS_G])
    start = st.aircraft.tip(st.aircraft.states[0], 0.0)[0]

    def aircraft_alone():
        ac.start(start, 1.0, env, gust, g)
        ac.fly((1.0, 0.0, 0.0), 4.5)

    per_s = best(aircraft_alone, args.repeats) / 4.5
    f16 = best(lambda: hd.run(sc), args.repeats)
    point = best(lambda: hd.run(hd.load_scenario("approach-moderate-docking")), args.repeats)
    print(f"aircraft alone (RK4 at 10 ms, inner loop, wind): {per_s:.3f} CPU s per simulated s "
          f"({per_s / 400 * 1e3:.3f} ms per derivative with its wind)")
    print(f"approach-f16-moderate, one 4.5 s run: {f16:.2f} CPU s; approach-moderate-docking: {point:.3f} CPU s")


if __name__ == "__main__":
    main()
