"""The engagement's outputs (numba): the derived outputs at saved states (joints, the ``out``
scalars, the tow-point force, the tensions), the energies, the per-step loads of the elastic
chain, the raw measurement of a state for the sampled-data controllers, and the probe tip's
distance to the coupler plane (the capture test).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from .. import drogue_actuator as DA
from ..chain_dynamics import (
    WS_A, WS_B, WS_C, WS_CS, WS_DRAG, WS_E, WS_F, WS_QDD, WS_R, WS_TOW, WS_V, chain_energy, copy_matrix, copy_vector,
    make_workspace, make_workspace_jit,
)
from ..elastic import (
    EWS_EPSD, EWS_T, axial_tensions, elastic_exit_tension, make_elastic_workspace, make_elastic_workspace_jit,
    strain_energy, without_accelerations,
)
from ..layout import (
    EP_COUPLED, EP_CTRL, EP_ELASTIC, EP_JR, EP_LAW, EP_MU, EP_RD, EP_SPLIT, LAW_LOCKED, O_FPX, O_FPY, O_FPZ, O_LDD,
    O_PAXIAL, O_PX, O_Q, O_SIZE, O_SLACK, O_T0, O_VPX, PS_G, R_COUPLED, R_DROGUE, R_DROGUE_V, R_L, R_PROBE, R_PROBE_V,
    R_Q, R_REEL_V, R_T0, RAW_SIZE, Z_L, Z_LD,
)
from .chain import chain_kinematics, tail_start
from .evaluation import (
    CONTROLLED, eng_evaluate, eng_evaluate_bare, eng_evaluate_elastic, eng_evaluate_elastic_bare, loop_kind,
)
from .probe import probe_force, probe_tip


@njit(**JIT_NO_ALLOC)
def plane_distance(z, n, l, ws, t, ep):
    """Signed distance [m] of the probe tip aft of the coupler plane (through joint n, normal to
    the last link, e_{n-1} pointing aft); positive before contact. Uses ws[WS_E], ws[WS_R] as filled by
    :func:`~.evaluation.eng_evaluate` for z."""
    px, py, pz, _, _, _ = probe_tip(t, z, n, ep)
    e = ws[WS_E]
    r = ws[WS_R]
    k = n - 1
    return (px - r[n, 0]) * e[k, 0] + (py - r[n, 1]) * e[k, 1] + (pz - r[n, 2]) * e[k, 2]


@njit(**JIT)
def eng_energy(z, n, l, M, J, ps, ep, chart, joints, jvel):
    """(hose kinetic, elastic bending (``moment``), reel kinetic) energy [J] of state z
    (:func:`~hosedrogue.model.chain_dynamics.chain_energy`; gravity's work is in the balance's terms);
    with elastic links the elastic energy includes their strain energy. The joints' positions and
    velocities (n+1, 3) [m, m/s] go to ``joints`` and ``jvel``: those of :func:`eng_outputs`
    bit for bit (:func:`~.chain.chain_kinematics` is the first half of an evaluation), all that a
    remesh event compares of the states before and after it."""
    ws = make_workspace_jit(n)
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    copy_matrix(joints, ws[WS_R])
    copy_matrix(jvel, ws[WS_V])
    T, _, U = chain_energy(n, l, M, J, ps, ws[WS_E], ws[WS_CS], ws[WS_R], ws[WS_V], z[2 * n: 4 * n])
    nh = tail_start(n, ep)
    if ep[EP_ELASTIC] != 0.0:
        U += strain_energy(n, l, z[4 * n: 5 * n], ps)
    Tr = 0.0
    if ep[EP_LAW] != LAW_LOCKED:
        Tr = 0.5 * ep[EP_JR] * (z[nh + Z_LD] / ep[EP_RD]) ** 2
    return T, U, Tr


@njit(**JIT_NO_ALLOC)
def state_loads(t, z, n, l, M, J, ps, ep, chart, ws, ews, row):
    """The loads of an elastic state z from its kinematics alone (no solve): exit tension
    (:func:`~hosedrogue.model.elastic.elastic_exit_tension`) and drogue-end tension [N], probe
    load [N] and slack [m] into ``row`` (4,): the per-step record the run's peaks are taken from
    (docs/engagement.md, "What a run reports")."""
    nh = tail_start(n, ep)
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    lam = z[4 * n: 5 * n]
    T, epsd = ews[EWS_T], ews[EWS_EPSD]
    axial_tensions(n, l, lam, z[5 * n: 6 * n], z[nh + Z_LD], ps, T, epsd)
    row[0] = elastic_exit_tension(n, l, lam, ps, ws[WS_E], epsd)
    row[1] = T[n - 1]
    r, v = ws[WS_R], ws[WS_V]
    f = 0.0
    if ep[EP_COUPLED] != 0.0:
        px, py, pz, vpx, vpy, vpz = probe_tip(t, z, n, ep)
        fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
        f = math.sqrt(fx * fx + fy * fy + fz * fz)
    row[2] = f
    arc = 0.0
    for k in range(n):
        arc += lam[k]
    row[3] = arc - math.sqrt(r[n, 0] ** 2 + r[n, 1] ** 2 + r[n, 2] ** 2)


@njit(**JIT)
def evaluate_state(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, ews, dM, out):
    """The true accelerations and outputs of state z, rigid (:func:`~.evaluation.eng_evaluate`) or
    elastic (:func:`~.evaluation.eng_evaluate_elastic`)."""
    if ep[EP_ELASTIC] != 0.0:
        eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, 0.0, z)
    else:
        eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)


@njit(**JIT_INLINE)
def raw_measurement(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw, elastic, controlled):
    """The raw measurement (``hosedrogue.model.sampled.R_*``) of state z at time t [s]: drogue and
    probe tip positions and velocities, free length, take-up speed (-L'), exit tension of the
    evaluation with the commands as they are, coupled flag, an actuated drogue's dynamic pressure
    (NaN without control surfaces). ``elastic``: the links' kind (``ep[EP_ELASTIC]``), a constant
    of the compiled caller (:func:`eng_raw`, which the control step calls too), which then holds that kind's
    evaluation only, with the drogue controller or without it (``controlled``: the run's
    :func:`~.evaluation.loop_kind` is :data:`~.evaluation.CONTROLLED`)."""
    if elastic and controlled:
        eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, make_elastic_workspace_jit(n), dM,
                             out, 0.0, z)
    elif elastic:
        eng_evaluate_elastic_bare(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, make_elastic_workspace_jit(n),
                                  dM, out, 0.0, z)
    elif controlled:
        eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    else:
        eng_evaluate_bare(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    r, v = ws[WS_R], ws[WS_V]
    for i in range(3):
        raw[R_DROGUE + i] = r[n, i]
        raw[R_DROGUE_V + i] = v[n, i]
        raw[R_PROBE + i] = out[O_PX + i]
        raw[R_PROBE_V + i] = out[O_VPX + i]
    raw[R_L] = z[tail_start(n, ep) + Z_L]
    raw[R_REEL_V] = -z[tail_start(n, ep) + Z_LD]
    raw[R_T0] = out[O_T0]
    raw[R_COUPLED] = ep[EP_COUPLED]
    raw[R_Q] = out[O_Q] if ep[EP_CTRL] != 0.0 and DA.is_actuated(loop.act) else math.nan


def _raw(elastic, controlled):
    """:func:`raw_measurement` as a compiled function of its own, for one kind of link, with the
    drogue controller or without it."""

    @njit(**JIT)
    def eng_raw(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw):
        """:func:`raw_measurement` of rigid or elastic links (the kind this function is for)."""
        raw_measurement(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw, elastic, controlled)

    return eng_raw


eng_raw_rigid, eng_raw_elastic = _raw(False, True), _raw(True, True)
eng_raw_rigid_bare, eng_raw_elastic_bare = _raw(False, False), _raw(True, False)


def eng_raw(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw):
    """The raw measurement of state z at time t [s] into ``raw`` (:func:`raw_measurement`),
    compiled for the chain's kind of link (``ep[EP_ELASTIC]``: :data:`eng_raw_rigid` or
    :data:`eng_raw_elastic`).

    Parameters
    ----------
    t : float
        Time [s].
    z : numpy.ndarray
        The engagement's state.
    n, l, M, J, ps, env, gust, ep, chart, loop : int, numpy.ndarray or LoopArrays
        The chain (links, lengths [m], masses [kg], inertias), the model's scalars, air and gusts,
        the engagement's scalars, the charts and the loop's arrays.
    ws, ws2, dM, out : tuple or numpy.ndarray
        The evaluation's scratch.
    raw : numpy.ndarray
        Receives the measurement (``hosedrogue.model.layout.R_*``).
    """
    raw_kernel(ep)(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw)


def raw_kernel(ep, controlled=None):
    """:func:`raw_measurement` compiled for the kind of link of ``ep`` (``ep[EP_ELASTIC]``), with
    or without the drogue controller (``controlled``; default: whether ``ep`` has it,
    :func:`~.evaluation.loop_kind`):
    :data:`eng_raw_rigid`, :data:`eng_raw_elastic` or their ``_bare`` twins, called as
    :func:`eng_raw` calls them.

    Parameters
    ----------
    ep : numpy.ndarray
        The engagement's parameters (``hosedrogue.model.layout.EP_*``).
    controlled : bool, optional
        The variant with the drogue controller's code (True) or without it (False); default:
        whether ``ep`` has it.

    Returns
    -------
    numba dispatcher
        The compiled raw measurement.
    """
    if loop_kind(ep) == CONTROLLED if controlled is None else controlled:
        return eng_raw_elastic if ep[EP_ELASTIC] != 0.0 else eng_raw_rigid
    return eng_raw_elastic_bare if ep[EP_ELASTIC] != 0.0 else eng_raw_rigid_bare


def measured_exit_tension(z, n, l, M, J, ps, env, gust, ep, chart, loop, controlled):
    """The exit tension T_0 [N] of state z at t = 0 by the raw measurement's kernel
    (:func:`raw_kernel`; ``out[O_T0]`` of the evaluation), the variant with or without the drogue
    controller as ``controlled`` says: what the sampled-data stepper, which compiles that kernel for its
    measurements, asks for the reel's set point at rest instead of the output kernel
    (:func:`eng_outputs`, whose evaluation is the same function of the same state: the same
    number bit for bit), so that a process that steps compiles one of the two, not both.

    Parameters
    ----------
    z : numpy.ndarray
        The engagement's state.
    n, l, M, J, ps, env, gust, ep, chart, loop : int, numpy.ndarray or LoopArrays
        The chain and the model, as :func:`eng_raw`'s (``l``, ``M``, ``J`` are copied: the
        evaluation sets the variable link in them).
    controlled : bool
        The variant compiled with the drogue controller (the run's parameters have it, though
        ``ep`` may have switched it off; :func:`~.evaluation.loop_kind`).

    Returns
    -------
    float
    """
    raw = np.empty(RAW_SIZE)
    raw_kernel(ep, controlled)(0.0, z, n, l.copy(), M.copy(), J.copy(), ps, env, gust, ep, chart, loop, make_workspace(n),
           make_workspace(n), np.empty(2), np.zeros(O_SIZE), raw)
    return float(raw[R_T0])


def _outputs(elastic, controlled):
    """:func:`eng_outputs`'s kernel compiled for one kind of link (``elastic``) and with the drogue
    controller or without it (``controlled``, :func:`~.evaluation.loop_kind`): constants of the
    compiled function, whose other branches numba prunes before typing. The body is written here,
    not inlined into the closure from a function of its own (numba's ``inline="always"`` copies and
    re-processes its IR: docs/develop.md, "The compiled core")."""

    @njit(**JIT_NO_ALLOC)
    def derived_outputs(ts, zs, n, l, M, J, ps, env, gust, ep, chart, loop, joints, jvel, scal, tow, tension_drogue,
                        drogue_drag, link_tension, loads, scratch):
        """Derived outputs at saved states: joints (N, n+1, 3), joint velocities, the ``out`` scalars
        (N, O_SIZE), tow-point force (N, 3), the tension in the last link [N] (N,), the drogue's
        drag (N, 3) [N] and, for elastic links, every link's tension EA eps + c_a deps/dt [N] (N, n;
        untouched for rigid links). The tow-point force includes the weight of the hose mass lumped
        at the exit (half the exit link's with ``split`` lumping, as the fixed-length chain's).
        Elastic links: each state's loads as :func:`state_loads` writes them (exit and drogue-end
        tension [N], probe load [N], slack [m]) into ``loads`` (N, 4), the same numbers from the same
        functions of the same state, which the time loop then need not compute at the saved steps
        (:func:`~.steps.eng_steps`); untouched for rigid links.
        ``elastic``: the links' kind (``ep[EP_ELASTIC]``), a constant of the compiled caller, as is
        ``controlled`` (evaluated with the drogue controller or without, :func:`~.evaluation.loop_kind`).
        ``scratch``: :func:`output_scratch`'s (made by the caller: a kernel that allocated it would
        compile numba's runtime and the allocators into every output kernel)."""
        ws, ws2, ews, dM, out = scratch
        for i in range(ts.shape[0]):
            if elastic and controlled:
                eng_evaluate_elastic(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, 0.0,
                                     zs[i])
            elif elastic:
                eng_evaluate_elastic_bare(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out,
                                          0.0, zs[i])
            if elastic:
                copy_matrix(joints[i], ws[WS_R])
                copy_matrix(jvel[i], ws[WS_V])
                copy_vector(scal[i], out)
                for j in range(3):
                    tow[i, j] = ws[WS_TOW][j]
                    drogue_drag[i, j] = ws[WS_DRAG][j]
                if ep[EP_SPLIT] != 0.0:
                    tow[i, 2] += 0.5 * ep[EP_MU] * l[0] * ps[PS_G]
                tension_drogue[i] = ews[EWS_T][n - 1]  # the last link's tension EA eps + c_a deps/dt
                copy_vector(link_tension[i], ews[EWS_T])
                # state_loads' row: its exit tension, last link's tension, probe load and slack are the
                # evaluation's (elastic_exit_tension, axial_tensions, probe_force, arc minus chord)
                loads[i, 0] = out[O_T0]
                loads[i, 1] = ews[EWS_T][n - 1]
                fx, fy, fz = out[O_FPX], out[O_FPY], out[O_FPZ]
                loads[i, 2] = math.sqrt(fx * fx + fy * fy + fz * fz)
                loads[i, 3] = out[O_SLACK]
                continue
            if controlled:
                eng_evaluate(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
            else:
                eng_evaluate_bare(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
            out[O_PAXIAL] = 0.0
            copy_matrix(joints[i], ws[WS_R])
            copy_matrix(jvel[i], ws[WS_V])
            copy_vector(scal[i], out)
            Ldd = out[O_LDD]
            # total force of the hose on the exit: F_0 + sum (F_k - M_k A_k)
            for j in range(3):
                tow[i, j] = ws[WS_TOW][j] + Ldd * ws2[WS_TOW][j]
                drogue_drag[i, j] = ws[WS_DRAG][j]
            if ep[EP_SPLIT] != 0.0:
                tow[i, 2] += 0.5 * ep[EP_MU] * l[0] * ps[PS_G]
            # last link's tension: the drogue joint's load minus its inertia, along the link
            # (joint n's acceleration from the recursion: A_n = L'' e_0 + sum of link terms)
            e = ws[WS_E]
            qdd = ws[WS_QDD]
            Ax = Ldd * e[0, 0]
            Ay = Ldd * e[0, 1]
            Az = Ldd * e[0, 2]
            for k in range(n):
                Ax += l[k] * (ws[WS_A][k, 0] * qdd[2 * k] + ws[WS_B][k, 0] * qdd[2 * k + 1]) + ws[WS_C][k, 0]
                Ay += l[k] * (ws[WS_A][k, 1] * qdd[2 * k] + ws[WS_B][k, 1] * qdd[2 * k + 1]) + ws[WS_C][k, 1]
                Az += l[k] * (ws[WS_A][k, 2] * qdd[2 * k] + ws[WS_B][k, 2] * qdd[2 * k + 1]) + ws[WS_C][k, 2]
            F = ws[WS_F]
            m = M[n - 1]
            tension_drogue[i] = ((F[n, 0] - m * Ax) * e[n - 1, 0] + (F[n, 1] - m * Ay) * e[n - 1, 1]
                                 + (F[n, 2] - m * Az) * e[n - 1, 2])

    return derived_outputs


eng_outputs_rigid, eng_outputs_elastic = _outputs(False, True), _outputs(True, True)
eng_outputs_rigid_bare, eng_outputs_elastic_bare = _outputs(False, False), _outputs(True, False)


def eng_outputs(ts, zs, n, l, M, J, ps, env, gust, ep, chart, loop, joints, jvel, scal, tow, tension_drogue,
                drogue_drag, link_tension, loads, controlled=None):
    """Derived outputs at saved states into the given arrays, by the kernel (``derived_outputs`` of
    :func:`_outputs`) compiled for the chain's kind of link (``ep[EP_ELASTIC]``:
    :data:`eng_outputs_rigid` or :data:`eng_outputs_elastic`), with the drogue controller or
    without it (the ``_bare`` ones).

    Parameters
    ----------
    ts, zs : numpy.ndarray
        Saved times [s] (N,) and states (N, len(z)).
    n, l, M, J, ps, env, gust, ep, chart, loop : int, numpy.ndarray or LoopArrays
        The chain and the model, as :func:`eng_raw`'s.
    joints, jvel, scal, tow, tension_drogue, drogue_drag, link_tension, loads : numpy.ndarray
        Receive the outputs (see ``derived_outputs``; ``loads`` (N, 4) the elastic links' loads).
    controlled : bool, optional
        Take the variant compiled with the drogue controller (default: whether ``ep`` has it,
        :func:`~.evaluation.loop_kind`): a caller evaluating a run's state with its controller
        switched off in a copy of ``ep`` passes the run's, so that the process compiles one
        variant, not both (the same numbers).
    """
    if loop_kind(ep) == CONTROLLED if controlled is None else controlled:
        kernel = eng_outputs_elastic if ep[EP_ELASTIC] != 0.0 else eng_outputs_rigid
    else:
        kernel = eng_outputs_elastic_bare if ep[EP_ELASTIC] != 0.0 else eng_outputs_rigid_bare
    kernel(ts, zs, n, l, M, J, ps, env, gust, ep, chart, loop, joints, jvel, scal, tow, tension_drogue, drogue_drag,
           link_tension, loads, output_scratch(n))


def output_scratch(n):
    """The scratch of the output kernels (:func:`eng_outputs`) for a chain of n links: two
    workspaces, the elastic workspace without room for accelerations (the outputs read none), dM
    (2,) and the outputs ``out`` (O_SIZE,) zeroed.

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    tuple
    """
    return (make_workspace(n), make_workspace(n), without_accelerations(make_elastic_workspace(n)), np.empty(2),
            np.zeros(O_SIZE))
