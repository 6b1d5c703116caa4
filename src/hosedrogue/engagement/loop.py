"""What the engagement adds to its state after the 7 tail entries: the pilot's or the receiver's
states, the commanded reel's held command, and the drogue controller's (docs/engagement.md,
"Drogue controller during the approach" and "Pilot model"; docs/controllers.md).

The state is ``z = [q, qd, L, L', 5 work states, pilot (4, if flown) or receiver (9, if flown),
reel command (1, law "python"), xc, (ua or the drogue's surfaces)]``: after the block of ``EP_NPIL`` states the layout is the fixed-length closed loop's ``[x, xc, (ua)]``
(:mod:`hosedrogue.model.integrate`) with ``x`` everything before the controller, so the one
control law (:func:`~hosedrogue.model.integrate.control_law`) and the one actuator law serve both.
The remesh (:mod:`.chain`) keeps everything after the hose entries unchanged, so it carries them.
"""

from __future__ import annotations

import math

import numpy as np

from ..controllers.linear import LinearController
from ..model import layout as LY
from ..model.integrate import LoopArrays, loop_arrays, loop_states, sensor_noise
from ..spec.params import Actuator, ParameterError, Sensor
from ..spec.sections import DrogueActuator, Pilot, Receiver, Reel


def engagement_loop(control: LinearController | None, y_ref: np.ndarray, actuator: Actuator, sensor: Sensor,
                    duration_s: float, seed: int, drogue_actuator: DrogueActuator | None = None) -> LoopArrays:
    """The controller, actuator and sensor arrays of the kernels (:func:`~hosedrogue.model.integrate.loop_arrays`;
    a zero controller without noise when there is none: ``EP_CTRL`` keeps the kernels from using it).

    Parameters
    ----------
    control : LinearController or None
        Measured drogue offset [m] -> force [N]; None: no control force.
    y_ref : array (2,)
        Drogue balance position [y, z] [m] the offset is measured from.
    actuator : Actuator
        Force [N] and rate [N/s] limits, time constant [s] (the fixed-length semantics).
    sensor : Sensor
        Noise [m] on the measured offset and its sample time [s].
    duration_s : float
        Simulated time [s] the noise samples cover.
    seed : int
        Turbulence seed (the noise is an independent stream of it, as in the fixed-length loop).
    drogue_actuator : DrogueActuator, optional
        The drogue's control surfaces (the fixed-length semantics; without a controller they
        stay at neutral).

    Returns
    -------
    LoopArrays
    """
    if control is None:
        return loop_arrays(LinearController.static_zero(), y_ref, actuator, np.zeros((1, 2)), 1.0, drogue_actuator)
    return loop_arrays(control, y_ref, actuator, sensor_noise(sensor, duration_s, seed), sensor.sample_time_s,
                       drogue_actuator)


def no_loop() -> LoopArrays:
    """The loop arrays of a run without a drogue controller (the kernels take them all the same).

    Returns
    -------
    LoopArrays
    """
    return engagement_loop(None, np.zeros(2), Actuator(), Sensor(), 1.0, 0)


def has_drogue_controller(control, drogue_actuator) -> bool:
    """Whether a run has a drogue controller in its compiled loop (``ep[EP_CTRL]``): a built-in
    controller, or an actuated drogue (whose surfaces a zero controller commands).

    Parameters
    ----------
    control : LinearController or None
        The drogue controller.
    drogue_actuator : DrogueActuator or None
        The drogue's control surfaces.

    Returns
    -------
    bool
    """
    return control is not None or drogue_actuator is not None


def extra_states(ep: np.ndarray, control: LinearController | None, actuator: Actuator,
                 pilot: Pilot | None, receiver: Receiver | None = None, reel: Reel | None = None,
                 drogue_actuator: DrogueActuator | None = None) -> np.ndarray:
    """The initial pilot or receiver, held reel command, controller and actuator states; sets
    ``EP_CTRL``, ``EP_NPIL``, ``EP_PIL``, ``EP_RCV`` (and the receiver's response) and ``EP_REEL_SLOT``.

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters (the probe's start point ``EP_P0Y``, ``EP_P0Z`` [m]), changed in place.
    control : LinearController or None
        The drogue controller (states start at zero).
    actuator : Actuator
        A rate-limited one adds the applied force [N] (starting at zero).
    pilot : Pilot or None
        An enabled pilot adds the probe tip's y, z [m] (at the start point) and rates (zero).
    receiver : Receiver, optional
        The receiver flown by a velocity command (docs/controllers.md): adds the probe tip's
        position [m] (at the start point), velocity and held command [m/s] (both the closure
        speed ``EP_VC`` forward).
    reel : Reel, optional
        A reel of law "python" adds its held take-up speed command [m/s] (zero).
    drogue_actuator : DrogueActuator, optional
        The drogue's control surfaces add their states (at rest) after the controller's, and
        set ``EP_CTRL`` even without a controller (their force and drag act all the same).

    Returns
    -------
    array
        The states after the 7 tail entries.
    """
    parts = []
    ep[LY.EP_NPIL] = 0.0
    ep[LY.EP_PIL] = 0.0
    ep[LY.EP_RCV] = 0.0
    ep[LY.EP_REEL_SLOT] = 0.0
    if pilot is not None and pilot.enabled:
        ep[LY.EP_PIL] = 1.0
        ep[LY.EP_NPIL] = LY.PIL_STATES
        parts.append([ep[LY.EP_P0Y], ep[LY.EP_P0Z], 0.0, 0.0])
    elif receiver is not None:
        set_receiver(ep, receiver)
        ep[LY.EP_NPIL] = LY.RCV_STATES
        vc = ep[LY.EP_VC]
        parts.append([ep[LY.EP_P0X], ep[LY.EP_P0Y], ep[LY.EP_P0Z], vc, 0.0, 0.0, vc, 0.0, 0.0])
    if reel is not None and reel.law == "python":
        ep[LY.EP_NPIL] += 1.0
        ep[LY.EP_REEL_SLOT] = ep[LY.EP_NPIL]
        parts.append([0.0])
    ep[LY.EP_CTRL] = 1.0 if has_drogue_controller(control, drogue_actuator) else 0.0
    if ep[LY.EP_CTRL] != 0.0:
        ctrl = control if control is not None else LinearController.static_zero()
        parts.append(loop_states(ctrl, actuator, drogue_actuator))
    return np.concatenate([np.asarray(p, dtype=np.float64) for p in parts]) if parts else np.zeros(0)


def set_pilot(ep: np.ndarray, pilot: Pilot | None, step_s: float) -> None:
    """Write the pilot's entries of ``ep`` (``EP_PIL_*``, ``EP_H``).

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters, changed in place.
    pilot : Pilot or None
        Reaction time [s], lag [s], velocity time constant [s], speed [m/s] and acceleration
        [m/s^2] bounds; None or disabled: nothing to write.
    step_s : float
        The RK4 step [s] (the drogue history has one row per step).

    Raises
    ------
    ParameterError
        A reaction time shorter than one step (the delayed drogue would be read ahead of the
        history written so far).
    """
    ep[LY.EP_H] = step_s
    if pilot is None or not pilot.enabled:
        return
    if pilot.reaction_time_s < step_s:
        raise ParameterError(f"pilot.reaction_time_s = {pilot.reaction_time_s!r}: must be at least the RK4 step "
                             f"numerics.step_s = {step_s!r} s")
    ep[LY.EP_PIL_DELAY] = pilot.reaction_time_s
    ep[LY.EP_PIL_LAG] = pilot.lag_s
    ep[LY.EP_PIL_TV] = pilot.velocity_time_constant_s
    ep[LY.EP_PIL_VMAX] = pilot.max_speed_m_s
    ep[LY.EP_PIL_AMAX] = pilot.max_acceleration_m_s2


def set_receiver(ep: np.ndarray, receiver: Receiver) -> None:
    """Write the receiver's entries of ``ep`` (``EP_RCV``, ``EP_RCV_TV``, ``EP_RCV_VMAX``,
    ``EP_RCV_AMAX``).

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters, changed in place.
    receiver : Receiver
        Velocity time constant [s], per-axis speed [m/s] and acceleration [m/s^2] bounds.
    """
    ep[LY.EP_RCV] = 1.0
    ep[LY.EP_RCV_TV] = receiver.velocity_time_constant_s
    ep[LY.EP_RCV_VMAX:LY.EP_RCV_VMAX + 3] = receiver.max_speed_m_s
    ep[LY.EP_RCV_AMAX:LY.EP_RCV_AMAX + 3] = receiver.max_acceleration_m_s2


def drogue_history(ep: np.ndarray, total_steps: int) -> np.ndarray:
    """The drogue history the pilot's delay reads: one row per global RK4 step (y, z [m], y', z'
    [m/s]), NaN until written; a (1, 4) placeholder without a pilot.

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters (``EP_PIL``).
    total_steps : int
        Steps of the run.

    Returns
    -------
    array (total_steps + 1, 4) or (1, 4)
    """
    rows = total_steps + 1 if ep[LY.EP_PIL] != 0.0 else 1
    return np.full((rows, 4), math.nan)
