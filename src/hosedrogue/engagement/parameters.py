"""The engagement's parameter array of the compiled kernels (``hosedrogue.model.layout.EP_*``):
the chain's, the reel's, the probe's and the bow wave's scalars, from a run's sections."""

from __future__ import annotations

import math

import numpy as np

from ..environment.bow_wave import BowWaveField
from ..model import layout as LY
from ..spec.params import Params
from ..spec.sections import BowWave, Probe, Reel
from .chain import Chain

LAW_CODES = {"locked": LY.LAW_LOCKED, "constant-tension": LY.LAW_CONSTANT_TENSION, "response": LY.LAW_RESPONSE,
             "python": LY.LAW_COMMANDED}


def engagement_parameters(params: Params, reel: Reel, probe: Probe | None, chain: Chain,
                          drogue_eq: np.ndarray, bow_wave: BowWave | None = None) -> np.ndarray:
    """The engagement parameter array of the compiled kernels (``model.layout.EP_*``).

    Parameters
    ----------
    params : Params
        Hose mass per length [kg/m], lumping and link inertia [kg m^2], drogue mass [kg] and
        inertia [kg m^2].
    reel : Reel
        The drum unit (law, radius [m], inertia [kg m^2], friction [N m s], tension set point [N],
        torque [N m] and speed [m/s] limits, gains, payout schedule [s, m, m/s, m/s^2]).
    probe : Probe or None
        The receiver's probe (standoff and offsets [m], closure speed [m/s], push [m], stop
        time [s], contact stiffness [N/m] and damping [N s/m]); None or disabled: parked far aft.
    chain : Chain
        The initial discretization (its nominal link length [m]).
    drogue_eq : array (3,)
        Drogue position at the start [m] in S_p, from which the probe starts.
    bow_wave : BowWave, optional
        The receiver's forebody (radius [m], probe offset from the nose [m], shape, nose
        length [m]); None or disabled: no bow wave.

    Returns
    -------
    array (EP_SIZE,)
        Not coupled yet (``EP_COUPLED`` 0, capture time ``EP_T_CAP`` infinite).
    """
    ep = np.zeros(LY.EP_SIZE)
    hose = params.hose
    ep[LY.EP_MU] = hose.mass_per_length_kg_m
    ep[LY.EP_MD] = params.drogue.mass_kg
    ep[LY.EP_SPLIT] = 1.0 if hose.mass_lumping == "split" else 0.0
    ep[LY.EP_JLINK] = -1.0 if hose.link_inertia == "rod" else hose.link_inertia_kg_m2
    ep[LY.EP_JD] = params.drogue.inertia_kg_m2
    ep[LY.EP_L0] = chain.l_nom
    ep[LY.EP_LAW] = LAW_CODES[reel.law]
    ep[LY.EP_RD] = reel.drum_radius_m
    ep[LY.EP_JR] = reel.inertia_kg_m2
    ep[LY.EP_CR] = reel.friction_n_m_s
    ep[LY.EP_TSET] = reel.tension_set_n
    ep[LY.EP_TAU_MAX] = reel.max_torque_n_m
    ep[LY.EP_V_IN_MAX] = reel.max_takeup_speed_m_s
    ep[LY.EP_V_OUT_MAX] = reel.max_payout_speed_m_s
    ep[LY.EP_K_GOV] = reel.governor_gain_n_s_m
    ep[LY.EP_KS] = reel.takeup_gain_1_s
    ep[LY.EP_DB] = reel.slack_dead_band_m
    ep[LY.EP_KV] = reel.speed_gain_n_s_m
    ep[LY.EP_PAY_T0] = reel.payout_start_s
    ep[LY.EP_PAY_DIST] = reel.payout_m
    ep[LY.EP_PAY_V] = reel.payout_speed_m_s
    ep[LY.EP_PAY_A] = reel.payout_acceleration_m_s2
    ep[LY.EP_L_MIN] = reel.min_length_m
    ep[LY.EP_L_MAX] = reel.max_length_m
    ep[LY.EP_REEL_TV] = reel.speed_time_constant_s
    if probe is not None and probe.enabled:
        ep[LY.EP_PROBE] = 1.0
        ep[LY.EP_P0X] = drogue_eq[0] - probe.standoff_m
        ep[LY.EP_P0Y] = drogue_eq[1] + probe.offset_y_m
        ep[LY.EP_P0Z] = drogue_eq[2] + probe.offset_z_m
        ep[LY.EP_VC] = probe.closure_speed_m_s
        ep[LY.EP_PUSH] = probe.push_m
        ep[LY.EP_T_STOP] = probe.stop_time_s
        ep[LY.EP_KP] = probe.stiffness_n_m
        ep[LY.EP_CP] = probe.damping_n_s_m
    else:
        ep[LY.EP_VC] = 0.0
        ep[LY.EP_P0X] = drogue_eq[0] - 1e3  # parked far aft, never used
    ep[LY.EP_T_CAP] = math.inf
    ep[LY.EP_ELASTIC] = 1.0 if hose.elastic else 0.0
    ep[LY.EP_SCHEME] = LY.SCHEME_SDIRK2 if params.numerics.integrator == "sdirk2" else LY.SCHEME_RK4
    ep[LY.EP_ITER] = params.numerics.sdirk_corrections
    set_bow_wave(ep, params, bow_wave)
    return ep


def set_bow_wave(ep: np.ndarray, params: Params, bow_wave: BowWave | None) -> None:
    """Write the bow-wave entries of ``ep`` (``EP_BW*``): shape code, source minus probe tip [m],
    flux [m^3/s], line length [m]. The source sits still relative to the probe tip; its flux is
    that of the forebody in the tanker's airspeed (the closure speed, ~1 m/s of 150 m/s, aside).

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters, changed in place.
    params : Params
        Its ``flight.airspeed_m_s`` [m/s] is the free stream of the forebody.
    bow_wave : BowWave or None
        None or disabled: ``EP_BW`` = off.
    """
    if bow_wave is None or not bow_wave.enabled:
        ep[LY.EP_BW] = LY.BW_OFF
        return
    bw = BowWaveField.of(bow_wave, params.flight.airspeed_m_s)
    ep[LY.EP_BW] = LY.BW_RANKINE if bow_wave.shape == "rankine" else LY.BW_LINE
    ep[[LY.EP_BW_DX, LY.EP_BW_DY, LY.EP_BW_DZ]] = bw.source_position_m(np.zeros(3))
    ep[LY.EP_BW_Q] = bw.flux_m3_s
    ep[LY.EP_BW_LEN] = bow_wave.nose_length_m
