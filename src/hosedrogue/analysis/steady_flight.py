"""The balance position in a steady coordinated turn or climb (docs/model.md §9): sweeps over the
bank and flight-path angles, and a turn's effect taken apart.

A steady turn or climb at constant speed is a steady frame: the balance position solves the same
static equations as in level flight with the frame's apparent forces
(:func:`hosedrogue.analysis.equilibrium.solve_equilibrium` of parameters whose
``tanker_motion`` holds the bank and flight-path angles). In a coordinated level turn at bank phi
the tow point's acceleration makes the apparent gravity ``g / cos(phi)`` along the tanker's
z axis; :func:`turn_breakdown` states what the turn does besides that, term by term, with the
continuous hose (:func:`hosedrogue.analysis.continuum.solve_continuum`, whose loads can take the
terms one at a time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.frame import SteadyFrame, steady_frame
from ..spec.params import Params
from .continuum import solve_continuum
from .equilibrium import Equilibrium, solve_equilibrium


def steady_params(params: Params, bank_deg: float = 0.0, flight_path_deg: float = 0.0) -> Params:
    """``params`` in a steady coordinated turn and/or climb (no segments), validated.

    Parameters
    ----------
    params : Params
        The model and flight condition.
    bank_deg : float
        Bank angle [deg] (> 0 turning right).
    flight_path_deg : float
        Flight-path angle [deg] (> 0 climbing).

    Returns
    -------
    Params
    """
    return params.replace(tanker_motion={"bank_deg": bank_deg, "flight_path_deg": flight_path_deg, "segments": []})


@dataclass(frozen=True)
class SteadySweep:
    """Balance positions over one angle of steady flight (bank or flight path), in the tanker's
    body axes at the tow point."""

    angle: str  #: "bank_deg" or "flight_path_deg"
    angles_deg: np.ndarray  #: the angles [deg] (k,)
    drogue_position_m: np.ndarray  #: (k, 3) [m]
    exit_tension_n: np.ndarray  #: (k,) [N]
    tow_force_n: np.ndarray  #: (k, 3) [N]


def sweep_steady(params: Params, angle: str, angles_deg) -> SteadySweep:
    """The balance position at each angle of steady flight.

    Parameters
    ----------
    params : Params
        The model and flight condition (its ``tanker_motion`` is replaced).
    angle : {"bank_deg", "flight_path_deg"}
        Which angle the sweep varies (the other is zero).
    angles_deg : array_like
        The angles [deg].

    Returns
    -------
    SteadySweep
    """
    if angle not in ("bank_deg", "flight_path_deg"):
        raise ValueError(f"angle = {angle!r}: must be 'bank_deg' or 'flight_path_deg'")
    angles = np.asarray(angles_deg, dtype=float)
    eqs: list[Equilibrium] = [solve_equilibrium(steady_params(params, **{angle: float(a)})) for a in angles]
    return SteadySweep(angle, angles, np.array([e.drogue_position_m for e in eqs]),
                       np.array([e.exit_tension_n for e in eqs]), np.array([e.tow_force_n for e in eqs]))


#: The parts of a coordinated level turn, in the order :func:`turn_breakdown` adds them.
TURN_TERMS = ("apparent gravity g/cos(phi)", "wake at the load factor", "centrifugal field", "air's rotation")


@dataclass(frozen=True)
class TurnBreakdown:
    """What a steady coordinated level turn does to the balance position of the continuous hose,
    term by term (each added to the ones before it, :data:`TURN_TERMS`), in body axes [m]."""

    bank_deg: float  #: the bank angle [deg]
    level_m: np.ndarray  #: drogue position in level flight (3,) [m]
    steps_m: np.ndarray  #: drogue position after each term is added (len(TURN_TERMS), 3) [m]

    @property
    def turn_m(self) -> np.ndarray:
        """The turn's whole effect on the drogue position (3,) [m]."""
        return self.steps_m[-1] - self.level_m

    @property
    def contributions_m(self) -> np.ndarray:
        """Each term's share of it (len(TURN_TERMS), 3) [m]; they sum to :attr:`turn_m`."""
        return np.diff(np.vstack([self.level_m, self.steps_m]), axis=0)

    @property
    def beyond_apparent_gravity_m(self) -> np.ndarray:
        """What the turn does besides the apparent gravity ``g / cos(phi)`` (3,) [m]."""
        return self.steps_m[-1] - self.steps_m[0]


def turn_breakdown(params: Params, bank_deg: float) -> TurnBreakdown:
    """The continuous hose's balance position in a level coordinated turn, built up term by term.

    Parameters
    ----------
    params : Params
        The model and flight condition (bending and the link discretization are irrelevant: the
        continuous hose, bending neglected).
    bank_deg : float
        Bank angle [deg] (> 0 turning right).

    Returns
    -------
    TurnBreakdown
    """
    level = steady_params(params)
    full = steady_frame(steady_params(params, bank_deg).tanker_motion, params.flight.airspeed_m_s)
    zero = (0.0, 0.0, 0.0)
    g_app = (0.0, 0.0, full.acceleration_m_s2[2])
    frames = (SteadyFrame(g_app, zero, 1.0), SteadyFrame(g_app, zero, full.wake_factor),
              SteadyFrame(full.acceleration_m_s2, full.omega_rad_s, full.wake_factor, air_omega_rad_s=zero), full)
    steps = np.array([solve_continuum(level, frame=f).drogue_position_m for f in frames])
    return TurnBreakdown(float(bank_deg), solve_continuum(level).drogue_position_m, steps)


def apparent_gravity_m_s2(bank_deg: float, g: float) -> float:
    """The apparent gravity of a coordinated level turn, ``g / cos(phi)`` [m/s^2].

    Parameters
    ----------
    bank_deg : float
        Bank angle [deg].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    float
    """
    return g / math.cos(math.radians(bank_deg))
