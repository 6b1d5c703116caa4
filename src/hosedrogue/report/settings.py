"""Grid sizes and run lengths of a report build: the full reference version and the fast one.

Every difference between the two versions is a field of :class:`ReportSettings`; the sections
read these fields, never the version's name.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..studies.docking_grid import (ACTUATOR_LEVELS, CLOSURE_SPEEDS_M_S, DEFLECTION_LIMITS_DEG, FORCE_CONTROLLERS,
                                    FORCE_LEVELS, FORCE_LIMITS_N, SERVO_BANDWIDTHS_HZ)
from ..studies.drogue_actuator import LEVELS as ACTUATOR_CLAIM_LEVELS
from ..studies.whip_loads import CLOSURE_SPEEDS_M_S as WHIP_CLOSURE_SPEEDS_M_S
from ..studies.whip_loads import STIFFNESSES_N as WHIP_STIFFNESSES_N

__all__ = ["ReportSettings", "FULL", "FAST"]


@dataclass(frozen=True)
class ReportSettings:
    """Grid sizes and run lengths of one report build (``FULL`` or ``FAST``).

    Parameters
    ----------
    name : str
        ``"full"`` or ``"fast"`` (recorded in report.json).
    fast : bool
        The fast version: the page shows a banner and each section says where it is coarser.
    sweep_altitudes_m : tuple of float
        Fig. 3 altitudes [m].
    sweep_airspeeds_m_s : tuple of float
        Fig. 3 airspeeds [m/s].
    run_duration_s : float or None
        Length of every turbulence run [s]; None: the scenario's own.
    steps_s : tuple of float
        RK4 steps of the step-convergence study [s].
    reference_step_s : float
        Reference step of that study [s].
    links_paper_bending : tuple of int
        Link counts of the link-convergence study with the paper's bending force.
    links_consistent : tuple of int
        Link counts with bending off and with the ``"moment"`` option.
    spread_seeds : int
        Turbulence realisations for the spread of the peak values.
    sensitivity_altitudes_m : tuple of float
        Linearization conditions of the Table 2 sensitivity study [m].
    sensitivity_airspeeds_m_s : tuple of float
        Linearization conditions of that study [m/s].
    anim_fps : int
        Frames per second of simulated time in the GIF [1/s].
    bode_points : int
        Frequency points of Fig. 7.
    long_run_seeds : tuple of int
        Turbulence seeds of the long-runs blow-up study.
    long_run_cap_s : float
        Length cap of its runs [s] (the turbulence record has this length too).
    long_run_hour_s : float or None
        Length of the stable model's run [s]; None: the scenario's hour.
    accuracy_links : tuple of int
        Link counts of the accuracy-per-cost study (each a doubling of the previous).
    accuracy_steps_s : tuple of float
        RK4 steps of the ``paper-turbulence`` step study [s] (each must divide 0.1 s).
    accuracy_reference_step_s : float
        Reference step of that study [s].
    docking_runs : int
        Runs (turbulence seeds) per campaign of the docking section's grid (turbulence level x
        controller x bow wave).
    docking_workers : int or None
        Dask worker processes of the docking campaigns; None: run them in this process.
    docking_closure_speeds_m_s : tuple of float
        Probe closure speeds of the closure-speed study [m/s].
    docking_force_limits_n : tuple of float
        Force limits per axis of the force-limit study [N].
    docking_force_levels : tuple of str
        Turbulence levels of the force-limit study.
    docking_force_controllers : tuple of str
        Drogue controllers of the force-limit study.
    engagement_links : int or None
        Links of the engagement section's runs; None: the shipped scenarios' mesh (then the two
        fields below are ignored).
    engagement_step_s : float or None
        Integration step of those runs [s] (with ``engagement_links``).
    engagement_output_every : int or None
        Output every this many steps (with ``engagement_links``).
    engagement_duration_s : float or None
        Simulated length of those runs [s]; None: the scenarios' own.
    engagement_animation_after_contact_s : float
        The engagement GIF runs from 0.5 s before contact to this long after it [s].
    whip_stiffnesses_n : tuple of float
        Axial stiffnesses of the whip-load study [N].
    whip_closure_speeds_m_s : tuple of float
        Probe closure speeds of that study [m/s].
    whip_links : int or None
        Links of its runs; None: the shipped scenarios' mesh and step.
    whip_step_s : float or None
        Integration step of its runs [s] (with ``whip_links``).
    manoeuvre_banks_deg : tuple of float
        Bank angles of the steady-turn sweep [deg].
    manoeuvre_flight_paths_deg : tuple of float
        Flight-path angles of the steady climb and descent sweep [deg].
    manoeuvre_runs : int
        Runs per capture campaign of the approach in a turn and in level flight.
    manoeuvre_workers : int or None
        Dask worker processes of those campaigns; None: in this process.
    actuator_seeds : int
        Turbulence realisations per case of the actuated drogue's claims (level x controller x drogue).
    actuator_levels : tuple of str
        Turbulence cases of those claims (``hosedrogue.studies.drogue_actuator.LEVELS``).
    actuator_runs : int
        Runs per campaign of the capture rate against the surfaces' deflection limit and bandwidth.
    actuator_deflections_deg : tuple of float
        Deflection limits of that study [deg].
    actuator_bandwidths_hz : tuple of float
        Servo bandwidths of that study [Hz].
    actuator_capture_levels : tuple of str
        Turbulence levels of that study.
    receiver_trim_points : int
        Airspeeds of the F-16's trim curve in the receiver aircraft section, beside Table 3.6-2's
        16 points (each trim about 0.3 s of CPU).
    """

    name: str
    fast: bool
    sweep_altitudes_m: tuple
    sweep_airspeeds_m_s: tuple
    run_duration_s: float | None
    steps_s: tuple
    reference_step_s: float
    links_paper_bending: tuple
    links_consistent: tuple
    spread_seeds: int
    sensitivity_altitudes_m: tuple
    sensitivity_airspeeds_m_s: tuple
    anim_fps: int
    bode_points: int
    long_run_seeds: tuple
    long_run_cap_s: float
    long_run_hour_s: float | None
    accuracy_links: tuple
    accuracy_steps_s: tuple
    accuracy_reference_step_s: float
    docking_runs: int
    docking_workers: int | None
    docking_closure_speeds_m_s: tuple
    docking_force_limits_n: tuple
    docking_force_levels: tuple
    docking_force_controllers: tuple
    engagement_links: int | None
    engagement_step_s: float | None
    engagement_output_every: int | None
    engagement_duration_s: float | None
    engagement_animation_after_contact_s: float
    whip_stiffnesses_n: tuple
    whip_closure_speeds_m_s: tuple
    whip_links: int | None
    whip_step_s: float | None
    manoeuvre_banks_deg: tuple
    manoeuvre_flight_paths_deg: tuple
    manoeuvre_runs: int
    manoeuvre_workers: int | None
    actuator_seeds: int
    actuator_levels: tuple
    actuator_runs: int
    actuator_deflections_deg: tuple
    actuator_bandwidths_hz: tuple
    actuator_capture_levels: tuple
    receiver_trim_points: int = 68  # as docs/img/receiver_trim.png


#: The reference version of the report.
FULL = ReportSettings(
    name="full",
    fast=False,
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
    long_run_seeds=(2018, 2019, 2020),
    long_run_cap_s=3600.0,
    long_run_hour_s=None,
    accuracy_links=(5, 10, 20, 40, 80, 160),
    accuracy_steps_s=(0.01, 0.02, 0.025),
    accuracy_reference_step_s=0.000625,
    docking_runs=200,
    docking_workers=2,  # the wall times in docs/engagement.md are on two
    docking_closure_speeds_m_s=CLOSURE_SPEEDS_M_S,
    docking_force_limits_n=FORCE_LIMITS_N,
    docking_force_levels=FORCE_LEVELS,
    docking_force_controllers=FORCE_CONTROLLERS,
    engagement_links=None,
    engagement_step_s=None,
    engagement_output_every=None,
    engagement_duration_s=None,
    engagement_animation_after_contact_s=6.0,  # the whip and the hose's settling after it
    whip_stiffnesses_n=WHIP_STIFFNESSES_N,
    whip_closure_speeds_m_s=WHIP_CLOSURE_SPEEDS_M_S,
    whip_links=None,
    whip_step_s=None,
    manoeuvre_banks_deg=tuple(float(b) for b in range(0, 46, 5)),
    manoeuvre_flight_paths_deg=(-10.0, -7.5, -5.0, -2.5, 0.0, 2.5, 5.0, 7.5, 10.0),
    manoeuvre_runs=200,
    manoeuvre_workers=2,
    actuator_seeds=8,  # as spread_seeds: the claims' peaks over the realisations
    actuator_levels=ACTUATOR_CLAIM_LEVELS,
    actuator_runs=200,
    actuator_deflections_deg=DEFLECTION_LIMITS_DEG,
    actuator_bandwidths_hz=SERVO_BANDWIDTHS_HZ,
    actuator_capture_levels=ACTUATOR_LEVELS,
)

#: The fast version (``--fast``): coarser grids, shorter runs; the page says so prominently.
FAST = ReportSettings(
    name="fast",
    fast=True,
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
    long_run_seeds=(2018,),
    long_run_cap_s=300.0,
    long_run_hour_s=120.0,
    accuracy_links=(5, 10, 20),
    accuracy_steps_s=(0.02,),
    accuracy_reference_step_s=0.005,
    docking_runs=4,  # per cell: the machinery and the page, not the statistics (the full report: 200)
    docking_workers=None,  # 4 runs per cell do not pay for starting a cluster
    docking_closure_speeds_m_s=(0.5, 1.0, 2.0),  # the ends and the shipped speed
    docking_force_limits_n=(25.0, 100.0),  # the smallest and the middle one
    docking_force_levels=("moderate",),
    docking_force_controllers=("pid",),
    engagement_links=40,  # the doubling check then runs 80
    engagement_step_s=0.0025,  # the stiff SDIRK at 40 links of 0.4 m (the shipped: 5 ms at 160, the locked reel 2 ms)
    engagement_output_every=4,  # output every 10 ms, as shipped
    engagement_duration_s=8.0,  # contact at 2 s and the whip after it
    engagement_animation_after_contact_s=4.0,
    whip_stiffnesses_n=(1e5, 1e6, 1e8),  # the ends and the shipped stiffness
    whip_closure_speeds_m_s=(1.0, 2.5),
    whip_links=40,
    whip_step_s=0.0025,  # as the fast engagement runs
    manoeuvre_banks_deg=(0.0, 15.0, 30.0, 45.0),
    manoeuvre_flight_paths_deg=(-10.0, 0.0, 10.0),
    manoeuvre_runs=2,  # the campaigns' machinery, not their statistics
    manoeuvre_workers=None,
    actuator_seeds=1,
    actuator_levels=("paper", "severe"),  # the paper's case and the one where the claim fails
    actuator_runs=4,
    actuator_deflections_deg=(2.0, 20.0),  # below the PID's peak force in moderate turbulence, and the default
    actuator_bandwidths_hz=(10.0, 30.0),  # below the PID's stability limit, and the default
    actuator_capture_levels=("moderate",),
    receiver_trim_points=8,  # the curve's shape, not its detail (the book's 16 points are trimmed in both)
)
