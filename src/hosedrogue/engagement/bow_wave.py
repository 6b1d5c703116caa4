"""The drogue's steady displacement by the receiver's bow wave (docs/engagement.md, "Bow wave").

The probe tip is held still on the drogue's axis, a given distance aft of the drogue; the hose is
solved for its balance position in the steady air plus the bow wave of the forebody behind the
tip (the engagement kernels' forces with the reel locked, so the free length is that of the
hose). The displacement is the drogue's position minus its balance position without the bow wave.
"""

from __future__ import annotations

import numpy as np
import scipy.optimize

from ..errors import ParameterError
from ..model import layout as LY
from ..model.engagement import evaluation as EV
from ..model.chain_dynamics import WS_QDD, WS_R, make_workspace
from ..spec.params import Params
from .chain import chain_equilibrium, initial_chain
from .parameters import engagement_parameters, set_bow_wave
from .loop import no_loop
from ..spec.sections import BowWave, Reel


def _accelerations(q, chain, model, ep, z):
    """qdd [rad/s^2] and the drogue position [m] at hose angles q, at rest, reel locked (L'' = 0),
    in steady air (the model's gusts never used)."""
    n = chain.n
    z[: 2 * n] = q
    ws = make_workspace(n)
    ws2 = make_workspace(n)
    out = np.empty(LY.O_SIZE)
    EV.eng_evaluate(0.0, z, n, chain.l.copy(), chain.M.copy(), chain.J.copy(), model.ps, model.steady_env,
                    model.gust_values, ep, chain.chart, no_loop(), ws, ws2, np.empty(2), out)
    return ws[WS_QDD].copy(), ws[WS_R][n].copy()


def _distances(distances_m) -> np.ndarray:
    d = np.atleast_1d(np.asarray(distances_m, dtype=np.float64))
    if not np.all(np.isfinite(d) & (d > 0)):
        raise ParameterError(f"distances_m = {distances_m!r}: must be finite numbers > 0 m")
    return d


def _enabled(bow_wave: BowWave) -> BowWave:
    return BowWave(enabled=True, forebody_radius_m=bow_wave.forebody_radius_m,
                          probe_offset_m=bow_wave.probe_offset_m, shape=bow_wave.shape,
                          nose_length_m=bow_wave.nose_length_m)


def _probe_line(params: Params):
    """The balance position without the bow wave and the drogue's axis along which the probe is held:
    chain, model, engagement parameters (reel locked, probe held, bow wave off), full state, hose
    angles [rad], drogue position [m] and the unit vector aft along the last link."""
    chain = initial_chain(params)
    eq, model = chain_equilibrium(params, chain)
    n = chain.n
    z = np.concatenate([eq.state, [float(np.sum(chain.l)), 0.0], np.zeros(LY.Z_TAIL - 2)])
    ep = engagement_parameters(params, Reel(law="locked"), None, chain, eq.drogue_position_m)
    ep[LY.EP_PROBE] = 0.0  # the tip is held: no capture test, no closure
    ep[LY.EP_VC] = 0.0
    q0 = eq.state[: 2 * n].copy()
    _, drogue0 = _accelerations(q0, chain, model, ep, z.copy())
    axis = drogue0 - model.joint_positions(q0)[-2]
    axis /= np.linalg.norm(axis)  # aft along the last link
    return chain, model, ep, z, q0, drogue0, axis


def bow_wave_speed_at_drogue(params: Params, bow_wave: BowWave, distances_m) -> np.ndarray:
    """Speed [m/s] of the bow wave's perturbation at the drogue's balance position (without the
    bow wave), probe tip held at each distance aft of it on the drogue's axis: the wind change
    that moves the drogue in :func:`bow_wave_displacement`.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight condition (airspeed [m/s], altitude [m], wake) and links.
    bow_wave : BowWave
        The forebody (radius [m], probe offset from the nose [m], shape, nose length [m]).
    distances_m : array_like (m,)
        Distances [m] of the probe tip aft of the drogue, each > 0.

    Returns
    -------
    array (m,)
        |u| [m/s] of the perturbation velocity at the undisplaced drogue.

    Raises
    ------
    ParameterError
        A distance not a finite number > 0, or a balance position not found.
    """
    from ..environment.bow_wave import BowWaveField

    d = _distances(distances_m)
    drogue0, axis = _probe_line(params)[5:]
    field = BowWaveField.of(bow_wave, params.flight.airspeed_m_s)
    return np.array([np.linalg.norm(field.velocity(drogue0[None, :], drogue0 + di * axis)) for di in d])


def bow_wave_displacement(params: Params, bow_wave: BowWave, distances_m) -> np.ndarray:
    """Steady drogue displacement [m] caused by the bow wave alone, probe held at each distance.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight condition (airspeed [m/s], altitude [m], wake) and links; turbulence
        is not used (steady air).
    bow_wave : BowWave
        The forebody (radius [m], probe offset from the nose [m], shape, nose length [m]); used
        as if enabled.
    distances_m : array_like (m,)
        Distances [m] of the probe tip aft of the drogue along the drogue's axis (its last link
        at the balance position), each > 0.

    Returns
    -------
    array (m, 3)
        Drogue position with the bow wave minus without it [m] in S_p (x forward, y right, z down).

    Raises
    ------
    ParameterError
        A distance not a finite number > 0, or a balance position not found.
    """
    d = _distances(distances_m)
    chain, model, ep, z, q0, drogue0, axis = _probe_line(params)
    set_bow_wave(ep, params, _enabled(bow_wave))
    out = np.empty((d.size, 3))
    for i, dist in enumerate(d):
        ep[[LY.EP_P0X, LY.EP_P0Y, LY.EP_P0Z]] = drogue0 + dist * axis
        sol = scipy.optimize.root(lambda q: _accelerations(q, chain, model, ep, z)[0], q0, method="hybr",
                                  options={"xtol": 1e-12})
        if not sol.success:
            raise ParameterError(f"distances_m = {dist!r}: no balance position found ({sol.message})")
        out[i] = _accelerations(sol.x, chain, model, ep, z)[1] - drogue0
    return out
