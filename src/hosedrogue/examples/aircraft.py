"""An example docking controller for the receiver flown as an aircraft (``[receiver] model``;
docs/receiver.md, "In the engagement"), written as a user would write it. A scenario names it:

.. code-block:: toml

    [receiver]
    entry = "hosedrogue.examples.aircraft:f16_docking"
    model = "f16"

The aircraft's inner loop moves a reference point at the commanded velocity and holds the probe
tip on it; the tip follows that point with the lag of the airframe (about a second), so a
controller that fed back the measured tip as :func:`hosedrogue.examples.controllers.pd_docking`
does would close its loop around that lag. This one steers the reference point itself - the
integral of its own commands, which it keeps - onto the drogue predicted ``lead_s`` ahead, and
corrects the slow remainder from the measured tip.
"""

from __future__ import annotations

import numpy as np


class AircraftDocking:
    """Probe-tip velocity command (v_x, v_y, v_z) [m/s] for an aircraft receiver's inner loop.

    Lateral and vertical: ``v = ff v_d + kp (d + lead v_d - r) + kt (d - p)`` with d and v_d the
    measured drogue position and velocity, r the reference point (the tip's start plus the
    integral of the commands so far) and p the measured tip [m]; forward: the closure speed until
    capture, then on for ``push_m`` and a hold (zero).

    Parameters
    ----------
    kp_1_s : float
        Gain on the reference point's offset [1/s].
    kt_1_s : float
        Gain on the measured tip's offset [1/s].
    lead_s : float
        How far ahead the drogue is aimed at [s] (about the airframe's lag).
    feedforward : float
        Fraction of the drogue's velocity fed forward [-].
    closure_speed_m_s : float
        Forward speed relative to the tanker until capture [m/s].
    push_m : float
        Distance pushed on after capture [m].
    """

    def __init__(self, kp_1_s=4.0, kt_1_s=0.5, lead_s=0.3, feedforward=1.0, closure_speed_m_s=1.0, push_m=1.0):
        self.kp, self.kt, self.lead, self.ff = float(kp_1_s), float(kt_1_s), float(lead_s), float(feedforward)
        self.closure, self.push = float(closure_speed_m_s), float(push_m)
        self.x_capture = None
        self.ref = np.zeros(3)
        self.last = (0.0, np.zeros(3))

    def reset(self, m) -> None:
        """Start of a run: the reference point at the tip, moving at the closure speed.

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """
        self.x_capture = None
        self.ref = np.array(m.probe_position_m, dtype=float)
        self.last = (0.0, np.array([self.closure, 0.0, 0.0]))

    def __call__(self, t: float, m):
        """The velocity command at time t [s] for the measurement m.

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        tuple of float
            (v_x, v_y, v_z) [m/s], tanker frame.
        """
        t_last, v_last = self.last
        self.ref = self.ref + (t - t_last) * v_last  # where the held command has taken the point
        if m.coupled:
            x = m.probe_position_m[0]
            if self.x_capture is None:
                self.x_capture = x
            v = np.array([self.closure if x - self.x_capture < self.push else 0.0, 0.0, 0.0])
        else:
            d, vd, p = m.drogue_position_m, m.drogue_velocity_m_s, m.probe_position_m
            v = self.ff * vd + self.kp * (d + self.lead * vd - self.ref) + self.kt * (d - p)
            v[0] = self.closure
        self.last = (t, v)
        return float(v[0]), float(v[1]), float(v[2])


def f16_docking(**options) -> AircraftDocking:
    """Factory of :class:`AircraftDocking` (its parameters as options).

    Parameters
    ----------
    **options
        ``kp_1_s`` [1/s], ``kt_1_s`` [1/s], ``lead_s`` [s], ``feedforward`` [-],
        ``closure_speed_m_s`` [m/s], ``push_m`` [m].

    Returns
    -------
    AircraftDocking
    """
    return AircraftDocking(**options)
