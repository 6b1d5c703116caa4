"""Many runs of one model in one compiled call.

Envelope and docking studies run the same hose, flight condition and controller under many
turbulence seeds. :func:`simulate_batch` generates every run's gust record up front, then a
single numba call integrates all runs (the RK4 loop of :func:`hosedrogue.model.integrate.rk4_steps`)
and reduces each to the statistics of :mod:`hosedrogue.results.statistics` on the fly (its compiled
accumulator, its window rule), so neither Python overhead nor full time histories dominate a
campaign.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..jit import JIT

from ..results import statistics
from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..controllers.linear import LinearController
from ..environment.turbulence import generate_gusts
from ..results.statistics import SUMMARY_COLUMNS, capture_column
from ..model.integrate import applied_force_at, drogue_yz, loop_arrays, rk4_steps
from ..model.layout import OK
from ..model.chain_dynamics import make_workspace_jit
from ..model.system import HoseModel
from ..spec.params import Actuator, ParameterError, Params
from .simulate import closed_loop_state, fixed_steps

_NFIXED = len(SUMMARY_COLUMNS)


@njit(**JIT)
def _run_summaries(z0, h, nsteps, l, M, S, J, ps, env, gusts, Ac, Bc, Cc, Dc, y_ref, act, noise,
                   noise_dt, max_yaw, t_w0, t_w1, radii, out):
    n = l.shape[0]
    nx = 4 * n
    ws = make_workspace_jit(n)
    z = np.empty(z0.shape[0])
    work = np.empty((5, z0.shape[0]))
    u = np.empty(2)
    acc = np.zeros(statistics.ACCUMULATOR_FIXED + radii.shape[0])
    for run in range(gusts.shape[0]):
        gust = gusts[run]
        z[:] = z0
        statistics.reset(acc)
        status = OK
        t = 0.0
        for step in range(1, nsteps + 1):
            status, _ = rk4_steps(0.0, step, step, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc,
                                  y_ref, act, noise, noise_dt, max_yaw, ws, work, u, False)
            t = step * h
            if status != OK:
                break
            if statistics.in_window_at(t, t_w0, t_w1):
                yy, zz = drogue_yz(z, l, ws)
                applied_force_at(t, z, nx, yy, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
                statistics.accumulate(acc, yy - y_ref[0], zz - y_ref[1], u[0], u[1], radii)
        out[run, 0] = 1.0 if status == OK else 0.0
        out[run, 1] = t
        statistics.finish(acc, out[run, 2:])


def simulate_batch(params: Params, seeds, duration_s: float, controller: LinearController | None = None,
                   capture_radii_m=statistics.DEFAULT_CAPTURE_RADII_M, actuator: Actuator = Actuator(),
                   equilibrium: Equilibrium | None = None):
    """Statistics of one run per turbulence seed, all integrated in one compiled call.

    Every run starts at the balance position; the statistics window is the turbulence window
    (:func:`hosedrogue.results.statistics.turbulence_window`).

    Parameters
    ----------
    params : Params
        Model, environment and numerics; ``params.turbulence.seed`` is replaced by each seed.
    seeds : iterable of int
        Turbulence seeds, one run each.
    duration_s : float
        Simulated time per run [s].
    controller : LinearController, optional
        Controller from drogue offset [m] to force [N] (default: none).
    capture_radii_m : sequence of float
        Capture radii [m], each > 0.
    actuator : Actuator
        Force [N] and rate [N/s] limits.
    equilibrium : Equilibrium, optional
        Reuse a solved balance position.

    Returns
    -------
    pandas.DataFrame
        A ``seed`` column, :data:`hosedrogue.results.statistics.SUMMARY_COLUMNS` and one
        ``inside_<r>m_frac`` column per capture radius; statistics are NaN for a run that stopped
        before the window.
    """
    import pandas as pd

    seeds = [int(s) for s in seeds]
    if not seeds:
        raise ParameterError("seeds = []: give at least one turbulence seed")
    radii = np.asarray(capture_radii_m, dtype=np.float64)
    if radii.ndim != 1 or radii.size == 0 or not np.all(np.isfinite(radii) & (radii > 0)):
        raise ParameterError(f"capture_radii_m = {list(capture_radii_m)!r}: must be numbers > 0 m")
    if params.hose.elastic:
        raise ParameterError(f"hose.axial_stiffness_n = {params.hose.axial_stiffness_n!r}: the compiled batch runs "
                             "rigid links (axial_stiffness_n = inf); run an elastic hose seed by seed with simulate")
    model = HoseModel(params, duration_s=duration_s)
    eq = equilibrium if equilibrium is not None else solve_equilibrium(params, model=model)
    V = params.flight.airspeed_m_s
    gusts = np.stack([generate_gusts(params.turbulence, V, seed=s, run_duration_s=duration_s).values
                      for s in seeds])
    ctrl = controller if controller is not None else LinearController.static_zero()
    z0 = closed_loop_state(eq.state, ctrl, actuator)
    h, nsteps = fixed_steps(params, duration_s)
    loop = loop_arrays(ctrl, eq.drogue_position_m[1:].copy(), actuator, np.zeros((1, 2)), 1.0)
    t_w0, t_w1 = statistics.turbulence_window(params.turbulence)
    out = np.zeros((len(seeds), _NFIXED + radii.size))
    l, M, S, J, ps, env, _ = model.kernel_args()
    _run_summaries(z0, h, nsteps, l, M, S, J, ps, env, gusts, *loop,
                   math.radians(params.numerics.max_yaw_deg), t_w0, t_w1, radii, out)
    df = pd.DataFrame(out, columns=list(SUMMARY_COLUMNS) + [capture_column(r) for r in radii])
    df.insert(0, "seed", seeds)
    df["completed"] = df["completed"].astype(bool)
    return df
