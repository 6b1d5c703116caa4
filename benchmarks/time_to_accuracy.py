"""Time to accuracy: the fewest links (segments) that put the steady drogue within 1 cm and 1 mm
of the continuous hose, and the wall time of a 60 s run at that resolution, for hosedrogue's two
mass lumpings and for MoorDyn. Printed as figures (never asserted).

Accuracy: the steady drogue position against :func:`hosedrogue.analysis.continuum.solve_continuum`
on ``moordyn_compare.CASE`` (the paper's hose, bending off, wake off: MoorDyn has no wake), rod
link inertia (m l^2 / 12: the paper's fixed 2.816 kg m^2 per link is meant for 0.8 m links).

Wall time of a 60 s run:
* hosedrogue: ``simulate`` of the paper's turbulence case (``paper-turbulence`` scenario: wake and
  smoothed gusts on) at that link count and lumping, bending off, rod inertia, equilibrium
  excluded, best of 3. Step: the scenario's 0.02 s, or ``1 / |lambda|_max`` of the linearized
  hose when that is smaller (the fastest mode's frequency grows like the link count: 1.95 n
  rad/s, so explicit RK4 needs h ~ 1/n, as MoorDyn's axial wave does).
* MoorDyn: a 60 s run of the same set-up as ``moordyn_compare.py`` (steady air, no turbulence:
  its cost per step does not depend on the forcing), at 0.9 of its largest stable step. Its
  axial stretch is an error of its own (4.4 mm at EA = 5e6 N), so the 1 mm column uses a 20x
  stiffer line (0.22 mm of stretch) at the matching smaller step.
Counts too large to run (``aft`` at 1 mm needs ~1600 links) are estimated from the error's
observed order and the measured cost per link and step, and marked as estimates.

Run:  PYTHONPATH=src:<moordyn site> .venv/bin/python benchmarks/time_to_accuracy.py
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))

import moordyn_compare as mc  # noqa: E402
from hosedrogue.analysis.continuum import solve_continuum  # noqa: E402
from hosedrogue.analysis.equilibrium import solve_equilibrium  # noqa: E402
from hosedrogue.analysis.linearize import linearize  # noqa: E402
from hosedrogue.model.system import HoseModel  # noqa: E402
from hosedrogue.scenarios import load_scenario  # noqa: E402
from hosedrogue.simulation import simulate  # noqa: E402
from hosedrogue.simulation.budget import on_step_grid  # noqa: E402
from hosedrogue.studies.accuracy import fewest_links, lumping_convergence, links_for_tolerance  # noqa: E402

TOLERANCES_M = (1e-2, 1e-3)
CASE = mc.CASE.replace(hose={"link_inertia": "rod"})
RUN_S = 60.0
MAX_RUN_LINKS = 400
#: MoorDyn axial stiffness per tolerance [N]: stretch 4.4 mm (1 cm) and 0.22 mm (1 mm).
MD_EA = {1e-2: mc.EA_N, 1e-3: 20 * mc.EA_N}
MD_SEGMENTS = (1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 24, 32)


def hose_step(n: int, lumping: str) -> float:
    """RK4 step for n links: the scenario's 0.02 s or 1 / |lambda|_max, whichever is smaller."""
    lam = float(np.abs(linearize(CASE.replace(hose={"links": n, "mass_lumping": lumping})).poles).max())
    return min(0.02, 1.0 / lam)


def hose_run_wall(n: int, lumping: str, repeats: int = 3) -> tuple[float, float]:
    """Best wall time [s] of a 60 s paper-turbulence run at n links, and the step used [s]."""
    h = hose_step(n, lumping)
    every = max(1, int(round(0.04 / h))) if h < 0.04 else 1
    p = load_scenario("paper-turbulence").params.replace(
        hose={"links": n, "mass_lumping": lumping, "bending": "off", "link_inertia": "rod"},
        numerics={"step_s": h, "output_every": every})
    model = HoseModel(p)
    eq = solve_equilibrium(p, model=model)
    # a run ends on its step and output grids (simulation.budget): the durations are put on them,
    # and the wall time scaled to RUN_S (the grid moves it by less than one output interval)
    simulate(p, on_step_grid(0.1, h, every), equilibrium=eq, model=model)  # compile / cache load
    run_s = on_step_grid(RUN_S, h, every)
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = simulate(p, run_s, equilibrium=eq, model=model)
        best = min(best, time.perf_counter() - t0)
        if not res.completed:
            raise RuntimeError(f"{lumping} n = {n}, h = {h}: {res.message}")
    return best * RUN_S / run_s, h


def hosedrogue_rows(cont) -> list[tuple]:
    rows = []
    for lumping in ("split", "aft"):
        for tol in TOLERANCES_M:
            n = fewest_links(lumping, tol, base=CASE, continuum=cont, max_links=MAX_RUN_LINKS)
            if n is not None:
                wall, h = hose_run_wall(n, lumping)
                rows.append((lumping, tol, n, wall, h, False))
                continue
            # too many links to run: error order from 100 / 200 / 400 links, cost ~ n^2
            st = lumping_convergence(lumping, links=(100, 200, 400), base=CASE, continuum=cont, dynamics=False)
            n_est = int(math.ceil(links_for_tolerance(st, tol)))
            wall_ref, h_ref = hose_run_wall(200, lumping, repeats=1)
            scale = n_est / 200
            rows.append((lumping, tol, n_est, wall_ref * scale * scale, h_ref / scale, True))
    return rows


def moordyn_rows(cont) -> list[tuple]:
    rows = []
    ref = cont.drogue_position_m
    pitch, _ = mc.chord_angles(ref)
    start = mc.SLACK_START * CASE.hose.length_m * mc.chord_direction(pitch + mc.DISPLACEMENT_RAD[0],
                                                                      mc.DISPLACEMENT_RAD[1])
    for tol in TOLERANCES_M:
        ea = MD_EA[tol]
        for N in MD_SEGMENTS:
            dt = mc.DT_MARGIN * mc.moordyn_largest_stable_dt(N, start, ea)
            r, t_end, resid, stretch, _ = mc.moordyn_steady(N, dt, ref, ea)
            err = float(np.linalg.norm(r - ref))
            print(f"  MoorDyn EA {ea:.3g} N, N = {N:3d}: dtM {dt:.3e} s, error {err * 1e3:.3f} mm "
                  f"(stretch {stretch * 1e3:.3f} mm, residual {resid * 1e3:.3f} mm)", flush=True)
            if resid < mc.SETTLE_TOLERANCE_M and err <= tol:
                best = math.inf
                for _ in range(3):
                    with mc.MoorDynHose(N, dt, start, ea) as m:
                        t0 = time.perf_counter()
                        m.advance(RUN_S)
                        best = min(best, time.perf_counter() - t0)
                rows.append(("MoorDyn", tol, N, best, dt, False))
                break
        else:
            rows.append(("MoorDyn", tol, None, math.nan, math.nan, False))
    return rows


def main() -> int:
    try:
        import moordyn  # noqa: F401
    except ImportError as exc:
        print(f"moordyn is not installed ({exc}); MoorDyn rows skipped")
        have_md = False
    else:
        have_md = True
    cont = solve_continuum(CASE)
    print(f"continuum drogue (wake off, bending off): {cont.drogue_position_m} m")
    rows = hosedrogue_rows(cont)
    if have_md:
        rows += moordyn_rows(cont)
    print("\nmodel     accuracy   links   wall of 60 s [s]   step [s]")
    for model, tol, n, wall, h, est in rows:
        mark = " (estimate)" if est else ""
        print(f"{model:8s}  {tol * 1e3:5.0f} mm  {str(n):>6s}   {wall:12.3f}{mark}   {h:.2e}")
    split_1mm = [r for r in rows if r[0] == "split" and r[1] == 1e-3]
    md_1mm = [r for r in rows if r[0] == "MoorDyn" and r[1] == 1e-3]
    if split_1mm and md_1mm and math.isfinite(md_1mm[0][3]):
        print(f"\nat 1 mm: split is {md_1mm[0][3] / split_1mm[0][3]:.1f} x faster than MoorDyn (target >= 10)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
