"""The engagement's entry point, :func:`simulate_engagement`: the compiled loop of
:mod:`.driver` when every controller is compiled in it, else the stepper (:mod:`.stepper`)
driven by the sampled-data controllers (:func:`hosedrogue.simulation.drive.drive`;
docs/controllers.md)."""

from __future__ import annotations

import numpy as np

from ..controllers.sampled import SampledController, linear_controller_factory
from ..spec.params import Actuator, ParameterError, Params, Sensor
from ..spec.sections import BowWave, Pilot, Probe, Receiver, Reel
from ..simulation.drive import control_step, drive
from ..simulation.simulate import sampled_controller
from . import driver
from .aircraft_receiver import AircraftEngagementStepper
from .result import EngagementResult
from .stepper import EngagementStepper


def simulate_engagement(params: Params, duration_s: float, *, reel: Reel | None = None, probe: Probe | None = None,
                        bow_wave: BowWave | None = None, pilot: Pilot | None = None, control=None,
                        actuator: Actuator = Actuator(), sensor: Sensor = Sensor(), x0: np.ndarray | None = None,
                        equilibrium=None, seed: int | None = None, length_rate_m_s: float = 0.0,
                        energy: bool = False, gravity_m_s2: float | None = None, receiver: Receiver | None = None,
                        sample_time_s: float = 0.0, drogue_actuator=None) -> EngagementResult:
    """Simulate an engagement from the balance position at rest (steady air plus the
    ``params.turbulence`` gusts if enabled).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics (RK4, ``numerics.step_s``, ``output_every``). The link
        masses are lumped as ``hose.mass_lumping`` says (docs/model.md §2; ``split`` converges at
        second order, the engagement scenarios set it).
    duration_s : float
        Simulated time [s]; a miss ends the run earlier with the reason in ``outcome``.
    reel : Reel, optional
        The drum unit (default ``Reel()``: constant tension at the steady trail tension); law
        "python": the user's take-up law (its ``entry``, ``sample_time_s``, ``options``).
    probe : Probe, optional
        The receiver's probe (None: no probe).
    bow_wave : BowWave, optional
        The receiver's forebody moving with the probe tip (radius [m], probe offset [m], shape);
        its perturbation velocity is added to the air at every hose drag point and at the drogue.
    pilot : Pilot, optional
        Flies the probe's lateral and vertical position toward the delayed drogue
        (docs/engagement.md, "Pilot model"); needs a probe.
    control : LinearController, SampledController or Controller, optional
        Drogue controller: measured drogue offset [m] from its balance position at the start ->
        force [N] at the drogue, until capture (docs/engagement.md, "Drogue controller during
        the approach"); sampled with ``sample_time_s`` > 0; or the user's sampled-data drogue
        controller (docs/controllers.md).
    actuator : Actuator
        Force [N] and rate [N/s] limits of the control force (the fixed-length loop's semantics).
    sensor : Sensor
        Noise [m] on the measured drogue position, its sample time [s]; the delay [s] of the
        sampled-data controllers' measurement.
    x0 : array (4n,), optional
        Initial hose state [q, qd] instead of the balance position at rest (then, without a
        probe, no balance position is solved: the probe starts from it).
    equilibrium : Equilibrium, optional
        Reuse a solved balance position of the initial mesh.
    seed : int, optional
        Overrides ``params.turbulence.seed`` (and seeds the sensor noise).
    length_rate_m_s : float
        Initial L' [m/s] (positive paying out).
    energy : bool
        Also evaluate the energy terms at every output time (for the energy balance).
    gravity_m_s2 : float, optional
        Overrides g [m/s^2] (0 for the energy balance without gravity).
    receiver : Receiver, optional
        The user's docking controller flying the probe by a velocity command through the
        receiver's response (docs/controllers.md); needs a probe, excludes the pilot.
    sample_time_s : float
        With a :class:`LinearController` ``control``: 0 (continuous, the default) or the sample
        time [s] of its zero-order-hold discretization.
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue steers itself with these control surfaces (docs/model.md §10): the
        controller's force command (continuous or sampled) is mixed to them, or with ``command =
        "deflection"`` a user's controller commands their deflections [rad]; once coupled they
        return to neutral. ``actuator`` must then have no limits.

    Returns
    -------
    EngagementResult
        Time histories, events and outcome (``completed`` False and ``message`` saying why if a
        state failed, or a sampled-data controller).

    Raises
    ------
    ParameterError
        ``duration_s`` not a finite number > 0 or shorter than one step, ``x0`` of the wrong
        shape or not finite, a pilot or bow wave without a probe, a free length outside the
        reel's end stops, a controller's entry that cannot be imported.
    """
    controllers = sampled_controllers(reel, receiver, control, sample_time_s, drogue_actuator)
    if drogue_actuator is not None and not isinstance(sampled_controller(control), SampledController):
        drogue_actuator.check_force_command()  # a built-in controller (or none) commands a force
    if not controllers:
        return driver.simulate_engagement(params, duration_s, reel=reel, probe=probe, bow_wave=bow_wave, pilot=pilot,
                                          control=control, actuator=actuator, sensor=sensor, x0=x0,
                                          equilibrium=equilibrium, seed=seed, length_rate_m_s=length_rate_m_s,
                                          energy=energy, gravity_m_s2=gravity_m_s2, drogue_actuator=drogue_actuator)
    return drive(*sampled_stepper(params, duration_s, controllers, reel=reel, probe=probe, bow_wave=bow_wave,
                                  pilot=pilot, receiver=receiver, control=control, actuator=actuator, sensor=sensor,
                                  x0=x0, equilibrium=equilibrium, seed=seed, length_rate_m_s=length_rate_m_s,
                                  energy=energy, gravity_m_s2=gravity_m_s2, drogue_actuator=drogue_actuator))


def sampled_stepper(params: Params, duration_s: float, controllers: dict, *, control=None, **options):
    """The stepper of an engagement with sampled-data controllers, and those controllers built:
    what :func:`simulate_engagement` hands to :func:`~hosedrogue.simulation.drive.drive` (a live
    flight drives the same, its pilot one of the controllers: :mod:`hosedrogue.fly`).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics.
    duration_s : float
        Simulated time [s].
    controllers : dict
        Role -> :class:`~hosedrogue.controllers.sampled.SampledController`
        (:func:`sampled_controllers`), at least one.
    control : LinearController, optional
        The built-in continuous drogue controller compiled in the loop (ignored when the drogue's
        controller is among ``controllers``).
    **options
        The other keyword arguments of :func:`simulate_engagement` (``reel``, ``probe``,
        ``bow_wave``, ``pilot``, ``receiver``, ``actuator``, ``sensor``, ``x0``,
        ``drogue_actuator``, ...).

    Returns
    -------
    stepper : EngagementStepper
        Reset (an :class:`~.aircraft_receiver.AircraftEngagementStepper` when the receiver is an aircraft), its control step the greatest common divisor of the controllers' sample times.
    controllers : dict
        ``controllers``.
    built : dict
        Role -> the controller object its factory made (a bad entry is an error before the run).
    """
    built = {role: c.build() for role, c in controllers.items()}
    receiver = options.get("receiver")
    kind = AircraftEngagementStepper if receiver is not None and receiver.model else EngagementStepper
    stepper = kind(params, duration_s, control_step_s=control_step(controllers, params.numerics.step_s),
                                control=None if "drogue" in controllers else control,
                                drogue_command="drogue" in controllers, **options)
    return stepper, controllers, built


def sampled_controllers(reel: Reel | None, receiver: Receiver | None, control, sample_time_s: float = 0.0,
                        drogue_actuator=None) -> dict:
    """The sampled-data controllers of an engagement: the user's take-up law (``reel.law =
    "python"``), the user's docking controller (``receiver``) and the drogue controller when it is
    the user's (a ``SampledController`` or ``Controller(type="python")``) or a built-in one with a
    sample time (through :class:`~hosedrogue.controllers.sampled.DiscreteLinearController`).

    Parameters
    ----------
    reel : Reel or None
        The drum unit.
    receiver : Receiver or None
        The receiver's section.
    control : LinearController, SampledController, Controller or None
        The drogue controller.
    sample_time_s : float
        The built-in drogue controller's sample time [s] (0: continuous, not sampled).
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (the sampled built-in controller's anti-windup).

    Returns
    -------
    dict
        Role -> :class:`~hosedrogue.controllers.sampled.SampledController`; empty when every
        controller runs compiled in the loop.

    Raises
    ------
    ParameterError
        A sampled section without its ``entry``.
    """
    out = {}
    if control is not None:
        drogue = sampled_controller(control)
        if isinstance(drogue, SampledController):
            out["drogue"] = drogue
        elif sample_time_s:
            factory = linear_controller_factory(drogue, sample_time_s, drogue_actuator)
            out["drogue"] = SampledController("drogue", factory, sample_time_s)
    if reel is not None and reel.law == "python":
        out["reel"] = _section_controller("reel", reel)
    if receiver is not None:
        out["receiver"] = _section_controller("receiver", receiver)
    return out


def _section_controller(role: str, section) -> SampledController:
    if section.entry == "":
        raise ParameterError(f"{section._section}.entry: missing; give the factory \"package.module:factory\" (or "
                             "fly the run with hosedrogue.engagement.EngagementStepper, which takes the commands)")
    return SampledController(role, section.entry, section.sample_time_s, dict(section.options))
