"""Every parameter of every public function and class is documented (numpydoc).

In the spirit of python-control's docstring test: walk the package, and for each public function
and class defined in a public module check that every parameter of its signature appears in the
``Parameters`` section of its docstring (for a class: the class's or ``__init__``'s docstring;
a dataclass field may instead carry a ``#:`` comment, which the API reference shows too).
Parameters must state their units in words or brackets; this test checks their presence only.
"""

import dataclasses
import importlib
import inspect
import pkgutil
import re

import pytest

import hosedrogue

#: Modules still to be documented, exempt until then: each is being restructured by other work
#: (or is outside this change), so its docstrings are written where it ends up. Remove a line once
#: its module passes; a module that passes while listed fails the test (keeps the list short).
UNDOCUMENTED: set[str] = set()

#: Optional dependencies some modules import; without them the module is skipped, not failed.
OPTIONAL = {"pythonfmu"}

_SECTION = re.compile(r"^([A-Z][A-Za-z ]+)\n-{3,}\s*$", re.M)


def public_modules() -> list[str]:
    names = [hosedrogue.__name__]
    for info in pkgutil.walk_packages(hosedrogue.__path__, prefix="hosedrogue."):
        parts = info.name.split(".")
        if not any(p.startswith("_") for p in parts[1:]):
            names.append(info.name)
    return sorted(names)


def documented_parameters(doc: str | None) -> set[str]:
    """Names listed in the Parameters (and Other Parameters) sections of a numpydoc docstring."""
    if not doc:
        return set()
    text = inspect.cleandoc(doc)
    heads = list(_SECTION.finditer(text))
    names: set[str] = set()
    for k, head in enumerate(heads):
        if head.group(1).strip() not in ("Parameters", "Other Parameters", "Attributes"):
            continue
        end = heads[k + 1].start() if k + 1 < len(heads) else len(text)
        for line in text[head.end():end].splitlines():
            if line and not line[0].isspace():
                left = line.split(" : ")[0].strip()
                names.update(n.strip().lstrip("*") for n in left.split(","))
    return names


def field_comments(cls) -> set[str]:
    """Dataclass fields documented by a ``#:`` comment on or above their line (in the class or a
    dataclass it derives from)."""
    found = set()
    for base in cls.__mro__[1:]:
        if dataclasses.is_dataclass(base):
            found |= field_comments(base)
    try:
        lines = inspect.getsource(cls).splitlines()
    except (OSError, TypeError):
        return found
    for i, line in enumerate(lines):
        m = re.match(r"\s*(\w+)\s*:", line)
        if m and ("#:" in line or (i and lines[i - 1].strip().startswith("#:"))):
            found.add(m.group(1))
    return found


def signature_parameters(obj) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.name not in ("self", "cls")]


def undocumented(module) -> list[str]:
    """``name(param)`` for every undocumented parameter of the module's public functions and classes."""
    missing = []
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isclass(obj):
            if issubclass(obj, BaseException) and obj.__init__ is BaseException.__init__:
                continue
            init = obj.__dict__.get("__init__")
            params = signature_parameters(obj) if init is not None or dataclasses.is_dataclass(obj) else []
            known = documented_parameters(obj.__doc__) | documented_parameters(getattr(init, "__doc__", None))
            if dataclasses.is_dataclass(obj):
                known |= field_comments(obj)
        elif inspect.isfunction(obj):
            params = signature_parameters(obj)
            known = documented_parameters(obj.__doc__)
        else:
            continue
        missing += [f"{name}({p})" for p in params if p not in known]
    return missing


@pytest.mark.parametrize("name", public_modules())
def test_public_parameters_are_documented(name):
    try:
        module = importlib.import_module(name)
    except ImportError as exc:
        if exc.name in OPTIONAL:
            pytest.skip(f"needs {exc.name}")
        raise
    missing = undocumented(module)
    if name in UNDOCUMENTED:
        assert missing, f"{name} is documented now: remove it from UNDOCUMENTED"
        return
    assert not missing, f"{name}: parameters without documentation: {', '.join(missing)}"


def test_the_checker_sees_a_missing_parameter():
    def documented(a, b):
        """Add.

        Parameters
        ----------
        a, b : float
            Terms [m].
        """

    def half(a, b):
        """Add.

        Parameters
        ----------
        a : float
            Term [m].
        """

    def none(a):
        """Add."""

    for fn, expected in ((documented, set()), (half, {"b"}), (none, {"a"})):
        assert set(signature_parameters(fn)) - documented_parameters(fn.__doc__) == expected
