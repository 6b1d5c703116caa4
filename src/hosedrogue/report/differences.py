"""Report section "Where this project and the paper differ": each reading of the paper, what is
used here and its effect."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..spec.params import PAPER
from .markup import html_table, slash_join

if TYPE_CHECKING:
    from .convergence import ConvergenceResult
    from .parameters import ParametersResult
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build"]


def _bending_finding(c) -> str:
    """The link-count finding of the convergence section in one paragraph."""
    if c is None:
        return "not computed"
    return (f"Drogue z = {slash_join(c.paper_z_m, '.2f')} m for "
            f"{slash_join((int(n) for n in c.paper_links), 'd')} links with the paper's force "
            f"({'converges' if c.paper_converges else 'does not converge'}); with bending off "
            f"{slash_join(c.off_z_m, '.2f')} m and 'moment' "
            f"{slash_join(c.moment_z_m, '.2f')} m for "
            f"{slash_join((int(n) for n in c.consistent_links), 'd')} links (converge). "
            f"The force 8 E I gamma / l^2 with gamma ~ kappa l grows as 1/l.")


def _lqr_weights() -> str:
    """The paper's LQR weights split per channel, e.g. ``lateral Q = diag(12000, 8000), R = 0.4; ...``."""
    from ..controllers.lqr import PAPER_LQR_Q, PAPER_LQR_R

    q, r = np.diag(PAPER_LQR_Q), np.diag(PAPER_LQR_R)
    return "; ".join(f"{ch} Q = diag({q[2 * i]:g}, {q[2 * i + 1]:g}), R = {r[i]:g}"
                     for i, ch in enumerate(("lateral", "vertical")))


def _rows(parameters, convergence) -> list[tuple[str, str, str, str]]:
    from ..model.system import link_inertias

    hose, fl = PAPER.hose, PAPER.flight
    l, m_link = parameters.link_length_m, parameters.link_mass_kg
    rod_inertia = float(link_inertias(PAPER.replace(hose={"link_inertia": "rod"}), [l])[0])  # m l^2 / 12
    return [
        ("Tangential drag (Eq. 23)", "squares v_t: the drag sign is lost",
         "D_t = -1/2 rho v_t |v_t| A c_t n_k (opposes the axial relative flow)",
         f"tiny (c_t = {hose.tangential_drag_coefficient:g}), but the paper's sign pushes the hose the wrong way "
         "half the time"),
        ("Drag shared between joints (Eq. 19)", "indices shifted by one",
         "half of link k's drag on joint k-1, half on joint k; the half on joint 0 goes into the tow point",
         "a consistent lumping; the paper's indices would drop or double a half-link"),
        ("Bending force direction (Eq. 20)", "direction e_{k+1} - e_k printed un-normalized",
         "unit vector of e_{k+1} - e_k, magnitude 8 E I gamma / l^2",
         "otherwise the magnitude would be scaled by ~gamma again"),
        ("Link inertia (Table 1)", f"{hose.link_inertia_kg_m2:g} kg m^2 per link",
         f"used as printed (default); equals mu l * l = {m_link * l:.3f}, probably a slip for a rod's "
         f"m l^2/12 = {rod_inertia:.3f} kg m^2 (option 'rod')",
         f"raises the rotational inertia of the links {hose.link_inertia_kg_m2 / rod_inertia:.0f}-fold; slows the "
         "higher hose modes"),
        ("Hose length", "not stated in the text",
         f"Table 1 row 'Length/m {hose.length_m:g}' read as {hose.length_m:g} m ({hose.links} links of {l:g} m)",
         f"consistent with the {hose.link_inertia_kg_m2:g} reading above"),
        ("Linearization flight condition", "not stated",
         f"{fl.airspeed_m_s:g} m/s, {fl.altitude_m:g} m, wake on (the Fig. 12 condition)",
         "Table 2 models differ by factors of 2-3 in DC gain and ~0.6 in frequency; see Table 2"),
        ("LQR states, weights and observer", "integrator augmentation (Eq. 34) but u = -K x-hat (Eq. 36); "
         "a 4 x 4 Q and 2 x 2 R without units; no observer described",
         f"Q on the two balanced states of each 2nd-order channel ({_lqr_weights()}), u = -K x, static "
         "prefilter for reference steps; steady-state Kalman observer (documented in the code); the "
         "integral-action reading is a sensitivity",
         "reproduces Table 3's lateral LQR row; the vertical row and both overshoots differ (every "
         "closed-loop pole is real); see Table 3"),
        ("Turbulence realisation", "one unspecified record",
         f"Dryden MIL-F-8785C filters, seed {PAPER.turbulence.seed}; spread over seeds shown",
         "peak values can only be compared within the realisation spread"),
        ("Equivalent bending force and link count (finding)", "8 E I gamma / l^2 per joint (Eq. 20)",
         "kept as the default for fidelity; 'moment' option (E I gamma / l restoring moment) converges",
         _bending_finding(convergence)),
    ]


def build(out: ReportFolder, settings: ReportSettings, *, parameters: ParametersResult,
          convergence: ConvergenceResult | None) -> None:
    """Write ``differences.csv`` and the differences section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Build settings (unused).
    parameters : hosedrogue.report.parameters.ParametersResult
        Link length [m] and mass [kg].
    convergence : hosedrogue.report.convergence.ConvergenceResult or None
        The link-count finding (None: not computed).

    Returns
    -------
    None
    """
    import pandas as pd

    rows = _rows(parameters, convergence)
    out.csv(pd.DataFrame(rows, columns=["topic", "paper", "this project", "effect"]), "differences.csv")
    out.section("differences", "differences", (
        '<section id="differences"><h2>Where this project and the paper differ</h2>'
        "<p>The paper's text came from a PDF with garbled equations and a few slips; this project follows "
        "one documented reading. Each difference, what the paper has, what is used here, and its effect:</p>"
        + html_table(["topic", "paper", "this project", "effect"], rows, table_id="table-differences")
        + '<p class=data>Data: <a href="differences.csv">differences.csv</a>.</p></section>'
    ))
    return None
