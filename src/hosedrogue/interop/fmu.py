"""FMI 2.0 co-simulation export of the hose-drogue model.

The FMU is built with `pythonfmu <https://github.com/NTNU-IHB/PythonFMU>`_: its platform binary
implements the FMI 2.0 C API and forwards every call to the Python class
:class:`hosedrogue.interop.fmu_slave.HoseDrogue`, which runs the very same model code as
``hosedrogue simulate`` (no second implementation that could drift from it). The FMU therefore
needs a Python with ``hosedrogue`` installed at run time (in-process for Python hosts such as
fmpy; see ``docs/interop.md``).

Interface (SI units, frame S_p: x forward, y right, z down, origin at the tow point):

=================================  ==========  =================================================
variable                           causality   meaning
=================================  ==========  =================================================
``u_hor_n``, ``u_ver_n``           input       control force at the drogue [N] (lateral, vertical)
``gust_u_m_s`` .. ``gust_w_m_s``   input       gust velocity along x, y, z [m/s], uniform
``drogue_x_m`` .. ``drogue_z_m``   output      drogue position [m]
``tow_tension_n``                  output      force at the tow point (hose exit) [N], magnitude
``altitude_m``                     parameter   flight altitude [m]
``airspeed_m_s``                   parameter   true airspeed [m/s]
``wake_enabled``                   parameter   tanker wake on/off
=================================  ==========  =================================================

Inputs are held constant over a communication step (zero-order hold); the step is split into
sub-steps no longer than ``numerics.step_s`` of classical RK4 on
:meth:`hosedrogue.model.system.HoseModel.derivative`, the arithmetic of
:func:`hosedrogue.simulate` with a control function. The FMU starts at the balance position of
its flight condition (solved when initialization ends).
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..params import PAPER, Params, params_from_dict

#: File in the FMU's ``resources`` folder holding the exported parameter set (JSON).
PARAMS_RESOURCE = "hosedrogue_params.json"

#: Name of the generated entry-point script (and of the Python module inside the FMU).
SCRIPT_NAME = "hosedrogue_fmu"

#: (name, unit, description) of the FMU inputs, in value-reference order.
FMU_INPUTS = (
    ("u_hor_n", "N", "lateral control force at the drogue (S_p y)"),
    ("u_ver_n", "N", "vertical control force at the drogue (S_p z, down)"),
    ("gust_u_m_s", "m/s", "gust velocity along S_p x (forward), uniform over the hose"),
    ("gust_v_m_s", "m/s", "gust velocity along S_p y (right), uniform over the hose"),
    ("gust_w_m_s", "m/s", "gust velocity along S_p z (down), uniform over the hose"),
)

#: (name, unit, description) of the FMU outputs.
FMU_OUTPUTS = (
    ("drogue_x_m", "m", "drogue position along S_p x (forward)"),
    ("drogue_y_m", "m", "drogue position along S_p y (right)"),
    ("drogue_z_m", "m", "drogue position along S_p z (down)"),
    ("tow_tension_n", "N", "magnitude of the force the hose exerts at the tow point (exit tension)"),
)

#: (name, unit, description) of the real FMU parameters (set before initialization).
FMU_REAL_PARAMETERS = (
    ("altitude_m", "m", "flight altitude"),
    ("airspeed_m_s", "m/s", "true airspeed"),
)


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


def prepare_python_host(links: int = 2) -> None:
    """Import and compile everything the FMU runs, in this Python process, before a Python host
    (fmpy) loads an exported FMU here.

    pythonfmu's binary runs the FMU's Python code inside the host's interpreter when the host is
    Python itself. Modules that are first imported *during* a call into the FMU are then left
    unusable afterwards (seen here: ``scipy.optimize`` emptied - "module has no attribute
    'root'" - and segmentation faults in a later garbage collection, in a fresh fmpy session).
    Importing the slave's code and running one tiny model first means the FMU's calls import
    nothing new. Simulink, OpenModelica and other non-Python hosts start their own interpreter and
    do not need this.

    Parameters
    ----------
    links : int
        Links of the throw-away model that compiles the kernels [-].
    """
    from . import fmu_slave  # noqa: F401  the slave class and pythonfmu

    core = HoseDrogueCore(fmu_params(PAPER.replace(hose={"links": links}), PAPER.flight.altitude_m,
                                     PAPER.flight.airspeed_m_s, PAPER.wake.enabled))
    core.set_gust((0.0, 0.0, 0.0))
    core.step(0.0, PAPER.numerics.step_s, (0.0, 0.0))
    core.outputs()


@dataclass
class StepFailure(Exception):
    """The state stopped being valid during a step (non-finite, or a yaw beyond the limit)."""

    t_s: float  #: time at which it was detected [s]
    reason: str  #: why the state is no longer valid

    def __str__(self) -> str:
        return f"stopped at t = {self.t_s:.6g} s: {self.reason}"


class HoseDrogueCore:
    """The FMU's simulation, independent of pythonfmu (tested directly and through fmpy).

    Parameters
    ----------
    params : Params
        The parameters to simulate (see :func:`fmu_params`).
    """

    def __init__(self, params: Params):
        from ..analysis.equilibrium import solve_equilibrium
        from ..model.system import HoseModel

        self.params = params
        self._gust = (0.0, 0.0, 0.0)
        self.model = HoseModel(params, gusts=constant_gusts(self._gust))
        self.equilibrium = solve_equilibrium(params, model=self.model)
        self.x = self.equilibrium.state.copy()
        self.t_s = 0.0
        self.u_n = np.zeros(2)
        self._max_yaw = math.radians(params.numerics.max_yaw_deg)

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
        """Hold the control force ``u_n`` = (u_hor, u_ver) [N] (also for the outputs until the next step).

        Parameters
        ----------
        u_n : sequence of 2 float
            Control force at the drogue [N].
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
            Control force (u_hor, u_ver) [N].

        Raises
        ------
        StepFailure
            If the state becomes non-finite or a link yaw passes ``numerics.max_yaw_deg``.
        """
        self.set_force(u_n)
        u = self.u_n
        count = max(1, int(math.ceil(h_s / self.params.numerics.step_s - 1e-9)))
        h = h_s / count
        f = self.model.derivative
        x = self.x
        n = self.model.n
        for k in range(count):
            t = t_s + k * h
            # the arithmetic of hosedrogue.simulate with a control function, operation for operation
            k1 = f(t, x, u)
            k2 = f(t + h / 2, x + h / 2 * k1, u)
            k3 = f(t + h / 2, x + h / 2 * k2, u)
            k4 = f(t + h, x + h * k3, u)
            x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            if not np.all(np.isfinite(x)):
                raise StepFailure(t + h, "the state became non-finite (numerical divergence)")
            if np.max(np.abs(x[1: 2 * n: 2])) > self._max_yaw:
                raise StepFailure(t + h, "a link's yaw passed numerics.max_yaw_deg")
        self.x = x
        self.t_s = t_s + h_s

    def outputs(self) -> dict[str, float]:
        """The FMU outputs at the current state (see :data:`FMU_OUTPUTS`)."""
        out = self.model.outputs(self.x, self.t_s, self.u_n)
        drogue = out.joints_m[-1]
        return {"drogue_x_m": float(drogue[0]), "drogue_y_m": float(drogue[1]),
                "drogue_z_m": float(drogue[2]), "tow_tension_n": float(np.linalg.norm(out.tow_force_n))}


_SCRIPT = '''"""Entry point of a hosedrogue FMU (written by `hosedrogue export-fmu`).

The model runs in the Python that loads this FMU; it needs the hosedrogue package installed.
"""
from hosedrogue.interop.fmu_slave import HoseDrogue, hold_entry_point_globals  # noqa: F401  (pythonfmu finds the class here)

hold_entry_point_globals(globals())  # pythonfmu's binary releases a reference to these globals it does not own
'''


def export_fmu(out_path: str | Path, params: Params = PAPER) -> Path:
    """Write an FMI 2.0 co-simulation FMU of the hose-drogue model.

    Parameters
    ----------
    out_path : str or Path
        The ``.fmu`` file to write (its folder is created).
    params : Params
        Parameters of the model (link count, hose, drogue, default flight condition and wake
        switch, integration step ``numerics.step_s``); the flight condition and wake switch stay
        adjustable as FMU parameters.

    Returns
    -------
    Path
        The written FMU.

    Raises
    ------
    ParameterError
        If ``out_path`` does not end in ``.fmu`` or pythonfmu is not installed.
    """
    out = Path(out_path)
    if out.suffix != ".fmu":
        raise ParameterError(f"--out = {str(out)!r}: must be a file name ending in .fmu")
    if out.exists() and out.is_dir():
        raise ParameterError(f"--out = {str(out)!r}: is a directory, expected a .fmu file name")
    try:
        from pythonfmu import FmuBuilder
    except ImportError:
        raise ParameterError("export-fmu: needs pythonfmu (pip install 'hosedrogue[fmu]')") from None
    fmu_params(params, params.flight.altitude_m, params.flight.airspeed_m_s, params.wake.enabled)  # validate
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="hosedrogue_fmu_") as tmp:
        tmp = Path(tmp)
        script = tmp / f"{SCRIPT_NAME}.py"
        script.write_text(_SCRIPT)
        resource = tmp / PARAMS_RESOURCE
        resource.write_text(json.dumps(params.to_dict(), indent=1) + "\n")
        partial = out.with_name(out.name + ".partial.fmu")
        try:
            FmuBuilder.build_FMU(script, dest=partial, project_files=[resource],
                                 needsExecutionTool=False, canHandleVariableCommunicationStepSize=True)
            shutil.move(partial, out)
        finally:
            partial.unlink(missing_ok=True)
    return out


def load_exported_params(resources: str | Path) -> Params:
    """The parameter set stored in an FMU's ``resources`` folder by :func:`export_fmu`.

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
