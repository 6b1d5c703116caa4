"""Validated, immutable sections: the field metadata and the validator every section shares.

A *section* is a frozen dataclass whose fields carry metadata (kind, range, unit) made by the
helpers below (reals, integers, choices, flags, 3-vectors, text, option tables and entry points
naming Python code); :class:`Section` validates every field at construction, so a bad value raises a
one-line :class:`~hosedrogue.errors.ParameterError` naming the field, the value and what is
allowed. The model's sections (:mod:`hosedrogue.spec.params`) and the run's sections
(:mod:`hosedrogue.spec.sections`: actuator, sensor, reel, probe, bow wave, pilot) are built on it,
and so is the scenario reference of the documentation (every field with its unit, default,
range and meaning: :func:`field_table`).
"""

from __future__ import annotations

import ast
import dataclasses
import inspect
import math
import re
import textwrap
from typing import Any, Mapping

from ..errors import ParameterError

INF = math.inf


def real(lo: float, hi: float = INF, *, lo_open: bool = True, hi_open: bool = False, unit: str = "",
         inf_ok: bool | str = False, optional: bool = False) -> dict:
    """Metadata of a real-valued field in the range (lo, hi] (openness selectable).

    Parameters
    ----------
    lo, hi : float
        Bounds of the allowed range, in the field's unit.
    lo_open, hi_open : bool
        Whether the bound itself is excluded.
    unit : str
        The field's unit ("m", "m/s", "N", ...; "" for none).
    inf_ok : bool or str
        Whether ``inf`` is allowed (as "no limit", or what the string says it means); then ``hi``
        must be ``inf``. ``None`` (``null`` in a strict JSON file the package wrote) reads as ``inf``.
    optional : bool
        Whether the field may be left out (``None``: its meaning is the section's to say, e.g.
        "unchanged"); a scenario file then simply omits the key.

    Returns
    -------
    dict
        The field's metadata.
    """
    meta = {"kind": "float", "lo": lo, "hi": hi, "lo_open": lo_open, "hi_open": hi_open, "unit": unit,
            "inf_ok": inf_ok}
    if optional:
        meta["optional"] = True
    return meta


def integer(lo: int, hi: int, unit: str = "") -> dict:
    """Metadata of an integer field in [lo, hi].

    Parameters
    ----------
    lo, hi : int
        Inclusive bounds.
    unit : str
        The field's unit ("" for a count).

    Returns
    -------
    dict
    """
    return {"kind": "int", "lo": lo, "hi": hi, "unit": unit}


def choice(*choices: str) -> dict:
    """Metadata of a field that takes one of the given strings.

    Parameters
    ----------
    *choices : str
        The allowed values.

    Returns
    -------
    dict
    """
    return {"kind": "choice", "choices": choices}


def flag() -> dict:
    """Metadata of a boolean field (``true`` or ``false`` in TOML).

    Returns
    -------
    dict
    """
    return {"kind": "bool"}


def vec3(lo: float, hi: float = INF, *, lo_open: bool = False, unit: str = "",
         labels: tuple = ("u", "v", "w")) -> dict:
    """Metadata of a field of three reals (one number means the same three), each in [lo, hi].

    Parameters
    ----------
    lo, hi : float
        Bounds of each component, in the field's unit.
    lo_open : bool
        Whether ``lo`` itself is excluded.
    unit : str
        The components' unit.
    labels : tuple of str
        What the three components are, for the messages and the reference (default the gust
        axes u, v, w).

    Returns
    -------
    dict
    """
    return {"kind": "vec3", "lo": lo, "hi": hi, "lo_open": lo_open, "hi_open": False, "unit": unit,
            "labels": tuple(labels)}


def records(section: type) -> dict:
    """Metadata of a field holding a list of sub-tables, each a ``section`` (a scenario file's
    ``[[table.field]]`` array of tables); validated item by item, held as a tuple of sections.

    Parameters
    ----------
    section : type
        The :class:`Section` class of one item.

    Returns
    -------
    dict
    """
    return {"kind": "records", "section": section}


def text() -> dict:
    """Metadata of a free-text field (a name, a Python entry point ``"package.module:factory"``).

    Returns
    -------
    dict
    """
    return {"kind": "str"}


def table() -> dict:
    """Metadata of a field that holds a table of keyword options (``[reel.options]``), passed as
    they are to a user's factory (:func:`entry`); a mapping with string keys.

    Returns
    -------
    dict
    """
    return {"kind": "table"}


_DOTTED = r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*"
#: An entry point: ``"package.module:factory"`` (dotted module path, a colon, a dotted attribute path).
ENTRY_PATTERN = re.compile(f"^{_DOTTED}:{_DOTTED}$")
#: An entry point in a file: ``"path/to/file.py:factory"`` (a scenario file's relative path is
#: relative to its folder); the file is imported by its path, never evaluated as text.
FILE_ENTRY_PATTERN = re.compile(f"^(?P<path>[^:]*[^:/\\\\]\\.py):{_DOTTED}$")


def entry() -> dict:
    """Metadata of a field naming Python code: ``"package.module:factory"`` in a file, or (from
    Python) the factory itself; "" for none. Only its form is checked here: the code is imported
    by that name when the run starts (:mod:`hosedrogue.controllers.sampled`).

    Returns
    -------
    dict
    """
    return {"kind": "entry"}


def describe(meta: Mapping[str, Any]) -> str:
    """What a field allows, as the error messages and the scenario reference say it.

    Parameters
    ----------
    meta : Mapping
        The field's metadata (from one of the helpers above).

    Returns
    -------
    str
        E.g. ``"a finite number in (0, 400] m/s"``, ``"one of 'aft', 'split'"``.
    """
    kind = meta["kind"]
    if kind == "int":
        return f"an integer in [{meta['lo']}, {meta['hi']}]"
    if kind == "bool":
        return "true or false"
    if kind == "choice":
        return "one of " + ", ".join(repr(c) for c in meta["choices"])
    if kind == "str":
        return "a string"
    if kind == "records":
        return f"a list of tables [[{meta['section']._section}]] (their keys: the rows {meta['section']._section}.*)"
    if kind == "table":
        return "a table of options (keyword arguments of the factory)"
    if kind == "entry":
        return 'an entry point "package.module:factory" (or, from Python, the factory itself)'
    lo, hi = meta["lo"], meta["hi"]
    left = "(" if meta.get("lo_open") else "["
    closed_inf = meta.get("inf_ok", False)
    right = ")" if (meta.get("hi_open") or (hi == INF and not closed_inf)) else "]"
    unit = f" {meta['unit']}" if meta.get("unit") else ""
    hi_s = "inf" if hi == INF else f"{hi:g}"
    what = "a number" if closed_inf else "a finite number"
    range_text = f"{what} in {left}{lo:g}, {hi_s}{right}{unit}"
    if closed_inf:
        range_text += f" (inf: {closed_inf if isinstance(closed_inf, str) else 'no limit'})"
    if meta.get("optional"):
        range_text += ", or left out"
    if kind == "vec3":
        return f"one number or a list of 3 numbers [{', '.join(meta.get('labels', ('u', 'v', 'w')))}], each {range_text}"
    return range_text


def _check_real(name: str, value: Any, meta: Mapping[str, Any]) -> float:
    if value is None and meta.get("inf_ok"):  # strict JSON (jsonio) writes inf as null
        return INF
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ParameterError(f"{name} = {value!r}: must be {describe({**meta, 'kind': 'float'})}")
    v = float(value)
    lo, hi = meta["lo"], meta["hi"]
    finite_ok = math.isfinite(v) or (meta.get("inf_ok") and v == INF)
    bad = (
        not finite_ok
        or (v <= lo if meta.get("lo_open") else v < lo)
        or (v >= hi if meta.get("hi_open") else v > hi)
    )
    if bad:
        raise ParameterError(f"{name} = {value!r}: must be {describe({**meta, 'kind': 'float'})}")
    return v


def validate_field(section: str, f: dataclasses.Field, value: Any) -> Any:
    """The checked value of field ``f`` of ``section``, or a one-line ParameterError.

    Parameters
    ----------
    section : str
        The section's name, for the message (``"hose"``).
    f : dataclasses.Field
        The field, with its metadata.
    value : Any
        The value given.

    Returns
    -------
    Any
        The value converted to its kind (a float, an int, a tuple of 3 floats, ...).
    """
    meta = f.metadata
    name = f"{section}.{f.name}"
    kind = meta["kind"]
    if kind == "float":
        if value is None and meta.get("optional"):
            return None
        return _check_real(name, value, meta)
    if kind == "records":
        return _check_records(name, value, meta["section"])
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int) or not meta["lo"] <= value <= meta["hi"]:
            raise ParameterError(f"{name} = {value!r}: must be {describe(meta)}")
        return int(value)
    if kind == "bool":
        if not isinstance(value, bool):
            raise ParameterError(f"{name} = {value!r}: must be true or false")
        return value
    if kind == "choice":
        if value not in meta["choices"]:
            raise ParameterError(f"{name} = {value!r}: must be {describe(meta)}")
        return value
    if kind == "str":
        if not isinstance(value, str):
            raise ParameterError(f"{name} = {value!r}: must be a string")
        return value
    if kind == "table":
        if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
            raise ParameterError(f"{name} = {value!r}: must be {describe(meta)}")
        return dict(value)
    if kind == "entry":
        return check_entry(name, value)
    if kind == "vec3":
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            value = (value, value, value)
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise ParameterError(f"{name} = {value!r}: must be {describe(meta)}")
        return tuple(_check_real(f"{name}[{i}]", v, meta) for i, v in enumerate(value))
    raise AssertionError(kind)  # pragma: no cover - metadata is defined in this module


def _check_records(name: str, value: Any, section: type) -> tuple:
    """``value`` (a list of sections or of tables of their fields) as a tuple of sections; an error
    in item i names it ``name[i]`` (counted from 0)."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (list, tuple)):
        raise ParameterError(f"{name} = {value!r}: must be a list of tables ([[{name}]])")
    items = []
    for i, item in enumerate(value):
        if isinstance(item, section):
            items.append(item)
            continue
        try:
            items.append(section.from_mapping(item))
        except ParameterError as exc:
            raise ParameterError(str(exc).replace(section._section, f"{name}[{i}]", 1)) from None
    return tuple(items)


def check_entry(name: str, value: Any) -> Any:
    """The checked value of an entry-point field: ``""``, a ``"package.module:factory"`` string,
    or a callable (the factory, given from Python).

    Parameters
    ----------
    name : str
        The field's name for the message (``"reel.entry"``).
    value : Any
        The value given.

    Returns
    -------
    str or callable

    Raises
    ------
    ParameterError
        Neither "" nor of the form ``package.module:factory`` nor callable.
    """
    if callable(value) or value == "":
        return value
    if not isinstance(value, str) or not (ENTRY_PATTERN.match(value) or FILE_ENTRY_PATTERN.match(value)):
        raise ParameterError(f'{name} = {value!r}: must be an entry point "package.module:factory" '
                             "(a module importable by that name, a colon, the factory's name) or "
                             '"path/to/file.py:factory" (a Python file, relative to the scenario file\'s folder)')
    return value


class Section:
    """Mixin of a frozen dataclass: validates every field at construction.

    Subclasses set ``_section`` (the TOML table's name) and may override
    :meth:`_check_consistency` for cross-field rules.
    """

    _section: str = ""

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            checked = validate_field(self._section, f, getattr(self, f.name))
            object.__setattr__(self, f.name, checked)
        self._check_consistency()

    def _check_consistency(self) -> None:
        """Cross-field checks; overridden where needed."""

    @classmethod
    def from_mapping(cls, data: Any, base: "Section | None" = None):
        """The section from a TOML table, fields not given taken from ``base`` (else the defaults).

        Parameters
        ----------
        data : Mapping
            ``{field: value}`` in the units of the field names.
        base : Section, optional
            The section whose values the table overrides.

        Returns
        -------
        Section
            A new, validated instance.

        Raises
        ------
        ParameterError
            ``data`` is not a table, names an unknown field, or a value is out of range.
        """
        if not isinstance(data, Mapping):
            raise ParameterError(f"{cls._section} = {data!r}: must be a table of fields ([{cls._section}])")
        known = [f.name for f in dataclasses.fields(cls)]
        for key in data:
            if key not in known:
                raise ParameterError(f"{cls._section}.{key}: unknown field; allowed: {', '.join(sorted(known))}")
        if base is None:
            return cls(**dict(data))
        return cls(**{name: data.get(name, getattr(base, name)) for name in known})

    def to_dict(self) -> dict[str, Any]:
        """``{field: value}``, tuples as lists, a list of sub-sections as a list of their tables, an
        optional field left out (None) omitted (TOML/JSON-ready).

        Returns
        -------
        dict
        """
        return {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)
                if getattr(self, f.name) is not None}


def _plain(v: Any) -> Any:
    if callable(v):
        return entry_name(v)
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if hasattr(v, "tolist") and not isinstance(v, (int, float, bool, str)):  # numpy arrays and scalars
        return v.tolist()
    if isinstance(v, Section):
        return v.to_dict()
    return [_plain(x) for x in v] if isinstance(v, (tuple, list)) else v


def entry_name(value: Any) -> str:
    """An entry point as text: the string itself, or ``"module:qualname"`` of a callable (how a
    factory given from Python is recorded in ``run.json``).

    Parameters
    ----------
    value : str or callable
        The entry.

    Returns
    -------
    str
    """
    if isinstance(value, str):
        return value
    module = getattr(value, "__module__", None) or type(value).__module__
    qualname = getattr(value, "__qualname__", None) or type(value).__qualname__
    return f"{module}:{qualname}"


def field_docs(cls: type) -> dict[str, str]:
    """The ``#:`` comment above each field of a section class (its meaning, as written in the code).

    Parameters
    ----------
    cls : type
        A section dataclass.

    Returns
    -------
    dict
        Field name -> its comment ("" when it has none), the lines joined by spaces.
    """
    try:
        source = textwrap.dedent(inspect.getsource(cls))
    except (OSError, TypeError):  # pragma: no cover - source not available (frozen application)
        return {f.name: "" for f in dataclasses.fields(cls)}
    lines = source.splitlines()
    docs = {}
    for node in ast.parse(source).body[0].body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            comment = []
            i = node.lineno - 2
            while i >= 0 and lines[i].strip().startswith("#:"):
                comment.insert(0, lines[i].strip()[2:].strip())
                i -= 1
            docs[node.target.id] = " ".join(comment)
    return {f.name: docs.get(f.name, "") for f in dataclasses.fields(cls)}


def field_table(cls: type) -> list[dict[str, Any]]:
    """Every field of a section: name, unit, default, what is allowed and its meaning.

    Parameters
    ----------
    cls : type
        A section dataclass (:class:`Section` subclass).

    Returns
    -------
    list of dict
        One dict per field in declaration order with keys ``name``, ``unit``, ``default``,
        ``allowed`` (:func:`describe`) and ``meaning`` (:func:`field_docs`).
    """
    docs = field_docs(cls)
    rows = []
    for f in dataclasses.fields(cls):
        default = f.default if f.default is not dataclasses.MISSING else f.default_factory()  # type: ignore[misc]
        rows.append({"name": f.name, "unit": f.metadata.get("unit", ""), "default": _plain(default),
                     "allowed": describe(f.metadata), "meaning": docs[f.name]})
    return rows
