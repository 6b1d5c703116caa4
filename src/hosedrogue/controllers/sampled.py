"""Sampled-data controllers: the interface of the user's controllers (and of the built-in ones
through it), the measurement they read, loading a factory by its entry point, and checking the
commands (docs/controllers.md).

The interface
-------------
* A controller comes from a factory: ``factory(**options) -> controller``.
* ``controller.reset(m)`` is called once when the run starts, with the first measurement; then
  ``controller(t, m) -> command`` at t = 0, T, 2T, ... (T its ``sample_time_s``). The command is
  held until the next call; the compiled loop runs in between.
* Commands by role (:data:`ROLES`): ``"drogue"`` the force (u_y_n, u_z_n) [N] at the drogue
  (through the actuator's limits); ``"reel"`` the take-up speed [m/s], positive reeling in (the
  motor's torque and speed limits apply); ``"receiver"`` the probe tip's velocity (v_x, v_y, v_z)
  [m/s] in the tanker frame (through the receiver's response).
* ``m`` is a :class:`Measurement`: vectors in the tanker frame S_p (x forward, y right, z down),
  passed through the sensor model (noise on the drogue position, a delay). The run reuses one
  :class:`Measurement` object and updates it in place: copy (``m.copy()``) what you keep.

A controller that raises, returns a non-finite value or one of the wrong shape stops the run
(:class:`ControllerError`, a one-line reason naming the controller and the time); the run keeps
what it computed and is marked incomplete. "Raises" means any exception, ``SystemExit``
(``sys.exit``) and a ``KeyboardInterrupt`` it raises itself included: only the user's own Ctrl-C
(:class:`CtrlC`) still interrupts the run. A factory, or an import of its module, that raises any
of them is a one-line :class:`~hosedrogue.errors.ParameterError` before the run.
"""

from __future__ import annotations

import importlib
import math
import signal
import threading
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..errors import ParameterError
from ..spec.fields import check_entry, entry_name
from ..model.sampled import (M_BALANCE, M_COUPLED, M_DROGUE, M_DROGUE_V, M_L, M_PROBE, M_PROBE_V, M_REEL_V, M_REL,
                             M_Q, M_REL_V, M_SIZE, M_T, M_T0)
from .discrete import (DiscreteLinearController, discretize, discretize_anti_windup,  # noqa: F401 (re-exported)
                       linear_controller_factory)

#: The roles of a sampled-data controller.
ROLES = ("drogue", "reel", "receiver")
#: The command each role returns, as the messages say it.
COMMANDS = {"drogue": "(u_y_n, u_z_n) [N]", "reel": "a take-up speed [m/s]", "receiver": "(v_x, v_y, v_z) [m/s]"}
#: The scenario table that configures each role.
TABLE_OF = {"drogue": "controller", "reel": "reel", "receiver": "receiver"}
#: How many numbers each role's command has.
COMMAND_SIZE = {"drogue": 2, "reel": 1, "receiver": 3}

_VECTORS = {"drogue_position_m": M_DROGUE, "drogue_velocity_m_s": M_DROGUE_V, "probe_position_m": M_PROBE,
            "probe_velocity_m_s": M_PROBE_V, "relative_position_m": M_REL, "relative_velocity_m_s": M_REL_V,
            "drogue_balance_m": M_BALANCE}


class Measurement:
    """What a sampled-data controller reads: the run's quantities at ``t_s`` (the call's time
    minus the sensor delay) in the tanker frame S_p (x forward, y right, z down; origin the tow
    point). Vectors are read-only (3,) arrays, updated in place by the run: copy what you keep.

    Attributes
    ----------
    t_s : float
        Time the quantities are of [s]: the call's time minus ``sensor.delay_s`` (0 before then).
    drogue_position_m : array (3,)
        Drogue position [m], with the sensor noise (``sensor.noise_std_m`` per axis).
    drogue_velocity_m_s : array (3,)
        Drogue velocity [m/s].
    probe_position_m, probe_velocity_m_s : array (3,)
        Probe tip position [m] and velocity [m/s]; NaN without a probe (the fixed-length hose).
    relative_position_m, relative_velocity_m_s : array (3,)
        Drogue minus probe tip [m, m/s] (the measured drogue position's noise included).
    hose_length_m : float
        Free hose length [m] (the fixed length without a reel).
    reel_speed_m_s : float
        Take-up speed [m/s], positive reeling in.
    exit_tension_n : float
        Hose tension at the exit [N].
    coupled : bool
        Whether the probe has captured the drogue.
    drogue_q_pa : float
        Dynamic pressure at the drogue [Pa], the air its control surfaces see (free stream,
        wake, turbulence, bow wave); NaN without ``[drogue_actuator]``.
    drogue_balance_m : array (3,)
        The drogue's balance position at the start [m] (the reference of the built-in controllers).

    Parameters
    ----------
    values : array_like (M_SIZE,), optional
        The measurement in the layout ``M_*`` of :mod:`hosedrogue.model.layout`, copied;
        default zeros.
    """

    __slots__ = ("_buf", *_VECTORS)

    def __init__(self, values=None):
        buf = np.zeros(M_SIZE) if values is None else np.array(values, dtype=np.float64).reshape(M_SIZE)
        object.__setattr__(self, "_buf", buf)
        for name, start in _VECTORS.items():
            view = buf[start:start + 3]
            view.flags.writeable = False
            object.__setattr__(self, name, view)

    def __setattr__(self, name, value):
        raise AttributeError(f"Measurement.{name}: a measurement is read-only")

    def __reduce__(self):
        """Copied and pickled as a measurement reading its buffer (``copy.deepcopy`` and pickle
        copy the buffer once, so a copied run's measurement reads the copied run's buffer)."""
        return Measurement.reading, (self._buf,)

    @classmethod
    def reading(cls, buf: np.ndarray) -> "Measurement":
        """A measurement that reads ``buf`` in place (no copy): the run writes the buffer, every
        controller sees the new values through the same object.

        Parameters
        ----------
        buf : numpy.ndarray (M_SIZE,)
            float64, C-contiguous.

        Returns
        -------
        Measurement
        """
        m = cls.__new__(cls)
        object.__setattr__(m, "_buf", buf)
        for name, start in _VECTORS.items():
            view = buf[start:start + 3]
            view.flags.writeable = False
            object.__setattr__(m, name, view)
        return m

    @property
    def t_s(self) -> float:
        """Time the quantities are of [s]."""
        return float(self._buf[M_T])

    @property
    def hose_length_m(self) -> float:
        """Free hose length [m]."""
        return float(self._buf[M_L])

    @property
    def reel_speed_m_s(self) -> float:
        """Take-up speed [m/s], positive reeling in."""
        return float(self._buf[M_REEL_V])

    @property
    def exit_tension_n(self) -> float:
        """Hose tension at the exit [N]."""
        return float(self._buf[M_T0])

    @property
    def coupled(self) -> bool:
        """Whether the probe has captured the drogue."""
        return bool(self._buf[M_COUPLED] != 0.0)

    @property
    def drogue_q_pa(self) -> float:
        """Dynamic pressure of the air the drogue's control surfaces see [Pa] (NaN without
        ``[drogue_actuator]``): what a controller divides by to turn a force into deflections."""
        return float(self._buf[M_Q])

    def copy(self) -> "Measurement":
        """A copy that the run does not update.

        Returns
        -------
        Measurement
        """
        return Measurement(self._buf)

    def as_array(self) -> np.ndarray:
        """The measurement as one float64 array (a copy), in the layout of
        :mod:`hosedrogue.model.sampled` (``M_*``).

        Returns
        -------
        numpy.ndarray (M_SIZE,)
        """
        return self._buf.copy()

    def __repr__(self) -> str:
        return (f"Measurement(t_s={self.t_s:g}, drogue_position_m={self.drogue_position_m.tolist()}, "
                f"relative_position_m={self.relative_position_m.tolist()}, hose_length_m={self.hose_length_m:g}, "
                f"coupled={self.coupled})")


class ControllerError(Exception):
    """A sampled-data controller failed (raised, or returned a bad command): the run stops there.

    The message is one line naming the role, the controller, the time [s] and the problem.
    """


@dataclass(frozen=True)
class SampledController:
    """A sampled-data controller of one role: its factory, options and sample time.

    Parameters
    ----------
    role : str
        ``"drogue"``, ``"reel"`` or ``"receiver"`` (:data:`ROLES`).
    entry : str or callable
        The factory: ``"package.module:factory"`` (imported by that name) or the callable.
    sample_time_s : float
        Time between calls [s], > 0; a whole multiple of the RK4 step.
    options : dict
        Keyword options of the factory.
    """

    role: str
    entry: Any
    sample_time_s: float
    options: dict = field(default_factory=dict, hash=False)

    def __post_init__(self) -> None:
        if self.role not in ROLES:
            raise ParameterError(f"role = {self.role!r}: must be one of {', '.join(map(repr, ROLES))}")
        check_entry(f"{self.table}.entry", self.entry)
        if self.entry == "":
            raise ParameterError(f'{self.table}.entry: missing; give the factory, "package.module:factory"')
        t = self.sample_time_s
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not (math.isfinite(t) and t > 0):
            raise ParameterError(f"{self.table}.sample_time_s = {t!r}: must be a finite number > 0 s")
        object.__setattr__(self, "sample_time_s", float(t))
        if not isinstance(self.options, dict):
            raise ParameterError(f"{self.table}.options = {self.options!r}: must be a table of options")

    @property
    def table(self) -> str:
        """The scenario table of the role (``controller``, ``reel``, ``receiver``)."""
        return TABLE_OF.get(self.role, "controller")

    @property
    def name(self) -> str:
        """The entry point as text (``"package.module:factory"``)."""
        return entry_name(self.entry)

    def factory(self) -> Callable:
        """The factory, imported by its entry point (:func:`load_entry`).

        Returns
        -------
        callable
        """
        return load_entry(self.entry, f"{self.table}.entry")

    def build(self):
        """A new controller: ``factory(**options)``, checked to have ``reset(m)`` and ``__call__``.

        Returns
        -------
        object
            The controller.

        Raises
        ------
        ParameterError
            The entry cannot be imported, the factory raised, or it returned no controller.
        """
        factory = self.factory()
        with CtrlC() as ctrl_c:
            try:
                controller = factory(**self.options)
            except BaseException as exc:  # sys.exit and the code's own KeyboardInterrupt too
                if ctrl_c.is_ctrl_c(exc):
                    raise
                raise ParameterError(f"{self.table}.options = {self.options!r}: the factory {self.name!r} raised "
                                     f"{type(exc).__name__}: {one_line(exc)}") from None
        if not callable(controller) or not callable(getattr(controller, "reset", None)):
            raise ParameterError(f"{self.table}.entry = {self.name!r}: the factory returned {type(controller).__name__}"
                                 ", not a controller with reset(m) and __call__(t, m)")
        return controller


class CtrlC:
    """Tells the user's own Ctrl-C from a ``KeyboardInterrupt`` raised by the user's code.

    While it is entered in the main thread with Python's default SIGINT handler, a handler of its
    own records the signal and raises ``KeyboardInterrupt`` as the default one does. Outside the
    main thread no signal raises there, so every ``KeyboardInterrupt`` is the code's; in the main
    thread under another program's handler the two cannot be told apart, and it counts as Ctrl-C.
    """

    def __init__(self):
        self.pressed = False
        self._old = None
        self._main = threading.current_thread() is threading.main_thread()

    def __enter__(self) -> "CtrlC":
        if self._main and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            self._old = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum, frame):
        self.pressed = True
        raise KeyboardInterrupt

    def __exit__(self, *exc) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)

    def is_ctrl_c(self, exc: BaseException) -> bool:
        """Whether ``exc``, raised out of the user's code, is the user's Ctrl-C (to let through).

        Parameters
        ----------
        exc : BaseException

        Returns
        -------
        bool
        """
        return isinstance(exc, KeyboardInterrupt) and (self.pressed or (self._main and self._old is None))


def one_line(exc: BaseException) -> str:
    """An exception's message on one line (whitespace runs folded to one space).

    Parameters
    ----------
    exc : BaseException

    Returns
    -------
    str
    """
    return " ".join(str(exc).split()) or "(no message)"


def load_entry(entry, name: str = "entry") -> Callable:
    """The callable an entry point names, imported by that name (``importlib``, never ``eval``).

    Parameters
    ----------
    entry : str or callable
        ``"package.module:factory"`` (the attribute may be dotted, ``module:Class.create``), or a
        callable, returned as it is.
    name : str
        The field's name for the messages (``"receiver.entry"``).

    Returns
    -------
    callable

    Raises
    ------
    ParameterError
        One line: the module cannot be imported (or raised while importing), has no such
        attribute, or the attribute is not callable.
    """
    entry = check_entry(name, entry)
    if callable(entry):
        return entry
    module_name, _, attr = entry.rpartition(":")
    with CtrlC() as ctrl_c:
        try:
            obj = _import_file(module_name) if module_name.endswith(".py") else importlib.import_module(module_name)
        except ImportError as exc:
            raise ParameterError(f"{name} = {entry!r}: cannot import module {module_name!r} ({one_line(exc)}); it must "
                                 "be importable by that name here and on every Dask worker (docs: Your own controllers)"
                                 ) from None
        except BaseException as exc:  # sys.exit and the module's own KeyboardInterrupt too
            if ctrl_c.is_ctrl_c(exc):
                raise
            raise ParameterError(f"{name} = {entry!r}: importing {module_name!r} raised {type(exc).__name__}: "
                                 f"{one_line(exc)}") from None
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise ParameterError(f"{name} = {entry!r}: {module_name!r} has no attribute {attr!r}")
        obj = getattr(obj, part)
    if not callable(obj):
        raise ParameterError(f"{name} = {entry!r}: {attr!r} is a {type(obj).__name__}, not a callable factory")
    return obj


def _import_file(path: str):
    """The module of a Python file, imported by its path (``importlib.util``, never ``eval``); once
    per process, under a name made of the file's absolute path, so two files of one name differ."""
    import hashlib
    import importlib.util
    import sys
    from pathlib import Path

    file = Path(path).resolve()
    if not file.is_file():
        raise ImportError(f"no such file {str(file)!r}")
    name = f"hosedrogue_user_{file.stem}_{hashlib.sha256(str(file).encode()).hexdigest()[:12]}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def command_problem(role: str, value, size: int | None = None) -> tuple[str | None, tuple]:
    """What is wrong with a controller's command, and its numbers.

    Parameters
    ----------
    role : str
        The role (:data:`ROLES`).
    value : Any
        What the controller returned.
    size : int, optional
        The drogue's command size when it is not the force's 2: one deflection [rad] per
        control surface (``[drogue_actuator] command = "deflection"``).

    Returns
    -------
    problem : str or None
        None for a good command, else e.g. ``"returned NaN"``, ``"returned an array of shape
        (3,), expected (u_y_n, u_z_n) [N]"``.
    values : tuple of float
        The command's numbers (empty if it has a problem).
    """
    expected = COMMANDS[role] if size is None or size == COMMAND_SIZE[role] else deflection_command_text(size)
    size = COMMAND_SIZE[role] if size is None else int(size)
    if isinstance(value, (str, bytes)) or value is None:
        return f"returned {value!r}, expected {expected}", ()
    try:
        if size == 1:
            values = (float(value),) if isinstance(value, (int, float)) else tuple(
                float(v) for v in np.asarray(value, dtype=np.float64).reshape(1))
        else:
            values = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        values = None
    if values is None or len(values) != size:
        try:
            what = f"an array of shape {np.shape(value)}"
        except Exception:  # a ragged or odd object: say its type
            what = f"a {type(value).__name__}"
        return f"returned {what}, expected {expected}", ()
    for v in values:
        if not math.isfinite(v):
            bad = "NaN" if math.isnan(v) else repr(v)
            return f"returned {bad} in {value!r}, expected finite numbers", ()
    return None, values


def deflection_command_text(surfaces: int) -> str:
    """How the messages say a deflection command of ``surfaces`` control surfaces.

    Parameters
    ----------
    surfaces : int
        n_s [-].

    Returns
    -------
    str
    """
    return f"{surfaces} deflections (delta_1 ... delta_{surfaces}) [rad]"
