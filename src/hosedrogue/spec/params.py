"""Typed, validated, immutable parameter sets.

The defaults of these dataclasses *are* the paper's case (Wu et al., 2018, Table 1 and Sec. 2.3):
``PAPER = Params()`` is the one definition of the paper preset. TOML files and dictionaries override
any field; unknown keys, wrong types and values outside the allowed range raise
:class:`ParameterError`, whose one-line message names the field, the value and what is allowed.

Units are SI and are part of every field name (``_m``, ``_kg``, ``_s``, ``_m_s``, ...).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from ..constants import H_MAX_ATMOSPHERE
from ..errors import ParameterError
from .fields import Section, choice, flag, integer, real, vec3
from .manoeuvres import TankerMotion
from .standards import standard_intensity

INF = math.inf



@dataclass(frozen=True)
class Tanker(Section):
    """The tanker aircraft (paper Table 1)."""

    _section = "tanker"
    #: Tanker mass [kg]; its weight sets the wake vortices' circulation W / (rho V b0).
    mass_kg: float = field(default=60000.0, metadata=real(0.0, unit="kg"))
    #: Wing span b [m]; the wake geometry is given in fractions of it.
    span_m: float = field(default=34.0, metadata=real(0.0, unit="m"))


@dataclass(frozen=True)
class Hose(Section):
    """The hose, modelled as ``links`` rigid links of equal length (paper Table 1; docs/model.md §2-3)."""

    _section = "hose"
    #: Trailed hose length from the tow point to the drogue [m].
    length_m: float = field(default=16.0, metadata=real(0.0, unit="m"))
    #: Number of rigid links n the hose is divided into [-] (link length ``length_m / links``).
    links: int = field(default=20, metadata=integer(1, 1000))
    #: Inner diameter of the hose wall [m]; with ``outer_diameter_m`` it sets the area moment
    #: pi (d_o^4 - d_i^4) / 64 of the bending stiffness. Must be smaller than the outer diameter.
    inner_diameter_m: float = field(default=0.051, metadata=real(0.0, lo_open=False, unit="m"))
    #: Outer diameter d_o of the hose [m]: the drag reference and the bending stiffness.
    outer_diameter_m: float = field(default=0.067, metadata=real(0.0, unit="m"))
    #: Mass per unit length of the hose [kg/m].
    mass_per_length_kg_m: float = field(default=4.4, metadata=real(0.0, unit="kg/m"))
    #: Young's modulus E of the hose wall [Pa]; bending stiffness E I [N m^2].
    elastic_modulus_pa: float = field(default=13.79e6, metadata=real(0.0, lo_open=False, unit="Pa"))
    #: Link rotational inertia J_y = J_z [kg m^2] used when ``link_inertia == "paper"``.
    link_inertia_kg_m2: float = field(default=2.816, metadata=real(0.0, lo_open=False, unit="kg m^2"))
    #: "paper": Table 1's 2.816 kg m^2 per link; "rod": m l^2 / 12 of each link (docs/model.md §2).
    link_inertia: str = field(default="paper", metadata=choice("paper", "rod"))
    #: "paper": Eq. 20 equivalent joint force; "moment": conservative restoring moment; "off".
    bending: str = field(default="paper", metadata=choice("paper", "moment", "off"))
    #: Where each link's mass sits (docs/model.md §2): "aft": all at its aft joint (the paper's
    #: lumping, first order in 1/links); "split": half at each end joint (the half at the tow
    #: point is carried by the tanker), second order in 1/links (docs/convergence.md).
    mass_lumping: str = field(default="aft", metadata=choice("aft", "split"))
    #: Drag coefficient c_n of the flow normal to a link [-], on the wetted area pi d_o l
    #: (force per link 0.5 rho pi d_o c_n l |v_n| v_n).
    normal_drag_coefficient: float = field(default=0.28, metadata=real(0.0, lo_open=False))
    #: Skin-friction coefficient c_t of the flow along a link [-], on the wetted area pi d_o l.
    tangential_drag_coefficient: float = field(default=0.001, metadata=real(0.0, lo_open=False))
    #: Link drag along the link: "midpoint" (the paper: one evaluation at the link's midpoint,
    #: blind to a link turning about its midpoint) or "gauss2" (two-point Gauss quadrature of the
    #: distributed drag; docs/model.md, docs/long-runs.md).
    drag_quadrature: str = field(default="midpoint", metadata=choice("midpoint", "gauss2"))
    #: Structural (Kelvin-Voigt) bending damping of the hose wall [N m^2 s]: bending moment
    #: c_b dkappa/dt, lumped at each inner joint as c_b / lbar (omega_k+1 - omega_k) on link k and
    #: the opposite on link k+1 (0 in the paper's case; the ``converged`` preset's value,
    #: eta E I / omega_ref, is derived in docs/long-runs.md).
    bending_damping_n_m2_s: float = field(default=0.0, metadata=real(0.0, 1e6, lo_open=False, unit="N m^2 s"))
    #: Axial stiffness EA of the hose [N]: every link becomes a spring of stiffness EA / l along
    #: itself, its length a coordinate of the chain (docs/model.md §11); inf (the paper's case):
    #: rigid, inextensible links. The engagement scenarios' 1e6 N is reasoned in docs/model.md §11.
    axial_stiffness_n: float = field(default=INF, metadata=real(0.0, unit="N", inf_ok="rigid links"))
    #: Kelvin-Voigt axial damping c_a of the hose wall [N s]: a link's tension is
    #: EA eps + c_a deps/dt for its strain eps (0: none; needs a finite ``axial_stiffness_n``);
    #: c_a = eta EA / omega for a loss factor eta at the frequency omega (docs/model.md §11).
    axial_damping_n_s: float = field(default=0.0, metadata=real(0.0, 1e9, lo_open=False, unit="N s"))

    def _check_consistency(self) -> None:
        if self.inner_diameter_m >= self.outer_diameter_m:
            raise ParameterError(
                f"hose.inner_diameter_m = {self.inner_diameter_m!r}: must be smaller than "
                f"hose.outer_diameter_m = {self.outer_diameter_m!r}"
            )
        if self.axial_damping_n_s > 0.0 and math.isinf(self.axial_stiffness_n):
            raise ParameterError(
                f"hose.axial_damping_n_s = {self.axial_damping_n_s!r}: an inextensible hose "
                f"(hose.axial_stiffness_n = inf) has no axial damping; give a finite axial_stiffness_n or 0"
            )

    @property
    def elastic(self) -> bool:
        """Whether the links stretch (a finite ``axial_stiffness_n``)."""
        return math.isfinite(self.axial_stiffness_n)

    @property
    def link_length_m(self) -> float:
        """Length of one link, ``length_m / links`` [m]."""
        return self.length_m / self.links


@dataclass(frozen=True)
class Drogue(Section):
    """The drogue (paper Table 1)."""

    _section = "drogue"
    #: Drogue mass [kg], lumped at the last joint.
    mass_kg: float = field(default=29.0, metadata=real(0.0, unit="kg"))
    #: Drogue diameter D [m]; drag area pi D^2 / 4 c_dro.
    diameter_m: float = field(default=0.61, metadata=real(0.0, unit="m"))
    #: Rotational inertia of the drogue about its pitch and yaw axes [kg m^2], added to the
    #: last link's.
    inertia_kg_m2: float = field(default=1.349, metadata=real(0.0, lo_open=False, unit="kg m^2"))
    #: Drag coefficient c_dro of the drogue [-], on its frontal area pi D^2 / 4.
    drag_coefficient: float = field(default=0.712, metadata=real(0.0, lo_open=False))


@dataclass(frozen=True)
class Flight(Section):
    """Flight condition of the tanker (paper Sec. 2.3.3: 150 m/s at 8000 m): straight and level, or
    the start of its manoeuvres (:class:`~hosedrogue.spec.manoeuvres.TankerMotion`)."""

    _section = "flight"
    #: Flight altitude [m]; sets the ICAO standard-atmosphere air density.
    altitude_m: float = field(
        default=8000.0, metadata=real(0.0, H_MAX_ATMOSPHERE, lo_open=False, unit="m")
    )
    #: True airspeed of the tanker [m/s] (the free stream the hose sees; at the start when the
    #: tanker manoeuvres, [tanker_motion]).
    airspeed_m_s: float = field(default=150.0, metadata=real(0.0, 400.0, unit="m/s"))
    #: Multiplies the ICAO density [-]; 0 switches all air forces off (used by energy checks).
    density_scale: float = field(default=1.0, metadata=real(0.0, 10.0, lo_open=False))


@dataclass(frozen=True)
class Wake(Section):
    """Hallock-Burnham tanker wake (docs/model.md §4). Geometry as fractions of the tanker span."""

    _section = "wake"
    #: Include the tanker's wake vortices in the air velocity at the hose.
    enabled: bool = field(default=True, metadata=flag())
    #: Lateral position of the tow point right of the centreline, over span [-] (right wing
    #: mid-span).
    tow_point_y_over_span: float = field(default=0.25, metadata=real(-0.5, 0.5, lo_open=False))
    #: Distance between the two vortices over span [-] (elliptic loading: pi/4).
    vortex_spacing_over_span: float = field(default=math.pi / 4, metadata=real(0.0, 1.0))
    #: Vortex core radius over span [-].
    core_radius_over_span: float = field(default=0.035, metadata=real(0.0, 1.0))
    #: Height of the vortices below the tow point [m] (z down).
    vertical_offset_m: float = field(default=0.0, metadata=real(-100.0, 100.0, lo_open=False, unit="m"))


@dataclass(frozen=True)
class Turbulence(Section):
    """Dryden turbulence (docs/model.md §4). Enabled with no window given, it acts for the whole
    run; the paper's case (isotropic 1.5 m/s, 530 m, on at 10 s for 20 s) states its window
    (``paper-turbulence``)."""

    _section = "turbulence"
    #: Include the Dryden gusts during ``[start_s, start_s + duration_s)``.
    enabled: bool = field(default=False, metadata=flag())
    #: Dryden spectrum family: "mil-f-8785c" or "mil-hdbk-1797" (see
    #: :mod:`hosedrogue.environment.turbulence`).
    model: str = field(default="mil-f-8785c", metadata=choice("mil-f-8785c", "mil-hdbk-1797"))
    #: Intensity per axis [u, v, w] (m/s); one number means isotropic.
    sigma_m_s: tuple = field(default=(1.5, 1.5, 1.5), metadata=vec3(0.0, 50.0, unit="m/s"))
    #: Scale length per axis [u, v, w] (m).
    scale_length_m: tuple = field(default=(530.0, 530.0, 530.0), metadata=vec3(1.0, 1e5, unit="m"))
    #: Time the gusts switch on [s] (default: the start of the run).
    start_s: float = field(default=0.0, metadata=real(0.0, lo_open=False, unit="s"))
    #: Length of the gust window [s]; the gusts are off again after it (default inf: to the end of the run).
    duration_s: float = field(default=math.inf, metadata=real(0.0, lo_open=False, unit="s", inf_ok=True))
    #: "uniform": the whole hose sees the tow point's gust; "frozen": delayed by distance / airspeed.
    distribution: str = field(default="uniform", metadata=choice("uniform", "frozen"))
    #: Sample interval of the gust record [s]; independent of the integration step.
    sample_time_s: float = field(default=0.005, metadata=real(0.0, 1.0, unit="s"))
    #: Reading the record between samples: "linear" (the paper's reproduction; kinks at every
    #: sample) or "cubic" (Catmull-Rom, continuous slope; with ``smoothing_s`` it lets RK4 take
    #: steps longer than the sample interval, docs/convergence.md).
    interpolation: str = field(default="linear", metadata=choice("linear", "cubic"))
    #: Width [s] of a symmetric (triangular) averaging of the gust record, window edges included;
    #: 0 = none (the paper's reproduction). Physically the hose and drogue average gusts over
    #: their size (0.02 s is 3 m of air at 150 m/s); numerically it makes the forcing smooth at
    #: the integration step, so RK4 keeps its order at steps beyond the sample interval.
    smoothing_s: float = field(default=0.0, metadata=real(0.0, 10.0, lo_open=False, unit="s"))
    #: Seed of the random generator of the gust record [-] (the same seed, the same gusts).
    seed: int = field(default=2018, metadata=integer(0, 2**63 - 1))

    #: Largest gust record [samples]: 1e7 x 3 axes x 8 bytes = 240 MB.
    MAX_SAMPLES = 10_000_000

    def _check_consistency(self) -> None:
        if math.isfinite(self.duration_s) and self.duration_s / self.sample_time_s > self.MAX_SAMPLES:
            raise ParameterError(
                f"turbulence.duration_s = {self.duration_s!r}: with sample_time_s = {self.sample_time_s!r} "
                f"the gust record would exceed {self.MAX_SAMPLES:.0e} samples; shorten it or sample coarser"
            )


@dataclass(frozen=True)
class Numerics(Section):
    """Time integration settings. The default step is justified in docs/convergence.md."""

    _section = "numerics"
    #: "rk4": fixed-step classical Runge-Kutta (the paper's); "adaptive": DOP853 with
    #: ``rtol`` and ``atol`` (cross-checks); "sdirk2": the fixed-step, L-stable two-stage SDIRK
    #: with each link's axial spring-damper implicit inside the O(n) recursion, for elastic
    #: hoses (``hose.axial_stiffness_n`` finite; docs/model.md §11).
    integrator: str = field(default="rk4", metadata=choice("rk4", "adaptive", "sdirk2"))
    #: RK4 step [s]; the adaptive integrator outputs every ``step_s * output_every``.
    step_s: float = field(default=0.005, metadata=real(0.0, 1.0, unit="s"))
    #: Keep every ``output_every``-th step in the result [-].
    output_every: int = field(default=2, metadata=integer(1, 10**6))
    #: Relative tolerance of the adaptive integrator [-].
    rtol: float = field(default=1e-9, metadata=real(0.0, 1.0))
    #: Absolute tolerance of the adaptive integrator, alike on every state component, in that
    #: component's own unit (link angles rad, their rates rad/s, controller and actuator states).
    atol: float = field(default=1e-11, metadata=real(0.0, 1.0, unit="state units"))
    #: Least corrections per stage of the "sdirk2" integrator [-]: each evaluates the chain at
    #: the stage's current guess with the axial, bending and string stiffness implicit; more
    #: follow (up to 6, or this many) until the last moves no stage velocity by more than 1 mm/s,
    #: and a step whose stages do not converge is split (docs/model.md §11). 2: with 1 the
    #: engagement scenarios take as long (more of the corrections beyond the first are needed).
    sdirk_corrections: int = field(default=2, metadata=integer(1, 10))
    #: A link yaw beyond this [deg] stops the run: the angle coordinates are singular at 90 deg.
    max_yaw_deg: float = field(default=85.0, metadata=real(0.0, 89.9, unit="deg"))

    #: Most RK4 steps one run may take (1e10 steps of a 20-link chain are ~a day of computing).
    MAX_STEPS = 10**10

    def steps(self, duration_s: float, name: str = "duration_s") -> tuple[float, int]:
        """The RK4 step [s] and the number of steps covering ``duration_s`` [s].

        Parameters
        ----------
        duration_s : float
            Simulated time [s].
        name : str
            How the error messages name the duration (``scenario.duration_s`` in a scenario).

        Returns
        -------
        (float, int)
            Step [s] and step count ``round(duration_s / step_s)``, at least 1.

        Raises
        ------
        ParameterError
            When ``duration_s`` rounds to no step at all, or to more than :data:`MAX_STEPS`.
        """
        h = self.step_s
        ratio = duration_s / h
        if not ratio <= self.MAX_STEPS:
            raise ParameterError(f"numerics.step_s = {h!r}: {name} = {duration_s!r} s would take more than "
                                 f"{self.MAX_STEPS:.0e} RK4 steps")
        nsteps = int(round(ratio))
        if nsteps < 1:
            raise ParameterError(f"{name} = {duration_s!r}: shorter than one RK4 step (numerics.step_s = {h} s)")
        return h, nsteps


SECTIONS = {
    "tanker": Tanker,
    "hose": Hose,
    "drogue": Drogue,
    "flight": Flight,
    "wake": Wake,
    "turbulence": Turbulence,
    "numerics": Numerics,
    "tanker_motion": TankerMotion,
}


@dataclass(frozen=True)
class Params:
    """All parameters of one model run. ``Params()`` is the paper's case."""

    #: The tanker aircraft (mass, span).
    tanker: Tanker = field(default_factory=Tanker)
    #: The hose (geometry, mass, stiffness, drag, discretization).
    hose: Hose = field(default_factory=Hose)
    #: The drogue (mass, size, inertia, drag).
    drogue: Drogue = field(default_factory=Drogue)
    #: The flight condition (altitude, airspeed).
    flight: Flight = field(default_factory=Flight)
    #: The tanker's wake vortices.
    wake: Wake = field(default_factory=Wake)
    #: The Dryden turbulence and its time window.
    turbulence: Turbulence = field(default_factory=Turbulence)
    #: Time integration settings.
    numerics: Numerics = field(default_factory=Numerics)
    #: The tanker's manoeuvres (default: straight and level flight at constant speed).
    tanker_motion: TankerMotion = field(default_factory=TankerMotion)

    def __post_init__(self) -> None:
        # the segments' timeline depends on the airspeed they start from (a speed change's length)
        self.tanker_motion.ramps(self.flight.airspeed_m_s)

    def replace(self, **sections: Mapping[str, Any]) -> "Params":
        """Return a copy with fields overridden, e.g. ``p.replace(flight={"airspeed_m_s": 200})``."""
        return params_from_dict(sections, base=self)

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """``{section: {field: value}}`` of every field, tuples as lists (TOML/JSON-ready); the
        ``tanker_motion`` only when the tanker manoeuvres (straight and level flight, the default,
        is what a parameter set without it means, so level runs record what they always did)."""
        return {name: getattr(self, name).to_dict() for name in SECTIONS
                if not (name == "tanker_motion" and self.tanker_motion == TankerMotion())}


#: The paper's case (Table 1, 16 m hose in 20 links, 150 m/s, 8000 m): the one definition.
PAPER = Params()

#: Named turbulence intensities are resolved by hosedrogue.environment.turbulence.
TURBULENCE_PRESET_KEY = "intensity"


def params_from_dict(data: Mapping[str, Any], base: Params = PAPER) -> Params:
    """Override ``base`` with a nested mapping ``{section: {field: value}}``.

    Unknown sections and fields are errors. ``wake = false`` / ``turbulence = true`` are short for
    ``[wake] enabled = false`` / ``[turbulence] enabled = true``. ``turbulence.intensity`` may name a standard
    intensity ("light", "moderate", "severe") that sets ``sigma_m_s`` from the altitude.

    Parameters
    ----------
    data : Mapping
        ``{section: {field: value}}`` with sections among ``SECTIONS`` (``"hose"``, ``"flight"``,
        ...) and fields in the units their names carry (``length_m`` [m], ``airspeed_m_s``
        [m/s], ...); a section may be missing (kept from ``base``), and ``wake`` or
        ``turbulence`` may be a bool (its ``enabled``).
    base : Params, optional
        The parameters overridden; default :data:`PAPER`, the paper's case.

    Returns
    -------
    Params
        ``base`` with the given fields replaced, every section validated again.

    Raises
    ------
    ParameterError
        One line naming the field if a section or field is unknown, a value has the wrong type
        or is outside its range, a cross-field check fails (inner diameter not smaller than the
        outer one, a gust record too long), or both ``intensity`` and ``sigma_m_s`` are given.
    """
    if not isinstance(data, Mapping):
        raise ParameterError(f"parameters = {data!r}: must be a table of sections")
    sections = {}
    for name, cls in SECTIONS.items():
        current = getattr(base, name)
        overrides = data.get(name, {})
        if isinstance(overrides, bool) and name in ("wake", "turbulence"):
            overrides = {"enabled": overrides}  # shorthand: `wake = false`
        if not isinstance(overrides, Mapping):
            raise ParameterError(f"{name} = {overrides!r}: must be a table of fields")
        if not overrides:
            # the base's section as it is: frozen and validated when it was made, so building it
            # again from its own values would give an equal object (a campaign's per-run seed
            # override validated all eight sections again: about 0.3 ms of a 20 ms docking run)
            sections[name] = current
            continue
        overrides = dict(overrides)
        if name == "turbulence" and TURBULENCE_PRESET_KEY in overrides:
            level = overrides.pop(TURBULENCE_PRESET_KEY)
            if "sigma_m_s" in overrides:
                raise ParameterError(
                    f"turbulence.intensity = {level!r}: give either intensity or sigma_m_s, not both"
                )
            altitude = data.get("flight", {}).get("altitude_m", base.flight.altitude_m)
            overrides["sigma_m_s"] = standard_intensity(level, altitude)
        known = {f.name for f in dataclasses.fields(cls)}
        for key in overrides:
            if key not in known:
                allowed = ", ".join(sorted(known | ({TURBULENCE_PRESET_KEY} if name == "turbulence" else set())))
                raise ParameterError(f"{name}.{key}: unknown field; allowed: {allowed}")
        values = {f.name: overrides.get(f.name, getattr(current, f.name)) for f in dataclasses.fields(cls)}
        sections[name] = cls(**values)
    for name in data:
        if name not in SECTIONS:
            raise ParameterError(f"{name}: unknown section; allowed: {', '.join(SECTIONS)}")
    return Params(**sections)


# the run sections of the control loop live with the other run sections; re-exported here
from .sections import Actuator, Sensor  # noqa: E402,F401
