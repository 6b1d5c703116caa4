"""What a run can do, checked before it starts: a duration that is a finite number of seconds, an
integrator its loop runs for its kind of link, reach its duration on its step grid, save at least
one sample after its start, and keep its output within a share of the machine's memory.

* **Duration and integrator** (every loop: ``simulate``, the steppers, the engagement, the FMUs'
  runs, scenarios). One rule, :func:`check_duration`, and one table, :data:`INTEGRATORS`, with
  its check :func:`check_integrator`: each refusal is one line naming the field, the value and
  what is allowed.
* **Step grid** (every run, from the commands and from Python alike). A run takes
  ``duration_s / step_s`` steps: that must be a whole number (to :data:`GRID_TOLERANCE`), or the
  run would end a fraction of a step early or late (``duration_s = 0.1`` at ``step_s = 0.03``
  ended at 0.09 s). A study that derives a duration from physics puts it on the grid itself with
  :func:`on_step_grid` (the nearest step), and its scenario records the duration run. Sample times
  and delays on the step (or control-step) grid: :func:`whole_multiple`.
* **Output grid.** It saves every ``output_every`` steps: a run of fewer steps than that would
  keep its start only, and its steps must be a whole number of output intervals, or the saved
  series would end at the last output time before the run's end (20 steps saved every 3 ended at
  18). Derived durations go on this grid too: :func:`on_step_grid` with ``every``.
* **Statistics window** (``command``). A turbulent run's statistics are taken over the turbulence window, which
  must overlap the run (else they would be of no sample).
* **Memory.** What a run keeps (its saved samples: state, joints and their velocities, some 64
  signals, in float64) is estimated by :func:`output_bytes` and refused beyond
  :data:`MEMORY_SHARE` of the machine's physical memory (:func:`machine_memory_bytes`), in one
  line naming the fields to change. The estimate is a lower bound: writing the files copies part of
  it again.
"""

from __future__ import annotations

import math
import os

from ..errors import ParameterError
from ..results.statistics import turbulence_window

__all__ = ["GRID_TOLERANCE", "INTEGRATORS", "MEMORY_SHARE", "check_duration", "check_integrator", "check_memory",
           "check_run", "machine_memory_bytes", "on_step_grid", "output_bytes", "positive_number",
           "whole_multiple"]

#: Share of the machine's physical memory that one run's (or campaign's) kept output may take [-].
MEMORY_SHARE = 0.5
#: Relative distance of ``duration_s / step_s`` from a whole number accepted as whole [-]: decimal
#: durations and steps are not exact binary numbers (0.3 / 0.1 = 2.9999999999999996).
GRID_TOLERANCE = 1e-9
#: Signals saved per sample beside the state and the joints (times, forces, tensions, probe,
#: controller, surfaces): an upper bound over the models [-].
SIGNALS_PER_SAMPLE = 64


def machine_memory_bytes() -> int:
    """The machine's physical memory [bytes] (``os.sysconf``; 16 GiB assumed where unknown).

    Returns
    -------
    int
    """
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):  # pragma: no cover - not POSIX
        return 16 * 2**30


def _gb(n: float) -> str:
    return f"{n / 1e9:.3g} GB"


def check_memory(needed_bytes: float, fields: str, what: str, advice: str) -> None:
    """Refuse work whose kept output exceeds :data:`MEMORY_SHARE` of the machine's memory.

    Parameters
    ----------
    needed_bytes : float
        The estimate [bytes].
    fields : str
        The fields that set it, with their values (``"runs = 10**20"``).
    what : str
        What needs it ("the run would keep 8.64e+09 samples of 20 links").
    advice : str
        Which fields to change, and how.

    Raises
    ------
    ParameterError
        One line: the fields, the estimate, the share of the machine's memory, the advice.
    """
    limit = MEMORY_SHARE * machine_memory_bytes()
    if not needed_bytes <= limit:
        raise ParameterError(f"{fields}: {what}, about {_gb(needed_bytes)}, more than {MEMORY_SHARE:.0%} of this "
                             f"machine's {_gb(machine_memory_bytes())} of memory; {advice}")


def output_bytes(links: int, samples: float) -> float:
    """The memory [bytes] a run's saved output takes (a lower bound, see the module).

    Parameters
    ----------
    links : int
        Links of the hose.
    samples : float
        Saved samples.

    Returns
    -------
    float
    """
    # state (at most 8 numbers per link: angles, rates, elastic stretch and its rate), the joints and
    # their velocities (3 + 3 per joint), the other signals
    return 8.0 * samples * (8 * links + 6 * (links + 1) + SIGNALS_PER_SAMPLE)


def on_step_grid(duration_s: float, step_s: float, every: int = 1) -> float:
    """``duration_s`` [s] moved to the nearest whole number of output intervals, ``every`` steps of
    ``step_s`` [s] (at least one): the duration a run of that step and ``output_every`` reaches
    exactly, its saved series included, for durations derived from physics (a probe's time to
    contact) or chosen by a user (an episode's time limit). Written with 12 significant digits, so
    902 steps of 0.005 s read 4.51 s.

    Parameters
    ----------
    duration_s : float
        The wanted duration [s], finite and > 0.
    step_s : float
        The run's step [s] (``numerics.step_s``).
    every : int
        The run's ``numerics.output_every`` [-]; 1 puts it on the step grid only.

    Returns
    -------
    float
        ``max(1, round(duration_s / (every * step_s))) * every * step_s`` [s], a whole number of
        output intervals to :data:`GRID_TOLERANCE`.
    """
    intervals = max(1, round(duration_s / (every * step_s)))
    return float(f"{intervals * every * step_s:.12g}")


def positive_number(name: str, value: object, hi: float = math.inf, unit: str = "s", text: str = "") -> float:
    """A value that must be a finite number in (0, ``hi``]: a run's duration (:func:`check_duration`),
    an environment's time limit or force bound (a bool is not a number here).

    Parameters
    ----------
    name : str
        The value's name, for the message.
    value : object
        What was given.
    hi : float
        The largest value allowed (default: no bound but finiteness).
    unit : str
        The unit the message gives.
    text : str
        More of what is allowed, appended to the message (", or one of ...").

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        One line naming the value, what was given and the range.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and 0 < value <= hi):
        allowed = f"> 0 {unit}" if hi == math.inf else f"in (0, {hi:g}] {unit}"
        raise ParameterError(f"{name} = {value!r}: must be a finite number {allowed}{text}")
    return float(value)


def check_duration(value, name: str = "duration_s", maximum: float = math.inf) -> float:
    """Refuse a run's duration that is not a finite number > 0 s (nor above ``maximum``): the one
    check of every loop (``simulate``, the steppers, the engagement, the FMU's own run, a scenario),
    :func:`positive_number` in seconds.

    Parameters
    ----------
    value : object
        The duration given [s]; a bool is not a number here.
    name : str
        How the message names it (``scenario.duration_s`` in a scenario).
    maximum : float
        The longest allowed [s] (default: no bound but finiteness).

    Returns
    -------
    float
        ``value`` as a float [s].

    Raises
    ------
    ParameterError
        One line naming the field, the value and what is allowed.
    """
    return positive_number(name, value, maximum, "s")


#: What each loop integrates with, by kind of link (False: rigid, True: elastic; docs/model.md
#: §5, §11): the one table the loops and the scenarios check a run's ``numerics.integrator``
#: against. The engagement (its driver, its stepper, the engagement FMU and the Gymnasium
#: environments) takes fixed steps, its hose changing length; the fixed-length stepper
#: (sampled-data control) runs rigid links only, by RK4 between samples.
INTEGRATORS = {
    "fixed-length": {False: ("rk4", "adaptive"), True: ("rk4", "sdirk2")},
    "engagement": {False: ("rk4",), True: ("rk4", "sdirk2")},
    "fixed-length stepper": {False: ("rk4",)},
}


def check_integrator(params, loop: str) -> None:
    """Refuse an integrator the loop does not run for the hose's kind of link (:data:`INTEGRATORS`).

    Parameters
    ----------
    params : hosedrogue.spec.params.Params
        The run's parameters (``numerics.integrator``, ``hose.axial_stiffness_n``).
    loop : str
        A key of :data:`INTEGRATORS`.

    Raises
    ------
    ParameterError
        One line naming the integrator, the loop and kind of link, and the integrators it runs.
    """
    integrator, elastic = params.numerics.integrator, params.hose.elastic
    kind = "an elastic hose (hose.axial_stiffness_n finite)" if elastic else "rigid links (hose.axial_stiffness_n = inf)"
    if elastic not in INTEGRATORS[loop]:  # the fixed-length stepper: rigid links only
        raise ParameterError(f"hose.axial_stiffness_n = {params.hose.axial_stiffness_n!r}: the {loop} runs rigid "
                             "links only (hose.axial_stiffness_n = inf)")
    allowed = INTEGRATORS[loop][elastic]
    if integrator not in allowed:
        raise ParameterError(f"numerics.integrator = {integrator!r}: the {loop} run of {kind} integrates with "
                             + " or ".join(repr(a) for a in allowed))


def check_run(params, duration_s: float, name: str = "duration_s", command: bool = False) -> tuple[float, int]:
    """Refuse, before it starts, a run that cannot reach its duration on its step grid or its output
    grid, would save nothing after its start, or would keep more output than the machine's memory allows.

    Parameters
    ----------
    params : hosedrogue.spec.params.Params
        The run's parameters (``numerics.step_s``, ``numerics.output_every``, ``hose.links``).
    duration_s : float
        Simulated time [s], finite and > 0.
    name : str
        How the messages name the duration (``scenario.duration_s`` in a scenario).
    command : bool
        Also refuse a turbulence (statistics) window outside the run. The commands ask for it on the
        user's run; the library's runs do not, since short runs of turbulent scenarios serve tests.
        The step grid is checked on every run (studies put derived durations on it with
        :func:`on_step_grid`).

    Returns
    -------
    (float, int)
        The step [s] and the number of steps (:meth:`hosedrogue.spec.params.Numerics.steps`).

    Raises
    ------
    ParameterError
        One line naming the fields to change and values that would do.
    """
    h, every = params.numerics.step_s, params.numerics.output_every
    params.numerics.steps(duration_s, name)  # at most Numerics.MAX_STEPS
    ratio = duration_s / h
    steps = round(ratio)
    if steps < 1 or abs(ratio - steps) > GRID_TOLERANCE * max(ratio, 1.0):
        below, above = math.floor(ratio) * h, math.ceil(ratio) * h
        raise ParameterError(f"{name} = {duration_s!r}: not a whole number of steps of numerics.step_s = {h!r} s "
                             f"({ratio:.6g} steps; the run would not end at {duration_s!r} s); give {name} = "
                             f"{below:.6g} or {above:.6g}, or a step that divides it")
    if steps < every:
        raise ParameterError(f"numerics.output_every = {every!r}: more than the run's {steps} steps ({name} = "
                             f"{duration_s!r} s at numerics.step_s = {h!r} s), so nothing after its start would be "
                             f"saved; give output_every <= {steps}")
    if steps % every:  # the saved series would end at the last output time before the run's end
        below, above = steps // every * every * h, -(-steps // every) * every * h
        raise ParameterError(f"{name} = {duration_s!r}: not a whole number of output intervals (numerics.output_every = "
                             f"{every!r} steps of numerics.step_s = {h!r} s; its {steps} steps would be saved to "
                             f"{below:.6g} s only); give {name} = {below:.6g} or {above:.6g}, or an output_every "
                             f"that divides {steps}")
    start, end = turbulence_window(params.turbulence)
    if command and (start >= duration_s or end <= start):  # the statistics would be of no sample ("peak nan m")
        raise ParameterError(f"turbulence.start_s = {start!r}: the turbulence window [{start:g}, {end:g}) s, over which "
                             f"the run's statistics are taken, must overlap the run [0, {duration_s:g}] s; give "
                             f"turbulence.start_s < {duration_s:g} or a longer {name}")
    samples = steps // every + 1
    check_memory(output_bytes(params.hose.links, samples),
                 f"{name} = {duration_s!r}, numerics.step_s = {h!r}, numerics.output_every = {every!r}",
                 f"the run would keep {samples:.3g} samples of {params.hose.links} links",
                 "raise step_s or output_every, or shorten the run")
    return h, steps


def whole_multiple(value_s: float, unit_s: float, name: str, unit_name: str) -> int:
    """``value_s / unit_s`` when it is a whole number >= 1 (to :data:`GRID_TOLERANCE`).

    Parameters
    ----------
    value_s : float
        A duration [s] (a sample time, a delay).
    unit_s : float
        The grid [s] it must lie on (the RK4 step, a control step).
    name, unit_name : str
        How the message names the two (``"receiver.sample_time_s"``, ``"numerics.step_s"``).

    Returns
    -------
    int

    Raises
    ------
    ParameterError
        One line naming both values.
    """
    ratio = value_s / unit_s
    count = int(round(ratio))
    if count < 1 or abs(ratio - count) > GRID_TOLERANCE * max(ratio, 1.0):
        raise ParameterError(f"{name} = {value_s!r}: must be a whole multiple of {unit_name} = {unit_s!r} s")
    return count
