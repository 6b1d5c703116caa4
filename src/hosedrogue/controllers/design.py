"""Design pipeline on the nonlinear model (paper Sec. 3): linearize about the balance position,
reduce each channel by balanced truncation, and design the paper's controllers on the reduced
model.

* :func:`reduced_channels` - lateral and vertical SISO models of a given order;
* :func:`paper_pid` - the paper's PID gains (Eq. 33) as a controller;
* :func:`tuned_pid` - PID gains tuned per channel to step targets (Table 3's by default,
  :mod:`.pid_tuning`);
* :func:`paper_lqr_design_for` - the paper's LQR (Eqs. 35-37, the paper's Q and R by default)
  read as a regulator of the balanced states, with Kalman observers
  (:mod:`.lqr_balanced`), designed on the reduced channels of *this* flight condition's
  linearization; the reading that reproduces the paper's Table 3 lateral LQR row;
* :func:`lqr_design_for` - the integral-action reading (Eq. 34, :mod:`.lqr`), kept as a
  sensitivity;
* :func:`lqr_controller_for` - either design by name, as the controller for the nonlinear loop;
* :func:`dc_sensitivity` - the steady-state sensitivity of a controller closed around a plant;
* :func:`controller_record` - what a run records of its controller (run.json).
"""

from __future__ import annotations

import math
import weakref

from dataclasses import dataclass

import control
import numpy as np

from ..analysis.linearize import LinearModel
from ..analysis.reduction import balanced_truncation, split_channels
from .linear import LinearController
from .lqr import PAPER_LQR_Q, PAPER_LQR_R, LQRDesign, lqr_integral_design, two_channel_plant
from .lqr_balanced import BalancedLQRDesign, lqr_balanced_design
from .pid import PAPER_PID, PIDGains, pid_controller
from ..spec.sections import LQR_DESIGNS  # noqa: F401 - the LQR readings, defined with the [controller] section

#: Order of the design model (paper Sec. 3.2: "the 2nd order reduced model is chosen").
DESIGN_ORDER = 2



@dataclass(frozen=True)
class ReducedChannels:
    """The two SISO design channels of a linearization, as returned by :func:`reduced_channels`."""

    lateral: control.StateSpace  #: u_hor [N] -> P_ny [m]
    vertical: control.StateSpace  #: u_ver [N] -> P_nz [m]
    order: int | None  #: None: full order (minimal realization of each channel)


def reduced_channels(lm: LinearModel, order: int | None) -> ReducedChannels:
    """Each channel of the linear model, balanced-truncated to ``order`` (None: full).

    Parameters
    ----------
    lm : LinearModel
        Linearization about the balance position; its ``ss`` has inputs [u_hor, u_ver] [N] and
        outputs [P_ny, P_nz] [m].
    order : int or None
        Number of states [-] kept in each channel by balanced truncation, >= 1; None keeps the
        full order (the minimal realization of each channel).

    Returns
    -------
    ReducedChannels
        Lateral u_hor [N] -> P_ny [m] and vertical u_ver [N] -> P_nz [m] models, with ``order``
        as requested (a channel may come out with fewer states if it has fewer significant
        Hankel singular values, see :func:`~hosedrogue.analysis.reduction.balanced_truncation`).

    Raises
    ------
    ValueError
        If ``order`` is not None and not an integer >= 1.
    """
    if not (order is None or isinstance(order, int)):  # a numpy integer, or a bad order: not remembered
        return _reduce(lm, order)
    key = id(lm)
    if key not in _REDUCED:  # the entry goes with the model (its weak reference's callback)
        _REDUCED[key] = (weakref.ref(lm, lambda _, key=key: _REDUCED.pop(key, None)), {})
    seen = _REDUCED[key][1]
    if order not in seen:
        seen[order] = _reduce(lm, order)
    return seen[order]


def _reduce(lm: LinearModel, order) -> ReducedChannels:
    lat, ver = split_channels(lm.ss)
    if order is not None:  # balanced_truncation checks the order
        lat = balanced_truncation(lat, order)
        ver = balanced_truncation(ver, order)
    return ReducedChannels(lat, ver, order)


#: The channels :func:`reduced_channels` computed, per living linear model (by identity) and
#: order: a report's Table 3 asks for the same few dozens of times, and each balanced
#: truncation is a Lyapunov solve (the same numbers computed once)
_REDUCED: dict[int, tuple] = {}


def paper_pid() -> LinearController:
    """The paper's PID gains on both channels, acting on the drogue's offset.

    Returns
    -------
    LinearController
        Measured offset [m] -> force [N] with the gains of ``PAPER_PID`` (Eq. 33).
    """
    return pid_controller(PAPER_PID["lateral"], PAPER_PID["vertical"])


def paper_step_targets() -> dict:
    """The paper's Table 3 PID rows as step targets, the default of :func:`tuned_pid`.

    Returns
    -------
    dict
        ``{"lateral": StepTargets, "vertical": StepTargets}``: rise time [s], settling time [s],
        overshoot [%].
    """
    from ..spec.paper import CHANNELS, TABLE3
    from .pid_tuning import StepTargets

    return {ch: StepTargets(**TABLE3[("PID", ch)]) for ch in CHANNELS}


def tuned_pid(lateral, vertical, targets: dict | None = None, min_damping: float = 0.0) -> dict:
    """PID gains tuned per channel so that each unit step meets its targets on the channel model
    (:func:`hosedrogue.controllers.pid_tuning.tune_pid_to_step`).

    Parameters
    ----------
    lateral, vertical : control.TransferFunction or control.StateSpace
        Channel models u_hor [N] -> P_ny [m] and u_ver [N] -> P_nz [m] (e.g. the 2nd-order
        :func:`reduced_channels`).
    targets : dict, optional
        ``{"lateral": StepTargets, "vertical": StepTargets}``; default :func:`paper_step_targets`.
    min_damping : float, optional
        Smallest damping ratio [-] of every closed-loop pole, in [0, 1] (default 0).

    Returns
    -------
    dict
        ``{"lateral": PIDTuning, "vertical": PIDTuning}``.

    Raises
    ------
    TargetsNotMet
        If a channel's targets cannot be met (its ``closest`` design attached).
    """
    from .pid_tuning import tune_pid_to_step

    targets = paper_step_targets() if targets is None else targets
    return {ch: tune_pid_to_step(g, targets[ch], min_damping=min_damping)
            for ch, g in (("lateral", lateral), ("vertical", vertical))}


def pid_gains(options: dict) -> dict:
    """The PID gains of a scenario's ``[controller]`` options: ``lateral``/``vertical`` =
    [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]] where given, the paper's (Eq. 33) otherwise.

    Parameters
    ----------
    options : dict
        The controller's options.

    Returns
    -------
    dict
        ``{"lateral": PIDGains, "vertical": PIDGains}``.
    """
    return {ch: PIDGains(*options[ch]) if ch in options else PAPER_PID[ch] for ch in ("lateral", "vertical")}


def paper_lqr_design_for(lm: LinearModel, Q=PAPER_LQR_Q, R=PAPER_LQR_R,
                         order: int = DESIGN_ORDER) -> BalancedLQRDesign:
    """The paper's LQR (balanced-state reading) on the reduced channels of ``lm``.

    Parameters
    ----------
    lm : LinearModel
        Linearization about the balance position.
    Q : array_like, shape (2 order, 2 order)
        Diagonal weight on the lateral then vertical balanced states [1/(m N)]; default the
        paper's diag(12000, 8000, 8000, 10000) (order 2).
    R : array_like, shape (2, 2)
        Diagonal weight on [u_hor, u_ver] [1/N^2]; default the paper's diag(0.4, 0.5).
    order : int, optional
        Order of each channel's design model (balanced truncation), default 2 as in the paper.

    Returns
    -------
    BalancedLQRDesign
        Per-channel gains and Kalman observers; its ``controller`` maps the measured offset [m]
        to the force [N].
    """
    ch = reduced_channels(lm, order)
    return lqr_balanced_design(ch.lateral, ch.vertical, Q, R)


def lqr_design_for(lm: LinearModel, Q=PAPER_LQR_Q, R=PAPER_LQR_R,
                   order: int = DESIGN_ORDER) -> LQRDesign:
    """The integral-action reading of the paper's LQR (Eq. 34) on the reduced channels of ``lm``.

    Parameters
    ----------
    lm : LinearModel
        Linearization about the balance position.
    Q : array_like, shape (4, 4)
        Weight on [P_ny, P_nz, z_ny, z_nz] [1/m^2, 1/(m s)^2]; default the paper's printed Q.
    R : array_like, shape (2, 2)
        Weight on [u_hor, u_ver] [1/N^2]; default the paper's.
    order : int, optional
        Order of each channel's design model, default 2.

    Returns
    -------
    LQRDesign
        Gain on the plant and integrator states; its ``controller`` maps the measured offset
        [m] to the force [N].
    """
    ch = reduced_channels(lm, order)
    return lqr_integral_design(two_channel_plant(ch.lateral, ch.vertical), Q, R)


def lqr_controller_for(lm: LinearModel, design: str = "balanced", Q=None, R=None) -> LinearController:
    """The LQR of the named reading as the controller of the nonlinear loop.

    Parameters
    ----------
    lm : LinearModel
        Linearization about the balance position.
    design : {"balanced", "integral"}
        "balanced": the paper's LQR read on the balanced states (default); "integral": weights
        on the offsets and their integrals (Eq. 34).
    Q, R : array_like, optional
        Weights of the chosen reading (see `paper_lqr_design_for`, `lqr_design_for`); default
        the paper's.

    Returns
    -------
    LinearController
        Measured offset [m] -> force [N], observer inside.

    Raises
    ------
    ValueError
        If ``design`` is not one of ``LQR_DESIGNS``.
    """
    Q = PAPER_LQR_Q if Q is None else np.asarray(Q, dtype=float)
    R = PAPER_LQR_R if R is None else np.asarray(R, dtype=float)
    if design == "balanced":
        return paper_lqr_design_for(lm, Q, R).controller
    if design == "integral":
        return lqr_design_for(lm, Q, R).controller
    raise ValueError(f"design must be one of {LQR_DESIGNS}, got {design!r}")


def design_controller(kind: str, options: dict, params, model=None, equilibrium=None) -> LinearController | None:
    """A scenario's drogue controller: the one design used by the fixed-length scenarios
    (:func:`hosedrogue.scenarios.runner.drogue_controller`) and the engagement.

    PID: the paper's gains (Eq. 33) unless ``lateral``/``vertical`` are given. LQR: the paper's
    LQR read on the balanced states of each 2nd-order channel (``design = "balanced"``, default)
    or the integral-action reading (``design = "integral"``), designed on the linearization of
    the fixed-length model of ``params`` about its balance position, with the paper's Q and R
    unless ``q_diag``/``r_diag`` are given.

    Parameters
    ----------
    kind : {"none", "pid", "lqr"}
        Controller type.
    options : dict
        PID ``lateral``/``vertical`` = [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]]; LQR
        ``design``, ``q_diag`` and ``r_diag`` [1/N^2].
    params : Params
        The flight condition and model (steady air; the turbulence is not used).
    model : HoseModel, optional
        The fixed-length model of ``params`` (built if missing; LQR only).
    equilibrium : Equilibrium, optional
        Its balance position (solved if missing; LQR only).

    Returns
    -------
    LinearController or None
        Measured drogue offset [m] -> control force [N]; None for ``kind = "none"``.
    """
    if kind == "none":
        return None
    if kind == "pid":
        gains = pid_gains(options)
        return pid_controller(gains["lateral"], gains["vertical"])
    from ..analysis.equilibrium import solve_equilibrium
    from ..analysis.linearize import linearize
    from ..model.system import HoseModel

    if params.hose.elastic:  # designed on the rigid twin: the linearization is the rigid chain's
        params = rigid_twin(params)
        model = equilibrium = None
    model = HoseModel(params) if model is None else model
    equilibrium = solve_equilibrium(params, model=model) if equilibrium is None else equilibrium
    Q = np.diag(options["q_diag"]) if "q_diag" in options else None
    R = np.diag(options["r_diag"]) if "r_diag" in options else None
    return lqr_controller_for(linearize(params, equilibrium, model), options.get("design", "balanced"), Q, R)


def rigid_twin(params):
    """``params`` with rigid links (``hose.axial_stiffness_n = inf``, no axial damping): the model a
    drogue controller for an elastic hose is designed on (the axial stretch moves the drogue's
    lateral and vertical dynamics by O(T / EA), 0.15 % at the engagement scenarios' 1e6 N).

    Parameters
    ----------
    params : Params
        Any parameters.

    Returns
    -------
    Params
    """
    return params.replace(hose={"axial_stiffness_n": math.inf, "axial_damping_n_s": 0.0},
                          numerics={"integrator": "rk4"} if params.numerics.integrator == "sdirk2" else {})


def dc_sensitivity(plant, controller: LinearController) -> tuple[tuple[float, float], tuple[float, float]]:
    """The steady-state (DC) sensitivity of the loop of a controller around a plant, per channel:
    ``|S(0)|`` with ``S(0) = (I - G(0) C(0))^-1`` (the controller carries the feedback sign, so the
    loop is u = C y), the fraction of a slow disturbance's offset the loop leaves; and ``|C(0)|``.

    Parameters
    ----------
    plant : control.StateSpace
        Two inputs [N] (u_hor, u_ver) to two outputs [m] (P_ny, P_nz), e.g. a linearization's ``ss``.
    controller : LinearController
        The controller, measured offsets [m] to forces [N].

    Returns
    -------
    ((float, float), (float, float))
        ``|S(0)|`` lateral and vertical [-] (the diagonal), and ``|C(0)|`` [N/m] (the diagonal).
    """
    c0 = np.real(np.asarray(control.dcgain(controller.as_statespace())))
    g0 = np.real(np.asarray(control.dcgain(plant)))
    s0 = np.linalg.inv(np.eye(2) - g0 @ c0)
    return tuple(float(abs(s0[i, i])) for i in range(2)), tuple(float(abs(c0[i, i])) for i in range(2))


def _matrix(a) -> list:
    return np.asarray(a, dtype=float).tolist()


def controller_record(kind: str, options: dict, controller: LinearController | None) -> dict:
    """What a closed-loop run records of its drogue controller (``run.json``'s
    ``controller_design``): the type, where its numbers come from, and the numbers.

    PID: the gains per channel (``kp_n_per_m``, ``ki_n_per_m_s``, ``kd_n_s_per_m``,
    ``n_filter_rad_s``) and ``source`` ("paper Eq. 33" or "scenario"). LQR: the reading
    (``design``), the weights, the regulator gain and the observer gain read from the controller
    that ran (u = C xc, xc' = A xc + B y): balanced reading ``gain_K`` = -C (force per balanced
    state) and ``observer_gain_L`` = B; integral reading ``gain_state`` = -C on the plant states,
    ``gain_integral_n_per_m_s`` = -C on the two integrators, ``observer_gain_L`` = B's plant rows.
    Every controller: its realization ``A, B, C, D`` (inputs P_ny, P_nz [m], outputs u_hor,
    u_ver [N], the feedback sign inside).

    Parameters
    ----------
    kind : {"none", "pid", "lqr"}
        The controller type.
    options : dict
        The scenario's ``[controller]`` options.
    controller : LinearController or None
        The controller that ran (:func:`design_controller`).

    Returns
    -------
    dict
        JSON-ready numbers; ``{"type": "none"}`` without a controller.
    """
    if kind == "none" or controller is None:
        return {"type": "none"}
    record: dict = {"type": kind}
    if kind == "pid":
        record["source"] = "scenario" if {"lateral", "vertical"} & set(options) else "paper Eq. 33"
        for ch, g in pid_gains(options).items():
            record[ch] = {"kp_n_per_m": g.kp, "ki_n_per_m_s": g.ki, "kd_n_s_per_m": g.kd,
                          "n_filter_rad_s": g.n_filter, "source": "scenario" if ch in options else "paper Eq. 33"}
    elif kind == "lqr":
        design = options.get("design", "balanced")
        record["design"] = design
        record["q_diag"] = list(options.get("q_diag", np.diag(PAPER_LQR_Q)))
        record["r_diag_per_n2"] = list(options.get("r_diag", np.diag(PAPER_LQR_R)))
        if design == "balanced":
            record["gain_K"] = _matrix(-controller.C)
            record["observer_gain_L"] = _matrix(controller.B)
        else:
            n = controller.n_states - 2
            record["gain_state"] = _matrix(-controller.C[:, :n])
            record["gain_integral_n_per_m_s"] = _matrix(-controller.C[:, n:])
            record["observer_gain_L"] = _matrix(controller.B[:n])
    record["realization"] = {"A": _matrix(controller.A), "B": _matrix(controller.B), "C": _matrix(controller.C),
                             "D": _matrix(controller.D), "inputs": ["P_ny_m", "P_nz_m"], "outputs": ["u_y_n", "u_z_n"]}
    return record
