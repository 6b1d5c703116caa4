"""Report section "Receiver aircraft": the F-16's trim against Stevens, Lewis & Johnson (2015)
Table 3.6-2, and the docking campaign of the F-16 receiver beside the point receiver on the same
seeds (docs/receiver.md, "In the engagement").

The study is :mod:`hosedrogue.studies.receiver`; this module writes its CSVs and figures, the
HTML section with every number read from the results and ``report.json["receiver"]``. The
campaigns are kept in ``receiver/campaigns/<scenario>/`` of the report folder, rewritten at every
build; their runs are the docking section's (``ReportSettings.docking_runs``, ``docking_workers``).
"""

from __future__ import annotations

import shutil
from typing import TYPE_CHECKING

import numpy as np

from ..studies.receiver import SCENARIOS, receiver_campaigns, trim_check
from .markup import esc, figure_html, html_table
from .settings import FULL
from .shared import campaign_execution

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build"]

#: The campaigns' folder inside the report folder (one subfolder per scenario).
CAMPAIGNS = "receiver/campaigns"

def _trim_html(check) -> str:
    rows = [(f"{r.airspeed_ft_s:g}", f"{r.throttle_book:g} / {r.throttle:.4f}", f"{r.alpha_deg_book:g} / {r.alpha_deg:.4f}",
             f"{r.elevator_deg_book:g} / {r.elevator_deg:.4f}", "yes" if r.within else "no")
            for r in check.table.itertuples()]
    return html_table(["airspeed [ft/s]", "throttle [-]: book / trim", "alpha [deg]: book / trim",
                       "elevator [deg]: book / trim", "all three round to the printed digits"], rows,
                      table_id="table-receiver-trim")


def _miss_stats(miss: np.ndarray) -> str:
    m = miss[np.isfinite(miss)]
    if not m.size:
        return "-"
    return " / ".join(f"{v:.3f}" for v in (m.mean(), np.median(m), np.percentile(m, 95), m.max()))


def _campaign_html(camp) -> str:
    rows = []
    for name in SCENARIOS:
        c = camp.capture[name]
        link = f'<a href="{CAMPAIGNS}/{name}/summary.json">{esc(name)}</a>'
        rows.append((("html", link), int(c["runs"]), f"{c['rate']:.3f}", f"{c['ci95'][0]:.3f} - {c['ci95'][1]:.3f}",
                     _miss_stats(camp.miss(name))))
    return html_table(["campaign", "runs", "capture rate [-]", "Wilson 95 % interval [-]",
                       "miss [m]: mean / median / 95th percentile / largest"], rows, table_id="table-receiver-capture")


def _html(check, camp, settings) -> str:
    p = camp.paired()
    f16, point = (camp.capture[n] for n in SCENARIOS)
    fast = (f"<p><strong>Fast version:</strong> {settings.docking_runs} runs per campaign against the full "
            f"report's {FULL.docking_runs}; the rates, intervals and miss statistics are rough.</p>"
            if settings.fast else "")
    diff = ("" if p["runs"] < 2 else
            f" On the {p['runs']} seeds where both reach the coupler plane the F-16 misses by "
            f"{1e3 * p['mean_m']:+.1f} mm on average (standard error {1e3 * p['se_m']:.1f} mm, "
            f"{p['mean_m'] / p['se_m']:.1f} of them from zero), by more in {p['first_larger']} of them.")
    return (
        '<section id="receiver-aircraft"><h2>Receiver aircraft</h2>' + fast
        + "<p>The receiver as an aircraft (docs/receiver.md): the F-16 of Stevens, Lewis &amp; Johnson (2015), "
        "its tables written as data with their source. Its level-flight trim at sea level, under the book's "
        f"g, against the book's Table 3.6-2: {check.within} of its {len(check.table)} points have throttle, "
        "angle of attack and elevator that all round to the printed digits.</p>"
        + _trim_html(check)
        + figure_html("fig-receiver-trim", "receiver_trim.png", "F-16 trim against Table 3.6-2",
                      "Throttle, angle of attack and elevator of the F-16's level-flight trim at sea level over "
                      "airspeed (lines) and the book's points (markers).", ("receiver_trim.csv", "receiver_trim_curve.csv"))
        + "<p>The same approach (1 m/s closure, moderate turbulence, the bow wave, the PD docking controller "
        "<code>pd_docking</code> every 20 ms) flown by the F-16 (<code>approach-f16-moderate</code>: trimmed "
        "behind the tanker, its inner loop tracking the controller's velocity command) and by the point receiver "
        "(<code>approach-moderate-docking</code>), on the same turbulence seeds. F-16: capture rate "
        f"{f16['rate']:.3f} [{f16['ci95'][0]:.3f}, {f16['ci95'][1]:.3f}]; point: {point['rate']:.3f} "
        f"[{point['ci95'][0]:.3f}, {point['ci95'][1]:.3f}] (Wilson 95 %).{diff}</p>"
        + _campaign_html(camp)
        + figure_html("fig-receiver-miss", "receiver_miss_cdf.png", "Miss distributions of the two receivers",
                      "Empirical CDFs of the miss distance at the coupler plane over the campaigns' runs, the F-16 "
                      "(solid) and the point receiver (dashed), beside the capture radius.", ("receiver_runs.csv",))
        + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings) -> None:
    """Check the F-16's trim, run the two receivers' campaigns: tables, figures, report.json.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``docking_runs``: runs per campaign; ``docking_workers``: dask workers (None: this process);
        ``receiver_trim_points``: airspeeds of the trim curve.

    Returns
    -------
    None
    """
    import pandas as pd

    out.status("receiver aircraft: trim")
    check = trim_check(settings.receiver_trim_points)
    out.csv(check.table, "receiver_trim.csv")
    out.csv(pd.DataFrame(check.curve), "receiver_trim_curve.csv")
    out.figure(check.figure(), "receiver_trim.png")
    folder = out.dir / CAMPAIGNS
    shutil.rmtree(folder, ignore_errors=True)  # the report's campaigns are its own: never resumed
    out.status("receiver aircraft: campaigns")
    camp = receiver_campaigns(settings.docking_runs, folder, **campaign_execution(settings.docking_workers))
    out.csv(pd.DataFrame(camp.runs), "receiver_runs.csv")
    out.figure(camp.figure(), "receiver_miss_cdf.png")
    out.section("receiver-aircraft", "Receiver aircraft", _html(check, camp, settings))
    f16, point = (camp.capture[n] for n in SCENARIOS)
    p = camp.paired()
    out.summarize(f"Receiver aircraft: the F-16's trim matches {check.within} of Table 3.6-2's {len(check.table)} "
                  f"points to their printed digits; docking in moderate turbulence, F-16 capture rate {f16['rate']:.3f} "
                  f"[{f16['ci95'][0]:.3f}, {f16['ci95'][1]:.3f}] against the point receiver's {point['rate']:.3f} "
                  f"({p['runs']} paired seeds, F-16 miss {1e3 * p['mean_m']:+.1f} mm on average).")
    out.record("receiver", {"trim_points_within": check.within, "trim_points": len(check.table),
                            "capture": {n: camp.capture[n] for n in SCENARIOS},
                            "miss_paired_difference": {("f16_larger" if k == "first_larger" else k): v for k, v in p.items()
                                                       if np.isfinite(v)}})
    return None
