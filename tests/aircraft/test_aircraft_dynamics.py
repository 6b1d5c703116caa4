"""The aircraft's equations under a uniform wind: Galilean invariance, an exact property the wind
input must keep (the engagement will feed the turbulence there)."""

import numpy as np

from hosedrogue.aircraft import load_model, trim
from hosedrogue.aircraft.dynamics import derivative
from hosedrogue.aircraft.rigid_body import dcm_body_from_ned, quaternion_from_euler


def test_uniform_wind_changes_only_the_ground_track():
    """Flying in a uniform wind w (NED) with body velocity v + C_BN w is flying in still air with v:
    the same forces, so the same inertial acceleration (the body-axis rate of the velocity differs
    only by the turning of w's body components, -omega x C_BN w), the same angular accelerations and
    engine, and the position rate larger by w. Equal to round-off (1e-12 of each rate)."""
    f16 = load_model("f16")
    t = trim(f16, 150.0, 3000.0, bank_deg=20.0)
    x = t.state.copy()
    x[6:10] = quaternion_from_euler(0.35, 0.05, 1.1)  # any heading and attitude: the air does not care
    wind = np.array([12.0, -7.0, 2.5])
    moving = x.copy()
    moving[3:6] += dcm_body_from_ned(x[6:10]) @ wind
    still = derivative(f16, x, t.controls)
    windy = derivative(f16, moving, t.controls, wind_ned=wind)
    expected = still.copy()
    expected[:3] += wind
    expected[3:6] -= np.cross(x[10:13], dcm_body_from_ned(x[6:10]) @ wind)
    scale = np.maximum(np.abs(still), 1.0)
    np.testing.assert_allclose((windy - expected)[3:] / scale[3:], 0.0, atol=1e-12)
    np.testing.assert_allclose(windy[:3] - still[:3], wind, atol=1e-12 * 150)
