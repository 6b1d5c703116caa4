"""Numbers published in Wu, Sun, Huang & Liu (2018), kept for comparison only.

Source: Wu L., Sun Y., Huang B., Liu J., "Modeling Method and Control Strategy for Hose-Drogue
Aerial Refueling System", Transactions of Nanjing University of Aeronautics and Astronautics
35(2), 2018, Section 3.

These values are references that computed results are compared against, never inputs that
code is tuned to. The paper's PID gains (Eq. 33) are the exception in that they are used as
controller inputs; they live in `hosedrogue.controllers.pid.PAPER_PID`, and the LQR weights
(Eq. 37) in `hosedrogue.controllers.lqr`, so that each number is defined in one place.

Conventions: transfer functions map force [N] to drogue offset [m] (lateral: u_hor -> P_ny,
vertical: u_ver -> P_nz); coefficient arrays are in descending powers of s. The flight
condition of the paper's linearization is not stated in the paper.
"""

from __future__ import annotations

__all__ = ["TABLE2", "TABLE3", "CHANNELS", "FIG4_AIRSPEEDS_M_S", "SEC233_TURBULENCE_WINDOW", "SEC33_DISPLACEMENT_M", "SEC33_PEAK_FORCE_N",
           "DOCKING_REQUIREMENT_M", "table2_transfer_function"]

#: Channel names, in the order of the plant's inputs and outputs.
CHANNELS = ("lateral", "vertical")

#: Sec. 2.3.3: the turbulence case's gusts act from t = 10 s for 20 s (start_s, duration_s) [s]; the
#: reproduction's runs state this window (the ``paper-turbulence`` scenarios, the convergence and
#: accuracy studies), since turbulence enabled without a window acts for the whole run.
SEC233_TURBULENCE_WINDOW = {"start_s": 10.0, "duration_s": 20.0}

#: Fig. 4 (Sec. 2.3.3): the airspeeds [m/s] of the turbulence runs at 8000 m, controller off.
FIG4_AIRSPEEDS_M_S: tuple[int, ...] = (100, 150, 200, 250)

#: Table 2: reduced transfer functions [m/N], keyed by (channel, order) -> (num, den),
#: coefficients in descending powers of s as printed (the PDF text's thousands separators,
#: e.g. "17 910", are read as 17910).
TABLE2: dict[tuple[str, int], tuple[tuple[float, ...], tuple[float, ...]]] = {
    ("lateral", 6): (
        (0.0001395, 0.02602, 0.04885, 2.774, 2.17, 48.25),
        (1.0, 1.647, 129.1, 139.7, 3616.0, 1916.0, 17910.0),
    ),
    ("vertical", 6): (
        (0.0000899, 0.02536, 0.03685, 2.845, 2.106, 55.66),
        (1.0, 2.092, 140.4, 189.1, 4640.0, 3001.0, 32470.0),
    ),
    ("lateral", 2): (
        (0.000922, 0.01539),
        (1.0, 0.5367, 6.265),
    ),
    ("vertical", 2): (
        (0.000818, 0.0144),
        (1.0, 0.6557, 9.529),
    ),
}

#: Table 3: closed-loop unit-step response of the 2nd-order design models, keyed by
#: (controller, channel) -> {"rise_time_s" (10-90 %), "settling_time_s" (2 %), "overshoot_pct"}.
TABLE3: dict[tuple[str, str], dict[str, float]] = {
    ("PID", "lateral"): {"rise_time_s": 0.068, "settling_time_s": 1.02, "overshoot_pct": 3.78},
    ("PID", "vertical"): {"rise_time_s": 0.076, "settling_time_s": 1.31, "overshoot_pct": 4.32},
    ("LQR", "lateral"): {"rise_time_s": 0.839, "settling_time_s": 1.49, "overshoot_pct": 2.24},
    ("LQR", "vertical"): {"rise_time_s": 0.671, "settling_time_s": 1.45, "overshoot_pct": 5.07},
}


#: Sec. 3.3 (Fig. 12): peak drogue displacement range [m] at 150 m/s, 8000 m in the turbulence
#: case, without control ("off") and with either controller ("on").
SEC33_DISPLACEMENT_M: dict[str, tuple[float, float]] = {"off": (0.5, 1.0), "on": (0.005, 0.01)}

#: Sec. 3.3 (Fig. 13): approximate peak actuation force [N], keyed by (controller, channel).
SEC33_PEAK_FORCE_N: dict[tuple[str, str], float] = {
    ("PID", "lateral"): 20.0,
    ("PID", "vertical"): 30.0,
    ("LQR", "lateral"): 70.0,
    ("LQR", "vertical"): 40.0,
}

#: Sec. 3.3: "the current design requirements of keeping drogue motion within 10 cm" [m].
DOCKING_REQUIREMENT_M = 0.1


def table2_transfer_function(channel: str, order: int):
    """Return one of the paper's Table 2 transfer functions as a python-control object.

    Parameters
    ----------
    channel : {"lateral", "vertical"}
        Lateral: u_hor [N] -> P_ny [m]; vertical: u_ver [N] -> P_nz [m].
    order : {2, 6}
        Order of the reduced model.

    Returns
    -------
    control.TransferFunction
        Force [N] to drogue offset [m].

    Raises
    ------
    ValueError
        If `channel` or `order` is not one of the published ones.
    """
    import control

    key = (channel, order)
    if key not in TABLE2:
        valid = ", ".join(f"({c!r}, {o})" for c, o in TABLE2)
        raise ValueError(f"no Table 2 entry for channel={channel!r}, order={order!r}; valid: {valid}")
    num, den = TABLE2[key]
    return control.tf(list(num), list(den))
