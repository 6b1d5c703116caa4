"""Example sampled-data controllers, one per role, written as a user would write them
(docs/controllers.md). Scenario files name them by entry point, e.g.

.. code-block:: toml

    [receiver]
    entry = "hosedrogue.examples.controllers:pd_docking"
    sample_time_s = 0.02
    [receiver.options]
    kp_1_s = 2.0

* :func:`pd_docking` - a receiver's docking controller: proportional-derivative on the measured
  drogue-minus-probe offset with feed-forward of the drogue's velocity, a steady closure speed,
  and after capture a push then a hold;
* :func:`slack_takeup` - a reel's take-up law: speed proportional to the hose's slack beyond a
  dead band (the built-in ``response`` law's command, through the interface);
* :func:`constant_takeup` - a reel commanding a constant take-up speed (zero: the ``locked`` reel);
* :func:`discrete_pid` - the paper's PID (Eq. 33) discretized by zero-order hold at the sample
  time, written out per channel (the built-in PID in sampled-data mode, through the interface);
* :func:`fixed_deflection` and :func:`deflection_pid` - drogue controllers that command the
  control surfaces' deflections themselves (``[drogue_actuator] command = "deflection"``): fixed
  deflections, and the discretized PID's force turned into deflections by the controller's own
  minimum-norm mixing at the measured dynamic pressure ``m.drogue_q_pa``.

Each factory returns an object with ``reset(m)`` and ``__call__(t, m)``; ``m`` is the
measurement (:class:`hosedrogue.controllers.sampled.Measurement`), updated in place by the run.
"""

from __future__ import annotations

import math


class PDDocking:
    """Probe-tip velocity command (v_x, v_y, v_z) [m/s] toward the drogue.

    Lateral and vertical: ``v = ff v_drogue + kp e + kd e'`` with e the measured drogue minus
    probe-tip offset [m] and e' its rate [m/s], so the offset decays at about ``kp`` [1/s];
    forward: the closure speed until capture, then on for ``push_m`` and a hold (zero).

    Parameters
    ----------
    kp_1_s : float
        Proportional gain [1/s].
    kd : float
        Derivative gain [-] on the offset's rate.
    feedforward : float
        Fraction of the drogue's lateral and vertical velocity fed forward [-].
    closure_speed_m_s : float
        Forward speed relative to the tanker until capture [m/s].
    push_m : float
        Distance pushed on after capture [m].
    """

    def __init__(self, kp_1_s=2.0, kd=0.2, feedforward=1.0, closure_speed_m_s=1.0, push_m=1.0):
        self.kp, self.kd, self.ff = float(kp_1_s), float(kd), float(feedforward)
        self.closure = float(closure_speed_m_s)
        self.push = float(push_m)
        self.x_capture = None

    def reset(self, m) -> None:
        """Start of a run: nothing captured yet.

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """
        self.x_capture = None

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
        if m.coupled:
            x = m.probe_position_m[0]
            if self.x_capture is None:
                self.x_capture = x
            vx = self.closure if x - self.x_capture < self.push else 0.0
            return vx, 0.0, 0.0
        e, de, vd = m.relative_position_m, m.relative_velocity_m_s, m.drogue_velocity_m_s
        return (self.closure,
                self.ff * vd[1] + self.kp * e[1] + self.kd * de[1],
                self.ff * vd[2] + self.kp * e[2] + self.kd * de[2])


def pd_docking(**options) -> PDDocking:
    """Factory of :class:`PDDocking` (its parameters as options).

    Parameters
    ----------
    **options
        ``kp_1_s`` [1/s], ``kd`` [-], ``feedforward`` [-], ``closure_speed_m_s`` [m/s], ``push_m`` [m].

    Returns
    -------
    PDDocking
    """
    return PDDocking(**options)


class SlackTakeup:
    """Take-up speed command [m/s] proportional to the slack: ``gain (s - dead_band)`` beyond the
    dead band, up to ``max_speed_m_s``; the slack s = L - |r_drogue| [m] from the measured hose
    length and drogue position (the tow point is the frame's origin).

    Parameters
    ----------
    gain_1_s : float
        Take-up speed per metre of slack [1/s] (the built-in ``response`` law's 4 /s).
    dead_band_m : float
        Slack without take-up [m] (the built-in 0.02 m).
    max_speed_m_s : float
        Largest command [m/s] (the reel's take-up limit clips it again).
    """

    def __init__(self, gain_1_s=4.0, dead_band_m=0.02, max_speed_m_s=3.0):
        self.gain, self.dead_band, self.vmax = float(gain_1_s), float(dead_band_m), float(max_speed_m_s)

    def reset(self, m) -> None:
        """Nothing to reset (a static law).

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """

    def __call__(self, t: float, m) -> float:
        """The take-up speed command [m/s] at time t [s].

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        float
        """
        r = m.drogue_position_m
        slack = m.hose_length_m - math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
        return min(self.gain * max(slack - self.dead_band, 0.0), self.vmax)


def slack_takeup(**options) -> SlackTakeup:
    """Factory of :class:`SlackTakeup`.

    Parameters
    ----------
    **options
        ``gain_1_s`` [1/s], ``dead_band_m`` [m], ``max_speed_m_s`` [m/s].

    Returns
    -------
    SlackTakeup
    """
    return SlackTakeup(**options)


class ConstantTakeup:
    """A constant take-up speed command [m/s] (zero: the reel holds its length, as ``locked``).

    Parameters
    ----------
    speed_m_s : float
        The command [m/s], positive reeling in.
    """

    def __init__(self, speed_m_s=0.0):
        self.speed = float(speed_m_s)

    def reset(self, m) -> None:
        """Nothing to reset.

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """

    def __call__(self, t: float, m) -> float:
        """The command [m/s].

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        float
        """
        return self.speed


def constant_takeup(**options) -> ConstantTakeup:
    """Factory of :class:`ConstantTakeup`.

    Parameters
    ----------
    **options
        ``speed_m_s`` [m/s].

    Returns
    -------
    ConstantTakeup
    """
    return ConstantTakeup(**options)


class DiscretePID:
    """The paper's two-channel PID (Eq. 33: K_P + K_I/s + K_D N s/(s + N) per channel, on the
    measured drogue offset from its balance position, u = -C y) discretized by zero-order hold
    at the sample time T, channel by channel:

    * integrator ``x_i' = y``: ``x_i[k+1] = x_i[k] + T y[k]``;
    * derivative filter ``x_f' = -N x_f + y``: ``x_f[k+1] = a x_f[k] + (1 - a) / N y[k]``, a = exp(-N T);
    * force ``u[k] = -(K_I x_i[k] - K_D N^2 x_f[k] + (K_P + K_D N) y[k])`` [N].

    Parameters
    ----------
    sample_time_s : float
        T [s] (the scenario's ``sample_time_s``).
    lateral, vertical : sequence of 4 float, optional
        [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]]; default the paper's gains.
    """

    def __init__(self, sample_time_s, lateral=None, vertical=None):
        from hosedrogue.controllers.pid import PAPER_PID

        gains = []
        for name, given in (("lateral", lateral), ("vertical", vertical)):
            g = PAPER_PID[name]
            gains.append(tuple(float(v) for v in (given if given is not None else (g.kp, g.ki, g.kd, g.n_filter))))
        self.T = float(sample_time_s)
        self.gains = gains
        self.a = [math.exp(-n * self.T) for (_, _, _, n) in gains]
        self.xi = [0.0, 0.0]
        self.xf = [0.0, 0.0]
        self.t_last = None

    def reset(self, m) -> None:
        """Zero the integrators and filters.

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """
        self.xi = [0.0, 0.0]
        self.xf = [0.0, 0.0]
        self.t_last = None

    def __call__(self, t: float, m) -> list:
        """The force (u_y, u_z) [N] at time t [s]; advances the controller's states.

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        list of float
            (u_y, u_z) [N].
        """
        if self.t_last is not None and abs(t - self.t_last - self.T) > 1e-9 * max(self.T, 1.0):
            raise ValueError(f"called {t - self.t_last:g} s after the last call; the option sample_time_s = "
                             f"{self.T:g} s must be the scenario's sample_time_s")
        self.t_last = t
        u = [0.0, 0.0]
        y = (m.drogue_position_m[1] - m.drogue_balance_m[1], m.drogue_position_m[2] - m.drogue_balance_m[2])
        for c in (0, 1):
            kp, ki, kd, n = self.gains[c]
            u[c] = -(ki * self.xi[c] - kd * n * n * self.xf[c] + (kp + kd * n) * y[c])
            self.xi[c] += self.T * y[c]
            self.xf[c] = self.a[c] * self.xf[c] + (1.0 - self.a[c]) / n * y[c]
        return u


def discrete_pid(**options) -> DiscretePID:
    """Factory of :class:`DiscretePID`.

    Parameters
    ----------
    **options
        ``sample_time_s`` [s] (required), ``lateral`` and ``vertical`` gains.

    Returns
    -------
    DiscretePID
    """
    return DiscretePID(**options)


class FixedDeflection:
    """Commands every control surface to a fixed deflection (``[drogue_actuator] command =
    "deflection"``): the surfaces' force is then ``q S C_F sum_k t_k delta_k`` (docs/model.md §10).

    Parameters
    ----------
    deflections_deg : sequence of float
        One deflection per surface [deg], surface 1 first (returned in radians, the command's unit).
    """

    def __init__(self, deflections_deg=(0.0, 0.0, 0.0, 0.0)):
        self.command = [math.radians(float(d)) for d in deflections_deg]

    def reset(self, m) -> None:
        """Nothing to reset.

        Parameters
        ----------
        m : Measurement
            The first measurement.
        """

    def __call__(self, t: float, m) -> list:
        """The deflections [rad] at time t [s].

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement.

        Returns
        -------
        list of float
            delta_1 ... delta_n [rad].
        """
        return list(self.command)


def fixed_deflection(**options) -> FixedDeflection:
    """Factory of :class:`FixedDeflection`.

    Parameters
    ----------
    **options
        ``deflections_deg`` [deg], one per surface.

    Returns
    -------
    FixedDeflection
    """
    return FixedDeflection(**options)


class DeflectionPID(DiscretePID):
    """The discretized paper's PID (:class:`DiscretePID`) commanding the surfaces' deflections
    itself: its force F [N] mixed by the minimum-norm inversion at the measured dynamic pressure,
    ``delta_k = t_k^T F / ((n / 2) q S C_F)``, t_k = (-sin phi_k, cos phi_k) the direction surface k
    pushes (the built-in mixing of docs/model.md §10, here at the sample's q instead of every
    evaluation's). The options repeat the ``[drogue_actuator]`` fields the mixing needs.

    Parameters
    ----------
    sample_time_s : float
        T [s] (the scenario's ``sample_time_s``).
    surfaces : int
        n [-].
    roll_angle_deg : float
        Roll position of surface 1 [deg].
    force_slope_per_rad : float
        C_F,delta [1/rad].
    reference_area_m2 : float
        S [m^2].
    lateral, vertical : sequence of 4 float, optional
        The PID's gains (:class:`DiscretePID`).
    """

    def __init__(self, sample_time_s, surfaces=4, roll_angle_deg=0.0, force_slope_per_rad=0.45,
                 reference_area_m2=0.2922, lateral=None, vertical=None):
        super().__init__(sample_time_s, lateral, vertical)
        phi = [math.radians(roll_angle_deg) + 2.0 * math.pi * k / surfaces for k in range(surfaces)]
        self.directions = [(-math.sin(a), math.cos(a)) for a in phi]
        self.scale = 0.5 * surfaces * reference_area_m2 * force_slope_per_rad

    def __call__(self, t: float, m) -> list:
        """The deflections [rad] that make the PID's force at the measured q.

        Parameters
        ----------
        t : float
            Time [s].
        m : Measurement
            The measurement (``drogue_q_pa`` [Pa]).

        Returns
        -------
        list of float
            delta_1 ... delta_n [rad].
        """
        fy, fz = super().__call__(t, m)
        q = m.drogue_q_pa
        if not q > 1.0:
            raise ValueError(f"drogue_q_pa = {q!r}: no air to steer in (a [drogue_actuator] is needed)")
        return [(ty * fy + tz * fz) / (self.scale * q) for ty, tz in self.directions]


def deflection_pid(**options) -> DeflectionPID:
    """Factory of :class:`DeflectionPID`.

    Parameters
    ----------
    **options
        ``sample_time_s`` [s] (required), the surfaces' ``surfaces``, ``roll_angle_deg``,
        ``force_slope_per_rad``, ``reference_area_m2``, and the PID's ``lateral``, ``vertical``.

    Returns
    -------
    DeflectionPID
    """
    return DeflectionPID(**options)
