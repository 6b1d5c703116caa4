"""The fixed-length FMU, independent of pythonfmu: its interface table (:data:`HOSE_FMU`), the
simulation it runs (:class:`HoseDrogueCore`) and the exported parameter set it reads (see
:mod:`hosedrogue.interop.fmu` for the export), and the registry of every FMU the package exports
(:data:`INTERFACES`; the engagement FMU: :mod:`hosedrogue.interop.fmu_engagement`). The interface
table's classes are :mod:`hosedrogue.interop.fmu_interface`'s.

The fixed-length FMU (:data:`HOSE_FMU`), SI units, frame S_p (x forward, y right, z down, origin
at the tow point):

===================================  ==========  ================================================
variable                             causality   meaning
===================================  ==========  ================================================
``altitude_m``, ``airspeed_m_s``     parameter   flight condition [m], [m/s]
``wake_enabled``                     parameter   tanker wake on/off
``u_y_n``, ``u_z_n``                 input       control force at the drogue, S_p y and z [N]
``gust_u_m_s`` .. ``gust_w_m_s``     input       gust velocity along S_p x, y, z [m/s], uniform
``drogue_x_m`` .. ``drogue_z_m``     output      drogue position [m]
``drogue_vx_m_s`` .. ``_vz_m_s``     output      drogue velocity [m/s]
``tow_tension_n``                    output      magnitude of the force at the tow point [N]
===================================  ==========  ================================================

Inputs are held over a communication step (zero-order hold); the step is split into equal RK4
sub-steps no longer than ``numerics.step_s``, integrated by the compiled loop of
:func:`hosedrogue.simulate` (:func:`hosedrogue.model.integrate.rk4_steps`, the package's one RK4
step) with the force held as the state of a hold controller
(:func:`hosedrogue.model.sampled.held_command`, as the steppers hold it). The FMU starts at rest
at the balance position of its flight condition in still air.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..spec.params import PAPER, Params, params_from_dict
from .fmu_engagement import ENGAGEMENT_FMU
from .fmu_interface import (  # noqa: F401  (the interface's names, where the FMU modules have found them)
    INTERFACE_RESOURCE,
    TESTED_ON,
    FmuInterface,
    FmuVariable,
    StepFailure,
    check_interface,
    host_requirements,
    interface_record,
    python_requirement,
)

#: File in the FMU's ``resources`` folder holding the exported parameter set (JSON).
PARAMS_RESOURCE = "hosedrogue_params.json"

_FLIGHT = ("altitude_m", "airspeed_m_s", "wake_enabled")
_INPUTS = ("u_y_n", "u_z_n", "gust_u_m_s", "gust_v_m_s", "gust_w_m_s")

#: The fixed-length FMU: the hose at constant length behind the tanker.
HOSE_FMU = FmuInterface(
    kind="fixed-length",
    model_name="HoseDrogue",
    slave_module="hosedrogue.interop.fmu_slave",
    summary=("Probe-and-drogue refuelling hose of fixed length, rigid-link Kane model (after Wu et al., 2018); "
             "frame S_p: x forward, y right, z down, origin at the tow point; SI units"),
    notes=("The outputs start at rest at the balance position of the flight condition (the parameters) in still "
           "air, solved when initialization ends. Inputs are held over each communication step, which is split "
           "into RK4 sub-steps no longer than numerics.step_s (the DefaultExperiment's stepSize). A failed step "
           "(non-finite state, a link's yaw past numerics.max_yaw_deg) returns fmi2Discard with fmi2Terminated "
           "and logs its time and reason (status fmi2Discard, category logStatusDiscard; pythonfmu forwards "
           "log messages only with the importer's debug logging on)."),
    variables=(
        FmuVariable("altitude_m", "parameter", "flight altitude", field="flight.altitude_m"),
        FmuVariable("airspeed_m_s", "parameter", "true airspeed", field="flight.airspeed_m_s"),
        FmuVariable("wake_enabled", "parameter", "tanker wake on/off", kind="Boolean", field="wake.enabled"),
        FmuVariable("u_y_n", "input", "control force at the drogue along S_p y (lateral, right)"),
        FmuVariable("u_z_n", "input", "control force at the drogue along S_p z (vertical, down)"),
        FmuVariable("gust_u_m_s", "input", "gust velocity along S_p x (forward), uniform over the hose"),
        FmuVariable("gust_v_m_s", "input", "gust velocity along S_p y (right), uniform over the hose"),
        FmuVariable("gust_w_m_s", "input", "gust velocity along S_p z (down), uniform over the hose"),
        *(FmuVariable(f"drogue_{a}_m", "output", f"drogue position along S_p {a}", initial_depends_on=_FLIGHT)
          for a in "xyz"),
        # at rest at the start whatever the parameters: the velocity starts at exactly 0
        *(FmuVariable(f"drogue_v{a}_m_s", "output", f"drogue velocity along S_p {a}, relative to the tow point")
          for a in "xyz"),
        FmuVariable("tow_tension_n", "output",
                    "magnitude of the force the hose exerts at the tow point (|tow_force_x/y/z_n|)",
                    depends_on=_INPUTS, initial_depends_on=_FLIGHT + _INPUTS),
    ),
)

#: Every FMU the package exports, by kind.
INTERFACES = {HOSE_FMU.kind: HOSE_FMU, ENGAGEMENT_FMU.kind: ENGAGEMENT_FMU}


def fmu_params(params: Params, altitude_m: float, airspeed_m_s: float, wake_enabled: bool) -> Params:
    """The parameter set the FMU simulates: ``params`` at the given flight condition, with
    turbulence switched to the externally driven ``uniform`` gust field of the gust inputs.

    Parameters
    ----------
    params : Params
        Exported parameter set (hose, drogue, tanker, numerics, ...).
    altitude_m : float
        Flight altitude [m].
    airspeed_m_s : float
        True airspeed [m/s].
    wake_enabled : bool
        Tanker wake on or off.

    Returns
    -------
    Params
        Validated parameters (:class:`ParameterError` names a bad value).
    """
    return params.replace(
        flight={"altitude_m": altitude_m, "airspeed_m_s": airspeed_m_s},
        wake={"enabled": bool(wake_enabled)},
        turbulence={"enabled": True, "distribution": "uniform"},
    )


def parameter_starts(interface: FmuInterface, params: Params) -> dict[str, float | bool]:
    """The start values of an interface's parameters: the fields they set, read from ``params``.

    Parameters
    ----------
    interface : FmuInterface
        The FMU's interface.
    params : Params
        The exported parameter set.

    Returns
    -------
    dict
        Parameter name -> value (float in the unit of its name, or bool).
    """
    starts = {}
    for v in interface.of("parameter"):
        section, name = v.field.split(".")
        value = getattr(getattr(params, section), name)
        starts[v.name] = bool(value) if v.kind == "Boolean" else float(value)
    return starts


def constant_gusts(gust_m_s) -> "object":
    """A gust record that holds ``gust_m_s`` = (u, v, w) [m/s] at all times.

    Parameters
    ----------
    gust_m_s : sequence of 3 float
        Gust velocity along S_p x, y, z [m/s].

    Returns
    -------
    hosedrogue.environment.turbulence.GustRecord
        Two equal samples, acting for all times.
    """
    from ..environment.turbulence import GustRecord

    g = np.asarray(gust_m_s, dtype=np.float64).reshape(3)
    return GustRecord(t0_s=0.0, dt_s=1.0, values=np.vstack([g, g]), t_on_s=-math.inf, t_off_s=math.inf)


def _failure(t_s: float, code: int, detail: str) -> StepFailure:
    """The run's end at ``t_s`` [s] for the kernels' status ``code``: the status table's line
    (:mod:`hosedrogue.model.status`, the same as every loop's), then ``detail``."""
    from ..model.status import status_text

    return StepFailure(t_s, f"{status_text(code)}: {detail}")


class HoseDrogueCore:
    """The fixed-length FMU's simulation, independent of pythonfmu (tested directly and through fmpy).

    Parameters
    ----------
    params : Params
        The parameters to simulate (see :func:`fmu_params`).
    """

    def __init__(self, params: Params):
        from ..analysis.equilibrium import solve_equilibrium
        from ..model import chain_dynamics as CD
        from ..model.integrate import loop_arrays
        from ..model.sampled import held_command
        from ..model.system import HoseModel
        from ..spec.params import Actuator

        self.params = params
        self._gust = (0.0, 0.0, 0.0)
        self.model = HoseModel(params, gusts=constant_gusts(self._gust))
        self.equilibrium = solve_equilibrium(params, model=self.model)  # in still air
        self.x = self.equilibrium.state.copy()
        self.t_s = 0.0
        self.u_n = np.zeros(2)
        self._max_yaw = math.radians(params.numerics.max_yaw_deg)
        # the force (u_y, u_z) is the state of a hold controller behind the x of the closed loop:
        # z = [x, u], u' = 0, through an actuator without limits
        self._loop = tuple(loop_arrays(held_command(), self.equilibrium.drogue_position_m[1:].copy(), Actuator(),
                                       np.zeros((1, 2)), 1.0))
        self._z = np.empty(self.x.size + 2)
        self._ws = CD.make_workspace(self.model.n)
        self._work = np.empty((5, self._z.size))
        self._u = np.empty(2)

    def set_gust(self, gust_m_s) -> None:
        """Hold the uniform gust velocity ``gust_m_s`` = (u, v, w) [m/s] from now on.

        Parameters
        ----------
        gust_m_s : sequence of 3 float
            Gust velocity along S_p x, y, z [m/s].
        """
        g = tuple(float(v) for v in gust_m_s)
        if g != self._gust:
            self._gust = g
            self.model.gusts = constant_gusts(g)  # HoseModel reads its gust record at every call

    def set_force(self, u_n) -> None:
        """Hold the control force ``u_n`` = (u_y, u_z) [N] (also for the outputs until the next step).

        Parameters
        ----------
        u_n : sequence of 2 float
            Control force at the drogue along S_p y and z [N].
        """
        self.u_n = np.asarray(u_n, dtype=np.float64).reshape(2).copy()

    def step(self, t_s: float, h_s: float, u_n) -> None:
        """Advance from ``t_s`` by ``h_s`` [s] with the control force ``u_n`` [N] held constant.

        Parameters
        ----------
        t_s : float
            Time at the start of the step [s].
        h_s : float
            Communication step [s], > 0; split into equal RK4 sub-steps <= ``numerics.step_s``.
        u_n : sequence of 2 float
            Control force (u_y, u_z) [N].

        Raises
        ------
        StepFailure
            If the state becomes non-finite or a link yaw passes ``numerics.max_yaw_deg``; the
            state stays that of ``t_s``.
        """
        from ..model import layout as LY  # loaded with the model (__init__): the module's import stays light
        from ..model.integrate import rk4_steps

        self.set_force(u_n)
        count = max(1, int(math.ceil(h_s / self.params.numerics.step_s - 1e-9)))
        h = h_s / count
        n = self.model.n
        z = self._z  # the state of t_s and the held force; self.x stays that of t_s until the step succeeds
        z[:4 * n] = self.x
        z[4 * n:] = self.u_n
        status, k = rk4_steps(t_s, 1, count, z, h, *self.model.kernel_args(), *self._loop, self._max_yaw,
                              self._ws, self._work, self._u, False)
        if status == LY.NONFINITE:
            raise _failure(t_s + k * h, LY.NONFINITE, "check the inputs for NaN or values far beyond the model's range")
        if status != LY.OK:
            yaw = np.abs(z[1: 2 * n: 2])
            link = int(np.argmax(yaw)) + 1
            raise _failure(t_s + k * h, status, f"link {link} at {math.degrees(yaw[link - 1]):.1f} deg, "
                                                f"numerics.max_yaw_deg = {self.params.numerics.max_yaw_deg:g} deg")
        self.x = z[:4 * n].copy()
        self.t_s = t_s + h_s

    def outputs(self) -> dict[str, float]:
        """The outputs of :data:`HOSE_FMU` at the current state, force and gust.

        Returns
        -------
        dict of str to float
            ``drogue_x_m`` .. ``drogue_z_m`` [m], ``drogue_vx_m_s`` .. ``drogue_vz_m_s`` [m/s],
            ``tow_tension_n`` [N].
        """
        out = self.model.outputs(self.x, self.t_s, self.u_n)
        pos, vel = out.joints_m[-1], out.joint_velocities_m_s[-1]
        values = {f"drogue_{a}_m": float(pos[i]) for i, a in enumerate("xyz")}
        values.update({f"drogue_v{a}_m_s": float(vel[i]) for i, a in enumerate("xyz")})
        values["tow_tension_n"] = float(np.linalg.norm(out.tow_force_n))
        return values


def load_exported_params(resources: str | Path) -> Params:
    """The parameter set stored in an FMU's ``resources`` folder by the export.

    Parameters
    ----------
    resources : str or Path
        The unpacked FMU's ``resources`` folder.

    Returns
    -------
    Params
    """
    data = json.loads((Path(resources) / PARAMS_RESOURCE).read_text())
    return params_from_dict(data, base=PAPER)
