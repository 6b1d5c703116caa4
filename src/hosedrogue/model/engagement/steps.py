"""The engagement's time loop (numba): the segments of steps the driver runs between events (a
remesh, a chart switch, the coupler plane, a failure), by themselves or a control step at a time
for the sampled-data controllers. The steps are those of :mod:`hosedrogue.model.steppers` over the
chain's derivative: RK4 for rigid links, RK4 or the SDIRK (:mod:`hosedrogue.model.implicit`) for
elastic links, each compiled for the loops' rates it needs: a drogue controller (with or without a
pilot or receiver), a pilot or receiver only, none.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ...jit import JIT_INLINE, JIT_NO_ALLOC
from ..chain_dynamics import WS_CS, make_workspace
from ..elastic import make_elastic_workspace
from ..integrate import step_status
from ..layout import (
    CHART, C_ORIGIN, C_SAMPLE, C_SAVED, C_STATUS, C_STEP, C_TARGET, EP_COUPLED, EP_ELASTIC, EP_ITER, EP_L_MAX,
    EP_L_MIN, EP_PIL, EP_PROBE, EP_RCV, EP_SCHEME, MERGE, NONFINITE, OK, O_SIZE, PLANE, REEL_END, SCHEME_RK4, SPLIT,
    STAGE_LIMIT, YAW_LIMIT, Z_L,
)
from ..sampled import deliver
from ..steppers import rk4, sdirk2
from .chain import chain_kinematics, drogue_motion, elastic_pairs, set_variable_link, tail_start
from .evaluation import CONTROLLED, NO_LOOPS, STEERED, eng_deriv, eng_deriv_elastic, loop_kind
from .outputs import plane_distance, raw_kernel, state_loads


def _rate(loops):
    """:func:`~.evaluation.eng_deriv` for the loops ``loops`` (:func:`~.evaluation.loop_kind`) as
    the steppers' derivative (:mod:`hosedrogue.model.steppers`): ``model`` is ``(n, l, M, J, ps,
    env, gust, ep, chart, loop, hist, ws, ws2, dM, out)``; the rigid chain has no implicit stage
    (hg and guess are not read)."""

    @njit(**JIT_INLINE)
    def eng_rate(t, z, model, hg, guess, dz):
        n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out = model
        eng_deriv(loops, t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, dz)

    return eng_rate


def _rate_elastic(loops):
    """:func:`~.evaluation.eng_deriv_elastic` for the loops ``loops`` as the steppers' derivative:
    ``model`` is ``(n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out)``."""

    @njit(**JIT_INLINE)
    def eng_rate_elastic(t, z, model, hg, guess, dz):
        n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out = model
        eng_deriv_elastic(loops, t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, hg, guess,
                          dz)

    return eng_rate_elastic


# the steps of the rigid chain (RK4) and of the elastic chain (RK4 or the SDIRK, ep[EP_SCHEME]),
# for each kind of loops: with the drogue controller, with a pilot or receiver only (_steered),
# without loops (_bare)
_rigid_rk4, _ = rk4(_rate(CONTROLLED))
_elastic_rk4, _ = rk4(_rate_elastic(CONTROLLED))
_elastic_sdirk2 = sdirk2(_rate_elastic(CONTROLLED))
_rigid_rk4_steered, _ = rk4(_rate(STEERED))
_elastic_rk4_steered, _ = rk4(_rate_elastic(STEERED))
_elastic_sdirk2_steered = sdirk2(_rate_elastic(STEERED))
_rigid_rk4_bare, _ = rk4(_rate(NO_LOOPS))
_elastic_rk4_bare, _ = rk4(_rate_elastic(NO_LOOPS))
_elastic_sdirk2_bare = sdirk2(_rate_elastic(NO_LOOPS))


def eng_segment(z, t0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, loads, saved_loads=True):
    """Steps of size h from (t0, z) (global step index step0) for at most ``nsteps`` steps, in
    place, by the steps compiled for the chain's kind of link (``ep[EP_ELASTIC]``).

    Parameters
    ----------
    z : numpy.ndarray
        The engagement's state, advanced in place.
    t0, step0, h, nsteps, save_every : float or int
        Start time [s], its global step, the step [s], the most steps, the saving interval [steps].
    n, l, M, J, ps, env, gust, ep, chart, loop, hist : int, numpy.ndarray or LoopArrays
        The chain and the model (as :func:`~.outputs.eng_raw`'s) and the pilot's drogue history.
    max_yaw, switch_yaw, split_at, merge_at, allow_merge : float or bool
        The events' limits: yaw [rad] that fails, yaw [rad] that switches charts, exit-link
        lengths [m] that split and merge it, whether it may merge.
    zprev, ts, zs, loads : numpy.ndarray
        Receive the state before the last step, the saved times and states, the elastic links'
        per-step loads.
    saved_loads : bool
        Leave the saved steps' rows of ``loads`` to the saved states' outputs (the driver's
        assembly writes them: the same numbers); False: write every row here.

    Returns
    -------
    (int, int, int)
        Status, steps done, saved count.

    Notes
    -----
    The steps are RK4, or for elastic links the integrator ``ep[EP_SCHEME]`` (RK4 or the SDIRK of
    :mod:`hosedrogue.model.steppers`). Saves z at every global step that is a multiple of
    ``save_every`` (into ts, zs). Stops after the step at which the exit link's length leaves
    [merge_at, split_at] (SPLIT / MERGE), the probe tip crosses the coupler plane before coupling
    (PLANE; zprev then holds the state before the step), or the state fails (NONFINITE / YAW_LIMIT,
    or REEL_END: the free length left the reel's range). With a pilot (``ep[EP_PIL]``) the drogue's
    y, z, y', z' after every global step k go to ``hist[k]`` (row 0 at the start), for the pilot's
    delayed view of the drogue. With elastic links the loads of the state after every global step k
    go to ``loads[k]`` (:func:`~.outputs.state_loads`; ``loads`` has one row per step of the run, or
    is a (1, 4) placeholder for rigid links), except at the saved steps, whose loads the driver
    takes from the saved states' outputs (:func:`~.outputs.eng_outputs`, the same numbers;
    :func:`hosedrogue.engagement.result.assemble_result`).

    The scratch is allocated here and the steps compiled for the kind of link
    (:func:`steps_kernel`) called directly: a compiled segment that
    allocated it would compile the machine code of every step and evaluation once more (about 2 s
    of a cold start), and its literal arguments would compile the steps a second time beside the
    control step's (:func:`eng_advance`) signature (docs/develop.md, "The compiled core").
    """
    scratch = (np.empty((8, z.shape[0])), make_workspace(n), make_workspace(n), np.empty(2), np.zeros(O_SIZE),
               make_elastic_workspace(n), elastic_pairs(n, ep[EP_PIL] != 0.0, ep[EP_RCV] != 0.0))
    limits = (float(max_yaw), float(switch_yaw), float(split_at), float(merge_at), bool(allow_merge))
    kernel = steps_kernel(ep)
    return kernel(z, float(t0), 0, int(step0), float(h), int(nsteps), int(save_every), int(n), l, M, J, ps, env, gust,
                  ep, chart, loop, hist, limits, zprev, ts, zs, True, 0, scratch, loads, bool(saved_loads))


def _steps(elastic, implicit, loops):
    """:func:`eng_steps` compiled for one kind of link (``elastic``) and integrator (``implicit``:
    the SDIRK, else RK4) and for the loops' rates ``loops`` (:func:`~.evaluation.loop_kind`),
    constants of the compiled function (closures over bools and an int, which numba's
    cache keys on; it prunes the other kind's and integrator's branches before typing), as a
    function of its own without numba's runtime (``JIT_NO_ALLOC``): the steps inlined into it
    then take no reference counts of the arrays they unpack from the chain's tuple (in a function
    that allocates they would at every evaluation: 9 % of the docking campaigns' run). The body
    is written here, not inlined into the closure (numba's ``inline="always"`` copied and
    re-processed its IR: docs/develop.md, "The compiled core")."""

    @njit(**JIT_NO_ALLOC)
    def eng_steps(z, t0, s0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist, limits,
                  zprev, ts, zs, record, saved0, scratch, loads, saved_loads):
        """:func:`eng_segment` with its limits in one tuple (``limits``: max_yaw, switch_yaw, split_at,
        merge_at, allow_merge) and its scratch given (``scratch``: ``work`` (8, nz), the RK4 stages and
        the trial state, or the SDIRK's stages with its slope guess in ``work[7]``, carried from call to
        call, the workspaces ``ws``, ``ws2``, ``dM``, ``out`` of :func:`~.evaluation.eng_evaluate`, the elastic
        workspace ``ews`` and the state's second-order ``pairs`` of the SDIRK), the saved
        rows written from row ``saved0`` on and only if ``record``, the state ``s0`` steps after the
        time origin ``t0`` of its segment (step k after it is at ``t0 + k h``, as one uninterrupted
        segment counts: a segment continued in several calls takes the same times, and with elastic
        links the same SDIRK guesses), for rigid or ``elastic`` links (``ep[EP_ELASTIC]``; a constant
        of the compiled caller, which then holds the steps of that kind only), by the SDIRK if
        ``implicit`` (elastic links with ``ep[EP_SCHEME]`` the SDIRK), else RK4: a constant too, so an
        elastic run compiles one integrator, not both. ``saved_loads``: the
        loads of a saved state are left to its outputs (:func:`~.outputs.eng_outputs` writes the
        same numbers, at no extra cost: 4 us of the ~85 us of a saved step at 160 links), their rows
        of ``loads`` left as they are; the segment's caller, whose parameters do not change while it
        runs, fills them. Returns (status, steps done, saved count)."""
        max_yaw, switch_yaw, split_at, merge_at, allow_merge = limits
        work, ws, ws2, dM, out, ews, pairs = scratch
        nz = z.shape[0]
        saved = saved0
        nh = tail_start(n, ep)
        rigid = (n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out)
        flexible = (n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out)
        least = int(ep[EP_ITER])  # the SDIRK's least corrections per stage
        if elastic and s0 == 0:  # a segment's start: the SDIRK's first slope guess is dz/dt there
            eng_deriv_elastic(loops, t0, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0,
                              work[6], work[7])
            if step0 == 0:
                state_loads(t0, z, n, l, M, J, ps, ep, chart, ws, ews, loads[0])
        probing = ep[EP_PROBE] != 0.0 and ep[EP_COUPLED] == 0.0
        piloted = ep[EP_PIL] != 0.0  # read only where loops can hold a pilot (numba prunes on the constant)
        if loops != NO_LOOPS and piloted and step0 == 0:
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
                if not implicit:
                    if loops == CONTROLLED:
                        _elastic_rk4(t, z, h, flexible, work)
                    elif loops == STEERED:
                        _elastic_rk4_steered(t, z, h, flexible, work)
                    else:
                        _elastic_rk4_bare(t, z, h, flexible, work)
                else:
                    if loops == CONTROLLED:  # ws[WS_CS]: the frames
                        ok = _elastic_sdirk2(t, z, h, flexible, n, least, ws[WS_CS], pairs, work)
                    elif loops == STEERED:
                        ok = _elastic_sdirk2_steered(t, z, h, flexible, n, least, ws[WS_CS], pairs, work)
                    else:
                        ok = _elastic_sdirk2_bare(t, z, h, flexible, n, least, ws[WS_CS], pairs, work)
                    if ok != OK:
                        return STAGE_LIMIT, s - 1, saved  # z is the state after the last step done
            elif loops == CONTROLLED:
                _rigid_rk4(t, z, h, rigid, work)
            elif loops == STEERED:
                _rigid_rk4_steered(t, z, h, rigid, work)
            else:
                _rigid_rk4_bare(t, z, h, rigid, work)
            t = t0 + (s0 + s) * h
            status = step_status(z, n, max_yaw)
            if status != OK:
                return status, s, saved
            L = z[nh + Z_L]
            if L < ep[EP_L_MIN] or L > ep[EP_L_MAX]:
                return REEL_END, s, saved
            if loops != NO_LOOPS and piloted:
                hist[step0 + s, 0], hist[step0 + s, 1], hist[step0 + s, 2], hist[step0 + s, 3] = drogue_motion(
                    z, n, l, M, J, ep, chart, ws)
            saving = record and (step0 + s) % save_every == 0
            if elastic and not (saving and saved_loads):
                state_loads(t, z, n, l, M, J, ps, ep, chart, ws, ews, loads[step0 + s])
            if saving:
                ts[saved] = t
                for i in range(nz):
                    zs[saved, i] = z[i]
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
                # elastic links state_loads has just written them for this z, unless it was saved
                if not elastic or (saving and saved_loads):
                    chain_kinematics(z, n, l, M, J, ep, chart, ws)
                d = plane_distance(z, n, l, ws, t, ep)
                if d_before > 0.0 and d <= 0.0:
                    return PLANE, s, saved
                d_before = d
        return OK, nsteps, saved

    return eng_steps


#: :func:`eng_steps` compiled for rigid links (RK4) and for elastic links by RK4 and by the SDIRK
#: (:func:`link_kind`), for each kind of loops (:func:`~.evaluation.loop_kind`; the segment and the
#: control step call them, :func:`steps_kernel` picks one). Each is compiled on its first call only.
STEPS = {(loops, kind): _steps(kind != 0, kind == 2, loops)
         for loops in (NO_LOOPS, STEERED, CONTROLLED) for kind in (0, 1, 2)}


def link_kind(ep):
    """The kind of link and integrator of the engagement's parameters ``ep``: 0 rigid (RK4), 1
    elastic by RK4, 2 elastic by the SDIRK (``ep[EP_ELASTIC]``, ``ep[EP_SCHEME]``): the index of
    the compiled steps (:func:`steps_kernel`) and control step (:func:`eng_advance`).

    Parameters
    ----------
    ep : numpy.ndarray
        The engagement's parameters (``hosedrogue.model.layout.EP_*``).

    Returns
    -------
    int
        0, 1 or 2.
    """
    if ep[EP_ELASTIC] == 0.0:
        return 0
    return 1 if ep[EP_SCHEME] == SCHEME_RK4 else 2


def steps_kernel(ep):
    """:func:`eng_steps` compiled for the kind of link and integrator of ``ep`` (:func:`link_kind`),
    for its loops (:func:`~.evaluation.loop_kind`): a process compiles only the integrator and
    the loops its runs use (docs/develop.md, "The compiled core").

    Parameters
    ----------
    ep : numpy.ndarray
        The engagement's parameters (``hosedrogue.model.layout.EP_*``).

    Returns
    -------
    numba dispatcher
        The compiled steps, called as :func:`eng_segment` calls them.
    """
    return STEPS[loop_kind(ep), link_kind(ep)]


def eng_advance(ctr, z, h, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist, limits, zprev, ts, zs,
                record, scratch, ring, delay, sample_h, noise3, noise3_dt, balance, mbuf, loads):
    """Integrate from the counters ``ctr`` (``hosedrogue.model.layout.C_*``: global step, saved
    rows, the segment's origin ``C_ORIGIN``; updated in place) toward global step
    ``ctr[C_TARGET]`` by the steps compiled for the chain's kind of link, integrator and loops
    (:func:`steps_kernel`); when it is reached, the raw measurement of the next sample
    (``ctr[C_SAMPLE] + 1``, :func:`~.outputs.raw_kernel`) into the ring and its measurement
    (delayed by ``delay`` samples, :func:`~hosedrogue.model.sampled.deliver`) into ``mbuf``, and
    the sample counter moves on.

    Parameters
    ----------
    ctr : numpy.ndarray of int64
        The counters (``hosedrogue.model.layout.C_*``), updated in place.
    z, h, save_every : numpy.ndarray, float, int
        The state (advanced in place), the step [s], the saving interval [steps].
    n, l, M, J, ps, env, gust, ep, chart, loop, hist : int, numpy.ndarray or LoopArrays
        The chain and the model, as :func:`eng_segment`'s.
    limits : tuple
        max_yaw, switch_yaw, split_at, merge_at, allow_merge, as :func:`eng_segment`'s.
    zprev, ts, zs, record : numpy.ndarray or bool
        The state before the last step, the saved rows, whether to save.
    scratch : tuple
        ``(work, ws, ws2, dM, out, ews, pairs)`` as :func:`eng_steps` takes it (the caller makes it
        once per discretization: the driver's segment likewise keeps one for all its steps); with
        rigid links ``ews`` and ``pairs`` are not read.
    ring, delay, sample_h, noise3, noise3_dt, balance, mbuf : numpy.ndarray, int or float
        The sampled-data measurement: the ring of raw samples, the delay [samples], the sample
        time [s], the sensor's noise [m] and its sample time [s], the balance position, the
        measurement delivered.
    loads : numpy.ndarray
        The elastic links' per-step loads (:func:`eng_segment`).

    Returns
    -------
    int
        The status of the segment (an event - a remesh, the coupler plane - stops it early).

    Notes
    -----
    Python calling two compiled functions, the steps and the raw measurement, each of which a
    process compiles anyway (the driver's segment calls the same steps with the same argument
    types; the stepper's reset takes the first measurement by the same raw measurement): a
    compiled control step calling them would generate the machine code of both, with the whole
    evaluation below them, once more (2.8 s of a cold first Gymnasium transition; docs/develop.md,
    "The compiled core", fifth round). The same arithmetic in the same order: bit for bit the
    compiled control step's results.
    """
    step0, target, origin = int(ctr[C_STEP]), int(ctr[C_TARGET]), int(ctr[C_ORIGIN])
    status, done, saved = steps_kernel(ep)(
        z, origin * h, step0 - origin, step0, h, target - step0, save_every, n, l, M, J, ps, env, gust, ep, chart, loop,
        hist, limits, zprev, ts, zs, record, int(ctr[C_SAVED]), scratch, loads, False)
    ctr[C_STEP] = step0 + done
    ctr[C_SAVED] = saved
    ctr[C_STATUS] = status
    if step0 + done == target and status not in _FAILED:
        k = int(ctr[C_SAMPLE]) + 1
        work, ws, ws2, dM, out = scratch[:5]
        raw_kernel(ep)(target * h, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out,
                       ring[k % ring.shape[0]])
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
        ctr[C_SAMPLE] = k
    return status


#: The statuses after which the state is not valid and no sample is taken.
_FAILED = (NONFINITE, YAW_LIMIT, REEL_END, STAGE_LIMIT)
