"""Build the reproduction report (``hosedrogue reproduce``).

:func:`build_report` regenerates every result of Wu et al. (2018) Sec. 2.3 and 3 from this
project's model and writes, into one folder:

- ``index.html``: one self-contained page (inline CSS, no scripts, no external resources; the
  figures are ``<img>`` files beside it, referenced by relative paths);
- every figure as PNG and the data behind every figure and table as CSV (SI units in the column
  names);
- ``report.json``: the headline numbers (all finite) and the wall-clock time of each stage;
- ``anim_turbulence.gif``: the hose in turbulence with the controller off and on.

Nothing here tunes anything to the paper: the paper's numbers (:mod:`hosedrogue.paper`) are shown
beside this project's, with their ratio and a plain explanation of each large difference.

The work is split into stages (one progress-bar step each). Each stage computes its data,
writes its CSV and PNG files and returns what the page needs; the page is assembled at the end.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import html
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import __version__, paper
from ..params import PAPER, SECTIONS, Params

__all__ = ["ReportSettings", "FULL", "FAST", "build_report"]


# --- settings -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ReportSettings:
    """Grid sizes and run lengths of one report build (``FULL`` or ``FAST``)."""

    name: str
    sweep_altitudes_m: tuple  #: Fig. 3 altitudes [m]
    sweep_airspeeds_m_s: tuple  #: Fig. 3 airspeeds [m/s]
    run_duration_s: float | None  #: length of every turbulence run [s]; None: the scenario's own
    steps_s: tuple  #: RK4 steps of the step-convergence study [s]
    reference_step_s: float  #: reference step of that study [s]
    links_paper_bending: tuple  #: link counts with the paper's bending force
    links_consistent: tuple  #: link counts with bending off and with the "moment" option
    spread_seeds: int  #: turbulence realisations for the spread of the peak values
    sensitivity_altitudes_m: tuple  #: linearization conditions [m]
    sensitivity_airspeeds_m_s: tuple  #: linearization conditions [m/s]
    anim_fps: int  #: frames per second of simulated time in the GIF
    bode_points: int  #: frequency points of Fig. 7


FULL = ReportSettings(
    name="full",
    sweep_altitudes_m=(2000.0, 4000.0, 6000.0, 8000.0, 10000.0),
    sweep_airspeeds_m_s=tuple(float(v) for v in range(100, 251, 10)),
    run_duration_s=None,
    steps_s=(0.02, 0.01, 0.005, 0.0025),
    reference_step_s=0.000625,
    links_paper_bending=(5, 10, 20, 40, 80),
    links_consistent=(20, 40, 80, 160),
    spread_seeds=8,
    sensitivity_altitudes_m=(0.0, 2000.0, 5000.0, 8000.0, 10000.0),
    sensitivity_airspeeds_m_s=(100.0, 150.0, 200.0, 250.0),
    anim_fps=10,
    bode_points=600,
)

FAST = ReportSettings(
    name="fast",
    sweep_altitudes_m=(2000.0, 6000.0, 10000.0),
    sweep_airspeeds_m_s=(100.0, 150.0, 200.0, 250.0),
    run_duration_s=32.0,
    steps_s=(0.01, 0.005),
    reference_step_s=0.00125,
    links_paper_bending=(5, 10, 20, 40),
    links_consistent=(10, 20, 40),
    spread_seeds=2,
    sensitivity_altitudes_m=(0.0, 8000.0),
    sensitivity_airspeeds_m_s=(150.0, 250.0),
    anim_fps=4,
    bode_points=200,
)

#: The paper's turbulence cases at the four airspeeds of Fig. 4 [m/s].
FIG4_AIRSPEEDS_M_S = (100, 150, 200, 250)

#: A paper value and ours agree "closely" within this relative difference (ratio in [0.9, 1.1]):
#: the paper prints 3-4 significant digits and reads some values off figures.
CLOSE = 0.10

#: PNG resolution [dots per inch].
DPI = 110


# --- small helpers --------------------------------------------------------------------------------
def _fmt(x, digits: int = 4) -> str:
    """A number for the page: ``digits`` significant digits, scientific outside [1e-3, 1e5)."""
    if x is None:
        return "n/a"
    if isinstance(x, str):
        return x
    x = float(x)
    if not math.isfinite(x):
        return "n/a"
    if x == 0.0:
        return "0"
    if 1e-3 <= abs(x) < 1e5:
        return f"{x:.{digits}g}"
    return f"{x:.{digits - 1}e}"


def _ratio(ours: float, paper: float) -> float:
    return float(ours) / float(paper) if paper not in (0, 0.0) else float("nan")


def _esc(x) -> str:
    return html.escape(str(x))


def _html_table(headers, rows, table_id: str | None = None, caption: str | None = None) -> str:
    """An HTML table; cells are escaped unless given as ``("html", text)``."""
    def cell(v, tag):
        if isinstance(v, tuple) and len(v) == 2 and v[0] == "html":
            return f"<{tag}>{v[1]}</{tag}>"
        return f"<{tag}>{_esc(_fmt(v) if isinstance(v, (float, np.floating)) else v)}</{tag}>"

    tid = f' id="{table_id}"' if table_id else ""
    cap = f"<caption>{caption}</caption>" if caption else ""
    head = "".join(cell(h, "th") for h in headers)
    body = "".join("<tr>" + "".join(cell(v, "td") for v in r) + "</tr>" for r in rows)
    return f'<table{tid}>{cap}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'


def _finite_json(obj):
    """Convert numpy scalars/arrays to JSON types; non-finite numbers become None (the test
    of the report checks that none are left)."""
    if isinstance(obj, dict):
        return {str(k): _finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_finite_json(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj


class _Comparison:
    """Every paper number beside this project's: collected while the stages run."""

    def __init__(self):
        self.rows: list[dict] = []

    def add(self, section: str, quantity: str, unit: str, paper, ours: float, note: str) -> float:
        """``paper`` is a number or a (low, high) range. Returns the ratio ours/paper (for a
        range: 1 inside it, else ours over the nearer end)."""
        if isinstance(paper, tuple):
            lo, hi = paper
            ratio = 1.0 if lo <= ours <= hi else (ours / hi if ours > hi else ours / lo)
            paper_txt = f"{_fmt(lo)} to {_fmt(hi)}"
            ratio_txt = "inside range" if ratio == 1.0 else f"{_fmt(ratio, 3)} x nearer end"
        else:
            ratio = _ratio(ours, paper)
            paper_txt = _fmt(paper)
            ratio_txt = _fmt(ratio, 3)
        self.rows.append(dict(section=section, quantity=quantity, unit=unit, paper=paper_txt,
                              ours=float(ours), ratio=ratio, ratio_text=ratio_txt, note=note))
        return ratio

    def dataframe(self):
        import pandas as pd

        return pd.DataFrame(self.rows, columns=["section", "quantity", "unit", "paper", "ours", "ratio", "note"])


def _agrees(ratio: float, tol: float = CLOSE) -> bool:
    return math.isfinite(ratio) and abs(ratio - 1.0) <= tol


@dataclass
class _Out:
    """Files and page fragments produced so far."""

    dir: Path
    files: list[str] = field(default_factory=list)
    cmp: _Comparison = field(default_factory=_Comparison)
    sections: dict[str, str] = field(default_factory=dict)
    headline: dict[str, Any] = field(default_factory=dict)

    def figure(self, fig, name: str) -> str:
        from ..plotting.figures import save_figure

        save_figure(fig, self.dir / name, dpi=DPI)
        self.files.append(name)
        return name

    def csv(self, df, name: str) -> str:
        df.to_csv(self.dir / name, index=False, float_format="%.10g")
        self.files.append(name)
        return name


def _figure_html(fig_id: str, png: str, title: str, text: str, csvs: tuple[str, ...]) -> str:
    data = ", ".join(f'<a href="{_esc(c)}">{_esc(c)}</a>' for c in csvs)
    return (f'<figure id="{fig_id}"><img src="{_esc(png)}" alt="{_esc(title)}">'
            f"<figcaption><b>{_esc(title)}.</b> {text} <span class=data>Data: {data}.</span>"
            f"</figcaption></figure>")


def _turbulence_window(params: Params) -> tuple[float, float]:
    tb = params.turbulence
    return (tb.start_s, tb.start_s + tb.duration_s)


def _peaks(res) -> tuple[float, float]:
    """Peak |dy|, |dz| of the drogue from its balance position over the whole run [m]."""
    off = res.drogue_offset_m
    return float(np.max(np.abs(off[:, 1]))), float(np.max(np.abs(off[:, 2])))


def _rms_in(res, window) -> tuple[float, float]:
    m = (res.t_s >= window[0]) & (res.t_s < window[1])
    off = res.drogue_offset_m[m]
    return float(np.sqrt(np.mean(off[:, 1] ** 2))), float(np.sqrt(np.mean(off[:, 2] ** 2)))


def _force_peaks(res) -> tuple[float, float]:
    return float(np.max(np.abs(res.control_n[:, 0]))), float(np.max(np.abs(res.control_n[:, 1])))


def _run(name: str, settings: ReportSettings, seed: int | None = None):
    from ..runner import run_scenario
    from ..scenarios import load_scenario

    sc = load_scenario(name)
    if settings.run_duration_s is not None or seed is not None:
        sc = sc.with_overrides(duration_s=settings.run_duration_s, seed=seed)
    return sc, run_scenario(sc)


# --- stage: parameters and the readings of the paper ---------------------------------------------
#: Where each parameter comes from (paper Table 1 unless stated).
_SOURCES = {
    "tanker.mass_kg": "Table 1",
    "tanker.span_m": "Table 1",
    "hose.length_m": "Table 1 row 'Length/m 16', read as the hose length (the text never states it)",
    "hose.links": "Sec. 2.3.2: 'the hose is apart into 20 segments' (0.8 m each)",
    "hose.inner_diameter_m": "Table 1",
    "hose.outer_diameter_m": "Table 1",
    "hose.mass_per_length_kg_m": "Table 1",
    "hose.elastic_modulus_pa": "Table 1 (13.79 MPa)",
    "hose.link_inertia_kg_m2": "Table 1 (2.816 = mu l * l: probably a slip, see below)",
    "hose.link_inertia": "option: 'paper' uses Table 1's value (default), 'rod' m l^2/12",
    "hose.bending": "option: 'paper' = Eq. 20 equivalent joint force (default), 'moment', 'off'",
    "hose.normal_drag_coefficient": "Table 1 (c_n,k)",
    "hose.tangential_drag_coefficient": "Table 1 (c_t,k)",
    "drogue.mass_kg": "Table 1",
    "drogue.diameter_m": "Table 1",
    "drogue.inertia_kg_m2": "Table 1",
    "drogue.drag_coefficient": "Table 1 (c_dro)",
    "flight.altitude_m": "Sec. 2.3.3 and Fig. 12 (8000 m)",
    "flight.airspeed_m_s": "Fig. 12 (150 m/s)",
    "flight.density_scale": "project: 1 = ICAO standard atmosphere",
    "wake.enabled": "Sec. 2.2.3 (Hallock-Burnham wake, refs 22-23)",
    "wake.tow_point_y_over_span": "Sec. 2.3.2: tow point at the right wing's mid-span",
    "wake.vortex_spacing_over_span": "elliptic loading, b0 = pi b / 4 (not stated in the paper)",
    "wake.core_radius_over_span": "project reading: r_c = 0.035 b (not stated in the paper)",
    "wake.vertical_offset_m": "project reading: vortices at the tow point's height",
    "turbulence.enabled": "off in the preset; on in the turbulence scenarios (Sec. 2.3.3)",
    "turbulence.model": "Dryden (ref 24); MIL-F-8785C forming filters (project choice)",
    "turbulence.sigma_m_s": "Sec. 2.3.3: isotropic, 1.5 m/s",
    "turbulence.scale_length_m": "Sec. 2.3.3: 530 m",
    "turbulence.start_s": "Sec. 2.3.3: on at t = 10 s",
    "turbulence.duration_s": "Sec. 2.3.3: for 20 s",
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


def _stage_parameters(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    rows = []
    for section, values in PAPER.to_dict().items():
        units = {f.name: f.metadata.get("unit", "") for f in dataclasses.fields(SECTIONS[section])}
        for name, value in values.items():
            key = f"{section}.{name}"
            rows.append(dict(parameter=key, value=value if not isinstance(value, list) else " ".join(f"{v:g}" for v in value),
                             unit=units.get(name, "") or "-", source=_SOURCES.get(key, "project")))
    hose = PAPER.hose
    l = hose.link_length_m
    I_m4 = math.pi * (hose.outer_diameter_m**4 - hose.inner_diameter_m**4) / 64.0
    m_link = hose.mass_per_length_kg_m * l
    derived = [
        dict(parameter="derived: link length l", value=l, unit="m", source="length / links"),
        dict(parameter="derived: link mass mu l", value=m_link, unit="kg", source="Table 1"),
        dict(parameter="derived: area moment I = pi (d_o^4 - d_i^4) / 64", value=I_m4, unit="m^4", source="Eq. 21"),
        dict(parameter="derived: bending stiffness E I", value=hose.elastic_modulus_pa * I_m4, unit="N m^2", source="Eqs. 20-21"),
        dict(parameter="derived: mu l * l (compare Table 1's 2.816)", value=m_link * l, unit="kg m^2", source="MODEL.md 2"),
        dict(parameter="derived: slender-rod inertia m l^2 / 12", value=m_link * l * l / 12.0, unit="kg m^2", source="option 'rod'"),
    ]
    df = pd.DataFrame(rows + derived, columns=["parameter", "value", "unit", "source"])
    out.csv(df, "table1_parameters.csv")
    body = [(r["parameter"], _fmt(r["value"]) if isinstance(r["value"], (int, float)) and not isinstance(r["value"], bool)
             else r["value"], r["unit"], r["source"]) for r in rows + derived]
    out.sections["table1"] = (
        '<section id="table1"><h2>Table 1 as used: parameters</h2>'
        "<p>Every parameter of the paper's case (<code>hosedrogue.params.PAPER</code>), its unit and "
        "where it comes from. The hose length is not stated in the paper's text; the row "
        "'Length/m 16' of Table 1 is read as the hose length: 16 m in 20 links of 0.8 m, which is "
        "consistent with the link inertia (2.816 kg m<sup>2</sup> = &mu; l &middot; l for l = 0.8 m).</p>"
        + _html_table(["parameter", "value", "unit", "source"], body, table_id="table-parameters")
        + '<p class=data>Data: <a href="table1_parameters.csv">table1_parameters.csv</a>.</p></section>'
    )
    out.headline["parameters"] = {"hose_length_m": hose.length_m, "links": hose.links, "link_length_m": l,
                                  "bending_stiffness_n_m2": hose.elastic_modulus_pa * I_m4}


# --- stage: convergence ---------------------------------------------------------------------------
def _stage_convergence(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..analysis.convergence import STEP_CASES, link_convergence, step_convergence
    from ..plotting.figures import plot_convergence

    studies = [step_convergence(c, settings.steps_s, settings.reference_step_s) for c in STEP_CASES]
    link_studies = {
        "paper bending (Eq. 20)": link_convergence(settings.links_paper_bending),
        "bending off": link_convergence(settings.links_consistent, params=PAPER.replace(hose={"bending": "off"})),
        "bending 'moment'": link_convergence(settings.links_consistent, params=PAPER.replace(hose={"bending": "moment"})),
    }
    ctx["link_studies"] = link_studies
    rows = []
    for st in studies:
        order = np.concatenate([[np.nan], st.observed_order])
        for h, e, o in zip(st.steps_s, st.max_error_m, order):
            rows.append(dict(case=st.case, step_s=h, max_error_m=e, observed_order=o,
                             reference_step_s=st.reference_step_s, duration_s=st.duration_s))
    out.csv(pd.DataFrame(rows), "convergence_steps.csv")
    lrows = []
    for label, ls in link_studies.items():
        for k, n in enumerate(ls.links):
            x, y, z = ls.drogue_position_m[k]
            lrows.append(dict(bending=label, links=int(n), drogue_x_m=x, drogue_y_m=y, drogue_z_m=z,
                              lowest_lateral_rad_s=ls.lowest_lateral_rad_s[k],
                              lowest_vertical_rad_s=ls.lowest_vertical_rad_s[k]))
    out.csv(pd.DataFrame(lrows), "convergence_links.csv")
    fig = plot_convergence(studies, link_studies)
    out.figure(fig, "fig_convergence.png")

    h0 = PAPER.numerics.step_s
    at_default = {st.case: float(st.max_error_m[np.argmin(np.abs(st.steps_s - h0))]) for st in studies}
    worst = max(at_default.values())
    step_rows = [(st.case, *[f"{1000 * e:.3g}" for e in st.max_error_m],
                  " / ".join(f"{o:.2f}" for o in st.observed_order)) for st in studies]
    step_table = _html_table(["case", *[f"h = {h:g} s: error [mm]" for h in settings.steps_s], "observed order"],
                             step_rows, table_id="table-step-convergence")

    def zs(ls):
        return ls.drogue_position_m[:, 2]

    paper_ls = link_studies["paper bending (Eq. 20)"]
    off_ls = link_studies["bending off"]
    mom_ls = link_studies["bending 'moment'"]
    d_paper = np.abs(np.diff(zs(paper_ls)))
    d_off = np.abs(np.diff(zs(off_ls)))
    paper_converges = bool(d_paper[-1] < 0.7 * d_paper[0]) if d_paper.size > 1 else False
    off_converges = bool(np.all(d_off[1:] < 0.7 * d_off[:-1])) if d_off.size > 1 else False
    # first-order Richardson estimate of the continuum limit from the two finest bending-off runs
    n1, n2 = off_ls.links[-2], off_ls.links[-1]
    z_limit = float(zs(off_ls)[-1] + (zs(off_ls)[-1] - zs(off_ls)[-2]) * n1 / (n2 - n1))
    z20 = {label: float(zs(ls)[list(ls.links).index(20)]) for label, ls in link_studies.items() if 20 in list(ls.links)}
    ctx["bending_finding"] = dict(paper_z=zs(paper_ls), paper_links=paper_ls.links, off_z=zs(off_ls),
                                  mom_z=zs(mom_ls), off_links=off_ls.links, paper_converges=paper_converges,
                                  z_limit=z_limit)
    lz = lambda ls: "/".join(f"{z:.2f}" for z in zs(ls))  # noqa: E731
    ln = lambda ls: "/".join(str(int(n)) for n in ls.links)  # noqa: E731
    link_rows = [(label, ln(ls), lz(ls), " / ".join(f"{w:.3f}" for w in ls.lowest_lateral_rad_s),
                  " / ".join(f"{w:.3f}" for w in ls.lowest_vertical_rad_s)) for label, ls in link_studies.items()]
    link_table = _html_table(["bending model", "links", "drogue z [m]", "lowest lateral mode [rad/s]",
                              "lowest vertical mode [rad/s]"], link_rows, table_id="table-link-convergence")
    verdict = "below" if worst < 1e-4 else "above"
    out.sections["convergence"] = (
        '<section id="convergence"><h2>Convergence: integration step and number of links</h2>'
        f"<p>The RK4 step study runs three cases (a strong free swing, the paper's turbulence case, "
        f"and the same with the paper's PID in the loop) at several steps and compares the drogue "
        f"position with a run at {settings.reference_step_s:g} s. At the default step "
        f"<b>{h0:g} s</b> the largest drogue-position error over the three cases is "
        f"<b>{1000 * worst:.3g} mm</b>, {verdict} 0.1 mm: the default step is converged for every "
        f"result in this report. The observed order is about 4 for the smooth swing (RK4); with "
        f"turbulence it is irregular because the gust record is interpolated between its "
        f"{PAPER.turbulence.sample_time_s:g} s samples, but the errors stay small.</p>"
        + step_table +
        f"<p>The link-count study solves the balance position and linearizes it for several link "
        f"counts. <b>Finding:</b> with the paper's equivalent bending force (Eq. 20, 8 E I &gamma; / l<sup>2</sup>) "
        f"the balance position does <b>{'' if paper_converges else 'not '}converge</b> as links are added: "
        f"drogue z = {lz(paper_ls)} m for {ln(paper_ls)} links, the changes "
        f"({' / '.join(f'{d:.3f}' for d in d_paper)} m) {'shrink' if paper_converges else 'do not shrink'}. "
        f"For a given hose shape the bend angle per joint is &gamma; &asymp; &kappa; l, so the force per joint is "
        f"&asymp; 8 E I &kappa; / l: it grows as 1/l as the links get shorter, instead of tending to the "
        f"distributed load of a beam. The equivalent force is not a consistent discretization of "
        f"bending. With bending off, or with the conservative <code>moment</code> option (restoring "
        f"moment E I &gamma; / l = E I &kappa;), the position converges: z = {lz(off_ls)} m (off) and "
        f"{lz(mom_ls)} m (moment) for {ln(off_ls)} links, the changes "
        f"({' / '.join(f'{d:.4f}' for d in d_off)} m) {'halving with each doubling (first order in l)' if off_converges else 'not yet regular'}; "
        f"a Richardson estimate of the continuum limit is z &asymp; {z_limit:.3f} m. The real hose's "
        f"bending stiffness (E I &asymp; {out.headline['parameters']['bending_stiffness_n_m2']:.1f} N m<sup>2</sup>) hardly matters: "
        f"bending off and 'moment' agree to millimetres. At the paper's 20 links the paper force moves "
        f"the drogue by {abs(z20.get('paper bending (Eq. 20)', np.nan) - z20.get('bending off', np.nan)) * 100:.1f} cm "
        f"relative to bending off, so the results at 20 links are little affected; the lowest mode "
        f"frequencies change by a few per cent.</p>"
        + link_table
        + _figure_html("fig-convergence", "fig_convergence.png", "Convergence study",
                       "(a) Largest drogue-position error against the RK4 step for the three cases, with "
                       "a 4th-order guide and the 0.1 mm line; (b) drogue balance height against the "
                       "number of links for the three bending models; (c) lowest lateral (solid) and "
                       "vertical (dashed) mode frequencies against the number of links.",
                       ("convergence_steps.csv", "convergence_links.csv"))
        + "</section>"
    )
    out.headline["convergence"] = {
        "default_step_s": h0,
        "max_drogue_error_at_default_step_m": at_default,
        "worst_error_at_default_step_m": worst,
        "links": {label: {"links": [int(n) for n in ls.links], "drogue_z_m": zs(ls).tolist(),
                          "lowest_lateral_rad_s": ls.lowest_lateral_rad_s.tolist(),
                          "lowest_vertical_rad_s": ls.lowest_vertical_rad_s.tolist()}
                  for label, ls in link_studies.items()},
        "paper_bending_converges": paper_converges,
        "continuum_drogue_z_estimate_m": z_limit,
    }


# --- stage: Fig. 3 --------------------------------------------------------------------------------
def _stage_sweep(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    from ..analysis.equilibrium import solve_equilibrium
    from ..analysis.sweep import steady_sweep
    from ..plotting.figures import plot_sweep

    bar = ctx.get("bar")
    count = [0]
    total = len(settings.sweep_altitudes_m) * len(settings.sweep_airspeeds_m_s)

    def tick():
        count[0] += 1
        if bar is not None:
            bar.set_postfix_str(f"Fig. 3 point {count[0]}/{total}")

    sw = steady_sweep(PAPER, settings.sweep_altitudes_m, settings.sweep_airspeeds_m_s, progress=tick)
    if bar is not None:
        bar.set_postfix_str("")
    sw.to_csv(out.dir / "fig03_sweep.csv")
    out.files.append("fig03_sweep.csv")
    out.figure(plot_sweep(sw), "fig03_sweep.png")
    df = sw.to_dataframe()
    drag = sw.grid("drogue_drag_n")
    ratio = sw.grid("balance_ratio")
    drag_up = bool(np.all(np.diff(drag, axis=1) > 0))
    ratio_down_v = bool(np.all(np.diff(ratio, axis=1) < 0))
    ratio_up_h = bool(np.all(np.diff(ratio, axis=0) > 0))
    eq = solve_equilibrium(PAPER)
    ctx["equilibrium"] = eq
    n_conv = int(df["converged"].sum())
    out.sections["fig3"] = (
        '<section id="fig3"><h2>Fig. 3: steady drogue drag and balance position</h2>'
        f"<p>The balance position solved at {len(sw.altitudes_m)} altitudes x {len(sw.airspeeds_m_s)} "
        f"airspeeds ({n_conv} of {len(df)} solves converged), tanker wake on. The paper gives Fig. 3 "
        f"only as a plot (no numbers in its text), so the comparison is with its stated trends: "
        f"drag rises with airspeed ({'yes' if drag_up else 'NO'}, at every altitude here), the "
        f"balance ratio D = V_D/L_H falls with airspeed ({'yes' if ratio_down_v else 'NO'}) and rises "
        f"with altitude, i.e. the drogue hangs lower in thinner air ({'yes' if ratio_up_h else 'NO'}). "
        f"At the paper's case (150 m/s, 8000 m) the drogue sits at x = {eq.drogue_position_m[0]:.2f} m, "
        f"y = {eq.drogue_position_m[1]:.3f} m, z = {eq.drogue_position_m[2]:.3f} m from the tow point, "
        f"with drogue drag {np.linalg.norm(eq.drogue_drag_n):.0f} N and D = {eq.balance_ratio:.3f} "
        f"(the lateral offset is the wake's sidewash).</p>"
        + _figure_html("fig03", "fig03_sweep.png", "Fig. 3 (paper Fig. 3)",
                       "Steady drogue drag (a) and balance ratio V_D/L_H (b) against airspeed, one curve "
                       "per altitude.", ("fig03_sweep.csv",))
        + "</section>"
    )
    out.headline["steady"] = {
        "drogue_position_m": eq.drogue_position_m.tolist(),
        "drogue_drag_n": float(np.linalg.norm(eq.drogue_drag_n)),
        "balance_ratio": float(eq.balance_ratio),
        "tow_force_n": eq.tow_force_n.tolist(),
        "sweep_points_converged": n_conv,
        "sweep_points": int(len(df)),
        "trend_drag_rises_with_airspeed": drag_up,
        "trend_ratio_falls_with_airspeed": ratio_down_v,
        "trend_ratio_rises_with_altitude": ratio_up_h,
    }


# --- stage: Fig. 4 --------------------------------------------------------------------------------
def _stage_turbulence_speeds(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..plotting.figures import plot_turbulence_speeds

    runs = []
    for v in FIG4_AIRSPEEDS_M_S:
        sc, res = _run(f"paper-turbulence-{v}", settings)
        runs.append(res)
    window = _turbulence_window(sc.params)
    cols = {"t_s": runs[0].t_s}
    for v, res in zip(FIG4_AIRSPEEDS_M_S, runs):
        n = min(res.t_s.size, runs[0].t_s.size)
        cols[f"dy_{v}_m_s_m"] = np.pad(res.drogue_offset_m[:n, 1], (0, runs[0].t_s.size - n), constant_values=np.nan)
        cols[f"dz_{v}_m_s_m"] = np.pad(res.drogue_offset_m[:n, 2], (0, runs[0].t_s.size - n), constant_values=np.nan)
    out.csv(pd.DataFrame(cols), "fig04_turbulence_speeds.csv")
    out.figure(plot_turbulence_speeds(runs, FIG4_AIRSPEEDS_M_S, window_s=window), "fig04_turbulence_speeds.png")
    rows, head = [], {}
    for v, res in zip(FIG4_AIRSPEEDS_M_S, runs):
        py, pz = _peaks(res)
        ry, rz = _rms_in(res, window)
        rows.append((f"{v}", f"{py:.3f}", f"{pz:.3f}", f"{ry:.3f}", f"{rz:.3f}", "yes" if res.completed else "NO"))
        head[str(v)] = {"peak_lateral_m": py, "peak_vertical_m": pz, "rms_lateral_m": ry, "rms_vertical_m": rz,
                        "completed": bool(res.completed)}
    radial = [math.hypot(head[str(v)]["rms_lateral_m"], head[str(v)]["rms_vertical_m"]) for v in FIG4_AIRSPEEDS_M_S]
    falls = bool(np.all(np.diff(radial) < 0))
    out.sections["fig4"] = (
        '<section id="fig4"><h2>Fig. 4: drogue displacement in turbulence at several airspeeds</h2>'
        f"<p>The paper's turbulence case (isotropic Dryden, 1.5 m/s, 530 m, on from "
        f"{window[0]:g} s to {window[1]:g} s, 8000 m) at four airspeeds, controller off, the same "
        f"turbulence seed at every airspeed. The paper states that the displacement falls as the "
        f"airspeed rises (the gust is a smaller fraction of the airspeed). Here the RMS radial "
        f"displacement in the turbulence window is {' / '.join(f'{r:.3f}' for r in radial)} m at "
        f"{' / '.join(str(v) for v in FIG4_AIRSPEEDS_M_S)} m/s: "
        f"{'it falls monotonically, as the paper says' if falls else 'NOT monotonic, unlike the paper'}. "
        f"Peaks of one realisation are noisier than RMS values. The drogue keeps swinging after the "
        f"gusts stop (lightly damped pendulum modes), as in the paper's figure.</p>"
        + _html_table(["airspeed [m/s]", "peak |dy| [m]", "peak |dz| [m]", "RMS dy in window [m]",
                       "RMS dz in window [m]", "completed"], rows, table_id="table-fig4")
        + _figure_html("fig04", "fig04_turbulence_speeds.png", "Fig. 4 (paper Fig. 4)",
                       "Lateral (top) and vertical (bottom, positive down) drogue displacement from the "
                       "balance position in turbulence at four airspeeds, 8000 m; the grey band is the "
                       "turbulence window.", ("fig04_turbulence_speeds.csv",))
        + "</section>"
    )
    out.headline["turbulence_speeds"] = head
    out.headline["turbulence_speeds"]["rms_radial_falls_with_airspeed"] = falls


# --- stage: linear model, Table 2 and Figs. 5-8 --------------------------------------------------
def _second_order_characteristics(num, den) -> dict:
    num = np.asarray(num, float)
    den = np.asarray(den, float)
    wn = math.sqrt(den[-1] / den[0])
    return {"dc_gain_m_n": num[-1] / den[-1], "natural_frequency_rad_s": wn,
            "damping_ratio": den[1] / den[0] / (2.0 * wn),
            "zero_1_s": -num[-1] / num[-2] if num.size >= 2 and num[-2] != 0 else float("nan")}


def _freq(sys, w):
    return np.squeeze(np.asarray(sys(1j * w), dtype=complex))


def _step(sys, t):
    import control

    return np.squeeze(np.asarray(control.step_response(sys, T=t).outputs, dtype=float))


def _stage_linear(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import control
    import pandas as pd

    from ..analysis.linearize import linearize
    from ..analysis.reduction import format_tf, hankel_singular_values, table2_form, truncation_error_bound
    from ..controllers.design import reduced_channels
    from ..paper import TABLE2, table2_transfer_function
    from ..plotting.figures import plot_bode_compare, plot_linear_steps, plot_pole_zero, plot_step_compare

    lm = linearize(PAPER, ctx.get("equilibrium"))
    full = reduced_channels(lm, None)
    r6 = reduced_channels(lm, 6)
    r2 = reduced_channels(lm, 2)
    ctx.update(lm=lm, full=full, r6=r6, r2=r2)
    ours = {"full": full, "6th order": r6, "2nd order": r2}
    paper_tf = {(ch, o): table2_transfer_function(ch, o) for ch in ("lateral", "vertical") for o in (6, 2)}

    # Table 2: transfer functions and coefficients
    t2_rows, coeff_rows, csv_rows = [], [], []
    for o in (6, 2):
        for ch in ("lateral", "vertical"):
            num, den = table2_form(getattr(r6 if o == 6 else r2, ch))
            pnum, pden = (np.asarray(v, float) for v in TABLE2[(ch, o)])
            t2_rows.append((f"{o}th order" if o == 6 else "2nd order", ch, format_tf(pnum, pden), format_tf(num, den)))
            for which, a, b in (("num", pnum, num), ("den", pden, den)):
                deg = a.size - 1
                bb = np.concatenate([np.zeros(max(0, a.size - b.size)), b])[-a.size:] if b.size <= a.size else b[-a.size:]
                for k in range(a.size):
                    pw = deg - k
                    r = _ratio(bb[k], a[k])
                    coeff_rows.append((f"{o}", ch, which, f"s^{pw}", _fmt(a[k]), _fmt(bb[k]), _fmt(r, 3)))
                    csv_rows.append(dict(order=o, channel=ch, polynomial=which, power=pw, paper=a[k], ours=bb[k], ratio=r))
    out.csv(pd.DataFrame(csv_rows), "table2.csv")

    # 2nd-order characteristics
    char_rows, char_csv, t2_head = [], [], {}
    for ch in ("lateral", "vertical"):
        pc = _second_order_characteristics(*TABLE2[(ch, 2)])
        oc = _second_order_characteristics(*table2_form(getattr(r2, ch)))
        t2_head[ch] = {}
        for key, label, unit in (("dc_gain_m_n", "DC gain", "m/N"), ("natural_frequency_rad_s", "natural frequency", "rad/s"),
                                 ("damping_ratio", "damping ratio", "-"), ("zero_1_s", "zero", "1/s")):
            r = _ratio(oc[key], pc[key])
            char_rows.append((ch, label, unit, _fmt(pc[key]), _fmt(oc[key]), _fmt(r, 3)))
            char_csv.append(dict(channel=ch, quantity=key, paper=pc[key], ours=oc[key], ratio=r))
            t2_head[ch][f"{key}_paper"] = pc[key]
            t2_head[ch][f"{key}_ours"] = oc[key]
            t2_head[ch][f"{key}_ratio"] = r
            if key != "zero_1_s":
                out.cmp.add("Table 2", f"2nd-order {ch} {label}", unit, pc[key], oc[key],
                            "the paper's linearization flight condition is not stated; ours is 150 m/s, "
                            "8000 m, wake on (see the linearization-condition table)")
        dc6_p = TABLE2[(ch, 6)][0][-1] / TABLE2[(ch, 6)][1][-1]
        n6, d6 = table2_form(getattr(r6, ch))
        out.cmp.add("Table 2", f"6th-order {ch} DC gain", "m/N", dc6_p, n6[-1] / d6[-1],
                    "as for the 2nd-order models: different (unstated) linearization condition")
    out.csv(pd.DataFrame(char_csv), "table2_characteristics.csv")

    # reduction error: a-priori bound vs the error on the frequency grid
    w = np.logspace(-2, 2, settings.bode_points)
    red_rows, red_csv = [], []
    for ch in ("lateral", "vertical"):
        g = getattr(full, ch)
        hsv = hankel_singular_values(g)
        gfull = _freq(g, w)
        dc = abs(float(np.real(control.dcgain(g))))
        peak = float(np.max(np.abs(gfull)))
        for o, red in ((6, r6), (2, r2)):
            bound = truncation_error_bound(hsv, o)
            err = float(np.max(np.abs(gfull - _freq(getattr(red, ch), w))))
            red_rows.append((ch, o, _fmt(bound), _fmt(err), _fmt(err / peak, 3)))
            red_csv.append(dict(channel=ch, order=o, hinf_bound_m_n=bound, max_error_on_grid_m_n=err,
                                full_dc_gain_m_n=dc, full_peak_gain_m_n=peak, hsv_1=hsv[0],
                                hsv_3=hsv[2] if hsv.size > 2 else np.nan))
    out.csv(pd.DataFrame(red_csv), "reduction_error.csv")

    # linearization-condition sensitivity
    sens_csv = []
    p_lat = _second_order_characteristics(*TABLE2[("lateral", 2)])
    p_ver = _second_order_characteristics(*TABLE2[("vertical", 2)])
    for h in settings.sensitivity_altitudes_m:
        for v in settings.sensitivity_airspeeds_m_s:
            p = PAPER.replace(flight={"altitude_m": h, "airspeed_m_s": v})
            c2 = reduced_channels(linearize(p), 2)
            cl = _second_order_characteristics(*table2_form(c2.lateral))
            cv = _second_order_characteristics(*table2_form(c2.vertical))
            dist = math.sqrt(sum(math.log(a[k] / b[k]) ** 2 for a, b in ((cl, p_lat), (cv, p_ver))
                                 for k in ("dc_gain_m_n", "natural_frequency_rad_s")))
            sens_csv.append(dict(altitude_m=h, airspeed_m_s=v,
                                 lateral_dc_gain_m_n=cl["dc_gain_m_n"], lateral_wn_rad_s=cl["natural_frequency_rad_s"],
                                 lateral_zeta=cl["damping_ratio"], vertical_dc_gain_m_n=cv["dc_gain_m_n"],
                                 vertical_wn_rad_s=cv["natural_frequency_rad_s"], vertical_zeta=cv["damping_ratio"],
                                 log_distance_to_paper=dist))
    sens = pd.DataFrame(sens_csv)
    out.csv(sens, "linearization_conditions.csv")
    best = sens.loc[sens["log_distance_to_paper"].idxmin()]
    sens_rows = [(f"{r.altitude_m:g}", f"{r.airspeed_m_s:g}", _fmt(r.lateral_dc_gain_m_n), _fmt(r.lateral_wn_rad_s),
                  _fmt(r.lateral_zeta, 3), _fmt(r.vertical_dc_gain_m_n), _fmt(r.vertical_wn_rad_s), _fmt(r.vertical_zeta, 3),
                  _fmt(r.log_distance_to_paper, 3)) for r in sens.itertuples()]
    sens_rows.append(("paper", "(not stated)", _fmt(p_lat["dc_gain_m_n"]), _fmt(p_lat["natural_frequency_rad_s"]),
                      _fmt(p_lat["damping_ratio"], 3), _fmt(p_ver["dc_gain_m_n"]), _fmt(p_ver["natural_frequency_rad_s"]),
                      _fmt(p_ver["damping_ratio"], 3), "0"))

    # Fig. 5: full model, both inputs to both outputs
    t5 = np.arange(0.0, 40.0 + 1e-9, 0.02)
    resp = control.step_response(lm.ss, T=t5)
    y5 = np.asarray(resp.outputs)  # (outputs, inputs, N)
    out.csv(pd.DataFrame({"t_s": t5, "P_ny_from_u_hor_m": y5[0, 0], "P_ny_from_u_ver_m": y5[0, 1],
                          "P_nz_from_u_hor_m": y5[1, 0], "P_nz_from_u_ver_m": y5[1, 1]}), "fig05_linear_steps.csv")
    out.figure(plot_linear_steps(t5, y5), "fig05_linear_steps.png")
    coupling = max(np.max(np.abs(y5[0, 1])), np.max(np.abs(y5[1, 0]))) / min(np.max(np.abs(y5[0, 0])), np.max(np.abs(y5[1, 1])))

    # Fig. 6: pole-zero maps
    pz = {label: {ch: (getattr(m, ch).poles(), getattr(m, ch).zeros()) for ch in ("lateral", "vertical")}
          for label, m in ours.items()}
    pz_ref = {label: {ch: (paper_tf[(ch, o)].poles(), paper_tf[(ch, o)].zeros()) for ch in ("lateral", "vertical")}
              for label, o in (("6th order", 6), ("2nd order", 2))}
    pz_csv = []
    for source, group in (("this project", pz), ("paper", pz_ref)):
        for label, chans in group.items():
            for ch, (poles, zeros) in chans.items():
                for kind, vals in (("pole", poles), ("zero", zeros)):
                    for z in np.asarray(vals, complex):
                        pz_csv.append(dict(source=source, model=label, channel=ch, kind=kind, real_1_s=z.real, imag_rad_s=z.imag))
    out.csv(pd.DataFrame(pz_csv), "fig06_pole_zero.csv")
    out.figure(plot_pole_zero(pz, reference=pz_ref), "fig06_pole_zero.png")
    # the pendulum poles each 2nd-order model keeps (upper half plane)
    slow = {ch: max(getattr(r2, ch).poles(), key=lambda p: p.imag) for ch in ("lateral", "vertical")}
    max_real = max(float(np.max(getattr(full, ch).poles().real)) for ch in ("lateral", "vertical"))

    # Fig. 7: Bode, Fig. 8: open-loop steps
    bode = {label: {ch: _freq(getattr(m, ch), w) for ch in ("lateral", "vertical")} for label, m in ours.items()}
    bode_ref = {f"paper {o}th order" if o == 6 else "paper 2nd order": {ch: _freq(paper_tf[(ch, o)], w) for ch in ("lateral", "vertical")}
                for o in (6, 2)}
    cols = {"omega_rad_s": w}
    for group in (bode, bode_ref):
        for label, chans in group.items():
            for ch, g in chans.items():
                key = label.replace(" ", "_")
                cols[f"{key}_{ch}_mag_db"] = 20 * np.log10(np.abs(g))
                cols[f"{key}_{ch}_phase_deg"] = np.degrees(np.unwrap(np.angle(g)))
    out.csv(pd.DataFrame(cols), "fig07_bode.csv")
    out.figure(plot_bode_compare(w, bode, reference=bode_ref), "fig07_bode.png")

    steps = {label: {ch: _step(getattr(m, ch), t5) for ch in ("lateral", "vertical")} for label, m in ours.items()}
    steps_ref = {f"paper {o}th order" if o == 6 else "paper 2nd order": {ch: _step(paper_tf[(ch, o)], t5) for ch in ("lateral", "vertical")}
                 for o in (6, 2)}
    cols = {"t_s": t5}
    for group in (steps, steps_ref):
        for label, chans in group.items():
            for ch, y in chans.items():
                cols[f"{label.replace(' ', '_')}_{ch}_m"] = y
    out.csv(pd.DataFrame(cols), "fig08_step_compare.csv")
    out.figure(plot_step_compare(t5, steps, reference=steps_ref), "fig08_step_compare.png")

    dc_err = {ch: float(np.real(control.dcgain(getattr(r2, ch)))) / float(np.real(control.dcgain(getattr(full, ch)))) - 1.0
              for ch in ("lateral", "vertical")}
    lat_dc = t2_head["lateral"]["dc_gain_m_n_ratio"]
    ver_dc = t2_head["vertical"]["dc_gain_m_n_ratio"]
    lat_wn = t2_head["lateral"]["natural_frequency_rad_s_ratio"]
    ver_wn = t2_head["vertical"]["natural_frequency_rad_s_ratio"]
    out.sections["table2"] = (
        '<section id="table2"><h2>Table 2: reduced transfer functions</h2>'
        f"<p>This project's model linearized about its balance position at <b>150 m/s, 8000 m, wake on</b> "
        f"(the flight condition of Fig. 12; {lm.A.shape[0]} states), each channel balanced-truncated to "
        f"6th and 2nd order, beside the paper's Table 2. <b>The paper does not state the flight condition "
        f"of its linearization</b>, so the two need not match. They do not: our 2nd-order DC gain is "
        f"{lat_dc:.2f} x (lateral) and {ver_dc:.2f} x (vertical) the paper's and our natural frequency "
        f"{lat_wn:.2f} x and {ver_wn:.2f} x. The pendulum frequency of the towed hose scales roughly with "
        f"airspeed and the square root of air density, the gain with their inverse squares, so the "
        f"linearization condition matters by factors of 2-3 across the envelope (table below). In "
        f"this grid the condition nearest to the paper's 2nd-order models (smallest log-distance of "
        f"DC gain and natural frequency over both channels) is <b>{best.altitude_m:g} m, "
        f"{best.airspeed_m_s:g} m/s</b>: an observation, not a fit; every other result here uses 150 m/s, 8000 m.</p>"
        + _html_table(["model", "channel", "paper Table 2 [m/N]", "this project [m/N]"], t2_rows, table_id="table-2")
        + "<h3>2nd-order models: DC gain, natural frequency, damping</h3>"
        + _html_table(["channel", "quantity", "unit", "paper", "this project", "ratio"], char_rows,
                      table_id="table-2-characteristics")
        + "<details><summary>Every Table 2 coefficient, paper vs this project</summary>"
        + _html_table(["order", "channel", "polynomial", "power", "paper", "this project", "ratio"], coeff_rows,
                      table_id="table-2-coefficients")
        + "</details>"
        + "<h3>Sensitivity of the 2nd-order model to the linearization condition</h3>"
        + _html_table(["altitude [m]", "airspeed [m/s]", "lat. DC gain [m/N]", "lat. w_n [rad/s]", "lat. zeta [-]",
                       "vert. DC gain [m/N]", "vert. w_n [rad/s]", "vert. zeta [-]", "log-distance to paper [-]"],
                      sens_rows, table_id="table-linearization-conditions")
        + "<h3>Balanced truncation error</h3><p>The a-priori H-infinity bound of balanced truncation "
          "(twice the sum of the discarded Hankel singular values) and the largest error actually seen on "
          f"the frequency grid of Fig. 7 ({w[0]:g} to {w[-1]:g} rad/s; a lower estimate of the H-infinity norm).</p>"
        + _html_table(["channel", "order", "bound 2 sum(sigma) [m/N]", "max |G - G_r| on grid [m/N]",
                       "relative to the full model's peak gain [-]"], red_rows, table_id="table-reduction-error")
        + '<p class=data>Data: <a href="table2.csv">table2.csv</a>, <a href="table2_characteristics.csv">'
          'table2_characteristics.csv</a>, <a href="linearization_conditions.csv">linearization_conditions.csv</a>, '
          '<a href="reduction_error.csv">reduction_error.csv</a>.</p></section>'
    )
    out.sections["fig5_8"] = (
        '<section id="fig5-8"><h2>Figs. 5-8: the linearized model and its reductions</h2>'
        + _figure_html("fig05", "fig05_linear_steps.png", "Fig. 5 (paper Fig. 5)",
                       f"Step responses of the full linearized model ({lm.A.shape[0]} states) to a 1 N force, "
                       f"both inputs to both outputs. The cross-coupling peaks are {100 * coupling:.1f} % of "
                       f"the direct responses: the channels are practically decoupled, as the paper finds, "
                       f"which justifies one SISO design per channel.", ("fig05_linear_steps.csv",))
        + _figure_html("fig06", "fig06_pole_zero.png", "Fig. 6 (paper Fig. 6)",
                       f"Pole-zero maps per channel of the full model (minimal realization of each channel), "
                       f"its 6th- and 2nd-order balanced truncations (blue) and the paper's Table 2 models (grey). "
                       f"Every pole of the full model is stable (largest real part {max_real:.2g} 1/s: the "
                       f"higher hose modes are very lightly damped). The 2nd-order models keep the pendulum "
                       f"poles {slow['lateral'].real:.3f} &plusmn; {abs(slow['lateral'].imag):.3f}j (lateral) and "
                       f"{slow['vertical'].real:.3f} &plusmn; {abs(slow['vertical'].imag):.3f}j 1/s (vertical). Each "
                       f"channel's minimal realization keeps every mode; near-cancelling pole-zero pairs are "
                       f"the modes that channel barely sees.", ("fig06_pole_zero.csv",))
        + _figure_html("fig07", "fig07_bode.png", "Fig. 7 (paper Fig. 7)",
                       "Frequency response of the full model and its 6th- and 2nd-order reductions (solid), "
                       "and of the paper's Table 2 models (dashed). The reductions follow the full model up to "
                       "and through the pendulum resonance; the paper's models resonate higher with a lower "
                       "gain (their linearization condition differs).", ("fig07_bode.csv",))
        + _figure_html("fig08", "fig08_step_compare.png", "Fig. 8 (paper Fig. 8)",
                       "Open-loop response to a 1 N force step of the full and reduced models (solid) and the "
                       "paper's Table 2 models (dashed). The 6th-order model is hard to tell from the full one; "
                       "the 2nd-order model keeps the pendulum swing, but its final offset is "
                       f"{100 * dc_err['lateral']:+.1f} % (lateral) and {100 * dc_err['vertical']:+.1f} % (vertical) off "
                       "the full model's (balanced truncation does not preserve the DC gain). The paper's 2nd-order "
                       f"models settle at {1 / lat_dc:.2f} x (lateral) and {1 / ver_dc:.2f} x (vertical) the offset "
                       "of ours, with a faster swing.", ("fig08_step_compare.csv",))
        + "</section>"
    )
    out.headline["table2"] = t2_head
    out.headline["table2"]["nearest_linearization_condition"] = {"altitude_m": float(best.altitude_m),
                                                                 "airspeed_m_s": float(best.airspeed_m_s)}
    out.headline["linear_model"] = {"states": int(lm.A.shape[0]), "cross_coupling_ratio": float(coupling),
                                    "max_pole_real_part_1_s": max_real,
                                    "second_order_dc_gain_error_vs_full": dc_err}


# --- stage: controllers on linear models, Table 3 and Figs. 10-11 --------------------------------
def _metrics_dict(m) -> dict:
    return {"rise_time_s": m.rise_time_s, "settling_time_s": m.settling_time_s, "overshoot_pct": m.overshoot_pct}


def _lqr_steps(design, plant, t):
    """Unit reference steps of the LQR loop: (y_lat, y_ver, u_lat, u_ver, metrics_lat, metrics_ver)."""
    import control

    from ..controllers.lqr import lqr_tracking_closed_loop
    from ..controllers.stepinfo import step_metrics

    cl = lqr_tracking_closed_loop(design, plant)
    if np.any(np.real(cl.poles()) >= 0.0):
        raise RuntimeError("LQR closed loop unstable")
    resp = control.step_response(cl, T=t)
    y = np.asarray(resp.outputs)
    dc = np.real(np.asarray(control.dcgain(cl)))
    m_lat = step_metrics(t, y[0, 0], final_value=float(dc[0, 0]))
    m_ver = step_metrics(t, y[1, 1], final_value=float(dc[1, 1]))
    return y[0, 0], y[1, 1], y[2, 0], y[3, 1], m_lat, m_ver


def _thin(t, every_after_1s: int = 10):
    """Indices keeping every sample before 1 s and every ``every_after_1s``-th after (CSV size)."""
    idx = np.arange(t.size)
    return idx[(t < 1.0) | (idx % every_after_1s == 0)]


def _stage_controllers(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..controllers.design import lqr_design_for
    from ..controllers.lqr import lqr_integral_design, two_channel_plant
    from ..controllers.pid import PAPER_PID
    from ..controllers.stepinfo import closed_loop_step
    from ..paper import TABLE2, TABLE3, table2_transfer_function
    from ..plotting.figures import plot_closed_loop_steps

    lm, full, r6, r2 = ctx["lm"], ctx["full"], ctx["r6"], ctx["r2"]
    chans = ("lateral", "vertical")
    # Fig. 10 shows PID and LQR together: 30 s (the LQR with the paper's weights is slow);
    # the PID settles within ~2 s, so its other responses use a short, finer record.
    t10 = np.arange(0.0, 30.0 + 1e-9, 0.002)
    t_pid = np.arange(0.0, 5.0 + 1e-9, 0.0005)
    paper2 = {ch: table2_transfer_function(ch, 2) for ch in chans}
    paper6 = {ch: table2_transfer_function(ch, 6) for ch in chans}

    # PID on every model
    pid, pid10 = {}, {}
    for label, models in (("paper 2nd", paper2), ("paper 6th", paper6), ("ours 2nd", {c: getattr(r2, c) for c in chans}),
                          ("ours 6th", {c: getattr(r6, c) for c in chans}), ("ours full", {c: getattr(full, c) for c in chans})):
        pid[label] = {ch: closed_loop_step(models[ch], PAPER_PID[ch].transfer_function(), t_pid) for ch in chans}
        if label in ("paper 2nd", "ours 2nd"):
            pid10[label] = {ch: closed_loop_step(models[ch], PAPER_PID[ch].transfer_function(), t10) for ch in chans}
    # LQR: designed on the paper's 2nd-order models, and on ours (evaluated on our 2nd, 6th and full)
    d_paper = lqr_integral_design(two_channel_plant(paper2["lateral"], paper2["vertical"]))
    d_ours = lqr_design_for(lm)
    lqr = {"paper 2nd": _lqr_steps(d_paper, None, t10), "ours 2nd": _lqr_steps(d_ours, None, t10),
           "ours 6th": _lqr_steps(d_ours, two_channel_plant(r6.lateral, r6.vertical), t10),
           "ours full": _lqr_steps(d_ours, lm.ss, t10)}

    def m_of(ctrl, label, ch):
        if ctrl == "PID":
            return _metrics_dict(pid[label][ch].metrics)
        return _metrics_dict(lqr[label][4 if ch == "lateral" else 5])

    # Table 3
    metric_names = (("rise_time_s", "rise time 10-90 %", "s"), ("settling_time_s", "settling time 2 %", "s"),
                    ("overshoot_pct", "overshoot", "%"))
    t3_rows, t3_csv, t3_head = [], [], {}
    for ctrl in ("PID", "LQR"):
        for ch in chans:
            for key, label, unit in metric_names:
                paper_v = TABLE3[(ctrl, ch)][key]
                vals = {lab: m_of(ctrl, lab, ch)[key] for lab in ("paper 2nd", "ours 2nd", "ours 6th", "ours full")}
                t3_rows.append((ctrl, ch, f"{label} [{unit}]", _fmt(paper_v), _fmt(vals["paper 2nd"]),
                                _fmt(_ratio(vals["paper 2nd"], paper_v), 3), _fmt(vals["ours 2nd"]),
                                _fmt(_ratio(vals["ours 2nd"], paper_v), 3), _fmt(vals["ours 6th"]), _fmt(vals["ours full"])))
                t3_csv.append(dict(controller=ctrl, channel=ch, metric=key, paper=paper_v,
                                   on_paper_2nd=vals["paper 2nd"], ratio_paper_2nd=_ratio(vals["paper 2nd"], paper_v),
                                   on_ours_2nd=vals["ours 2nd"], ratio_ours_2nd=_ratio(vals["ours 2nd"], paper_v),
                                   on_ours_6th=vals["ours 6th"], on_ours_full=vals["ours full"]))
                t3_head[f"{ctrl}_{ch}_{key}"] = {"paper": paper_v, "on_paper_model": vals["paper 2nd"],
                                                  "on_our_2nd_order": vals["ours 2nd"], "on_our_full": vals["ours full"]}
                if ctrl == "PID":
                    note = ("reproduced: same gains on the same (paper's) model" if _agrees(_ratio(vals["paper 2nd"], paper_v), 0.06)
                            else "the paper's 2 % settling time is sensitive to the band crossing of the slow tail")
                else:
                    note = ("the paper's Q and R weigh outputs in metres against forces in newtons, so control is "
                            "expensive and the loop is slow; the reference enters only through the integrator "
                            "here; likely different units or unstated scaling in the paper")
                out.cmp.add("Table 3 (on the paper's Table 2 models)", f"{ctrl} {ch} {label}", unit, paper_v,
                            vals["paper 2nd"], note)
                note2 = ("our 2nd-order model has a higher DC gain and a lower natural frequency than the paper's "
                         "(different linearization condition), so the same gains give a different loop")
                out.cmp.add("Table 3 (on this project's 2nd-order models)", f"{ctrl} {ch} {label}", unit, paper_v,
                            vals["ours 2nd"], note2 if ctrl == "PID" else note2 + "; and as above for the LQR weights")
    out.csv(pd.DataFrame(t3_csv), "table3.csv")

    # Fig. 10: PID and LQR on the 2nd-order models; Fig. 11: PID on full / 6th / 2nd
    rows10 = {"paper's Table 2 models": {"PID": {c: pid10["paper 2nd"][c].y for c in chans},
                                         "LQR (paper Q, R)": {"lateral": lqr["paper 2nd"][0], "vertical": lqr["paper 2nd"][1]}},
              "this project's 2nd-order models": {"PID": {c: pid10["ours 2nd"][c].y for c in chans},
                                                  "LQR (paper Q, R)": {"lateral": lqr["ours 2nd"][0], "vertical": lqr["ours 2nd"][1]}}}
    keep = _thin(t10, 5)
    cols = {"t_s": t10[keep]}
    for row, curves in rows10.items():
        for lab, ys in curves.items():
            for ch, y in ys.items():
                cols[f"{'paper' if row.startswith('paper') else 'ours'}_{lab.split()[0]}_{ch}_m"] = np.asarray(y)[keep]
    for lab in ("paper 2nd", "ours 2nd"):
        cols[f"{lab.split()[0]}_LQR_lateral_force_n"] = lqr[lab][2][keep]
        cols[f"{lab.split()[0]}_LQR_vertical_force_n"] = lqr[lab][3][keep]
        for ch in chans:
            cols[f"{lab.split()[0]}_PID_{ch}_force_n"] = np.asarray(pid10[lab][ch].u)[keep]
    out.csv(pd.DataFrame(cols), "fig10_closed_loop_steps.csv")
    out.figure(plot_closed_loop_steps(t10, rows10, log_time=True), "fig10_closed_loop_steps.png")

    n11 = int(round(4.0 / (t_pid[1] - t_pid[0]))) + 1
    t11 = t_pid[:n11]
    rows11 = {"PID on this project's models": {lab.split()[1]: {c: pid[lab][c].y[:n11] for c in chans}
                                                for lab in ("ours full", "ours 6th", "ours 2nd")}}
    ref11 = {"PID on this project's models": {f"paper {lab.split()[1]}": {c: pid[lab][c].y[:n11] for c in chans}
                                               for lab in ("paper 6th", "paper 2nd")}}
    cols = {"t_s": t11[::2]}
    for group in (rows11, ref11):
        for curves in group.values():
            for lab, ys in curves.items():
                for ch, y in ys.items():
                    cols[f"PID_{lab.replace(' ', '_')}_{ch}_m"] = np.asarray(y)[::2]
    out.csv(pd.DataFrame(cols), "fig11_pid_orders.csv")
    out.figure(plot_closed_loop_steps(t11, rows11, reference_rows=ref11), "fig11_pid_orders.png")

    num_l, den_l = TABLE2[("lateral", 2)]
    dc_paper_lat = num_l[-1] / den_l[-1]
    kick = {ch: PAPER_PID[ch].kp + PAPER_PID[ch].kd * PAPER_PID[ch].n_filter for ch in chans}
    slow_paper = float(np.max(np.real(d_paper.regulator_poles)))
    slow_ours = float(np.max(np.real(d_ours.regulator_poles)))
    kz = np.diag(np.asarray(d_paper.gain_integral))
    pid_rep = all(_agrees(_ratio(m_of("PID", "paper 2nd", ch)[k], TABLE3[("PID", ch)][k]), 0.06)
                  for ch in chans for k in ("rise_time_s", "settling_time_s", "overshoot_pct"))
    pid_worst = max(abs(_ratio(m_of("PID", "paper 2nd", ch)[k], TABLE3[("PID", ch)][k]) - 1)
                    for ch in chans for k in ("rise_time_s", "settling_time_s", "overshoot_pct"))
    lqr_p = {ch: m_of("LQR", "paper 2nd", ch)["rise_time_s"] for ch in chans}
    out.sections["table3"] = (
        '<section id="table3"><h2>Table 3: closed-loop step responses (PID and LQR)</h2>'
        "<p>Unit reference steps of each channel in closed loop: rise time 10-90 %, settling time to "
        "2 % and overshoot, computed (a) on the <b>paper's own Table 2 models</b>, which isolates the "
        "controller design from the model, and (b) on <b>this project's</b> reduced and full models. "
        "PID: the paper's gains (Eq. 33). LQR: integral augmentation (Eq. 34) with the paper's "
        "Q = diag(12000, 8000, 8000, 10000) on [P_ny, P_nz, z_ny, z_nz] and R = diag(0.4, 0.5) on the "
        "forces, taken in SI units, designed on the 2nd-order model; the reference enters through the "
        "integrator (z' = y - r); a steady-state Kalman observer estimates the reduced state (the paper "
        "does not describe one; it does not affect these reference steps).</p>"
        f"<p><b>PID</b> on the paper's models reproduces Table 3 "
        f"({'within' if pid_rep else 'NOT within'} 6 %; largest difference {100 * pid_worst:.1f} %). "
        f"<b>LQR</b> with the paper's Q and R gives rise times of {lqr_p['lateral']:.2f} s (lateral) and "
        f"{lqr_p['vertical']:.2f} s (vertical) on the paper's own models, not the paper's 0.839 s and "
        f"0.671 s. The reason is in the weights: with outputs in metres and forces in newtons, an "
        f"error of 1 m costs as much as a force of sqrt(q/r) = sqrt(12000 / 0.4) = {math.sqrt(12000 / 0.4):.0f} N, "
        f"while holding the drogue 1 m away takes 1/(DC gain) = {1 / dc_paper_lat:.0f} N (paper's lateral "
        f"model): the optimum accepts large errors rather than spend force, so control is expensive; the "
        f"integral gains come out at K_z = {kz[0]:.1f} / {kz[1]:.1f} N/(m s) (= sqrt(q_z/r): the integral "
        f"weight dominates) and the slowest closed-loop pole is at {slow_paper:.3f} 1/s (time constant "
        f"{-1 / slow_paper:.1f} s; {slow_ours:.3f} 1/s on our model). Since the reference enters only "
        f"through the integrator, the response is as slow as that pole. Sub-second rise times need "
        f"weights some orders of magnitude larger relative to R, a feed-forward of the reference, or "
        f"different units (e.g. centimetres) - the paper states none of these, so its LQR numbers "
        f"cannot be reproduced from the text. No weight is changed here.</p>"
        "<p>On this project's models the same PID gains give a faster, less damped loop: our "
        "2nd-order model has a higher gain and a lower natural frequency than the paper's, so the loop "
        "gain is higher. On the 6th-order and full models the PID loop stays stable but the higher "
        "hose modes add overshoot and lengthen settling (Fig. 11). The PID gains are large: the "
        f"derivative kick K_P + K_D N is {kick['lateral'] / 1000:.0f} kN (lateral) and "
        f"{kick['vertical'] / 1000:.0f} kN (vertical) per metre of step, i.e. {kick['lateral'] / 100:.0f} N per "
        "centimetre (lateral) - fine for centimetre-scale disturbances, not for large reference steps.</p>"
        + _html_table(["controller", "channel", "metric", "paper Table 3", "on paper's 2nd-order model",
                       "ratio", "on our 2nd-order model", "ratio", "on our 6th-order model", "on our full model"],
                      t3_rows, table_id="table-3")
        + '<p class=data>Data: <a href="table3.csv">table3.csv</a>.</p></section>'
    )
    out.sections["fig10_11"] = (
        '<section id="fig10-11"><h2>Figs. 10-11: closed-loop step responses</h2>'
        + _figure_html("fig10", "fig10_closed_loop_steps.png", "Fig. 10 (paper Fig. 10)",
                       "Closed-loop unit reference steps of the PID and the LQR (paper weights) on the paper's "
                       "Table 2 models (top) and on this project's 2nd-order models (bottom). Logarithmic time "
                       "axis: the PID rises in under 0.1 s, the LQR with the paper's weights in several seconds.",
                       ("fig10_closed_loop_steps.csv",))
        + _figure_html("fig11", "fig11_pid_orders.png", "Fig. 11 (paper Fig. 11)",
                       "The paper's PID on this project's full, 6th- and 2nd-order models (solid) and on the "
                       "paper's 6th- and 2nd-order models (dashed). As in the paper, the design on the "
                       "2nd-order model also works on the higher-order models.", ("fig11_pid_orders.csv",))
        + "</section>"
    )
    out.headline["table3"] = t3_head
    out.headline["lqr"] = {"slowest_pole_on_paper_model_1_s": slow_paper, "slowest_pole_on_our_model_1_s": slow_ours,
                           "integral_gain_n_per_m_s": kz.tolist()}


# --- stage: controllers on the nonlinear model, Figs. 12-13 --------------------------------------
def _stage_closed_loop(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..plotting.figures import plot_control_forces, plot_controller_on_off

    names = {"off": "paper-turbulence", "PID": "paper-turbulence-pid", "LQR": "paper-turbulence-lqr"}
    runs = {}
    for key, name in names.items():
        sc, runs[key] = _run(name, settings)
    window = _turbulence_window(sc.params)
    ctx.update(runs=runs, window=window)
    t = runs["off"].t_s
    n = min(r.t_s.size for r in runs.values())
    cols = {"t_s": t[:n]}
    for key, r in runs.items():
        cols[f"dy_{key}_m"] = r.drogue_offset_m[:n, 1]
        cols[f"dz_{key}_m"] = r.drogue_offset_m[:n, 2]
    out.csv(pd.DataFrame(cols), "fig12_controller_on_off.csv")
    cols = {"t_s": t[:n]}
    for key in ("PID", "LQR"):
        cols[f"u_hor_{key}_n"] = runs[key].control_n[:n, 0]
        cols[f"u_ver_{key}_n"] = runs[key].control_n[:n, 1]
    out.csv(pd.DataFrame(cols), "fig13_control_forces.csv")
    out.figure(plot_controller_on_off(runs["off"], {"PID": runs["PID"], "LQR": runs["LQR"]}, window_s=window),
               "fig12_controller_on_off.png")
    out.figure(plot_control_forces({"PID": runs["PID"], "LQR": runs["LQR"]}, window_s=window), "fig13_control_forces.png")

    peaks = {k: _peaks(r) for k, r in runs.items()}
    forces = {k: _force_peaks(runs[k]) for k in ("PID", "LQR")}
    rms = {k: _rms_in(r, window) for k, r in runs.items()}
    red = {k: (peaks["off"][0] / peaks[k][0], peaks["off"][1] / peaks[k][1]) for k in ("PID", "LQR")}
    rows, csv_rows = [], []
    for k in ("off", "PID", "LQR"):
        f = forces.get(k, (0.0, 0.0))
        rr = red.get(k, (1.0, 1.0))
        rows.append((k, f"{1000 * peaks[k][0]:.1f}", f"{1000 * peaks[k][1]:.1f}", f"{1000 * rms[k][0]:.1f}",
                     f"{1000 * rms[k][1]:.1f}", f"{rr[0]:.1f}", f"{rr[1]:.1f}", f"{f[0]:.1f}", f"{f[1]:.1f}",
                     "yes" if runs[k].completed else "NO"))
        csv_rows.append(dict(controller=k, peak_lateral_m=peaks[k][0], peak_vertical_m=peaks[k][1],
                             rms_lateral_in_window_m=rms[k][0], rms_vertical_in_window_m=rms[k][1],
                             reduction_lateral=rr[0], reduction_vertical=rr[1],
                             peak_force_hor_n=f[0], peak_force_ver_n=f[1], completed=runs[k].completed))
    out.csv(pd.DataFrame(csv_rows), "closed_loop_peaks.csv")

    # realisation spread: the paper's single record cannot be reproduced, so show the spread
    spread_csv = []
    base_seed = sc.params.turbulence.seed
    for i in range(settings.spread_seeds):
        seed = base_seed + i
        for key, name in names.items():
            r = runs[key] if i == 0 else _run(name, settings, seed=seed)[1]
            py, pz = _peaks(r)
            fy, fz = _force_peaks(r) if key != "off" else (0.0, 0.0)
            spread_csv.append(dict(seed=seed, controller=key, peak_lateral_m=py, peak_vertical_m=pz,
                                   peak_force_hor_n=fy, peak_force_ver_n=fz, completed=r.completed))
    spread = pd.DataFrame(spread_csv)
    out.csv(spread, "realization_spread.csv")
    sp_rows, sp_head = [], {}
    for key in ("off", "PID", "LQR"):
        s = spread[spread.controller == key]
        vals = {}
        for col, scale, unit in (("peak_lateral_m", 1000, "mm"), ("peak_vertical_m", 1000, "mm"),
                                 ("peak_force_hor_n", 1, "N"), ("peak_force_ver_n", 1, "N")):
            vals[col] = (float(s[col].min()), float(s[col].median()), float(s[col].max()))
        sp_head[key] = {c: {"min": v[0], "median": v[1], "max": v[2]} for c, v in vals.items()}
        sp_rows.append((key, *(f"{scale * v[0]:.1f} / {scale * v[1]:.1f} / {scale * v[2]:.1f}" for (c, v), scale in
                               zip(vals.items(), (1000, 1000, 1, 1)))))

    C = out.cmp
    ns = settings.spread_seeds

    def spread_txt(key, col, scale=1.0, unit="m", digits=3):
        lo, hi = sp_head[key][col]["min"], sp_head[key][col]["max"]
        return f"over {ns} realisations {scale * lo:.{digits}g}-{scale * hi:.{digits}g} {unit}"

    for j, (ax, col) in enumerate((("lateral", "peak_lateral_m"), ("vertical", "peak_vertical_m"))):
        C.add("Fig. 12", f"peak {ax} displacement, controller off", "m", paper.SEC33_DISPLACEMENT_M["off"], peaks["off"][j],
              f"one realisation ({spread_txt('off', col)}); the paper's record cannot be regenerated")
    for k in ("PID", "LQR"):
        for j, (ax, col) in enumerate((("lateral", "peak_lateral_m"), ("vertical", "peak_vertical_m"))):
            if k == "PID":
                note = (f"{spread_txt(k, col, 1000, 'mm', 2)}: the paper's high-gain PID on this plant holds the "
                        f"drogue to millimetres; the value depends on the realisation")
            else:
                note = ("the literal paper weights give a slow loop (slowest pole "
                        f"{out.headline['lqr']['slowest_pole_on_our_model_1_s']:.2f} 1/s, Table 3), which only "
                        f"partly rejects gusts near the pendulum frequency ({spread_txt(k, col)}); not adjusted")
            C.add("Fig. 12", f"peak {ax} displacement, {k} on", "m", paper.SEC33_DISPLACEMENT_M["on"], peaks[k][j], note)
    paper_forces = {(k, j): paper.SEC33_PEAK_FORCE_N[(k, ch)] for k in ("PID", "LQR") for j, ch in enumerate(paper.CHANNELS)}
    for (k, j), pv in paper_forces.items():
        ax = ("lateral u_hor", "vertical u_ver")[j]
        col = ("peak_force_hor_n", "peak_force_ver_n")[j]
        lo = sp_head[k][col]["min"]
        below = f"; the paper's value is below all {ns} of ours" if pv < lo else ""
        if k == "PID":
            note = (f"{spread_txt(k, col, 1, 'N', 3)}{below}: the force is set by the gust loads on hose and "
                    "drogue, which depend on the turbulence record and on the plant; the paper's record, "
                    "gust distribution along the hose and actuator model are unknown")
        else:
            note = (f"{spread_txt(k, col, 1, 'N', 3)}{below}: our LQR (literal weights) is slower and lets the "
                    "drogue move, so its force history differs from the paper's")
        C.add("Fig. 13", f"peak {ax} force, {k}", "N", pv, forces[k][j], note)
    pid_lo = (sp_head["PID"]["peak_force_hor_n"]["min"], sp_head["PID"]["peak_force_ver_n"]["min"])

    out.sections["fig12_13"] = (
        '<section id="fig12-13"><h2>Figs. 12-13: the controllers on the nonlinear model in turbulence</h2>'
        f"<p>The paper's turbulence case at 150 m/s, 8000 m (turbulence on from {window[0]:g} s to "
        f"{window[1]:g} s), controller off, with the paper's PID and with the LQR (paper Q, R, designed on "
        f"this flight condition's 2nd-order model, Kalman observer). The controller reads the drogue's "
        f"offset from its balance position and applies u_hor, u_ver at the drogue. Peaks are over the "
        f"whole run, RMS values over the turbulence window. The paper reports 0.5-1 m without control, "
        f"0.5-1 cm with either controller, and peak forces of about 20 N (lateral) and 30 N (vertical) "
        f"for the PID and 70 N and 40 N for the LQR.</p>"
        f"<p>Here: <b>off</b> {peaks['off'][0]:.3f} m lateral and {peaks['off'][1]:.3f} m vertical "
        f"({'inside' if all(0.5 <= p <= 1.0 for p in peaks['off']) else 'not both inside'} the paper's range); <b>PID</b> {1000 * peaks['PID'][0]:.1f} mm and "
        f"{1000 * peaks['PID'][1]:.1f} mm (reduction {red['PID'][0]:.0f} x and {red['PID'][1]:.0f} x) with "
        f"peak forces {forces['PID'][0]:.0f} N and {forces['PID'][1]:.0f} N; <b>LQR with the literal paper "
        f"weights</b> {peaks['LQR'][0]:.3f} m and {peaks['LQR'][1]:.3f} m (reduction only "
        f"{red['LQR'][0]:.1f} x and {red['LQR'][1]:.1f} x) with peak forces {forces['LQR'][0]:.0f} N and "
        f"{forces['LQR'][1]:.0f} N. The PID result "
        f"{'agrees with the paper claim of a sub-centimetre drogue' if max(peaks['PID']) < 0.01 else 'does NOT reach the paper claim of a sub-centimetre drogue'} but "
        f"needs about {forces['PID'][0] / 20:.1f} x and {forces['PID'][1] / 30:.1f} x the paper's forces "
        f"(the smallest peaks over {ns} realisations are {pid_lo[0]:.0f} N and {pid_lo[1]:.0f} N); "
        f"the LQR result does not reproduce the paper: with the paper's weights taken literally the loop "
        f"is slow (Table 3), and this report does not change them.</p>"
        + _html_table(["controller", "peak |dy| [mm]", "peak |dz| [mm]", "RMS dy [mm]", "RMS dz [mm]",
                       "reduction lateral [-]", "reduction vertical [-]", "peak |u_hor| [N]", "peak |u_ver| [N]",
                       "completed"], rows, table_id="table-closed-loop")
        + f"<p>Spread over {settings.spread_seeds} turbulence realisations (seeds {base_seed} to "
          f"{base_seed + settings.spread_seeds - 1}), min / median / max. A single published "
          f"record can only be compared within this spread.</p>"
        + _html_table(["controller", "peak |dy| [mm]", "peak |dz| [mm]", "peak |u_hor| [N]", "peak |u_ver| [N]"],
                      sp_rows, table_id="table-realization-spread")
        + _figure_html("fig12", "fig12_controller_on_off.png", "Fig. 12 (paper Fig. 12)",
                       "Drogue displacement with the controller off (red) and on (blue), per controller (rows): "
                       "lateral, vertical, the controlled displacement alone in millimetres, and the y-z "
                       "trajectory seen from behind (z down).", ("fig12_controller_on_off.csv",))
        + _figure_html("fig13", "fig13_control_forces.png", "Fig. 13 (paper Fig. 13)",
                       "Control forces u_hor (lateral) and u_ver (vertical, positive down) of the PID and the LQR "
                       "in the same turbulence.", ("fig13_control_forces.csv",))
        + '<p class=data>Data: <a href="closed_loop_peaks.csv">closed_loop_peaks.csv</a>, '
          '<a href="realization_spread.csv">realization_spread.csv</a>.</p></section>'
    )
    out.headline["closed_loop"] = {
        k: {"peak_lateral_m": peaks[k][0], "peak_vertical_m": peaks[k][1], "rms_lateral_m": rms[k][0],
            "rms_vertical_m": rms[k][1], "completed": bool(runs[k].completed),
            **({"reduction_lateral": red[k][0], "reduction_vertical": red[k][1],
                "peak_force_hor_n": forces[k][0], "peak_force_ver_n": forces[k][1]} if k != "off" else {})}
        for k in ("off", "PID", "LQR")}
    out.headline["realization_spread"] = sp_head


# --- stage: 3D view and animation ----------------------------------------------------------------
def _stage_hose_3d(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..plotting.figures import plot_hose_3d

    runs, window = ctx["runs"], ctx["window"]
    off, on = runs["off"], runs["PID"]
    t = off.t_s
    m = (t >= window[0]) & (t <= window[1])
    k_lat = int(np.flatnonzero(m)[np.argmax(np.abs(off.drogue_offset_m[m, 1]))])
    k_ver = int(np.flatnonzero(m)[np.argmax(np.abs(off.drogue_offset_m[m, 2]))])
    k_mid = int(np.argmin(np.abs(t - 0.5 * (window[0] + window[1]))))
    shapes = [(off.joints_m[0], "equilibrium (t = 0 s)"),
              (off.joints_m[k_lat], f"off, t = {t[k_lat]:.1f} s (largest lateral)"),
              (off.joints_m[k_ver], f"off, t = {t[k_ver]:.1f} s (largest vertical)"),
              (off.joints_m[k_mid], f"off, t = {t[k_mid]:.1f} s"),
              (on.joints_m[min(k_lat, on.t_s.size - 1)], f"PID on, t = {t[k_lat]:.1f} s")]
    rows = []
    for joints, label in shapes:
        for j, (x, y, z) in enumerate(joints):
            rows.append(dict(shape=label, joint=j, x_m=x, y_m=y, z_m=z))
    out.csv(pd.DataFrame(rows), "fig_hose3d.csv")
    out.figure(plot_hose_3d([s[0] for s in shapes], [s[1] for s in shapes]), "fig_hose3d.png")
    out.sections["hose3d"] = (
        '<section id="hose3d"><h2>The hose in 3D</h2>'
        + _figure_html("fig-hose3d", "fig_hose3d.png", "Hose shape",
                       "The hose (20 links, dots at the joints, big dot the drogue) at its balance position and "
                       "at moments in the turbulence with the controller off, and with the PID on at the moment "
                       "of the largest lateral excursion. The axes are scaled independently: the lateral and "
                       "vertical excursions (about 1 m) are exaggerated relative to the 15 m length.",
                       ("fig_hose3d.csv",))
        + "</section>"
    )


def _stage_animation(out: _Out, settings: ReportSettings, ctx: dict) -> None:
    import pandas as pd

    from ..plotting.figures import animate_hose

    runs, window = ctx["runs"], ctx["window"]
    off, on = runs["off"], runs["PID"]
    path = animate_hose(off, on, out.dir / "anim_turbulence.gif", fps=settings.anim_fps, window_s=window,
                        labels=("controller off", "PID on"))
    out.files.append(path.name)
    frame_t = np.arange(window[0], window[1] + 1e-9, 1.0 / settings.anim_fps)
    rows = []
    for key, r in (("off", off), ("PID", on)):
        idx = np.clip(np.searchsorted(r.t_s, frame_t), 0, r.t_s.size - 1)
        for i in idx:
            for j, (x, y, z) in enumerate(r.joints_m[i]):
                rows.append(dict(run=key, t_s=r.t_s[i], joint=j, x_m=x, y_m=y, z_m=z))
    out.csv(pd.DataFrame(rows), "anim_turbulence.csv")
    size_mb = path.stat().st_size / 1e6
    out.sections["animation"] = (
        '<section id="animation"><h2>Animation: the hose in turbulence, controller off and on</h2>'
        f'<figure id="anim"><img src="anim_turbulence.gif" alt="hose animation">'
        f"<figcaption><b>Animation.</b> Side view (x-z) and rear view (y-z, from behind) of the hose and "
        f"drogue during the turbulence window ({window[0]:g}-{window[1]:g} s, {settings.anim_fps} frames per "
        f"simulated second, real time), controller off (red) and PID on (blue), same turbulence. "
        f"({size_mb:.1f} MB) <span class=data>Data: <a href=\"anim_turbulence.csv\">anim_turbulence.csv</a>."
        f"</span></figcaption></figure></section>"
    )
    out.headline["animation_size_mb"] = size_mb


# --- differences and the comparison table --------------------------------------------------------
def _differences_section(out: _Out, ctx: dict) -> None:
    import pandas as pd

    bf = ctx.get("bending_finding")
    hose = PAPER.hose
    l = hose.link_length_m
    m_link = hose.mass_per_length_kg_m * l
    bend = ("not computed")
    if bf is not None:
        bend = (f"Drogue z = {'/'.join(f'{z:.2f}' for z in bf['paper_z'])} m for "
                f"{'/'.join(str(int(n)) for n in bf['paper_links'])} links with the paper's force "
                f"({'converges' if bf['paper_converges'] else 'does not converge'}); with bending off "
                f"{'/'.join(f'{z:.2f}' for z in bf['off_z'])} m and 'moment' "
                f"{'/'.join(f'{z:.2f}' for z in bf['mom_z'])} m for "
                f"{'/'.join(str(int(n)) for n in bf['off_links'])} links (converge). "
                f"The force 8 E I gamma / l^2 with gamma ~ kappa l grows as 1/l.")
    rows = [
        ("Tangential drag (Eq. 23)", "squares v_t: the drag sign is lost",
         "D_t = -1/2 rho v_t |v_t| A c_t n_k (opposes the axial relative flow)",
         "tiny (c_t = 0.001), but the paper's sign pushes the hose the wrong way half the time"),
        ("Drag shared between joints (Eq. 19)", "indices shifted by one",
         "half of link k's drag on joint k-1, half on joint k; the half on joint 0 goes into the tow point",
         "a consistent lumping; the paper's indices would drop or double a half-link"),
        ("Bending force direction (Eq. 20)", "direction e_{k+1} - e_k printed un-normalized",
         "unit vector of e_{k+1} - e_k, magnitude 8 E I gamma / l^2",
         "otherwise the magnitude would be scaled by ~gamma again"),
        ("Link inertia (Table 1)", "2.816 kg m^2 per link",
         f"used as printed (default); equals mu l * l = {m_link * l:.3f}, probably a slip for a rod's "
         f"m l^2/12 = {m_link * l * l / 12:.3f} kg m^2 (option 'rod')",
         "raises the rotational inertia of the links 15-fold; slows the higher hose modes"),
        ("Hose length", "not stated in the text", "Table 1 row 'Length/m 16' read as 16 m (20 links of 0.8 m)",
         "consistent with the 2.816 reading above"),
        ("Linearization flight condition", "not stated",
         "150 m/s, 8000 m, wake on (the Fig. 12 condition)",
         "Table 2 models differ by factors of 2-3 in DC gain and ~0.6 in frequency; see Table 2"),
        ("LQR weights and observer", "Q, R printed without units; no observer described",
         "Q, R in SI units (m, m s, N); steady-state Kalman observer (documented in the code)",
         "the LQR is much slower than the paper's; see Table 3"),
        ("Turbulence realisation", "one unspecified record", "Dryden MIL-F-8785C filters, seed 2018; spread over seeds shown",
         "peak values can only be compared within the realisation spread"),
        ("Equivalent bending force and link count (finding)", "8 E I gamma / l^2 per joint (Eq. 20)",
         "kept as the default for fidelity; 'moment' option (E I gamma / l restoring moment) converges", bend),
    ]
    df = pd.DataFrame(rows, columns=["topic", "paper", "this project", "effect"])
    out.csv(df, "differences.csv")
    out.sections["differences"] = (
        '<section id="differences"><h2>Where this project and the paper differ</h2>'
        "<p>The paper's text came from a PDF with garbled equations and a few slips; this project follows "
        "one documented reading. Each difference, what the paper has, what is used here, and its effect:</p>"
        + _html_table(["topic", "paper", "this project", "effect"], rows, table_id="table-differences")
        + '<p class=data>Data: <a href="differences.csv">differences.csv</a>.</p></section>'
    )


def _comparison_section(out: _Out) -> None:
    df = out.cmp.dataframe()
    out.csv(df, "comparison.csv")
    rows = []
    for r in out.cmp.rows:
        cls = "ok" if r["ratio_text"] == "inside range" or _agrees(r["ratio"]) else "diff"
        rows.append((r["section"], r["quantity"], r["unit"], r["paper"], _fmt(r["ours"]),
                     ("html", f'<span class="{cls}">{_esc(r["ratio_text"])}</span>'),
                     "reproduced" if cls == "ok" else r["note"]))
    out.sections["comparison"] = (
        '<section id="comparison"><h2>Every paper number beside this project\'s</h2>'
        "<p>Paper value, this project's value, their ratio (green: within 10 % or inside the paper's "
        "range) and, for each large difference, the plain reason. Table 1's inputs are used unchanged "
        "(above); Fig. 3 and Fig. 4 give no numbers in the paper's text and are compared by their stated "
        "trends in their sections. No number has been adjusted to match.</p>"
        + _html_table(["source", "quantity", "unit", "paper", "this project", "ratio", "explanation"], rows,
                      table_id="table-comparison")
        + '<p class=data>Data: <a href="comparison.csv">comparison.csv</a>.</p></section>'
    )


_CSS = """
body{font-family:Helvetica,Arial,sans-serif;max-width:1180px;margin:0 auto;padding:0 18px 60px;color:#222;line-height:1.45}
h1{font-size:1.6em;margin-bottom:.2em} h2{border-bottom:2px solid #ccd;padding-bottom:.15em;margin-top:1.8em}
table{border-collapse:collapse;margin:.6em 0 1em;font-size:.86em} th,td{border:1px solid #ccc;padding:3px 7px;text-align:left;vertical-align:top}
th{background:#eef} tr:nth-child(even) td{background:#fafafa} caption{text-align:left;font-weight:bold}
figure{margin:1em 0 1.6em} figure img{max-width:100%;border:1px solid #ddd} figcaption{font-size:.9em;color:#333}
.data{color:#666;font-size:.9em} .ok{color:#176b1e;font-weight:bold} .diff{color:#a33;font-weight:bold}
.banner{background:#fff3cd;border:2px solid #d39e00;padding:10px 14px;font-size:1.1em;margin:1em 0}
.meta{color:#555;font-size:.9em} code{background:#f3f3f3;padding:0 3px} nav a{margin-right:.8em}
"""


def _page(out: _Out, settings: ReportSettings, elapsed_s: float) -> str:
    h = out.headline
    cl = h.get("closed_loop", {})
    conv = h.get("convergence", {})
    t2 = h.get("table2", {})
    banner = ""
    if settings.name == "fast":
        banner = ('<div class="banner" id="fast-banner"><b>FAST VERSION.</b> This report was built with '
                  "<code>--fast</code>: coarser Fig. 3 grid, shorter turbulence runs "
                  f"({settings.run_duration_s:g} s), fewer convergence steps and link counts, "
                  f"{settings.spread_seeds} turbulence realisations and a coarser animation. Numbers differ "
                  "slightly from the full report; run <code>hosedrogue reproduce</code> without "
                  "<code>--fast</code> for the reference version.</div>")
    summary = []
    if conv:
        summary.append(f"RK4 at the default step {conv['default_step_s']:g} s: drogue error at most "
                       f"{1000 * conv['worst_error_at_default_step_m']:.3g} mm. The paper's equivalent bending force "
                       f"{'converges' if conv['paper_bending_converges'] else 'does not converge'} with the link count "
                       "(it scales as 1/l); bending off / 'moment' converge.")
    if "steady" in h:
        s = h["steady"]
        summary.append(f"Balance position at 150 m/s, 8000 m: drogue {s['drogue_position_m'][2]:.2f} m below and "
                       f"{-s['drogue_position_m'][0]:.2f} m behind the tow point, drag {s['drogue_drag_n']:.0f} N, "
                       f"V_D/L_H = {s['balance_ratio']:.3f}; Fig. 3 trends as the paper states.")
    if t2:
        summary.append(f"Table 2 (linearization condition not stated in the paper): our 2nd-order DC gain is "
                       f"{t2['lateral']['dc_gain_m_n_ratio']:.2f} x / {t2['vertical']['dc_gain_m_n_ratio']:.2f} x and "
                       f"natural frequency {t2['lateral']['natural_frequency_rad_s_ratio']:.2f} x / "
                       f"{t2['vertical']['natural_frequency_rad_s_ratio']:.2f} x the paper's (lateral / vertical).")
    if "table3" in h:
        t3 = h["table3"]
        summary.append(f"Table 3: the paper's PID on the paper's models reproduces it (rise "
                       f"{t3['PID_lateral_rise_time_s']['on_paper_model']:.3f} / {t3['PID_vertical_rise_time_s']['on_paper_model']:.3f} s "
                       f"vs 0.068 / 0.076 s); the LQR with the paper's Q, R gives rise "
                       f"{t3['LQR_lateral_rise_time_s']['on_paper_model']:.1f} / {t3['LQR_vertical_rise_time_s']['on_paper_model']:.1f} s "
                       "vs 0.839 / 0.671 s - not reproduced (weights in SI units make control expensive).")
    if cl:
        summary.append(f"Turbulence at 150 m/s, 8000 m: peak displacement {cl['off']['peak_lateral_m']:.2f} / "
                       f"{cl['off']['peak_vertical_m']:.2f} m off (paper 0.5-1 m), "
                       f"{1000 * cl['PID']['peak_lateral_m']:.1f} / {1000 * cl['PID']['peak_vertical_m']:.1f} mm with PID "
                       f"(paper 5-10 mm) at {cl['PID']['peak_force_hor_n']:.0f} / {cl['PID']['peak_force_ver_n']:.0f} N "
                       f"(paper 20 / 30 N), {cl['LQR']['peak_lateral_m']:.2f} / {cl['LQR']['peak_vertical_m']:.2f} m with "
                       f"the literal-weight LQR (paper 5-10 mm) at {cl['LQR']['peak_force_hor_n']:.0f} / "
                       f"{cl['LQR']['peak_force_ver_n']:.0f} N (paper 70 / 40 N).")
    order = ["comparison", "table1", "differences", "convergence", "fig3", "fig4", "table2", "fig5_8", "table3",
             "fig10_11", "fig12_13", "hose3d", "animation"]
    nav_names = {"comparison": "paper vs ours", "table1": "Table 1", "differences": "differences",
                 "convergence": "convergence", "fig3": "Fig. 3", "fig4": "Fig. 4", "table2": "Table 2",
                 "fig5_8": "Figs. 5-8", "table3": "Table 3", "fig10_11": "Figs. 10-11", "fig12_13": "Figs. 12-13",
                 "hose3d": "3D", "animation": "animation"}
    anchors = {"fig5_8": "fig5-8", "fig10_11": "fig10-11", "fig12_13": "fig12-13"}
    nav = "".join(f'<a href="#{anchors.get(k, k)}">{nav_names[k]}</a>' for k in order if k in out.sections)
    body = "".join(out.sections[k] for k in order if k in out.sections)
    when = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    title = "hosedrogue: reproduction of Wu et al. (2018), Sec. 2.3 and 3" + (" (FAST VERSION)" if settings.name == "fast" else "")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f"<title>{_esc(title)}</title><style>{_CSS}</style></head><body>"
        f"<h1>{_esc(title)}</h1>"
        f"<p class=meta>Wu L., Sun Y., Huang B., Liu J., <i>Modeling Method and Control Strategy for Hose-Drogue "
        f"Aerial Refueling System</i>, Trans. Nanjing Univ. Aeronaut. Astronaut. 35(2), 2018. Every result below is "
        f"regenerated from this project's own model (hosedrogue {_esc(__version__)}, {_esc(settings.name)} build, "
        f"{elapsed_s:.0f} s, {when}). Frame S_p: origin at the tow point, x forward, y right, z down; SI units.</p>"
        f"{banner}"
        '<section id="summary"><h2>Summary</h2><ul>' + "".join(f"<li>{_esc(s)}</li>" for s in summary) + "</ul>"
        '<p class=meta>Headline numbers: <a href="report.json">report.json</a>.</p></section>'
        f"<nav>{nav}</nav>{body}</body></html>\n"
    )


# --- the build ------------------------------------------------------------------------------------
_STAGES: tuple[tuple[str, Callable], ...] = (
    ("parameters", _stage_parameters),
    ("convergence", _stage_convergence),
    ("steady sweep (Fig. 3)", _stage_sweep),
    ("turbulence at four airspeeds (Fig. 4)", _stage_turbulence_speeds),
    ("linear model (Table 2, Figs. 5-8)", _stage_linear),
    ("controllers on linear models (Table 3, Figs. 10-11)", _stage_controllers),
    ("controllers in turbulence (Figs. 12-13)", _stage_closed_loop),
    ("hose in 3D", _stage_hose_3d),
    ("animation", _stage_animation),
)


def build_report(out_dir, fast: bool = False, progress: bool = True) -> dict:
    """Regenerate the paper's Sec. 2.3 and 3 results and write the report into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Output folder (created if needed; existing files of the same names are overwritten).
    fast : bool
        Coarser grids, shorter runs and fewer convergence steps (well under a minute); the page
        says prominently that it is the fast version.
    progress : bool
        Show a tqdm progress bar over the stages on stderr.

    Returns
    -------
    dict
        The headline numbers, as written to ``report.json``.
    """
    from tqdm import tqdm

    settings = FAST if fast else FULL
    out = _Out(Path(out_dir))
    out.dir.mkdir(parents=True, exist_ok=True)
    ctx: dict[str, Any] = {}
    timings: dict[str, float] = {}
    t_start = time.perf_counter()
    bar = tqdm(total=len(_STAGES) + 1, desc="reproduce", unit="stage", disable=not progress, file=sys.stderr)
    ctx["bar"] = bar
    try:
        for label, stage in _STAGES:
            bar.set_description(f"reproduce: {label}")
            t0 = time.perf_counter()
            stage(out, settings, ctx)
            timings[label] = time.perf_counter() - t0
            bar.update(1)
        bar.set_description("reproduce: page")
        _differences_section(out, ctx)
        _comparison_section(out)
        elapsed = time.perf_counter() - t_start
        out.headline = {"build": {"version": __version__, "settings": settings.name, "fast": bool(fast),
                                  "elapsed_s": elapsed, "stage_times_s": timings}, **out.headline}
        headline = _finite_json(out.headline)
        (out.dir / "report.json").write_text(json.dumps(headline, indent=2) + "\n")
        (out.dir / "index.html").write_text(_page(out, settings, elapsed), encoding="utf-8")
        bar.update(1)
    finally:
        bar.close()
    return headline
