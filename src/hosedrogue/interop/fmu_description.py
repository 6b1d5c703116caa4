"""The parts of an FMU's ``modelDescription.xml`` and documentation that pythonfmu does not write.

pythonfmu writes the variables (names, causality, variability, start values) and the outputs of
``<ModelStructure>``. :func:`complete_model_description` adds, from the FMU's
:class:`~hosedrogue.interop.fmu_interface.FmuInterface`, what FMI 2.0 and strict importers expect
beyond that: the unit of every variable that has one and their ``<UnitDefinitions>`` (SI base-unit
exponents from :mod:`hosedrogue.units`), ``<InitialUnknowns>``, the ``dependencies`` of the
outputs and initial unknowns, and a description of the host the FMU needs.
:func:`documentation_html` writes the FMU's ``documentation/index.html`` from the same table.
"""

from __future__ import annotations

import html
from xml.etree.ElementTree import Element, SubElement

from ..units import UNITS
from ..version import __version__
from .fmu_interface import FmuInterface, host_requirements

#: Elements of ``fmiModelDescription`` in the order of the FMI 2.0 schema.
_SCHEMA_ORDER = ("ModelExchange", "CoSimulation", "UnitDefinitions", "TypeDefinitions", "LogCategories",
                 "DefaultExperiment", "VendorAnnotations", "ModelVariables", "ModelStructure")


def model_description_text(interface: FmuInterface, details: str = "") -> str:
    """The ``description`` attribute of an FMU's model description: what it is and what it needs.

    Parameters
    ----------
    interface : FmuInterface
        The FMU's interface.
    details : str
        What this export froze, one sentence (the engagement FMU's scenario), or "".

    Returns
    -------
    str
        One paragraph.
    """
    frozen = f" {details}." if details else ""
    return (f"{interface.summary}.{frozen} {host_requirements()} Documentation: documentation/index.html in "
            "the FMU.")


def _dependencies(interface: FmuInterface, names) -> str:
    """FMI ``dependencies``: the indices of ``names``, ascending, space separated ("" for none)."""
    return " ".join(str(i) for i in sorted(interface.index(n) for n in names))


def _unit_definitions(symbols) -> Element:
    """``<UnitDefinitions>`` of the unit symbols, in the order of :data:`hosedrogue.units.UNITS`."""
    units = Element("UnitDefinitions")
    for symbol in (s for s in UNITS if s in symbols):
        unit = SubElement(units, "Unit", {"name": symbol})
        SubElement(unit, "BaseUnit", UNITS[symbol].base_unit())
    return units


def _model_structure(root: Element, interface: FmuInterface) -> None:
    """Replace ``<ModelStructure>`` by the outputs and initial unknowns with their dependencies."""
    old = root.find("ModelStructure")
    if old is not None:
        root.remove(old)
    structure = SubElement(root, "ModelStructure")
    outputs = interface.of("output")
    if outputs:
        node = SubElement(structure, "Outputs")
        for v in outputs:
            SubElement(node, "Unknown", {"index": str(interface.index(v.name)),
                                         "dependencies": _dependencies(interface, v.depends_on)})
        # FMI 2.0: every output with initial="calculated" (as the slave registers them) is an initial unknown
        node = SubElement(structure, "InitialUnknowns")
        for v in outputs:
            SubElement(node, "Unknown", {"index": str(interface.index(v.name)),
                                         "dependencies": _dependencies(interface, v.initial_depends_on)})


def complete_model_description(root: Element, interface: FmuInterface, generation_tool: str,
                               details: str = "") -> Element:
    """Complete pythonfmu's model description of an FMU of ``interface`` (FMI 2.0 co-simulation).

    Adds the units and their definitions, the output and initial-unknown dependencies and the
    host description; the variables themselves are pythonfmu's, registered from the same table.

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The ``fmiModelDescription`` element pythonfmu built (changed in place).
    interface : FmuInterface
        The FMU's interface, in the order its variables were registered.
    generation_tool : str
        The ``generationTool`` attribute, e.g. ``"hosedrogue 0.1.0 (PythonFMU 0.7.0)"``.
    details : str
        What this export froze (:func:`model_description_text`).

    Returns
    -------
    xml.etree.ElementTree.Element
        ``root``.

    Raises
    ------
    ValueError
        If the registered variables are not the interface's, in its order.
    """
    scalars = root.find("ModelVariables").findall("ScalarVariable")
    registered = [sv.get("name") for sv in scalars]
    if registered != [v.name for v in interface.variables]:
        raise ValueError(f"{interface.kind}: registered variables {registered} are not the interface's")
    symbols = set()
    for sv, v in zip(scalars, interface.variables):
        if v.unit is not None:
            sv.find("Real").set("unit", v.unit)
            symbols.add(v.unit)
    _model_structure(root, interface)
    if symbols:
        root.insert(_position(root, "UnitDefinitions"), _unit_definitions(symbols))
    root.set("description", model_description_text(interface, details))
    root.set("generationTool", generation_tool)
    return root


def _position(root: Element, tag: str) -> int:
    """Where a new child ``tag`` goes among ``root``'s children, by the schema's order."""
    rank = _SCHEMA_ORDER.index(tag)
    children = list(root)
    for i, child in enumerate(children):
        if child.tag in _SCHEMA_ORDER and _SCHEMA_ORDER.index(child.tag) > rank:
            return i
    return len(children)


def documentation_html(interface: FmuInterface, starts: dict, details: str = "") -> str:
    """The FMU's ``documentation/index.html``: what it simulates, what the host needs, its variables.

    Parameters
    ----------
    interface : FmuInterface
        The FMU's interface.
    starts : dict
        Start value of each parameter and input, by name (in the unit of its name).
    details : str
        What this export froze (:func:`model_description_text`), or "".

    Returns
    -------
    str
        A self-contained HTML page.
    """
    def cell(text) -> str:
        return f"<td>{html.escape(str(text))}</td>"

    rows = []
    for v in interface.variables:
        deps = ", ".join(v.depends_on) if v.causality == "output" else ""
        rows.append("<tr>" + cell(v.name) + cell(v.causality) + cell(v.unit or "-")
                    + cell(starts.get(v.name, "calculated")) + cell(deps or "-") + cell(v.description) + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in ("variable", "causality", "unit", "start", "direct feedthrough from",
                                             "meaning"))
    return (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(interface.model_name)}"
            f"</title></head><body>\n<h1>{html.escape(interface.model_name)} ({html.escape(interface.kind)} FMU, "
            f"hosedrogue {html.escape(__version__)})</h1>\n<p>{html.escape(interface.summary)}.</p>\n"
            + (f"<p>{html.escape(details)}.</p>\n" if details else "") +
            f"<h2>Host</h2>\n<p>{html.escape(host_requirements())}</p>\n"
            f"<h2>Variables</h2>\n<table border=\"1\">\n<tr>{head}</tr>\n" + "\n".join(rows) + "\n</table>\n"
            f"<h2>Behaviour</h2>\n<p>{html.escape(interface.notes)}</p>\n</body></html>\n")
