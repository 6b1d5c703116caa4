"""The engagement FMU against ``simulate`` on the full ``engage-response`` (issue 20's check),
printed as figures (never asserted): the FMU exported by ``hosedrogue export-fmu --engagement``,
run in fmpy (in this process) by a script master that feeds it the scenario's probe path at every
integration step (``probe_position_input`` true: positions; with ``probe_velocity_feed`` true also
their velocities; the capture time from the ``simulate`` run), against ``hosedrogue simulate
engage-response``: the shipped scenario (160 elastic links, the SDIRK at 5 ms, 15 s) and the rigid
links it had before its hose became elastic (RK4 at 0.625 ms; docs/model.md §11). The FMU moves the
tip within a step on a parabola (positions) or a cubic (positions and velocities), met by the hose at
every integration stage's time as simulate's prescribed path is (docs/interop.md, "Against
simulate"; expect 1.4e-7 and 3.5e-9 m elastic, 1.4e-9 and 1.1e-10 m rigid).

Prints, for each hose and feed, the largest drogue-position difference (target <= 1e-6 m), that
before the push's speed ramp (where the path is a straight line and the two runs are the same
arithmetic), the hose-length difference, and the wall time of both runs.
tests/interop/test_fmu_engagement.py runs the same comparison on a coarse variant (20 links, 4 s) in
seconds; --links 20 --duration 4 --standoff 3.0006 --step S measures the convergence in the step
(that standoff, the test's, keeps the capture off the step grid: see there).

Run:  .venv/bin/python benchmarks/fmu_engagement.py                       (the full case, both hoses)
      .venv/bin/python benchmarks/fmu_engagement.py --hose elastic --links 20 --duration 4 --standoff 3.0006 --step 0.0025
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import tempfile
import time
from pathlib import Path

import numpy as np

TARGET_M = 1e-6
AXES = "xyz"


def probe_path(t_s, start_m, probe, t_cap_s):
    """engage-response's prescribed probe path (docs/engagement.md): forward at the closure speed,
    after the capture on to ``push_m`` further, ending in a half-cosine speed ramp to rest. The
    tip's position [m] and velocity [m/s]."""
    vc, t_stop = probe.closure_speed_m_s, probe.stop_time_s
    s, v = vc * t_s, vc
    if t_s > t_cap_s:
        cruise = max(probe.push_m - 0.5 * vc * t_stop, 0.0)
        t_ramp = t_cap_s + cruise / vc
        if t_s > t_ramp:
            tau = min(t_s - t_ramp, t_stop)
            w = math.pi / t_stop
            s = vc * t_cap_s + cruise + 0.5 * vc * (tau + math.sin(w * tau) / w)
            v = 0.5 * vc * (1.0 + math.cos(w * tau)) if tau < t_stop else 0.0
    return [*(np.asarray(start_m) + (s, 0.0, 0.0)), v, 0.0, 0.0]


def fly(fmu: Path, step_s: float, steps: int, path, feed: bool) -> np.ndarray:
    """Drive the FMU in fmpy: the tip's position (and velocity) at the end of each step; drogue
    positions and hose length."""
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    out = [vr[f"drogue_{a}_m"] for a in AXES] + [vr["hose_length_m"]]
    cmd = [vr[f"probe_cmd_{a}_m"] for a in AXES] + [vr[f"probe_cmd_v{a}_m_s"] for a in AXES]
    slave = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)), instanceName="benchmark",
                      modelIdentifier=md.coSimulation.modelIdentifier)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.setBoolean([vr["probe_position_input"], vr["probe_velocity_feed"]], [True, feed])
    slave.setReal([vr["sample_time_s"]] + cmd, [step_s, *path(0.0)])
    slave.exitInitializationMode()
    rows = [slave.getReal(out)]
    for k in range(steps):
        slave.setReal(cmd, list(path((k + 1) * step_s)))
        slave.doStep(currentCommunicationPoint=k * step_s, communicationStepSize=step_s)
        rows.append(slave.getReal(out))
    slave.terminate()
    slave.freeInstance()
    return np.array(rows)


#: engage-response's hose before it became elastic: rigid links, RK4 at 0.625 ms
RIGID = {"hose": {"axial_stiffness_n": float("inf"), "axial_damping_n_s": 0.0},
         "numerics": {"integrator": "rk4", "step_s": 0.000625}}


def compare(scenario, label: str) -> None:
    """Run ``scenario`` by simulate and its FMU in fmpy fed the probe path (both feeds); print the figures."""
    from hosedrogue import run
    from hosedrogue.interop.fmu import export_fmu

    p, probe = scenario.params, scenario.engagement.probe
    print(f"engage-response, {label}: {p.hose.links} links, {p.numerics.integrator} {p.numerics.step_s:g} s, "
          f"{scenario.duration_s:g} s (the machine's 2 cores are shared)")
    wall = time.perf_counter()
    result = run(scenario)
    sim_wall = time.perf_counter() - wall
    frame = result.to_dataframe()
    start = frame[[f"probe_{a}_m" for a in AXES]].to_numpy()[0]
    t_cap = result.outcome["contact_time_s"]
    t = frame["t_s"].to_numpy()
    ramp = t_cap + (probe.push_m - 0.5 * probe.closure_speed_m_s * probe.stop_time_s) / probe.closure_speed_m_s
    print(f"  outcome: {result.outcome['result']} at {t_cap:.4f} s; the push's ramp from {ramp:.4f} s; "
          f"simulate {sim_wall:.1f} s wall")
    with tempfile.TemporaryDirectory() as tmp:
        fmu = export_fmu(Path(tmp) / "engagement.fmu", scenario)
        steps = round(scenario.duration_s / p.numerics.step_s)
        for feed in (False, True):
            wall = time.perf_counter()
            rows = fly(fmu, p.numerics.step_s, steps, lambda t: probe_path(t, start, probe, t_cap), feed)
            fmu_wall = time.perf_counter() - wall
            diff = np.abs(rows[:, :3] - frame[[f"drogue_{a}_m" for a in AXES]].to_numpy()).max(axis=1)
            length = np.abs(rows[:, 3] - frame["hose_length_m"].to_numpy()).max()
            print(f"  {'positions and velocities' if feed else 'positions only'}: drogue max |dP| = {diff.max():.3g} m "
                  f"(target <= {TARGET_M:g} m), before the ramp {diff[t <= ramp].max():.3g} m; hose length max |dL| "
                  f"= {length:.3g} m; FMU in fmpy {fmu_wall:.1f} s wall ({steps} communication steps)")


def main() -> None:
    from hosedrogue import load_scenario
    from hosedrogue.interop.fmu import prepare_python_host

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hose", choices=("elastic", "rigid", "both"), default="both",
                    help="the shipped elastic hose, the former rigid links, or both")
    ap.add_argument("--links", type=int)
    ap.add_argument("--step", type=float,
                    help="integration step [s] (default the hose's: 5 ms elastic, 0.625 ms rigid)")
    ap.add_argument("--duration", type=float, help="[s]")
    ap.add_argument("--standoff", type=float, help="the probe's start standoff [m] (default the scenario's 3 m)")
    args = ap.parse_args()
    shipped = load_scenario("engage-response").with_overrides(duration_s=args.duration)
    if args.standoff is not None:
        e = shipped.engagement
        probe = dataclasses.replace(e.probe, standoff_m=args.standoff)
        shipped = dataclasses.replace(shipped, engagement=dataclasses.replace(e, probe=probe))
    prepare_python_host()
    for label in ("elastic", "rigid") if args.hose == "both" else (args.hose,):
        tables = RIGID if label == "rigid" else {"hose": {}, "numerics": {}}
        hose = tables["hose"] | ({"links": args.links} if args.links else {})
        numerics = tables["numerics"] | {"output_every": 1} | ({"step_s": args.step} if args.step else {})
        scenario = dataclasses.replace(shipped, params=shipped.params.replace(hose=hose, numerics=numerics))
        compare(scenario, "shipped, elastic" if label == "elastic" else "rigid links (before the hose became elastic)")


if __name__ == "__main__":
    main()
