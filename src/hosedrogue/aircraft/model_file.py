"""A receiver model from its file: mass properties, geometry, tables, coefficients and engine.

The file is TOML (docs/receiver.md, "Your own receiver"); the F-16 of Stevens, Lewis & Johnson is
the shipped example, ``hosedrogue/aircraft/data/f16.toml``, read by the name ``"f16"``. A file
declares its units in ``[units]`` (length ft or m, mass slug or kg, force lbf or N); this module
is the one place they are converted to SI, so everything after it works in SI (angles in the
tables and control deflections stay in degrees, as aerodynamic tables are written). Nothing in the
file is executed. Every error is a :class:`~hosedrogue.errors.ParameterError` naming the file, the
key, the value and what is allowed.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

import numpy as np

from ..constants import FT_TO_M, LBF_TO_N, SLUG_TO_KG
from ..errors import ParameterError
from .tables import Table, Term

#: Models shipped with the package, by name.
SHIPPED = {"f16": "f16.toml"}

#: The coefficients a model defines: body-axis forces and moments about the table reference.
COEFFICIENTS = ("CX", "CY", "CZ", "Cl", "Cm", "Cn")

#: Variables a table or a term may use: angles [deg], control deflections [deg], reduced rates [-].
VARIABLES = ("alpha", "beta", "elevator", "aileron", "rudder", "p_hat", "q_hat", "r_hat")

#: The control surfaces, in the order of the control vector after the throttle.
SURFACES = ("elevator", "aileron", "rudder")

ATMOSPHERES = ("stevens-lewis", "icao")

_UNITS = {"length": {"ft": FT_TO_M, "m": 1.0}, "mass": {"slug": SLUG_TO_KG, "kg": 1.0},
          "force": {"lbf": LBF_TO_N, "N": 1.0}}


@dataclass(frozen=True)
class Engine:
    """A table-driven engine with a power lag (the F-16's of Stevens, Lewis & Johnson, Appendix A.7).

    Thrust [N] acts along the body x axis through the centre of gravity. Tables are over
    ``("mach", "altitude")`` with altitude in metres.
    """

    idle: Table  #: thrust at idle [N]
    military: Table  #: thrust at military power [N]
    maximum: Table  #: thrust at maximum (afterburner) power [N]
    gearing: tuple[tuple[float, float, float, float], ...]  #: (throttle from, to, slope %, offset %)
    afterburner_threshold: float  #: power level [%] where the afterburner starts
    afterburner_rate: float  #: lag rate at or above the threshold [1/s]
    afterburner_entry: float  #: target [%] while crossing up
    afterburner_exit: float  #: target [%] while crossing down
    rate_points: tuple[tuple[float, float], ...]  #: (power difference %, rate 1/s) below the threshold


@dataclass(frozen=True)
class AircraftModel:
    """A receiver aircraft in SI units (read by :func:`load_model`)."""

    name: str  #: the model's name
    description: str  #: one line: what it is and where it comes from
    source: str  #: the file it was read from
    mass_kg: float  #: mass [kg]
    inertia_kg_m2: np.ndarray  #: (3, 3) inertia matrix about the centre of gravity, body axes [kg m^2]
    engine_momentum_kg_m2_s: float  #: engine angular momentum along body x [kg m^2/s]
    wing_area_m2: float  #: reference area [m^2]
    span_m: float  #: reference span [m]
    chord_m: float  #: mean aerodynamic chord [m]
    xcg_ref: float  #: moment reference of the tables, fraction of the chord [-]
    xcg: float  #: centre of gravity flown, fraction of the chord [-]
    atmosphere: str  #: "stevens-lewis" or "icao"
    limits_deg: dict  #: surface name to (low, high) deflection [deg]
    coefficients: dict  #: coefficient name to tuple of :class:`Term`
    engine: Engine  #: the engine

    def with_xcg(self, xcg: float) -> "AircraftModel":
        """The same aircraft with its centre of gravity at ``xcg`` (fraction of the chord).

        Parameters
        ----------
        xcg : float
            Centre of gravity [-], in [0, 1].

        Returns
        -------
        AircraftModel
        """
        if not (math.isfinite(xcg) and 0.0 <= xcg <= 1.0):
            raise ParameterError(f"xcg = {xcg!r}: must be a fraction of the chord in [0, 1]")
        return dataclasses.replace(self, xcg=float(xcg))


def load_model(model: str | Path = "f16") -> AircraftModel:
    """Read a receiver model: a shipped one by name (``"f16"``) or a TOML file by path.

    Parameters
    ----------
    model : str or Path
        ``"f16"`` or the path of a model file.

    Returns
    -------
    AircraftModel
    """
    if str(model) in SHIPPED:
        resource = files("hosedrogue.aircraft.data") / SHIPPED[str(model)]
        return _parse(tomllib.loads(resource.read_text(encoding="utf-8")), f"{model} ({SHIPPED[str(model)]})")
    path = Path(model)
    if not path.is_file():
        raise ParameterError(f"--model = {str(model)!r}: neither a shipped model ({', '.join(SHIPPED)}) nor a file")
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{path}: not a TOML file ({exc})") from None
    return _parse(doc, str(path))


class _Reader:
    """Typed access to the document with one-line errors naming the file and the key."""

    def __init__(self, doc: dict, where: str):
        self.doc, self.where = doc, where

    def fail(self, key: str, value, allowed: str):
        raise ParameterError(f"{self.where}: {key} = {value!r}: {allowed}")

    def section(self, key: str) -> dict:
        node = self.doc
        for part in key.split("."):
            node = node.get(part) if isinstance(node, dict) else None
            if not isinstance(node, dict):
                self.fail(key, node, "a table (section) is required")
        return node

    def number(self, sec: dict, key: str, name: str, positive: bool = False) -> float:
        v = sec.get(name)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
            self.fail(f"{key}.{name}", v, "a finite number" + (" > 0" if positive else "") + " is required")
        return float(v)

    def array(self, value, key: str, shape: tuple[int, ...]) -> np.ndarray:
        try:
            arr = np.array(value, dtype=float)
        except (TypeError, ValueError):
            self.fail(key, value, "an array of numbers is required")
        if arr.shape != shape or not np.all(np.isfinite(arr)):
            self.fail(key, f"shape {arr.shape}", f"finite numbers of shape {shape} (the table's axes) are required")
        return arr

    def axis(self, value, key: str) -> tuple[float, ...]:
        if not isinstance(value, list):
            self.fail(key, value, "a list of breakpoints is required")
        arr = self.array(value, key, (len(value),))
        if arr.size < 2 or np.any(np.diff(arr) <= 0):
            self.fail(key, value, "at least two strictly increasing breakpoints are required")
        return tuple(float(x) for x in arr)


def _parse(doc: dict, where: str) -> AircraftModel:
    r = _Reader(doc, where)
    units = r.section("units")
    scale = {}
    for kind, table in _UNITS.items():
        if units.get(kind) not in table:
            r.fail(f"units.{kind}", units.get(kind), f"one of {', '.join(table)}")
        scale[kind] = table[units[kind]]
    length, mass, force = scale["length"], scale["mass"], scale["force"]
    ms = r.section("mass")
    inertia = np.array([[r.number(ms, "mass", "jxx", True), 0.0, -r.number(ms, "mass", "jxz")],
                        [0.0, r.number(ms, "mass", "jyy", True), 0.0],
                        [-ms["jxz"], 0.0, r.number(ms, "mass", "jzz", True)]]) * mass * length**2
    if np.any(np.linalg.eigvalsh(inertia) <= 0):
        r.fail("mass.jxz", ms["jxz"], "the inertia matrix must be positive definite")
    geo = r.section("geometry")
    xcg = {k: r.number(geo, "geometry", k) for k in ("xcg_ref", "xcg")}
    atmosphere = r.section("atmosphere").get("model")
    if atmosphere not in ATMOSPHERES:
        r.fail("atmosphere.model", atmosphere, f"one of {', '.join(ATMOSPHERES)}")
    tables = _tables(r)
    return AircraftModel(
        name=str(doc.get("name", Path(where).stem)), description=str(doc.get("description", "")), source=where,
        mass_kg=r.number(ms, "mass", "mass", True) * mass, inertia_kg_m2=inertia,
        engine_momentum_kg_m2_s=r.number(ms, "mass", "engine_angular_momentum") * mass * length**2,
        wing_area_m2=r.number(geo, "geometry", "wing_area", True) * length**2,
        span_m=r.number(geo, "geometry", "span", True) * length,
        chord_m=r.number(geo, "geometry", "chord", True) * length,
        xcg_ref=xcg["xcg_ref"], xcg=xcg["xcg"], atmosphere=atmosphere, limits_deg=_limits(r),
        coefficients=_coefficients(r, tables), engine=_engine(r, length, force))


def _limits(r: _Reader) -> dict:
    sec = r.section("controls")
    out = {}
    for name in SURFACES:
        lim = sec.get(name)
        if not (isinstance(lim, list) and len(lim) == 2 and all(isinstance(v, (int, float)) for v in lim)
                and lim[0] < 0.0 < lim[1]):
            r.fail(f"controls.{name}", lim, "[low, high] in degrees with low < 0 < high is required")
        out[name] = (float(lim[0]), float(lim[1]))
    return out


def _tables(r: _Reader) -> dict[str, Table]:
    shared = r.doc.get("breakpoints", {})
    out = {}
    axes_seen: dict[tuple, tuple] = {}  # equal breakpoints as one object: a cell found once serves them all (tables.py)
    for name, spec in r.section("tables").items():
        key = f"tables.{name}"
        if not isinstance(spec, dict):
            r.fail(key, spec, "a table with axes and values is required")
        axes = spec.get("axes")
        if not (isinstance(axes, list) and 1 <= len(axes) <= 2 and all(a in VARIABLES for a in axes)):
            r.fail(f"{key}.axes", axes, f"one or two of {', '.join(VARIABLES)}")
        bps = []
        for a in axes:
            raw = spec.get(a, shared.get(a))
            if raw is None:
                r.fail(f"{key}.{a}", raw, f"breakpoints for axis {a!r} (here or in [breakpoints]) are required")
            bp = r.axis(raw, f"{key}.{a}")
            bps.append(axes_seen.setdefault(bp, bp))
        values = r.array(spec.get("values"), f"{key}.values", tuple(len(b) for b in bps))
        odd = spec.get("odd_in")
        if odd is not None and (odd not in axes or bps[axes.index(odd)][0] != 0.0):
            r.fail(f"{key}.odd_in", odd, "an axis of the table whose breakpoints start at 0")
        out[name] = Table(name, tuple(axes), tuple(bps), values, odd)
    return out


def _coefficients(r: _Reader, tables: dict[str, Table]) -> dict:
    sec = r.section("coefficients")
    out = {}
    for coef in COEFFICIENTS:
        terms = sec.get(coef)
        if not isinstance(terms, list) or not terms:
            r.fail(f"coefficients.{coef}", terms, "a list of terms {table, gain, times} is required")
        built = []
        for k, t in enumerate(terms):
            key = f"coefficients.{coef}[{k}]"
            if not isinstance(t, dict) or set(t) - {"table", "gain", "times"}:
                r.fail(key, t, "a term with the keys table, gain, times")
            if "table" in t and t["table"] not in tables:
                r.fail(f"{key}.table", t["table"], f"one of the tables {', '.join(sorted(tables))}")
            times = t.get("times", [])
            if not isinstance(times, list) or any(v not in VARIABLES for v in times):
                r.fail(f"{key}.times", times, f"a list of {', '.join(VARIABLES)}")
            gain = r.number(t, key, "gain") if "gain" in t else 1.0
            built.append(Term(tables.get(t.get("table")), gain, tuple(times)))
        out[coef] = tuple(built)
    extra = set(sec) - set(COEFFICIENTS)
    if extra:
        r.fail("coefficients", sorted(extra), f"only {', '.join(COEFFICIENTS)} are defined")
    return out


def _engine(r: _Reader, length: float, force: float) -> Engine:
    sec = r.section("engine")
    mach = r.axis(sec.get("mach"), "engine.mach")
    alt = tuple(a * length for a in r.axis(sec.get("altitude"), "engine.altitude"))
    thrust = {k: Table(k, ("mach", "altitude"), (mach, alt),
                       r.array(sec.get(k), f"engine.{k}", (len(mach), len(alt))) * force)
              for k in ("idle", "military", "maximum")}
    gearing = sec.get("gearing")
    try:
        pieces = tuple(tuple(float(v) for v in p) for p in gearing)
        ok = all(len(p) == 4 for p in pieces) and pieces[0][0] == 0.0 and pieces[-1][1] == 1.0 and all(
            a[1] == b[0] for a, b in zip(pieces, pieces[1:]))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        r.fail("engine.gearing", gearing, "[[throttle from, to, slope, offset], ...] covering 0 to 1 is required")
    points = r.array(sec.get("rate_points"), "engine.rate_points", (2, 2))
    if not (points[0, 0] < points[1, 0] and np.all(points[:, 1] > 0)):
        r.fail("engine.rate_points", sec.get("rate_points"), "two [difference %, rate 1/s] with increasing difference")
    return Engine(**thrust, gearing=pieces, rate_points=tuple(map(tuple, points.tolist())),
                  **{k: r.number(sec, "engine", k, k == "afterburner_rate") for k in
                     ("afterburner_threshold", "afterburner_rate", "afterburner_entry", "afterburner_exit")})
