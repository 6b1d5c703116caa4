"""The drogue that steers itself with control surfaces, against the ideal force of the paper
(docs/model.md, "Actuated drogue"; docs/docking-results.md, "Actuated drogue"):

* :func:`servo_margins` - the paper's PID and LQR closed around the linearized hose with a servo
  of each bandwidth: phase margin, crossover, closed-loop stability (what sizes the servo);
* :func:`convergence_table` - the actuated loop against the ideal-force loop as the servo gets
  fast (limits far away, no drag increment): the difference and its order in the bandwidth;
* :func:`claims_runs`, :func:`claims_table`, :func:`within_one_cm` - the paper's turbulence case
  and light / moderate / severe turbulence at its flight condition, PID and LQR, ideal force and
  actuated drogue: peaks, RMS, force, the time the surfaces are saturated, and where the paper's
  "within 1 cm" holds;
* the capture rate against the surfaces' authority (deflection limit) and servo bandwidth in the
  approach scenarios is a set of docking cells (:func:`hosedrogue.studies.docking_grid.actuator_specs`,
  :func:`hosedrogue.studies.docking.run_grid`, :func:`hosedrogue.studies.docking_statistics.actuator_table`).

Example (seconds)::

    from hosedrogue.studies.drogue_actuator import claims_runs, claims_table, servo_margins
    print(servo_margins((10.0, 30.0)))
    print(claims_table(claims_runs(seeds=1, levels=("paper",), controllers=("pid",))))
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import ParameterError
from ..spec.sections import DrogueActuator

__all__ = ["LEVELS", "CONTROLLERS", "VARIANTS", "MARGIN_BANDWIDTHS_HZ", "CONVERGENCE_BANDWIDTHS_HZ", "ONE_CM_M",
           "resolved_params", "with_surfaces", "authority_n", "claims_scenario", "claims_runs", "claims_table", "within_one_cm", "servo_margins",
           "convergence_table"]

#: Turbulence cases of the claims: the paper's (isotropic 1.5 m/s, its scenario) and the MIL-F-8785C
#: intensities at its altitude, each in the paper's 20 s window at 150 m/s, 8000 m.
LEVELS = ("paper", "light", "moderate", "severe")
#: The paper's controllers, by the scenario type.
CONTROLLERS = ("pid", "lqr")
#: Servo bandwidths of the margin table [Hz]: from the "few hertz" of the pendulum modes up.
MARGIN_BANDWIDTHS_HZ = (5.0, 10.0, 12.0, 15.0, 20.0, 30.0, 50.0, 100.0)
#: Servo bandwidths of the convergence to the ideal force [Hz] (each a doubling).
CONVERGENCE_BANDWIDTHS_HZ = (50.0, 100.0, 200.0)
#: The paper's claim: "the steady state position error varies within 1 cm" [m].
ONE_CM_M = 0.01
#: The drogues of the claims, by the ``force`` label of their rows: the ideal force (the paper's),
#: the [drogue_actuator] defaults, the defaults with a quarter of the authority (5 deg: 136 N per
#: axis at the paper's flight condition, about the ideal PID's peak in the paper's case), and a
#: 12 Hz servo (the paper's PID keeps 4 and 12 deg of phase margin: the edge of its stability).
VARIANTS = {"ideal": None, "actuated": {}, "actuated-5deg": {"max_deflection_deg": 5.0},
            "actuated-12hz": {"bandwidth_hz": 12.0}}


def resolved_params(params, section: DrogueActuator):
    """``params`` with the RK4 step halved (and ``output_every`` doubled: the same output times)
    until it resolves the surfaces' servo (:attr:`hosedrogue.spec.sections.DrogueActuator.max_step_s`).

    Parameters
    ----------
    params : hosedrogue.spec.params.Params
        The parameters (``numerics.step_s`` [s], ``output_every`` [-]).
    section : DrogueActuator
        The surfaces.

    Returns
    -------
    hosedrogue.spec.params.Params
    """
    h, every = params.numerics.step_s, params.numerics.output_every
    while h > section.max_step_s:
        h, every = h / 2.0, every * 2
    return params if h == params.numerics.step_s else params.replace(numerics={"step_s": h, "output_every": every})


def with_surfaces(scenario, section: DrogueActuator | None = None):
    """The scenario with its drogue steered by control surfaces, its RK4 step halved as often as
    the servo needs (:func:`resolved_params`).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        Any scenario (its ``[actuator]`` without limits).
    section : DrogueActuator, optional
        The surfaces (default: the defaults).

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    section = DrogueActuator() if section is None else section
    return dataclasses.replace(scenario, params=resolved_params(scenario.params, section),
                               loop=dataclasses.replace(scenario.loop, drogue_actuator=section))


def authority_n(section: DrogueActuator, params=None) -> float:
    """The largest force per axis [N] the surfaces make at the nominal dynamic pressure (free stream
    1/2 rho V^2 of the flight condition, the wake aside) for a command along one axis: the
    minimum-norm mixing saturates when the surface most aligned with the axis reaches its limit,
    ``F = (n_s / 2) q S C_F,delta delta_max / max_k abs(dot(t_k, axis))`` (the smaller of the two axes).

    Parameters
    ----------
    section : DrogueActuator
        The surfaces.
    params : Params, optional
        Flight condition (default the paper's).

    Returns
    -------
    float
    """
    from ..environment.atmosphere import density
    from ..model.drogue_actuator import surface_directions
    from ..spec.params import PAPER

    p = PAPER if params is None else params
    q = 0.5 * density(p.flight.altitude_m) * p.flight.density_scale * p.flight.airspeed_m_s ** 2
    t = np.abs(surface_directions(section))
    per = 0.5 * section.surfaces * q * section.reference_area_m2 * section.force_slope_per_rad
    return float(per * math.radians(section.max_deflection_deg) / t.max(axis=0).max())


def claims_scenario(level: str, controller: str, variant: str = "ideal", duration_s: float | None = None,
                    base=None):
    """The scenario of one claims case: ``paper-turbulence-<controller>`` (or the user's ``base``
    with that controller) in the level's turbulence.

    Parameters
    ----------
    level : str
        One of :data:`LEVELS` ("paper": the paper's 1.5 m/s isotropic; else the MIL-F-8785C
        intensity at 8000 m).
    controller : str
        "pid" or "lqr".
    variant : str
        A key of :data:`VARIANTS`: the ideal force, or the drogue's surfaces ("actuated": the
        ``[drogue_actuator]`` defaults, i.e. ``paper-turbulence-pid-actuated`` for the paper's PID
        case). Every variant runs at the RK4 step the default surfaces need (2.5 ms).
    duration_s : float, optional
        Run length [s] (default the scenario's, 60 s for the paper's).
    base : hosedrogue.scenarios.Scenario, optional
        The user's fixed-length scenario: its model, flight condition, turbulence (level "paper"
        keeps it; the others set its intensity) and its ``[drogue_actuator]`` (the actuated
        variants start from it instead of the defaults), flown with ``controller`` (the scenario's
        own options if it is that type). Named ``<base name>-<controller>[-<level>]``.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    from ..scenarios import load_scenario

    if level not in LEVELS or controller not in CONTROLLERS or variant not in VARIANTS:
        raise ParameterError(f"level, controller, variant = {level!r}, {controller!r}, {variant!r}: must be one of "
                             f"{LEVELS}, {CONTROLLERS} and {tuple(VARIANTS)}")
    if base is None:
        sc, surfaces = load_scenario(f"paper-turbulence-{controller}"), DrogueActuator()
    else:
        base.require_model("fixed-length", "--scenario", "the actuator study's claims cases fly the fixed-length "
                           "hose (an approach for the capture cells goes to --approach)")
        surfaces = base.loop.drogue_actuator or DrogueActuator()
        sc = base.with_controller(controller)
        sc = dataclasses.replace(sc, name=f"{base.name}-{controller}",
                                 loop=dataclasses.replace(sc.loop, drogue_actuator=None))
    sc = sc.with_overrides(duration_s=duration_s)
    params = resolved_params(sc.params, surfaces)  # every drogue at the surfaces' step: like with like
    if level != "paper":
        params = params.replace(turbulence={"intensity": level})
        sc = dataclasses.replace(sc, name=f"{sc.name}-{level}")
    sc = dataclasses.replace(sc, params=params)
    fields = VARIANTS[variant]
    return sc if fields is None else with_surfaces(sc, dataclasses.replace(surfaces, **fields))


def claims_runs(seeds: int = 1, duration_s: float | None = None, levels=LEVELS, controllers=CONTROLLERS,
                variants=tuple(VARIANTS), status=None, base=None):
    """One row per run of the claims cases: level x controller x drogue (:data:`VARIANTS`) x seed.

    Seed i is the scenario's seed (2018) plus i, the same record for every case of a level (common
    random numbers: the ideal and the actuated drogue meet the same gusts).

    Parameters
    ----------
    seeds : int
        Turbulence realisations per case [-], >= 1.
    duration_s : float, optional
        Run length [s] (default 60 s; the window is the paper's 10-30 s).
    levels, controllers, variants : sequence of str
        Subsets of :data:`LEVELS`, :data:`CONTROLLERS` and the keys of :data:`VARIANTS`.
    status : callable, optional
        ``status(text)`` is told which case runs.
    base : hosedrogue.scenarios.Scenario, optional
        The user's fixed-length scenario instead of the paper's (:func:`claims_scenario`).

    Returns
    -------
    pandas.DataFrame
        level, controller, force (the variant), seed, completed, the window statistics
        (peak and RMS offsets [m], peak forces [N]) and, actuated, the surfaces' statistics
        (:func:`hosedrogue.results.surfaces.surface_statistics`; NaN for the ideal force).
    """
    import pandas as pd

    from ..scenarios.runner import run

    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise ParameterError(f"seeds = {seeds!r}: must be an integer >= 1")
    rows = []
    for level in levels:
        for c in controllers:
            for variant in variants:
                case = claims_scenario(level, c, variant, duration_s, base)
                if status:
                    status(f"actuated drogue: {case.name}, {variant}")
                for i in range(seeds):
                    sc = case.with_overrides(seed=case.params.turbulence.seed + i)
                    r = run(sc)
                    rows.append({"level": level, "controller": c, "force": variant, "seed": sc.params.turbulence.seed,
                                 "completed": bool(r.completed), **r.statistics()})
    return pd.DataFrame(rows)


def claims_table(runs):
    """Per level, controller and force: medians and maxima over the seeds, and the fraction of
    seeds whose peak lateral and vertical offsets both stay within 1 cm.

    Parameters
    ----------
    runs : pandas.DataFrame
        :func:`claims_runs`.

    Returns
    -------
    pandas.DataFrame
        level, controller, force, seeds, completed_fraction; peak_dy_m, peak_dz_m (median and
        max), rms_radial_m (median), peak_u_n (median, max) [m, N]; deflection_saturated_frac and
        rate_saturated_frac (median, max) [-]; within_1cm_fraction [-].
    """
    import pandas as pd

    out = []
    for (level, c, force), g in runs.groupby(["level", "controller", "force"], sort=False):
        ok = g[g["completed"]]
        worst = np.maximum(g["peak_dy_m"], g["peak_dz_m"]).where(g["completed"], np.inf)
        row = {"level": level, "controller": c, "force": force, "seeds": len(g),
               "completed_fraction": float(g["completed"].mean())}
        for col in ("peak_dy_m", "peak_dz_m", "peak_u_n", "deflection_saturated_frac", "rate_saturated_frac"):
            vals = ok[col] if col in ok else pd.Series(dtype=float)
            row[f"{col}_median"] = float(vals.median()) if len(vals) else math.nan
            row[f"{col}_max"] = float(vals.max()) if len(vals) else math.nan
        row["rms_radial_m_median"] = float(ok["rms_radial_m"].median()) if len(ok) else math.nan
        row["within_1cm_fraction"] = float(np.mean(worst < ONE_CM_M))
        out.append(row)
    return pd.DataFrame(out)


def within_one_cm(table) -> dict:
    """Where the paper's "within 1 cm" holds: per controller and force, the levels at which every
    seed keeps both peak offsets below 1 cm, and those at which some seed does not.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`claims_table`.

    Returns
    -------
    dict
        ``"<controller>-<force>" -> {"holds": [levels], "fails": [levels], "worst_peak_m": {level: m}}``.
    """
    out = {}
    for (c, force), g in table.groupby(["controller", "force"], sort=False):
        holds = [r.level for r in g.itertuples() if r.within_1cm_fraction == 1.0]
        fails = [r.level for r in g.itertuples() if r.within_1cm_fraction < 1.0]
        worst = {r.level: float(max(r.peak_dy_m_max, r.peak_dz_m_max)) for r in g.itertuples()}
        out[f"{c}-{force}"] = {"holds": holds, "fails": fails, "worst_peak_m": worst}
    return out


def _servo_tf(bandwidth_hz: float, order: int, damping: float):
    import control

    w = 2 * math.pi * bandwidth_hz
    return control.tf([1.0], [1.0 / w, 1.0]) if order == 1 else control.tf([w * w], [1.0, 2 * damping * w, w * w])


def _margin(loop_jw: np.ndarray, w: np.ndarray) -> tuple[float, float]:
    """The smallest phase margin [deg] over the gain crossovers of a loop's frequency response
    (-C G A: the controller carries the sign) and the crossover where it is [Hz]."""
    mag = np.abs(loop_jw)
    idx = np.where(np.diff(np.sign(mag - 1.0)) != 0)[0]
    if idx.size == 0:
        return math.inf, math.nan
    pm = [(math.degrees(np.angle(loop_jw[i])) + 180.0 + 180.0) % 360.0 - 180.0 for i in idx]
    k = int(np.argmin(pm))
    return float(pm[k]), float(w[idx[k]] / (2 * math.pi))


def servo_margins(bandwidths_hz=MARGIN_BANDWIDTHS_HZ, order: int = 2, damping: float = 0.7, controllers=CONTROLLERS,
                  params=None):
    """The paper's controllers closed around the linearized hose through a servo of each bandwidth.

    The surfaces' force at the nominal dynamic pressure, mixed at that pressure, is the commanded
    force through the servo's transfer function (every surface has the same servo), so the loop
    of channel i is ``-C_ii(s) G_ii(s) A(s)``: its phase margin and crossover per channel, and the
    stability of the whole closed loop (two channels, every hose state, both servos). Ideal force:
    ``bandwidth_hz = inf``.

    Parameters
    ----------
    bandwidths_hz : sequence of float
        Servo bandwidths [Hz] (inf: no servo).
    order : {1, 2}
        Servo order.
    damping : float
        Damping of the second-order servo [-].
    controllers : sequence of str
        "pid", "lqr" (the scenarios' designs).
    params : Params, optional
        Flight condition and model (default the paper's turbulence case's).

    Returns
    -------
    pandas.DataFrame
        controller, bandwidth_hz, lateral/vertical phase margin [deg] and crossover [Hz], the
        largest real part of the closed-loop poles [1/s] and ``stable``.
    """
    import control
    import pandas as pd

    from ..analysis.equilibrium import solve_equilibrium
    from ..analysis.linearize import linearize
    from ..analysis.reduction import split_channels
    from ..controllers.design import design_controller
    from ..model.system import HoseModel
    from ..scenarios import load_scenario

    p = load_scenario("paper-turbulence-pid").params if params is None else params
    model = HoseModel(p)
    eq = solve_equilibrium(p, model=model)
    lm = linearize(p, eq, model)
    channels = split_channels(lm.ss)
    w = np.logspace(-2, 3.5, 20000)
    g = [np.asarray(control.frequency_response(ch, w).complex).ravel() for ch in channels]
    rows = []
    for c in controllers:
        ctrl = design_controller(c, {}, p)
        css = ctrl.as_statespace()
        cjw = [np.asarray(control.frequency_response(css, w).complex)[i, i].ravel() for i in range(2)]
        for f in bandwidths_hz:
            servo = control.tf([1.0], [1.0]) if math.isinf(f) else _servo_tf(f, order, damping)
            a = np.asarray(control.frequency_response(servo, w).complex).ravel()
            row = {"controller": c, "bandwidth_hz": float(f)}
            for i, name in enumerate(("lateral", "vertical")):
                row[f"{name}_margin_deg"], row[f"{name}_crossover_hz"] = _margin(-cjw[i] * g[i] * a, w)
            servos = control.append(control.ss(servo), control.ss(servo))
            loop = control.feedback(control.series(servos, lm.ss), css, sign=+1)
            row["max_pole_real_1_s"] = float(np.max(np.real(loop.poles())))
            row["stable"] = row["max_pole_real_1_s"] < 0.0
            rows.append(row)
    return pd.DataFrame(rows)


def convergence_table(bandwidths_hz=CONVERGENCE_BANDWIDTHS_HZ, duration_s: float = 2.0, step_s: float = 0.00025,
                      controller: str = "pid"):
    """The actuated loop's approach to the ideal-force loop as the servo gets fast.

    The paper's turbulence (on from t = 0) for ``duration_s``, the paper's controller; the surfaces'
    limits far beyond the force (90 deg, 1e5 deg/s), no drag increment, second-order servos
    (damping 0.7) of each bandwidth; RK4 at ``step_s`` for every run (ideal included).

    Parameters
    ----------
    bandwidths_hz : sequence of float
        Servo bandwidths [Hz], ascending.
    duration_s : float
        Run length [s].
    step_s : float
        RK4 step [s] (resolve the fastest servo: 2 pi f step below ~0.5).
    controller : str
        "pid" or "lqr".

    Returns
    -------
    pandas.DataFrame
        bandwidth_hz, max_offset_difference_m (largest |offset difference| over the run [m]),
        max_force_difference_n [N], order (the exponent p of difference ~ bandwidth^-p from the
        previous bandwidth; NaN first), bandwidth_x_difference_m_hz [m Hz], ideal_motion_m (the
        ideal loop's largest lateral or vertical offset [m]), completed.
    """
    import pandas as pd

    from ..scenarios import load_scenario
    from ..scenarios.runner import run

    base = load_scenario(f"paper-turbulence-{controller}").with_overrides(duration_s=duration_s)
    every = max(1, int(round(0.002 / step_s)))
    base = dataclasses.replace(base, params=base.params.replace(
        turbulence={"start_s": 0.0, "duration_s": duration_s}, numerics={"step_s": step_s, "output_every": every}))
    ideal = run(base)
    rows, prev = [], None
    for f in bandwidths_hz:
        r = run(with_surfaces(base, DrogueActuator(bandwidth_hz=float(f), max_deflection_deg=90.0, max_rate_deg_s=1e5,
                                                   drag_slope_per_rad2=0.0)))
        d = float(np.max(np.abs(r.drogue_offset_m - ideal.drogue_offset_m)))
        order = math.nan if prev is None else math.log(prev[1] / d) / math.log(f / prev[0])
        rows.append({"bandwidth_hz": float(f), "max_offset_difference_m": d,
                     "max_force_difference_n": float(np.max(np.abs(r.control_force_n - ideal.control_force_n))),
                     "order": order, "bandwidth_x_difference_m_hz": d * f,
                     "ideal_motion_m": float(np.max(np.abs(ideal.drogue_offset_m[:, 1:]))),
                     "completed": bool(r.completed)})
        prev = (f, d)
    return pd.DataFrame(rows)
