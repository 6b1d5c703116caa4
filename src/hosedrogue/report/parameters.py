"""Report section "Table 1 as used": every parameter of the paper's case, its unit and source."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..spec.params import PAPER, SECTIONS, Params
from .markup import fmt, html_table

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["ParametersResult", "build", "parameter_sources"]


@dataclass(frozen=True)
class ParametersResult:
    """Derived hose quantities that later sections quote.

    Parameters
    ----------
    link_length_m : float
        Length of one link [m].
    link_mass_kg : float
        Mass of one link, mu l [kg].
    area_moment_m4 : float
        Area moment of the hose cross-section, pi (d_o^4 - d_i^4) / 64 [m^4].
    bending_stiffness_n_m2 : float
        E I [N m^2].
    """

    link_length_m: float
    link_mass_kg: float
    area_moment_m4: float
    bending_stiffness_n_m2: float


def parameter_sources(p: Params = PAPER) -> dict[str, str]:
    """Where each parameter of the paper's case comes from (paper Table 1 unless stated).

    Parameters
    ----------
    p : Params
        The paper's preset (its values are quoted where the source names them).

    Returns
    -------
    dict
        ``"section.field"`` -> source text; fields not listed come from the project.
    """
    h, tb, fl = p.hose, p.turbulence, p.flight
    return {
        "tanker.mass_kg": "Table 1",
        "tanker.span_m": "Table 1",
        "hose.length_m": f"Table 1 row 'Length/m {h.length_m:g}', read as the hose length (the text never states it)",
        "hose.links": f"Sec. 2.3.2: 'the hose is apart into {h.links} segments' ({h.link_length_m:g} m each)",
        "hose.inner_diameter_m": "Table 1",
        "hose.outer_diameter_m": "Table 1",
        "hose.mass_per_length_kg_m": "Table 1",
        "hose.elastic_modulus_pa": f"Table 1 ({h.elastic_modulus_pa / 1e6:g} MPa)",
        "hose.link_inertia_kg_m2": f"Table 1 ({h.link_inertia_kg_m2:g} = mu l * l: probably a slip, see below)",
        "hose.link_inertia": "option: 'paper' uses Table 1's value (default), 'rod' m l^2/12",
        "hose.bending": "option: 'paper' = Eq. 20 equivalent joint force (default), 'moment', 'off'",
        "hose.normal_drag_coefficient": "Table 1 (c_n,k)",
        "hose.tangential_drag_coefficient": "Table 1 (c_t,k)",
        "drogue.mass_kg": "Table 1",
        "drogue.diameter_m": "Table 1",
        "drogue.inertia_kg_m2": "Table 1",
        "drogue.drag_coefficient": "Table 1 (c_dro)",
        "flight.altitude_m": f"Sec. 2.3.3 and Fig. 12 ({fl.altitude_m:g} m)",
        "flight.airspeed_m_s": f"Fig. 12 ({fl.airspeed_m_s:g} m/s)",
        "flight.density_scale": "project: 1 = ICAO standard atmosphere",
        "wake.enabled": "Sec. 2.2.3 (Hallock-Burnham wake, refs 22-23)",
        "wake.tow_point_y_over_span": "Sec. 2.3.2: tow point at the right wing's mid-span",
        "wake.vortex_spacing_over_span": "elliptic loading, b0 = pi b / 4 (not stated in the paper)",
        "wake.core_radius_over_span": "project reading: r_c = 0.035 b (not stated in the paper)",
        "wake.vertical_offset_m": "project reading: vortices at the tow point's height",
        "turbulence.enabled": "off in the preset; on in the turbulence scenarios (Sec. 2.3.3)",
        "turbulence.model": "Dryden (ref 24); MIL-F-8785C forming filters (project choice)",
        "turbulence.sigma_m_s": f"Sec. 2.3.3: isotropic, {tb.sigma_m_s[0]:g} m/s",
        "turbulence.scale_length_m": f"Sec. 2.3.3: {tb.scale_length_m[0]:g} m",
        "turbulence.start_s": f"Sec. 2.3.3: on at t = {tb.start_s:g} s",
        "turbulence.duration_s": f"Sec. 2.3.3: for {tb.duration_s:g} s",
        "turbulence.distribution": "project: the whole hose sees the tow point's gust (as the paper)",
        "turbulence.sample_time_s": "project: gust record interval, independent of the RK4 step",
        "turbulence.seed": "project: the paper's realisation cannot be reproduced",
        "numerics.integrator": "Sec. 2.3.1: fixed-step 4th-order Runge-Kutta",
        "numerics.step_s": "project: shown converged below",
        "numerics.output_every": "project: thins the saved output (every n-th step)",
        "numerics.rtol": "project: adaptive integrator (cross-checks only)",
        "numerics.atol": "project: adaptive integrator (cross-checks only)",
        "numerics.max_yaw_deg": "project: stop before the angle coordinates become singular",
    }


def _hose_properties(p: Params) -> ParametersResult:
    """Link length and mass, bending stiffness E I as the model uses it (Eqs. 20-21) and the area
    moment I it implies."""
    from ..model import layout as LY
    from ..model.system import HoseModel

    hose = p.hose
    l = hose.link_length_m
    model = HoseModel(p.replace(turbulence={"enabled": False}))  # no gust record needed
    bending_stiffness = float(model.ps[LY.PS_EI])
    return ParametersResult(link_length_m=l, link_mass_kg=hose.mass_per_length_kg_m * l,
                            area_moment_m4=bending_stiffness / hose.elastic_modulus_pa,
                            bending_stiffness_n_m2=bending_stiffness)


def _rows(p: Params, d: ParametersResult) -> list[dict]:
    """One row per parameter, then the derived quantities."""
    sources = parameter_sources(p)
    rows = []
    for section, values in p.to_dict().items():
        units = {f.name: f.metadata.get("unit", "") for f in dataclasses.fields(SECTIONS[section])}
        for name, value in values.items():
            key = f"{section}.{name}"
            rows.append(dict(parameter=key, value=value if not isinstance(value, list) else " ".join(f"{v:g}" for v in value),
                             unit=units.get(name, "") or "-", source=sources.get(key, "project")))
    l, m_link = d.link_length_m, d.link_mass_kg
    li = f"{p.hose.link_inertia_kg_m2:g}"
    return rows + [
        dict(parameter="derived: link length l", value=l, unit="m", source="length / links"),
        dict(parameter="derived: link mass mu l", value=m_link, unit="kg", source="Table 1"),
        dict(parameter="derived: area moment I = pi (d_o^4 - d_i^4) / 64", value=d.area_moment_m4, unit="m^4", source="Eq. 21"),
        dict(parameter="derived: bending stiffness E I", value=d.bending_stiffness_n_m2, unit="N m^2", source="Eqs. 20-21"),
        dict(parameter=f"derived: mu l * l (compare Table 1's {li})", value=m_link * l, unit="kg m^2", source="docs/model.md §2"),
        dict(parameter="derived: slender-rod inertia m l^2 / 12", value=m_link * l * l / 12.0, unit="kg m^2", source="option 'rod'"),
    ]


def _html(p: Params, rows: list[dict]) -> str:
    hose = p.hose
    body = [(r["parameter"], fmt(r["value"]) if isinstance(r["value"], (int, float)) and not isinstance(r["value"], bool)
             else r["value"], r["unit"], r["source"]) for r in rows]
    return (
        '<section id="table1"><h2>Table 1 as used: parameters</h2>'
        "<p>Every parameter of the paper's case (<code>hosedrogue.spec.params.PAPER</code>), its unit and "
        "where it comes from. The hose length is not stated in the paper's text; the row "
        f"'Length/m {hose.length_m:g}' of Table 1 is read as the hose length: {hose.length_m:g} m in "
        f"{hose.links} links of {hose.link_length_m:g} m, which is consistent with the link inertia "
        f"({hose.link_inertia_kg_m2:g} kg m<sup>2</sup> = &mu; l &middot; l for l = {hose.link_length_m:g} m).</p>"
        + html_table(["parameter", "value", "unit", "source"], body, table_id="table-parameters")
        + '<p class=data>Data: <a href="table1_parameters.csv">table1_parameters.csv</a>.</p></section>'
    )


def build(out: ReportFolder, settings: ReportSettings) -> ParametersResult:
    """Write ``table1_parameters.csv`` and the Table 1 section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Build settings (unused: the table does not depend on them).

    Returns
    -------
    ParametersResult
        Derived hose quantities.
    """
    import pandas as pd

    derived = _hose_properties(PAPER)
    rows = _rows(PAPER, derived)
    out.csv(pd.DataFrame(rows, columns=["parameter", "value", "unit", "source"]), "table1_parameters.csv")
    out.section("table1", "Table 1", _html(PAPER, rows))
    out.record("parameters", {"hose_length_m": PAPER.hose.length_m, "links": PAPER.hose.links,
                              "link_length_m": derived.link_length_m,
                              "bending_stiffness_n_m2": derived.bending_stiffness_n_m2})
    return derived
