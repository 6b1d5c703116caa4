"""Many runs of one model in one compiled call.

Envelope and docking studies run the same hose, flight condition and controller under many
turbulence seeds. :func:`simulate_batch` generates every run's gust record up front, then a
single numba call integrates all runs (RK4) and reduces each to docking statistics on the fly,
so neither Python overhead nor full time histories dominate a campaign.

Per run (inside the turbulence window ``[start_s, start_s + duration_s)``; the whole run when
turbulence is off): peak and RMS lateral, vertical and radial drogue displacement from the
balance position [m], the fraction of time inside each capture radius, the peak control force
per axis and in magnitude [N], whether the run completed, and when it stopped.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .analysis.equilibrium import Equilibrium, solve_equilibrium
from .controllers.linear import LinearController
from .environment.turbulence import generate_gusts
from .model.integrate import applied_force_at, drogue_yz, rk4_step, step_status
from .model.kernels import OK, make_workspace_jit
from .model.system import HoseModel
from .params import ParameterError, Params
from .simulation import Actuator

#: Fixed summary columns, followed by one ``inside_<radius>_frac`` column per capture radius.
SUMMARY_COLUMNS = (
    "completed", "t_end_s", "peak_dy_m", "peak_dz_m", "peak_radial_m", "rms_dy_m", "rms_dz_m",
    "rms_radial_m", "peak_u_hor_n", "peak_u_ver_n", "peak_u_n",
)
_NFIXED = len(SUMMARY_COLUMNS)


@njit(cache=True)
def _run_summaries(z0, h, nsteps, l, M, S, J, ps, env, gusts, Ac, Bc, Cc, Dc, y_ref, act, noise,
                   noise_dt, max_yaw, t_w0, t_w1, radii, out):
    runs = gusts.shape[0]
    n = l.shape[0]
    nx = 4 * n
    nz = z0.shape[0]
    nr = radii.shape[0]
    ws = make_workspace_jit(n)
    z = np.empty(nz)
    k1 = np.empty(nz)
    k2 = np.empty(nz)
    k3 = np.empty(nz)
    k4 = np.empty(nz)
    tmp = np.empty(nz)
    u = np.empty(2)
    inside = np.zeros(nr)
    for run in range(runs):
        gust = gusts[run]
        z[:] = z0
        peak_y = peak_z = peak_r = 0.0
        sq_y = sq_z = 0.0
        peak_u0 = peak_u1 = peak_u = 0.0
        count = 0
        inside[:] = 0.0
        status = OK
        t = 0.0
        for step in range(1, nsteps + 1):
            rk4_step(t, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt,
                     ws, k1, k2, k3, k4, tmp, u)
            t = step * h
            status = step_status(z, n, max_yaw)
            if status != OK:
                break
            if t_w0 <= t < t_w1:
                yy, zz = drogue_yz(z[:nx], l)
                dy = yy - y_ref[0]
                dzz = zz - y_ref[1]
                rr = math.sqrt(dy * dy + dzz * dzz)
                applied_force_at(t, z, nx, yy, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
                peak_y = max(peak_y, abs(dy))
                peak_z = max(peak_z, abs(dzz))
                peak_r = max(peak_r, rr)
                sq_y += dy * dy
                sq_z += dzz * dzz
                peak_u0 = max(peak_u0, abs(u[0]))
                peak_u1 = max(peak_u1, abs(u[1]))
                peak_u = max(peak_u, math.sqrt(u[0] * u[0] + u[1] * u[1]))
                for j in range(nr):
                    if rr <= radii[j]:
                        inside[j] += 1.0
                count += 1
        c = max(count, 1)
        out[run, 0] = 1.0 if status == OK else 0.0
        out[run, 1] = t
        out[run, 2] = peak_y
        out[run, 3] = peak_z
        out[run, 4] = peak_r
        out[run, 5] = math.sqrt(sq_y / c)
        out[run, 6] = math.sqrt(sq_z / c)
        out[run, 7] = math.sqrt((sq_y + sq_z) / c)
        out[run, 8] = peak_u0
        out[run, 9] = peak_u1
        out[run, 10] = peak_u
        for j in range(nr):
            out[run, 11 + j] = inside[j] / c


def radius_column(radius_m: float) -> str:
    return f"inside_{radius_m:g}m_frac"


def simulate_batch(params: Params, seeds, duration_s: float, controller: LinearController | None = None,
                   capture_radii_m=(0.1, 0.305), actuator: Actuator = Actuator(),
                   equilibrium: Equilibrium | None = None):
    """Summaries of one run per turbulence seed, all integrated in one compiled call.

    Returns a pandas DataFrame with a ``seed`` column, :data:`SUMMARY_COLUMNS` and one
    ``inside_<r>m_frac`` column per capture radius. Starts every run at the balance position.
    """
    import pandas as pd

    seeds = [int(s) for s in seeds]
    if not seeds:
        raise ParameterError("seeds = []: give at least one turbulence seed")
    radii = np.asarray(capture_radii_m, dtype=np.float64)
    if radii.ndim != 1 or radii.size == 0 or not np.all(np.isfinite(radii) & (radii > 0)):
        raise ParameterError(f"capture_radii_m = {list(capture_radii_m)!r}: must be numbers > 0 m")
    model = HoseModel(params)
    eq = equilibrium if equilibrium is not None else solve_equilibrium(params, model=model)
    V = params.flight.airspeed_m_s
    gusts = np.stack([generate_gusts(params.turbulence, V, seed=s).values for s in seeds])
    ctrl = controller if controller is not None else LinearController.static_zero()
    z0 = np.concatenate([eq.state, np.zeros(ctrl.n_states + (2 if actuator.rate_limited else 0))])
    h = params.numerics.step_s
    nsteps = int(round(duration_s / h))
    if nsteps < 1:
        raise ParameterError(f"duration_s = {duration_s!r}: shorter than one step ({h} s)")
    turb = params.turbulence
    t_w0, t_w1 = (turb.start_s, turb.start_s + turb.duration_s) if turb.enabled else (0.0, math.inf)
    out = np.zeros((len(seeds), _NFIXED + radii.size))
    _run_summaries(z0, h, nsteps, model.l, model.M, model.S, model.J, model.ps, model.env,
                   gusts, ctrl.A, ctrl.B, ctrl.C, ctrl.D, eq.drogue_position_m[1:].copy(),
                   actuator.as_array(), np.zeros((1, 2)), 1.0,
                   math.radians(params.numerics.max_yaw_deg), t_w0, t_w1, radii, out)
    df = pd.DataFrame(out, columns=list(SUMMARY_COLUMNS) + [radius_column(r) for r in radii])
    df.insert(0, "seed", seeds)
    df["completed"] = df["completed"].astype(bool)
    return df
