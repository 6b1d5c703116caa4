"""The engagement's time loop (numba): the rigid chain's RK4 step, the elastic chain's RK4 or
SDIRK step (:mod:`hosedrogue.model.implicit`) with its stages and substeps, and the segments of
steps the driver runs between events (a remesh, a chart switch, the coupler plane, a failure),
by themselves or a control step at a time for the sampled-data controllers.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...jit import JIT
from ..chain_dynamics import WS_CS, make_workspace_jit
from ..elastic import make_elastic_workspace_jit
from ..implicit import (
    SDIRK2_GAMMA, SDIRK_MAX_CORRECTIONS, SDIRK_MAX_SUBSTEPS, SDIRK_TOLERANCE_M_S, after_stage1, correction_size,
    stage_point,
)
from ..integrate import rk4_combine, rk4_stage, step_status
from ..layout import (
    CHART, C_ORIGIN, C_SAMPLE, C_SAVED, C_STATUS, C_STEP, C_TARGET, EP_COUPLED, EP_ELASTIC, EP_ITER, EP_L_MAX,
    EP_L_MIN, EP_PIL, EP_PROBE, EP_RCV, EP_SCHEME, MERGE, NONFINITE, OK, O_SIZE, PLANE, REEL_END, SCHEME_RK4, SPLIT,
    STAGE_LIMIT, YAW_LIMIT, Z_L,
)
from ..sampled import deliver
from .chain import chain_kinematics, drogue_motion, elastic_pairs_jit, set_variable_link, tail_start
from .evaluation import eng_deriv, eng_deriv_elastic
from .outputs import eng_raw, plane_distance, state_loads


@njit(**JIT)
def eng_elastic_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, work):
    """One step of size h [s] of the elastic engagement from (t, z), in place: RK4 or the SDIRK of
    :mod:`hosedrogue.model.implicit` (``ep[EP_SCHEME]``). ``work`` (8, len(z)): the stages (the
    SDIRK's in rows 0-3, the step's start in rows 4-5); ``work[7]`` holds the SDIRK's first slope
    guess (the last stage slope of the previous step, or dz/dt at z) and receives the next one.
    Returns OK, or STAGE_LIMIT if the SDIRK's stages did not converge even on 16 substeps (z
    then back at the step's start)."""
    if ep[EP_SCHEME] == SCHEME_RK4:
        k1, k2, k3, k4, tmp, g = work[0], work[1], work[2], work[3], work[4], work[5]
        eng_deriv_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, g, k1)
        rk4_stage(z, 0.5 * h, k1, tmp)
        eng_deriv_elastic(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                          0.0, g, k2)
        rk4_stage(z, 0.5 * h, k2, tmp)
        eng_deriv_elastic(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                          0.0, g, k3)
        rk4_stage(z, h, k3, tmp)
        eng_deriv_elastic(t + h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, g, k4)
        rk4_combine(z, h, k1, k2, k3, k4)
        return OK
    # the SDIRK: the step, or where a stage's corrections do not converge 2, 4, 8, 16 substeps
    z0, g0 = work[4], work[5]
    nz = z.shape[0]
    for i in range(nz):
        z0[i] = z[i]
        g0[i] = work[7][i]
    m = 1
    while m <= SDIRK_MAX_SUBSTEPS:
        hs = h / m
        ok = True
        for j in range(m):
            if not sdirk_step(t + j * hs, z, hs, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                              pairs, work):
                ok = False
                break
        if ok:
            return OK
        for i in range(nz):
            z[i] = z0[i]
            work[7][i] = g0[i]
        m *= 2
    return STAGE_LIMIT


@njit(**JIT)
def sdirk_stage(t, zbase, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg, Kg, K, Y):
    """One implicit stage from ``zbase`` (:mod:`hosedrogue.model.implicit`), the slope guess in Kg:
    corrections until the last moves no stage velocity by more than SDIRK_TOLERANCE_M_S, at least
    ``ep[EP_ITER]``, at most SDIRK_MAX_CORRECTIONS. The stage's slope into K (and Kg). Returns
    whether they converged."""
    nz = zbase.shape[0]
    least = int(ep[EP_ITER])
    for it in range(max(SDIRK_MAX_CORRECTIONS, least)):
        stage_point(zbase, Kg, hg, pairs, Y)
        eng_deriv_elastic(t, Y, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, hg, Kg, K)
        d = correction_size(n, hg, Kg, K, Y, ws[WS_CS])  # ws[WS_CS]: the frames of Y's evaluation
        for i in range(nz):
            Kg[i] = K[i]
        if not math.isfinite(d):
            return False
        if it + 1 >= least and d <= SDIRK_TOLERANCE_M_S:
            return True
    return False


@njit(**JIT)
def sdirk_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, work):
    """One SDIRK step of size h [s] from (t, z), in place, the first stage's guess in ``work[7]``
    (which receives the next one). Returns False (z then undefined) if a stage's corrections did
    not converge."""
    hg = h * SDIRK2_GAMMA
    Kg, K1, zhat, Y, K2 = work[0], work[1], work[2], work[3], work[7]
    nz = z.shape[0]
    for i in range(nz):
        Kg[i] = K2[i]
    if not sdirk_stage(t + hg, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg, Kg,
                       K1, Y):
        return False
    stage_point(z, K1, hg, pairs, Y)
    after_stage1(z, h, K1, zhat)
    for i in range(nz):
        Kg[i] = K1[i]  # the second stage's guess: the first stage's slope
    if not sdirk_stage(t + h, zhat, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg,
                       Kg, K2, Y):
        return False
    stage_point(zhat, K2, hg, pairs, Y)
    for i in range(nz):
        z[i] = Y[i]
    return True


@njit(**JIT)
def eng_segment(z, t0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, loads):
    """Steps of size h from (t0, z) (global step index step0) for at most ``nsteps`` steps, in
    place: RK4, or for elastic links the integrator ``ep[EP_SCHEME]`` (:func:`eng_elastic_step`).

    Saves z at every global step that is a multiple of ``save_every`` (into ts, zs). Stops after
    the step at which the exit link's length leaves [merge_at, split_at] (SPLIT / MERGE), the probe
    tip crosses the coupler plane before coupling (PLANE; zprev then holds the state before the
    step), or the state fails (NONFINITE / YAW_LIMIT, or REEL_END: the free length left the reel's
    range). Returns (status, steps done, saved count).
    With a pilot (``ep[EP_PIL]``) the drogue's y, z, y', z' after every global step k go to
    ``hist[k]`` (row 0 at the start), for the pilot's delayed view of the drogue. With elastic
    links the loads of the state after every global step k go to ``loads[k]``
    (:func:`~.outputs.state_loads`; ``loads`` has one row per step of the run, or is a (1, 4)
    placeholder for rigid links).
    """
    nz = z.shape[0]
    work = np.empty((8, nz))
    ws = make_workspace_jit(n)
    ws2 = make_workspace_jit(n)
    dM = np.empty(2)
    out = np.zeros(O_SIZE)
    return eng_steps(z, t0, 0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                     max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, True, 0, work, ws, ws2,
                     dM, out, loads)


@njit(**JIT)
def eng_steps(z, t0, s0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
              max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, saved0, work, ws, ws2,
              dM, out, loads):
    """:func:`eng_segment` with its scratch given (``work`` (8, nz): the RK4 stages and the trial
    state, or the SDIRK's stages with its slope guess in ``work[7]``, carried from call to call;
    the workspaces ``ws``, ``ws2``, ``dM``, ``out`` of :func:`~.evaluation.eng_evaluate`), the saved
    rows written from row ``saved0`` on and only if ``record``, the state ``s0`` steps after the
    time origin ``t0`` of its segment (step k after it is at ``t0 + k h``, as one uninterrupted
    segment counts: a segment continued in several calls takes the same times, and with elastic
    links the same SDIRK guesses). Returns (status, steps done, saved count)."""
    nz = z.shape[0]
    saved = saved0
    elastic = ep[EP_ELASTIC] != 0.0
    nh = tail_start(n, ep)
    ews = make_elastic_workspace_jit(n)
    pairs = elastic_pairs_jit(n, ep[EP_PIL] != 0.0, ep[EP_RCV] != 0.0)
    if elastic and s0 == 0:  # a segment's start: the SDIRK's first slope guess is dz/dt there
        eng_deriv_elastic(t0, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, work[6],
                          work[7])
        if step0 == 0:
            state_loads(t0, z, n, l, M, J, ps, ep, chart, ws, ews, loads[0])
    probing = ep[EP_PROBE] != 0.0 and ep[EP_COUPLED] == 0.0
    piloted = ep[EP_PIL] != 0.0
    if piloted and step0 == 0:
        hist[0, 0], hist[0, 1], hist[0, 2], hist[0, 3] = drogue_motion(z, n, l, M, J, ep, chart, ws)
    d_before = 0.0
    if probing:
        chain_kinematics(z, n, l, M, J, ep, chart, ws)  # the frames and joint positions of z
        d_before = plane_distance(z, n, l, ws, t0 + s0 * h, ep)
    for s in range(1, nsteps + 1):
        t = t0 + (s0 + s - 1) * h
        for i in range(nz):
            zprev[i] = z[i]
        if elastic:
            if eng_elastic_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs,
                                work) != OK:
                return STAGE_LIMIT, s - 1, saved  # z is the state after the last step done
        else:
            eng_rigid_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, work)
        t = t0 + (s0 + s) * h
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, s, saved
        L = z[nh + Z_L]
        if L < ep[EP_L_MIN] or L > ep[EP_L_MAX]:
            return REEL_END, s, saved
        if piloted:
            hist[step0 + s, 0], hist[step0 + s, 1], hist[step0 + s, 2], hist[step0 + s, 3] = drogue_motion(
                z, n, l, M, J, ep, chart, ws)
        if elastic:
            state_loads(t, z, n, l, M, J, ps, ep, chart, ws, ews, loads[step0 + s])
        if record and (step0 + s) % save_every == 0:
            ts[saved] = t
            zs[saved, :] = z
            saved += 1
        for k in range(n):
            if abs(z[2 * k + 1]) > switch_yaw:
                return CHART, s, saved
        set_variable_link(z[nh + Z_L], n, l, M, J, ep)
        if l[0] > split_at:
            return SPLIT, s, saved
        if allow_merge and l[0] < merge_at:
            return MERGE, s, saved
        if probing:
            # the coupler plane needs the kinematics only: the frames and joint positions that the
            # full evaluation would write, bit for bit (chain_kinematics is its first half); with
            # elastic links state_loads has just written them for this z
            if not elastic:
                chain_kinematics(z, n, l, M, J, ep, chart, ws)
            d = plane_distance(z, n, l, ws, t, ep)
            if d_before > 0.0 and d <= 0.0:
                return PLANE, s, saved
            d_before = d
    return OK, nsteps, saved


@njit(**JIT)
def eng_rigid_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, work):
    """One RK4 step of size h [s] of the rigid engagement from (t, z), in place (``work`` (8,
    len(z)): the stages in rows 0-4)."""
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    eng_deriv(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k1)
    rk4_stage(z, 0.5 * h, k1, tmp)
    eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k2)
    rk4_stage(z, 0.5 * h, k2, tmp)
    eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k3)
    rk4_stage(z, h, k3, tmp)
    eng_deriv(t + h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k4)
    rk4_combine(z, h, k1, k2, k3, k4)


@njit(**JIT)
def eng_advance(ctr, z, h, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist, max_yaw,
                switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, work, ws, ws2, dM, out, ring,
                delay, sample_h, noise3, noise3_dt, balance, mbuf, loads):
    """Integrate from the counters ``ctr`` (``hosedrogue.model.sampled.C_*``: global step,
    saved rows, the segment's origin ``C_ORIGIN``; updated in place) toward global step
    ``ctr[C_TARGET]`` (:func:`eng_steps`); when it is
    reached, the raw measurement of the next sample (``ctr[C_SAMPLE] + 1``) into the ring and
    its measurement (delayed by ``delay`` samples) into ``mbuf``, and the sample counter moves on
    (``loads``: the elastic links' per-step record, :func:`eng_segment`).
    Returns the status of the segment (an event - a remesh, the coupler plane - stops it early)."""
    step0 = ctr[C_STEP]
    target = ctr[C_TARGET]
    origin = ctr[C_ORIGIN]
    status, done, saved = eng_steps(z, origin * h, step0 - origin, step0, h, target - step0, save_every, n, l, M, J,
                                    ps, env, gust, ep, chart, loop, hist, max_yaw, switch_yaw, split_at, merge_at,
                                    allow_merge, zprev, ts, zs, record, ctr[C_SAVED], work, ws, ws2, dM, out, loads)
    ctr[C_STEP] = step0 + done
    ctr[C_SAVED] = saved
    ctr[C_STATUS] = status
    failed = status == NONFINITE or status == YAW_LIMIT or status == REEL_END or status == STAGE_LIMIT
    if ctr[C_STEP] == target and not failed:
        k = ctr[C_SAMPLE] + 1
        eng_raw(target * h, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, ring[k % ring.shape[0]])
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
        ctr[C_SAMPLE] = k
    return status
