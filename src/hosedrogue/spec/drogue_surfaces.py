"""The drogue's control surfaces as a run section (``[drogue_actuator]``): a drogue that steers
itself, the force its surfaces make in the local air, their limits and their servos
(docs/model.md §10). Validated at construction like every section
(:class:`hosedrogue.spec.fields.Section`); :class:`hosedrogue.spec.sections.Loop` holds it, the compiled
model is :mod:`hosedrogue.model.drogue_actuator`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ParameterError
from .fields import Section, choice, integer, real

__all__ = ["DrogueActuator"]


@dataclass(frozen=True)
class DrogueActuator(Section):
    """The drogue's control surfaces: the force they make, their limits and their servos
    (docs/model.md, "Actuated drogue": the model and where each default comes from).

    ``surfaces`` surfaces sit at equal roll intervals around the drogue; surface k deflected by
    delta_k pushes the drogue with ``q S C_F,delta delta_k`` along its own direction in the S_p
    y-z plane, q the dynamic pressure of the local air at the drogue (free stream, wake,
    turbulence, bow wave). A force command is mixed to the surfaces by the minimum-norm inversion
    at the measured q, each deflection command is clipped to the deflection limit and followed
    by the surface's servo, whose rate is clipped to the rate limit. Deflected surfaces add drag
    ``q S k_D sum delta_k^2`` along the relative wind.

    ``command`` says what the drogue's controller commands: a force (every controller; the
    mixing above) or, for a user's sampled-data controller (``[controller] type = "python"``),
    the surfaces' deflections themselves, one per surface [rad], still clipped to the deflection
    limit and followed by the servos (docs/controllers.md, "Commanding the control surfaces").
    """

    _section = "drogue_actuator"
    #: Number of control surfaces n [-], at roll intervals of 360 / n deg.
    surfaces: int = field(default=4, metadata=integer(3, 8))
    #: Roll position of surface 1 from the S_p y axis (right) toward z (down) [deg]; 0: the "+"
    #: layout (two surfaces per axis), 45: the "x" layout.
    roll_angle_deg: float = field(default=0.0, metadata=real(-180.0, 180.0, lo_open=False, unit="deg"))
    #: Deflection limit |delta_k| of every surface [deg] (the linear force slope holds to about 20 deg).
    max_deflection_deg: float = field(default=20.0, metadata=real(0.0, 90.0, unit="deg"))
    #: Rate limit |d delta_k / dt| of every surface's servo [deg/s].
    max_rate_deg_s: float = field(default=200.0, metadata=real(0.0, 1e5, unit="deg/s"))
    #: Order of the servo from the deflection command to the deflection [-]: 1 (a lag of
    #: bandwidth_hz) or 2 (natural frequency bandwidth_hz, damping ``damping``).
    servo_order: int = field(default=2, metadata=integer(1, 2))
    #: Servo bandwidth [Hz]: the corner frequency 1 / (2 pi tau) of the first-order servo, the
    #: natural frequency omega_n / (2 pi) of the second-order one.
    bandwidth_hz: float = field(default=30.0, metadata=real(0.0, 1000.0, unit="Hz"))
    #: Damping ratio zeta of the second-order servo [-].
    damping: float = field(default=0.7, metadata=real(0.0, 10.0))
    #: Side-force coefficient slope C_F,delta of one surface on the reference area [1/rad].
    force_slope_per_rad: float = field(default=0.45, metadata=real(0.0, 20.0, unit="1/rad"))
    #: Reference area S of the coefficients [m^2]: the paper's basket, pi (0.61 m)^2 / 4.
    reference_area_m2: float = field(default=0.2922, metadata=real(0.0, 10.0, unit="m^2"))
    #: Drag increment k_D of one surface on the reference area [1/rad^2]: Delta C_D = k_D delta_k^2.
    drag_slope_per_rad2: float = field(default=0.25, metadata=real(0.0, 50.0, lo_open=False, unit="1/rad^2"))
    #: What the drogue's controller commands [-]: "force", the force (u_y_n, u_z_n) [N] mixed to
    #: the surfaces at the measured dynamic pressure; "deflection", one deflection per surface
    #: [rad] (surface 1 first), from a user's controller (``[controller] type = "python"``) only.
    command: str = field(default="force", metadata=choice("force", "deflection"))

    @property
    def roll_angles_rad(self) -> list[float]:
        """Roll position phi_k of each surface [rad] (surface 1 first)."""
        return [math.radians(self.roll_angle_deg) + 2.0 * math.pi * k / self.surfaces for k in range(self.surfaces)]

    #: Largest ``rate x step`` of the servo RK4 may take [-]: the RK4 update of a lag x' = w (u - x)
    #: is a weighted mean of x and the stage inputs u (all weights positive, so the surfaces' limits
    #: hold exactly) for w h <= 1.2956 (the root of a^3 - 2 a^2 + 4 a - 4); with a margin.
    RK4_RATE_STEP = 1.25

    @property
    def max_step_s(self) -> float:
        """The largest RK4 step [s] that resolves the servo: ``RK4_RATE_STEP / w_max``, w_max its
        fastest rate [1/s] (omega for the first order; max(2 zeta omega, omega) for the second,
        2 zeta omega being its rate loop's and its soft stop's)."""
        w = 2.0 * math.pi * self.bandwidth_hz
        fastest = w if self.servo_order == 1 else max(2.0 * self.damping * w, w)
        return self.RK4_RATE_STEP / fastest

    def check_step(self, step_s: float) -> None:
        """Refuse an RK4 step [s] too long for the servo (:attr:`max_step_s`).

        Parameters
        ----------
        step_s : float
            The RK4 step [s] (``numerics.step_s``).

        Raises
        ------
        ParameterError
            One line naming ``numerics.step_s``, the servo and the largest step allowed.
        """
        if step_s > self.max_step_s:
            raise ParameterError(
                f"numerics.step_s = {step_s!r}: the drogue actuator's {self.bandwidth_hz:g} Hz servo needs an RK4 step "
                f"<= {self.max_step_s:.4g} s (its fastest rate x step <= {self.RK4_RATE_STEP:g}, where RK4 keeps the "
                "surfaces within their limits); shorten the step or slow the servo")

    def check_loop(self, ideal_actuator: bool, controller) -> None:
        """The loop's rules with the surfaces: they make the force and set its limits, so the
        ``[actuator]`` keeps its defaults; deflections are commanded by a user's controller only
        (a built-in PID or LQR commands a force).

        Parameters
        ----------
        ideal_actuator : bool
            Whether the loop's ``[actuator]`` has its defaults (no limits).
        controller : hosedrogue.spec.sections.Controller or None
            The loop's controller (None: not a scenario's section, e.g. a designed LinearController).

        Raises
        ------
        ParameterError
            One line naming the field.
        """
        if not ideal_actuator:
            raise ParameterError("actuator: with [drogue_actuator] the control surfaces make the force and limit it; "
                                 "remove the [actuator] limits")
        if controller is not None and self.command == "deflection" and controller.type != "python":
            raise ParameterError(f"drogue_actuator.command = 'deflection': controller.type = {controller.type!r} "
                                 "commands a force; deflections come from a user's controller (type 'python'), or "
                                 "set command = 'force'")

    def check_force_command(self) -> None:
        """Refuse ``command = "deflection"`` where a built-in controller commands the force (the
        drivers' continuous and sampled built-in paths).

        Raises
        ------
        ParameterError
            One line naming ``drogue_actuator.command``.
        """
        if self.command != "force":
            raise ParameterError("drogue_actuator.command = 'deflection': a built-in controller (a LinearController, "
                                 "continuous or sampled) commands a force; deflections come from a user's sampled-"
                                 "data controller, or set command = 'force'")

    @property
    def command_size(self) -> int:
        """How many numbers the drogue's controller returns: 2 (the force) or one per surface."""
        return 2 if self.command == "force" else self.surfaces

    def check_hose(self, axial_stiffness_n: float) -> None:
        """The surfaces' kernels run the rigid links' state layout: refuse an elastic hose.

        Parameters
        ----------
        axial_stiffness_n : float
            The hose's axial stiffness EA [N] (``hose.axial_stiffness_n``; inf: rigid links).

        Raises
        ------
        ParameterError
            One line naming ``hose.axial_stiffness_n`` and what is allowed with the surfaces.
        """
        if math.isfinite(axial_stiffness_n):
            raise ParameterError(f"hose.axial_stiffness_n = {axial_stiffness_n!r}: the drogue's control surfaces "
                                 "([drogue_actuator]) run with rigid links only for now; set it to inf or remove "
                                 "[drogue_actuator] (docs/model.md §11)")
