"""MATLAB ``.mat`` files (version 5, :func:`scipy.io.savemat`) of simulations and linear models.

Every array keeps full double precision (the CSV files round to 10 significant digits), every
signal has its name and unit next to it, and names follow the project's SI suffixes
(``_m``, ``_m_s``, ``_n``, ``_s``; :func:`hosedrogue.units.unit_of`). In MATLAB::

    r = load('timeseries.mat');  plot(r.t_s, r.signals.drogue_dy_m)
    m = load('linear_model.mat');  sys = ss(m.A, m.B, m.C, m.D, 'InputName', cellstr(m.input_names))
    c = load('pid.mat');  K = ss(c.A, c.B, c.C, c.D, 'InputName', cellstr(c.input_names), ...
                                 'OutputName', cellstr(c.output_names));  c.lateral.K_P

Controllers (:func:`pid_mat_dict`, :func:`lqr_mat_dict`) are written as the realization that runs
in the loop (measured offset [m] in, force [N] out, feedback sign inside) beside their gains.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..results.matlab_file import cellstr as _cellstr, save_mat as _save, state_names  # noqa: F401 - re-exported
from ..units import unit_of  # noqa: F401 - re-exported (the names' units)


def simulation_mat_dict(result) -> dict:
    """The content of a run's ``.mat`` file (:meth:`hosedrogue.results.run.RunResult.mat_dict`).

    Parameters
    ----------
    result : hosedrogue.results.run.RunResult
        A finished (or stopped) run of either hose model.

    Returns
    -------
    dict
    """
    return result.mat_dict()


def write_simulation_mat(result, path: str | Path) -> Path:
    """Write a run to a MATLAB file (:meth:`hosedrogue.results.run.RunResult.to_mat`).

    Parameters
    ----------
    result : hosedrogue.results.run.RunResult
        The run.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return result.to_mat(path)


def linear_mat_dict(lm, channels, table2: dict) -> dict:
    """The content of a linear model's ``.mat`` file.

    Parameters
    ----------
    lm : hosedrogue.analysis.linearize.LinearModel
        Full-order model ``x' = A x + B u, y = C x + D u`` about the balance position.
    channels : hosedrogue.controllers.design.ReducedChannels
        The lateral and vertical channels at the requested order.
    table2 : dict
        ``{"lateral": (num, den), "vertical": (num, den)}``: each channel's transfer function,
        descending powers of s, monic denominator (:func:`hosedrogue.analysis.reduction.table2_form`).

    Returns
    -------
    dict
        ``A, B, C, D`` (SI: states [rad, rad/s], inputs [N], outputs [m]); ``state_names``,
        ``input_names`` (``u_y_n``, ``u_z_n``: the control force at the drogue, lateral and vertical), ``input_units``, ``output_names``
        (``P_ny_m``, ``P_nz_m``), ``output_units``; ``x_eq`` (4n x 1, the balance state);
        per channel ``lateral`` / ``vertical`` structs with ``num``, ``den`` (1 x k),
        ``A, B, C, D`` of the reduced realization, ``poles`` [rad/s], ``input_name`` and
        ``output_name``; ``order`` (0 for full); ``flight`` struct (altitude_m, airspeed_m_s,
        wake, links).
    """
    params = lm.params
    n = params.hose.links
    out = {
        "A": np.asarray(lm.A, dtype=np.float64), "B": np.asarray(lm.B, dtype=np.float64),
        "C": np.asarray(lm.C, dtype=np.float64), "D": np.asarray(lm.D, dtype=np.float64),
        "state_names": _cellstr(state_names(n)),
        "input_names": _cellstr(["u_y_n", "u_z_n"]), "input_units": _cellstr(["N", "N"]),
        "output_names": _cellstr(["P_ny_m", "P_nz_m"]), "output_units": _cellstr(["m", "m"]),
        "x_eq": lm.equilibrium.state.reshape(-1, 1),
        "order": 0 if channels.order is None else int(channels.order),
        "flight": {"altitude_m": float(params.flight.altitude_m), "airspeed_m_s": float(params.flight.airspeed_m_s),
                   "wake": bool(params.wake.enabled), "links": int(n)},
    }
    for name, sys_, u, y in (("lateral", channels.lateral, "u_y_n", "P_ny_m"),
                             ("vertical", channels.vertical, "u_z_n", "P_nz_m")):
        num, den = table2[name]
        poles = np.sort_complex(np.asarray(sys_.poles()))
        out[name] = {
            "num": np.asarray(num, dtype=np.float64).reshape(1, -1),
            "den": np.asarray(den, dtype=np.float64).reshape(1, -1),
            "A": np.atleast_2d(np.asarray(sys_.A, dtype=np.float64)),
            "B": np.atleast_2d(np.asarray(sys_.B, dtype=np.float64)),
            "C": np.atleast_2d(np.asarray(sys_.C, dtype=np.float64)),
            "D": np.atleast_2d(np.asarray(sys_.D, dtype=np.float64)),
            "poles": poles.reshape(-1, 1),
            "input_name": u, "output_name": y,
        }
    return out


def write_linear_mat(lm, channels, table2: dict, path: str | Path) -> Path:
    """Write a linear model to a MATLAB file (see :func:`linear_mat_dict` for the variables).

    Parameters
    ----------
    lm : hosedrogue.analysis.linearize.LinearModel
        Full-order linear model.
    channels : hosedrogue.controllers.design.ReducedChannels
        Reduced lateral and vertical channels.
    table2 : dict
        Transfer functions per channel, ``{"lateral": (num, den), "vertical": (num, den)}``.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return _save(linear_mat_dict(lm, channels, table2), path)


#: The controller's inputs and outputs in a controller's ``.mat`` file: the measured drogue offset
#: [m] (lateral, vertical) in, the drogue force [N] out (the run's column names).
CONTROLLER_INPUTS = (("P_ny_m", "m"), ("P_nz_m", "m"))
CONTROLLER_OUTPUTS = (("u_y_n", "N"), ("u_z_n", "N"))
#: The realization's convention, written into the file.
CONTROLLER_CONVENTION = ("x' = A x + B y, u = C x + D y; y: measured drogue offset from the balance position [m], "
                         "u: force on the drogue [N]; the negative feedback sign is inside (u = -K y for a gain K)")
#: A PID channel's gains and their units (Eq. 33: K_P + K_I/s + K_D N s/(s + N)).
PID_GAIN_UNITS = (("K_P", "N/m"), ("K_I", "N/(m s)"), ("K_D", "N s/m"), ("N", "rad/s"))


def _struct_of_plant(plant: dict) -> dict:
    """The design plant's description (the CLI's ``plant``) as a MATLAB struct."""
    out = {"source": str(plant["source"]), "order": int(plant["order"])}
    if "flight" in plant:
        out["flight"] = {k: (bool(v) if isinstance(v, bool) else float(v)) for k, v in plant["flight"].items()}
    for ch in ("lateral", "vertical"):
        out[ch] = {"num": np.asarray(plant[ch]["num"], dtype=np.float64).reshape(1, -1),
                   "den": np.asarray(plant[ch]["den"], dtype=np.float64).reshape(1, -1)}
    return out


def _realization(controller, state_names, state_units) -> dict:
    names = list(state_names)
    if len(names) != controller.n_states:
        raise ValueError(f"{len(names)} state names for a controller of {controller.n_states} states")
    return {
        "A": np.atleast_2d(np.asarray(controller.A, dtype=np.float64)).reshape(controller.n_states, -1),
        "B": np.asarray(controller.B, dtype=np.float64), "C": np.asarray(controller.C, dtype=np.float64),
        "D": np.asarray(controller.D, dtype=np.float64),
        "state_names": _cellstr(names), "state_units": _cellstr(state_units),
        "input_names": _cellstr([n for n, _ in CONTROLLER_INPUTS]),
        "input_units": _cellstr([u for _, u in CONTROLLER_INPUTS]),
        "output_names": _cellstr([n for n, _ in CONTROLLER_OUTPUTS]),
        "output_units": _cellstr([u for _, u in CONTROLLER_OUTPUTS]),
        "convention": CONTROLLER_CONVENTION,
    }


def _step_struct(step: dict | None) -> dict:
    keys = ("rise_time_s", "settling_time_s", "overshoot_pct")
    if not step:
        return {}
    out = {k: float("nan") if step.get(k) is None else float(step[k]) for k in keys}
    if step.get("targets"):
        out.update({f"target_{k}": float(step["targets"][k]) for k in keys})
    if "targets_met" in step:  # a tuned design: whether its step meets the bounds (the closest otherwise)
        out["targets_met"] = bool(step["targets_met"])
    return out


def pid_mat_dict(gains: dict, controller, *, source: str, plant: dict, steps: dict | None = None) -> dict:
    """The content of a PID's ``.mat`` file (``hosedrogue design pid --format mat``).

    Parameters
    ----------
    gains : dict
        ``{"lateral": PIDGains, "vertical": PIDGains}``.
    controller : hosedrogue.controllers.linear.LinearController
        The two-channel realization (:func:`hosedrogue.controllers.pid.pid_controller`).
    source : str
        Where the gains come from ("tuned", "paper Eq. 33").
    plant : dict
        The design plant: ``source``, ``order``, optional ``flight``, per channel ``num``/``den``.
    steps : dict, optional
        Per channel the unit step's ``rise_time_s`` [s], ``settling_time_s`` [s],
        ``overshoot_pct`` [%] on the design model, and if tuned its ``targets`` (the bounds, same
        keys) and ``targets_met`` (False: the closest design found, which misses them).

    Returns
    -------
    dict
        ``type`` ('pid'), ``source``; the realization ``A, B, C, D`` with ``state_names``,
        ``state_units``, ``input_names`` (``P_ny_m``, ``P_nz_m``), ``input_units``,
        ``output_names`` (``u_y_n``, ``u_z_n``), ``output_units`` and ``convention``;
        ``gain_names`` / ``gain_units`` (K_P N/m, K_I N/(m s), K_D N s/m, N rad/s); per channel
        ``lateral`` / ``vertical`` structs with ``K_P``, ``K_I``, ``K_D``, ``N``, ``input_name``,
        ``output_name``, the error-to-force transfer function ``C_num`` / ``C_den`` (descending
        powers of s, positive form: u = C(s) (r - y)) and the step figures; ``plant``.
    """
    names, units = [], []
    channels = {}
    for ch, (u_name, _), (y_name, _) in zip(("lateral", "vertical"), CONTROLLER_OUTPUTS, CONTROLLER_INPUTS):
        g = gains[ch]
        if g.ki > 0.0:
            names.append(f"{ch}_integral_m_s")
            units.append("m s")
        if g.kd > 0.0:
            names.append(f"{ch}_filter_m_s")
            units.append("m s")
        tf = g.transfer_function()
        channels[ch] = {"K_P": g.kp, "K_I": g.ki, "K_D": g.kd, "N": g.n_filter,
                        "input_name": y_name, "output_name": u_name,
                        "C_num": np.asarray(tf.num[0][0], dtype=np.float64).reshape(1, -1),
                        "C_den": np.asarray(tf.den[0][0], dtype=np.float64).reshape(1, -1),
                        **_step_struct((steps or {}).get(ch))}
    return {"type": "pid", "source": str(source), **_realization(controller, names, units),
            "gain_names": _cellstr([n for n, _ in PID_GAIN_UNITS]), "gain_units": _cellstr([u for _, u in PID_GAIN_UNITS]),
            **channels, "plant": _struct_of_plant(plant)}


def lqr_mat_dict(design, *, reading: str, plant: dict, steps: dict | None = None) -> dict:
    """The content of an LQR's ``.mat`` file (``hosedrogue design lqr --format mat``).

    Parameters
    ----------
    design : BalancedLQRDesign or LQRDesign
        The balanced-state design (:func:`hosedrogue.controllers.lqr_balanced.lqr_balanced_design`)
        or the integral-action one (:func:`hosedrogue.controllers.lqr.lqr_integral_design`).
    reading : {"balanced", "integral"}
        Which it is.
    plant : dict
        The design plant (see :func:`pid_mat_dict`).
    steps : dict, optional
        Per channel the unit step's figures (see :func:`pid_mat_dict`).

    Returns
    -------
    dict
        ``type`` ('lqr'), ``design`` (the reading); the observer-based controller's realization
        (as :func:`pid_mat_dict`); balanced reading: per channel ``K`` (1 x n, force per balanced
        state [sqrt(N/m)]), ``prefilter`` [N/m] (reference steps only; runs regulate to 0),
        ``L`` (n x 1), the balanced model ``A_balanced``, ``B_balanced``, ``C_balanced``,
        ``Q_diag`` [1/(m N)], ``R`` [1/N^2], ``regulator_poles`` and ``observer_poles``
        [rad/s]; integral reading: ``K_x`` (2 x n), ``K_z`` (2 x 2) [N/(m s)], ``L`` (n x 2),
        ``Q``, ``R``, ``regulator_poles``, ``observer_poles``; ``plant``.
    """
    ctrl = design.controller
    out = {"type": "lqr", "design": str(reading)}
    channels = {}
    if reading == "balanced":
        names, units = [], []
        for ch, (u_name, _), (y_name, _) in zip(("lateral", "vertical"), CONTROLLER_OUTPUTS, CONTROLLER_INPUTS):
            c = getattr(design, ch)
            n = c.balanced.A.shape[0]
            names += [f"{ch}_xhat_{k + 1}" for k in range(n)]
            units += ["sqrt(m N)"] * n
            channels[ch] = {"K": np.atleast_2d(c.gain), "prefilter": float(c.prefilter),
                            "L": np.asarray(c.observer_gain).reshape(-1, 1),
                            "A_balanced": np.asarray(c.balanced.A), "B_balanced": np.asarray(c.balanced.B),
                            "C_balanced": np.asarray(c.balanced.C), "Q_diag": np.diag(c.Q).reshape(1, -1), "R": float(c.R),
                            "regulator_poles": np.sort_complex(c.regulator_poles).reshape(-1, 1),
                            "observer_poles": np.sort_complex(c.observer_poles).reshape(-1, 1),
                            "input_name": y_name, "output_name": u_name, **_step_struct((steps or {}).get(ch))}
    else:
        n = design.plant.nstates
        names = [f"xhat_{k + 1}" for k in range(n)] + ["lateral_integral_m_s", "vertical_integral_m_s"]
        units = ["design-model state"] * n + ["m s", "m s"]
        out.update({"K_x": np.asarray(design.gain_state), "K_z": np.asarray(design.gain_integral),
                    "L": np.asarray(design.observer_gain), "Q": np.asarray(design.Q), "R": np.asarray(design.R),
                    "regulator_poles": np.sort_complex(design.regulator_poles).reshape(-1, 1),
                    "observer_poles": np.sort_complex(design.observer_poles).reshape(-1, 1)})
        channels = {ch: _step_struct((steps or {}).get(ch)) for ch in ("lateral", "vertical")}
    return {**out, **_realization(ctrl, names, units), **{k: v for k, v in channels.items() if v},
            "plant": _struct_of_plant(plant)}


def write_controller_mat(content: dict, path: str | Path) -> Path:
    """Write a controller's ``.mat`` file (:func:`pid_mat_dict`, :func:`lqr_mat_dict`).

    Parameters
    ----------
    content : dict
        The variables.
    path : str or Path
        File to write (``.mat``).

    Returns
    -------
    Path
        The written file.
    """
    return _save(content, path)
