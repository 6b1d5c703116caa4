"""Report section "Manoeuvres" (docs/model.md §9): the tanker's turns, climbs and descents.

The studies are library code (:mod:`hosedrogue.studies.manoeuvres`): the balance position against
the bank angle and the flight-path angle and a 25-degree turn taken apart term by term, the turn
entry ``turn-entry-30`` open loop and with the paper's PID, and the capture rate of the approach
in moderate turbulence in a 25-degree turn against level flight (Monte Carlo campaigns with Wilson
intervals, kept in ``manoeuvres/<scenario>/`` of the report folder). This module writes their
CSVs, figures (:mod:`hosedrogue.studies.manoeuvres_figures`), the HTML section and
``report.json["manoeuvres"]``. Grids and run counts are the settings' ``manoeuvre_*`` fields.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .markup import esc, figure_html, html_table
from .shared import campaign_execution

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["ManoeuvresResult", "build"]


@dataclass(frozen=True)
class ManoeuvresResult:
    """Headline numbers of the section.

    Parameters
    ----------
    beyond_apparent_gravity_m : numpy.ndarray
        What the 25-degree turn does to the drogue besides the apparent gravity (3,) [m].
    settling_time_s : float
        Time after the roll's end for the drogue to stay within 1 cm of the turn's balance [s].
    capture_rates : tuple
        Capture rate in level flight and in the turn [-].
    """

    beyond_apparent_gravity_m: np.ndarray
    settling_time_s: float
    capture_rates: tuple


def _mm(v) -> str:
    return f"{1e3 * v:+.1f}"


def _write_csv(out, steady, entry, capture) -> None:
    import pandas as pd

    from ..analysis.steady_flight import TURN_TERMS

    for sw, name in ((steady.bank, "manoeuvres_bank.csv"), (steady.flight_path, "manoeuvres_flight_path.csv")):
        p = sw.drogue_position_m
        out.csv(pd.DataFrame({sw.angle: sw.angles_deg, "drogue_x_m": p[:, 0], "drogue_y_m": p[:, 1],
                              "drogue_z_m": p[:, 2], "exit_tension_n": sw.exit_tension_n}), name)
    b = steady.breakdown
    out.csv(pd.DataFrame({"term": list(TURN_TERMS), "dx_m": b.contributions_m[:, 0], "dy_m": b.contributions_m[:, 1],
                          "dz_m": b.contributions_m[:, 2]}), "manoeuvres_turn_breakdown.csv")
    d0, d1 = entry.open_loop_m - entry.level_m, entry.pid_m - entry.level_m
    out.csv(pd.DataFrame({"t_s": entry.t_s, "bank_deg": entry.bank_deg, "open_loop_dy_m": d0[:, 1],
                          "open_loop_dz_m": d0[:, 2], "pid_dy_m": d1[:, 1], "pid_dz_m": d1[:, 2],
                          "pid_u_y_n": entry.pid_force_n[:, 0], "pid_u_z_n": entry.pid_force_n[:, 1]}),
            "manoeuvres_turn_entry.csv")
    out.csv(pd.DataFrame({"case": list(capture.labels), "scenario": list(capture.scenarios),
                          "runs": [c["runs"] for c in capture.capture], "capture_rate": [c["rate"] for c in capture.capture],
                          "ci95_low": [c["ci95"][0] for c in capture.capture],
                          "ci95_high": [c["ci95"][1] for c in capture.capture]}), "manoeuvres_capture.csv")


def _steady_html(steady) -> str:
    from ..analysis.steady_flight import TURN_TERMS

    b = steady.breakdown
    rows = [(term, _mm(c[0]), _mm(c[1]), _mm(c[2])) for term, c in zip(TURN_TERMS, b.contributions_m)]
    rows.append((("html", "<b>the whole turn</b>"), *(_mm(v) for v in b.turn_m)))
    rows.append((("html", "<b>besides the apparent gravity</b>"), *(_mm(v) for v in b.beyond_apparent_gravity_m)))
    table = html_table(["term (added in this order)", "dx [mm]", "dy [mm]", "dz [mm]"], rows,
                       table_id="table-manoeuvres-breakdown",
                       caption=f"A {b.bank_deg:g}-degree coordinated level turn taken apart: the continuous hose's "
                               "drogue position (tanker body axes: x forward, y right, z down) as each term is added")
    bank, path = steady.bank, steady.flight_path
    i45 = int(np.argmax(bank.angles_deg))
    return (
        "<p><b>Steady flight.</b> A steady coordinated turn or climb is a steady frame: the balance position "
        "solves the level-flight statics with the frame's apparent forces. In a level turn at bank phi the "
        "tow point's centripetal acceleration makes the apparent gravity g / cos(phi) along the tanker's z "
        f"axis: at {bank.angles_deg[i45]:g} degrees the drogue hangs "
        f"{bank.drogue_position_m[i45, 2] - bank.drogue_position_m[0, 2]:.2f} m lower than in level flight and the "
        f"exit tension rises from {bank.exit_tension_n[0]:.0f} N to {bank.exit_tension_n[i45]:.0f} N. In a climb "
        "gravity tilts aft in the tanker's axes (the hose trails further aft and higher), in a descent forward. "
        f"Besides the apparent gravity a {b.bank_deg:g}-degree turn moves the drogue by "
        f"{', '.join(f'{1e3 * v:+.0f} mm' for v in b.beyond_apparent_gravity_m)} (x, y, z): the wake's vortices "
        "carry the turn's lift (1 / cos(phi) times the weight), and the hose, trailing along the curved path, sees "
        "the air turn relative to the tanker (toward the inside of the turn, and up: the path curves up in the "
        "banked tanker's axes); the centrifugal field's variation along the hose is a millimetre.</p>" + table)


def _entry_html(entry) -> str:
    s1, s2 = (entry.settling_time_s[b] for b in sorted(entry.settling_time_s, reverse=True))
    shift = entry.turn_m - entry.level_m
    fy, fz = entry.pid_final_force_n
    fine = f"{s2:.0f} s" if np.isfinite(s2) else "more than the run"
    return (
        f"<p><b>Turn entry</b> (scenario <code>turn-entry-30</code>, the converged model): from {entry.roll_start_s:g} s "
        f"the tanker rolls into 30 degrees at 5 deg/s, reaching it at {entry.roll_end_s:.1f} s. The hose lags the roll "
        "and swings: the drogue moves up to "
        f"{entry.peak_offset_m[0]:.2f} m sideways and {entry.peak_offset_m[1]:.2f} m vertically from its level balance "
        f"position, on its way to the turn's, {1e3 * shift[1]:+.0f} mm right and {1e3 * shift[2]:+.0f} mm down; after the "
        f"roll it is at most {entry.overshoot_m:.2f} m from the turn's balance position, within 1 cm of it for good "
        f"{s1:.0f} s after the roll and within 1 mm {fine} after. The paper's PID (designed for level flight, its "
        f"reference the level balance position) holds the drogue within {1e3 * entry.pid_peak_offset_m:.0f} mm of it "
        f"through the whole entry, ending with {abs(fz):.0f} N {'up' if fz < 0 else 'down'} and {abs(fy):.0f} N "
        f"{'left' if fy < 0 else 'right'} to hold it there in the turn.</p>")


def _capture_html(capture) -> str:
    rows = [(lbl, ("html", f"<code>{esc(name)}</code>"), c["runs"], f"{c['rate']:.3f}",
             f"[{c['ci95'][0]:.3f}, {c['ci95'][1]:.3f}]", c["by_result"].get("miss", 0),
             c["by_result"].get("failed latch", 0))
            for lbl, name, c in zip(capture.labels, capture.scenarios, capture.capture)]
    table = html_table(["case", "scenario", "runs", "capture rate", "95 % Wilson interval", "misses", "failed latches"],
                       rows, table_id="table-manoeuvres-capture",
                       caption="The receiver's approach in moderate turbulence (the same turbulence seeds in both)")
    verdict = ("the 95 % intervals overlap: no significant difference at this number of runs" if capture.overlap()
               else "the 95 % intervals do not overlap: a significant difference")
    (la, ca), (lb, cb) = zip(capture.labels, capture.capture)
    return (f"<p><b>Capture rate in a turn.</b> {esc(la)} {ca['rate']:.3f}, {esc(lb)} {cb['rate']:.3f} over "
            f"{ca['runs']} runs each: {verdict}. In the turn the run starts at the turn's balance position and the "
            "probe closes in the tanker's axes; the turbulence is a frozen field along the circular path.</p>" + table)


def _fast_note(settings) -> str:
    if not settings.fast:
        return ""
    return (f'<p class=diff id="manoeuvres-fast">FAST VERSION of this section: {len(settings.manoeuvre_banks_deg)} '
            f"bank angles and {len(settings.manoeuvre_flight_paths_deg)} flight-path angles, "
            f"{settings.manoeuvre_runs} runs per capture campaign (the full report: 200), so the capture rates say "
            "little.</p>")


def _html(settings, steady, entry, capture) -> str:
    return (
        '<section id="manoeuvres"><h2>Manoeuvres: turns, climbs and descents, speed changes</h2>'
        + _fast_note(settings)
        + "<p>The tanker flies coordinated turns (bank phi &gt; 0 right wing down, turning right at g tan(phi) / V about "
          "the vertical), climbs and descents (flight-path angle gamma &gt; 0 climbing) and speed changes. The hose "
          "equations are written in the tanker's body axes at the tow point, the frame of every output, with the "
          "frame's acceleration, angular velocity and angular acceleration as apparent forces, and the air at rest "
          "far from the tanker (docs: The model, section 9).</p>"
        + _steady_html(steady)
        + figure_html("fig-manoeuvres-steady", "fig_manoeuvres_steady.png", "Steady turns and climbs",
                      "Balance position (the paper's model) in a steady coordinated level turn against the bank angle "
                      "(left) and in a steady climb or descent against the flight-path angle (right): the drogue's "
                      "position from its level-flight one, and the exit tension.",
                      ("manoeuvres_bank.csv", "manoeuvres_flight_path.csv", "manoeuvres_turn_breakdown.csv"))
        + _entry_html(entry)
        + figure_html("fig-manoeuvres-entry", "fig_manoeuvres_turn_entry.png", "Turn entry",
                      "Roll into a 30-degree turn at 5 deg/s (shaded): bank angle, the drogue's lateral and vertical "
                      "position from its level balance position open loop and with the paper's PID (dashed: the "
                      "turn's balance position), and the PID's force.", ("manoeuvres_turn_entry.csv",))
        + _capture_html(capture)
        + figure_html("fig-manoeuvres-capture", "fig_manoeuvres_capture.png", "Capture in a turn",
                      "Capture rate of the approach in moderate turbulence in level flight and in a 25-degree turn, "
                      "with 95 % Wilson intervals.", ("manoeuvres_capture.csv",))
        + "</section>")


def build(out: ReportFolder, settings: ReportSettings) -> ManoeuvresResult:
    """Run the manoeuvre studies; write their CSV files, figures and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Bank and flight-path grids [deg], runs and workers of the capture campaigns.

    Returns
    -------
    ManoeuvresResult
    """
    from ..studies.manoeuvres_figures import plot_turn_capture, plot_turn_entry
    from ..studies.manoeuvres import steady_flight_study, turn_capture_study, turn_entry_study

    out.status("manoeuvres: steady flight")
    steady = steady_flight_study(banks_deg=settings.manoeuvre_banks_deg, paths_deg=settings.manoeuvre_flight_paths_deg)
    out.status("manoeuvres: turn entry")
    entry = turn_entry_study()
    out.status("manoeuvres: capture campaigns")
    folder = out.dir / "manoeuvres"
    shutil.rmtree(folder, ignore_errors=True)  # rewritten at every build, as the docking campaigns
    capture = turn_capture_study(settings.manoeuvre_runs, folder, **campaign_execution(settings.manoeuvre_workers))
    _write_csv(out, steady, entry, capture)
    out.figure(steady.figures()["steady_flight"], "fig_manoeuvres_steady.png")
    out.figure(plot_turn_entry(entry), "fig_manoeuvres_turn_entry.png")
    out.figure(plot_turn_capture(capture), "fig_manoeuvres_capture.png")
    out.section("manoeuvres", "manoeuvres", _html(settings, steady, entry, capture))
    b = steady.breakdown
    out.summarize(f"Manoeuvres: a {b.bank_deg:g}-degree turn lowers the drogue by {b.turn_m[2]:.2f} m, most of it the "
                  f"apparent gravity g / cos(phi); the rest ({1e3 * b.beyond_apparent_gravity_m[1]:.0f} mm right, "
                  f"{1e3 * b.beyond_apparent_gravity_m[2]:.0f} mm down) is the wake carrying the turn's lift and the air "
                  f"turning relative to the tanker; after a roll into 30 degrees the drogue settles within 1 cm "
                  f"in {entry.settling_time_s[0.01]:.0f} s; capture rate {capture.capture[0]['rate']:.2f} level, "
                  f"{capture.capture[1]['rate']:.2f} in a 25-degree turn ({capture.capture[0]['runs']} runs).")
    out.record("manoeuvres", {
        "bank_deg": steady.bank.angles_deg.tolist(), "bank_drogue_position_m": steady.bank.drogue_position_m.tolist(),
        "bank_exit_tension_n": steady.bank.exit_tension_n.tolist(),
        "flight_path_deg": steady.flight_path.angles_deg.tolist(),
        "flight_path_drogue_position_m": steady.flight_path.drogue_position_m.tolist(),
        "flight_path_exit_tension_n": steady.flight_path.exit_tension_n.tolist(),
        "breakdown_bank_deg": b.bank_deg, "turn_m": b.turn_m.tolist(),
        "beyond_apparent_gravity_m": b.beyond_apparent_gravity_m.tolist(),
        "turn_entry": {"peak_offset_m": entry.peak_offset_m.tolist(), "overshoot_m": entry.overshoot_m,
                       "settling_time_1cm_s": entry.settling_time_s[0.01],
                       "settling_time_1mm_s": entry.settling_time_s[0.001],
                       "pid_peak_offset_m": entry.pid_peak_offset_m, "pid_final_force_n": entry.pid_final_force_n.tolist()},
        "capture": {lbl: {"scenario": name, **c} for lbl, name, c in zip(capture.labels, capture.scenarios, capture.capture)},
    })
    return ManoeuvresResult(b.beyond_apparent_gravity_m, entry.settling_time_s[0.01],
                            tuple(c["rate"] for c in capture.capture))
