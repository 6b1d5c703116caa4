"""Tests of the air environment: Hallock-Burnham wake and Dryden turbulence (docs/model.md §4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg
import scipy.signal

from hosedrogue.environment.turbulence import (
    AXES,
    MODELS,
    GustRecord,
    discretize_filter,
    dryden_psd,
    forming_filter,
    generate_gusts,
    gust_at,
    standard_intensity,
)
from hosedrogue.environment.wake import wake_field, wake_scalars, wake_velocity
from hosedrogue.spec.params import ParameterError, Tanker, Turbulence, Wake, params_from_dict

# Paper case (Table 1, Sec. 2.3.3). The density is a round literal, not the ICAO value, so the
# wake checks do not depend on the atmosphere module.
V = 150.0
RHO = 0.5
SIGMA = 1.5
L_SCALE = 530.0
FT = 0.3048  # international foot [m], typed here independently of hosedrogue.constants

# Round-off budget for comparing two evaluations of the same closed form in float64 (a few
# operations, each within 1 ulp): 1e-12 relative is ~5000 ulp, far above round-off, far below
# any formula error.
RTOL_FLOAT = 1e-12


# ----------------------------------------------------------------------------------------------
# wake
# ----------------------------------------------------------------------------------------------
def _expected_wake(y, z, *, mass=60000.0, span=34.0, tow=0.25, spacing=math.pi / 4, core=0.035, dz0=0.0):
    """The Hallock-Burnham pair from docs/model.md §4, written with the polar angle of each offset.

    The starboard vortex, seen from behind (y right, z down), sweeps the air down on its inboard
    side and up outboard: at polar angle phi = atan2(dz, dy) its velocity is
    v_theta (sin phi, -cos phi). The port vortex turns the other way.
    """
    gamma = mass * 9.80665 / (RHO * V * spacing * span)
    rc = core * span
    y_tow = tow * span
    vy = vz = 0.0
    for y_v, sense in ((spacing * span / 2 - y_tow, 1.0), (-spacing * span / 2 - y_tow, -1.0)):
        dy, dz = y - y_v, z - dz0
        r = math.hypot(dy, dz)
        v_theta = gamma * r / (2 * math.pi * (r**2 + rc**2))
        phi = math.atan2(dz, dy)
        vy += sense * v_theta * math.sin(phi)
        vz += sense * v_theta * -math.cos(phi)
    return vy, vz


def test_wake_scalars_layout():
    wk = wake_scalars(Tanker(), Wake(), V, RHO)
    b0 = math.pi / 4 * 34.0
    expected = [1.0, 60000.0 * 9.80665 / (RHO * V * b0), b0 / 2 - 8.5, -b0 / 2 - 8.5, 0.0, 0.035 * 34.0]
    assert wk.dtype == np.float64 and wk.shape == (6,)
    np.testing.assert_allclose(wk, expected, rtol=RTOL_FLOAT)


@pytest.mark.parametrize(
    "y, z",
    [(0.0, 0.0), (3.0, -2.0), (-8.0, 1.5), (12.0, 4.0), (-30.0, -6.0), (4.85, 0.3)],
)
def test_wake_velocity_matches_closed_form(y, z):
    wk = wake_scalars(Tanker(), Wake(), V, RHO)
    vy, vz = wake_velocity(y, z, wk)
    ey, ez = _expected_wake(y, z)
    # two float64 evaluations of the same closed form: round-off only; absolute floor for
    # components that vanish by symmetry (vy on the vortex plane)
    np.testing.assert_allclose([vy, vz], [ey, ez], rtol=RTOL_FLOAT, atol=1e-12)


def test_wake_at_tow_point_hand_value():
    # Hand calculation (paper case, rho = 0.5): Gamma = 588 399 N / (0.5 * 150 * 26.7035 m)
    # = 293.79 m^2/s; the tow point is 4.8518 m inboard of the right vortex and 21.8518 m outboard
    # of the left one, both on the vortex plane, so both push the air straight down:
    # 293.79*4.8518/(2 pi (4.8518^2 + 1.19^2)) + 293.79*21.8518/(2 pi (21.8518^2 + 1.19^2))
    # = 9.0914 + 2.1326 = 11.224 m/s.
    vy, vz = wake_velocity(0.0, 0.0, wake_scalars(Tanker(), Wake(), V, RHO))
    assert vy == 0.0
    assert vz == pytest.approx(11.224, abs=1e-3)  # the hand value is rounded to 1 mm/s


def test_wake_sign_down_between_up_outside():
    wk = wake_scalars(Tanker(), Wake(vertical_offset_m=2.0), V, RHO)
    y_right, y_left, z_v = wk[2], wk[3], wk[4]
    between = np.linspace(y_left + 0.5, y_right - 0.5, 41)
    outside = np.concatenate(
        [np.linspace(y_left - 60.0, y_left - 0.5, 20), np.linspace(y_right + 0.5, y_right + 60.0, 20)]
    )
    for z in (z_v, z_v - 1.0, z_v + 1.0):
        assert all(wake_velocity(y, z, wk)[1] > 0.0 for y in between)  # +z is down
        assert all(wake_velocity(y, z, wk)[1] < 0.0 for y in outside)


def test_wake_circulation_equals_enclosed_vorticity():
    # Independent of the velocity formula's algebra: Stokes' theorem. A Hallock-Burnham vortex has
    # vorticity (1/r) d(r v_theta)/dr = Gamma rc^2 / (pi (r^2 + rc^2)^2), spread over the plane.
    # Round a circle of radius R centred on the right vortex (positive from +y towards +z) the
    # right vortex contributes -Gamma R^2 / (R^2 + rc^2) and the left vortex, turning the other
    # way, +(its vorticity integrated over the disc), which is done here by 2-D quadrature.
    wk = wake_scalars(Tanker(), Wake(), V, RHO)
    gamma, y_c, y_left, z_c, rc = wk[1], wk[2], wk[3], wk[4], wk[5]
    R = 5.0
    phi = np.linspace(0.0, 2 * np.pi, 2001)[:-1]  # periodic trapezoid rule: spectrally accurate
    vy, vz = wake_field(y_c + R * np.cos(phi), z_c + R * np.sin(phi), Tanker(), Wake(), V, RHO)
    line_integral = np.sum(-vy * np.sin(phi) + vz * np.cos(phi)) * R * (2 * np.pi / phi.size)

    def left_vorticity(r, a):
        d2 = (y_c + r * math.cos(a) - y_left) ** 2 + (r * math.sin(a)) ** 2
        return gamma * rc**2 / (math.pi * (d2 + rc**2) ** 2) * r

    left, _ = scipy.integrate.dblquad(left_vorticity, 0.0, 2 * np.pi, 0.0, R, epsabs=1e-14, epsrel=1e-12)
    assert left > 0.01  # the left vortex's share is resolved, not negligible
    # both sides are quadratures converged to ~1e-12 relative; 1e-10 leaves room
    assert line_integral == pytest.approx(-gamma * R**2 / (R**2 + rc**2) + left, rel=1e-10)


def test_wake_field_matches_kernel():
    rng = np.random.default_rng(1)
    y = rng.uniform(-40.0, 40.0, 200)
    z = rng.uniform(-20.0, 20.0, 200)
    wake = Wake(tow_point_y_over_span=0.1, vertical_offset_m=-1.0, core_radius_over_span=0.05)
    wk = wake_scalars(Tanker(), wake, V, RHO)
    vy, vz = wake_field(y, z, Tanker(), wake, V, RHO)
    kernel = np.array([wake_velocity(a, b, wk) for a, b in zip(y, z)])
    np.testing.assert_allclose(kernel, np.column_stack([vy, vz]), rtol=RTOL_FLOAT, atol=1e-13)


def test_wake_has_no_x_component_and_no_x_dependence():
    # Through the model's air-velocity kernel: the x component is the free stream alone, and the
    # wake part is the same at every x.
    from hosedrogue.model import chain_loads as CL, layout as LY

    wk = wake_scalars(Tanker(), Wake(), V, RHO)
    env = np.zeros(LY.ENV_SIZE)
    env[LY.ENV_V] = V
    env[LY.ENV_G_DT] = 1.0  # empty gust window [0, 0): no gusts
    env[LY.ENV_WAKE:LY.ENV_WAKE + 6] = wk
    gust = np.zeros((2, 3))
    for y, z in ((0.0, 0.0), (-3.0, 7.0)):
        ref = wake_velocity(y, z, wk)
        for x in (0.0, -0.8, -16.0, -250.0):
            wx, wy, wz = CL.air_velocity(x, y, z, 1.0, env, gust)
            assert wx == -V
            assert (wy, wz) == ref


def test_wake_disabled_is_zero():
    wake = Wake(enabled=False)
    wk = wake_scalars(Tanker(), wake, V, RHO)
    assert wk[0] == 0.0
    assert wake_velocity(0.0, 0.0, wk) == (0.0, 0.0)
    vy, vz = wake_field(np.linspace(-20, 20, 9), 1.0, Tanker(), wake, V, RHO)
    assert not vy.any() and not vz.any()


def test_wake_rejects_zero_density():
    with pytest.raises(ParameterError, match="rho = 0.0"):
        wake_scalars(Tanker(), Wake(), V, 0.0)


# ----------------------------------------------------------------------------------------------
# Dryden spectra and filters
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("axis", AXES)
def test_psd_integrates_to_variance(model, axis):
    integral, err = scipy.integrate.quad(lambda w: dryden_psd(model, axis, w, SIGMA, L_SCALE, V), 0.0, np.inf)
    # quad's own error estimate is ~1e-9 here; 1e-8 relative leaves room for it
    assert integral == pytest.approx(SIGMA**2, rel=1e-8)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("axis", AXES)
def test_forming_filter_variance_and_shape(model, axis):
    A, B, C = forming_filter(model, axis, SIGMA, L_SCALE, V)
    # Lyapunov: stationary state covariance; the realization is scaled so that it is I
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)
    np.testing.assert_allclose(P, np.eye(A.shape[0]), atol=1e-12)
    assert (C @ P @ C.T).item() == pytest.approx(SIGMA**2, rel=RTOL_FLOAT)
    # shape: |H(i w)|^2 / pi is the one-sided spectrum for unit-intensity white noise
    w = np.logspace(-4, 3, 57)
    H = np.array([(C @ np.linalg.solve(1j * wi * np.eye(A.shape[0]) - A, B)).item() for wi in w])
    psd = dryden_psd(model, axis, w, SIGMA, L_SCALE, V)
    np.testing.assert_allclose(np.abs(H) ** 2 / np.pi, psd, rtol=RTOL_FLOAT)


@pytest.mark.parametrize(
    "L, airspeed, dt",
    # the paper's filter (L/V = 3.5 s) over 3e-5 to 8.5 time constants, and an extreme one:
    # L = 1 m at 400 m/s sampled at 1 s, i.e. 400 time constants per sample
    [(L_SCALE, V, dt) for dt in (1e-4, 0.005, 0.02, 1.0, 30.0)] + [(1.0, 400.0, 1.0)],
)
def test_discretization_is_exact(L, airspeed, dt):
    A, B, _ = forming_filter("mil-f-8785c", "w", SIGMA, L, airspeed)
    Phi, Qd = discretize_filter(A, B, dt)
    # Van Loan against direct quadrature of int_0^dt e^{As} B B^T e^{A^T s} ds; breakpoints at
    # multiples of the time constant so the adaptive rule sees the integrand's decay
    tau = L / airspeed
    breaks = [p for p in tau * np.geomspace(0.01, 100.0, 9) if p < dt] or None
    direct, _ = scipy.integrate.quad_vec(
        lambda s: scipy.linalg.expm(A * s) @ B @ B.T @ scipy.linalg.expm(A.T * s),
        0.0,
        dt,
        epsabs=1e-15,
        epsrel=1e-12,
        points=breaks,
    )
    np.testing.assert_allclose(Phi, scipy.linalg.expm(A * dt), rtol=RTOL_FLOAT, atol=1e-15)
    # quad_vec converges to ~1e-12 of the largest entry and expm carries round-off of the same
    # order relative to the matrix norm, so tiny entries are compared on that absolute scale
    np.testing.assert_allclose(Qd, direct, rtol=1e-10, atol=1e-12 * np.abs(direct).max())
    # the stationary covariance (I) is preserved by one step: Phi I Phi^T + Qd = I
    np.testing.assert_allclose(Phi @ Phi.T + Qd, np.eye(2), atol=1e-12)


# ----------------------------------------------------------------------------------------------
# gust records: statistics
# ----------------------------------------------------------------------------------------------
RECORD_S = 8 * 3600.0  # 8 hours of flight at 150 m/s: 8150 scale lengths L/V = 3.53 s
SEGMENT_S = 2621.0  # Welch segment: bin spacing 2 pi / 2621 s = 0.0024 rad/s, < 0.01 rad/s / 4


@pytest.fixture(scope="module", params=[0.005, 0.02], ids=["dt=0.005", "dt=0.02"])
def long_record(request):
    turb = Turbulence(enabled=True, sample_time_s=request.param, start_s=0.0, seed=7)
    return generate_gusts(turb, V, RECORD_S)


def _std_standard_error(model, axis):
    """Relative standard error of the sample rms of a Gaussian record of length RECORD_S.

    var(sample variance) = (2/T) int R(tau)^2 d tau, and by Parseval
    int R^2 d tau = pi int_0^inf Phi(omega)^2 d omega; the rms error is half the variance error.
    """
    def phi2(w):
        return dryden_psd(model, axis, w, SIGMA, L_SCALE, V) ** 2

    int_phi2, _ = scipy.integrate.quad(phi2, 0, np.inf)
    return 0.5 * math.sqrt(2.0 * math.pi * int_phi2 / RECORD_S) / SIGMA**2


def _check_rms(record, model):
    rms = record.values.std(axis=0)
    for j, axis in enumerate(AXES):
        # The tolerance is 3 %: the sample rms of an 8-hour record scatters by
        # _std_standard_error = 0.78 % (u), 0.62 % (v, w) for MIL-F-8785C and 0.88 % (v, w) for
        # MIL-HDBK-1797, so 3 % is >= 3.4 standard errors. Any dt-dependent error (e.g. a noise
        # gain off by sqrt(dt)) would be a factor, not a few %.
        assert _std_standard_error(model, axis) < 0.03 / 3.4
        assert rms[j] == pytest.approx(SIGMA, rel=0.03), axis


def _check_welch(record, model):
    dt = record.dt_s
    nperseg = int(2 ** round(math.log2(SEGMENT_S / dt)))
    # detrend=False: the process has zero mean, and removing each segment's mean would bias the
    # lowest bins low.
    f_hz, p_hz = scipy.signal.welch(record.values, fs=1.0 / dt, nperseg=nperseg, detrend=False, axis=0)
    omega = 2 * np.pi * f_hz
    p_omega = p_hz / (2 * np.pi)  # one-sided, per rad/s
    n_seg = (record.values.shape[0] - nperseg) // (nperseg // 2) + 1
    edges = np.logspace(-2, 1, 7)  # half-decade bands over 0.01-10 rad/s
    for j, axis in enumerate(AXES):
        theory = dryden_psd(model, axis, omega, SIGMA, L_SCALE, V)
        for lo, hi in zip(edges[:-1], edges[1:]):
            band = (omega >= lo) & (omega < hi)
            m = int(band.sum())
            ratio = float(np.mean(p_omega[band, j] / theory[band]))
            # Expected scatter of a band average of Welch ratios (Hann window, 50 % overlap):
            # each bin is a chi^2 estimate of relative variance 1.056 / n_seg (Welch 1967, overlap
            # correlation 0.167^2 x 2), and neighbouring Hann bins are correlated (periodogram
            # correlation 0.444 at 1 bin, 0.028 at 2), which multiplies the variance of an m-bin
            # mean by 1.944 / m. So se = sqrt(2.05 / (m n_seg)): 10 % in the lowest band
            # (9 bins), 0.6 % in the highest (2850 bins). Tolerance: 4 se plus 1 % for bias
            # (window smoothing and aliasing of the sampled spectrum, both < 0.5 % here).
            se = math.sqrt(2.05 / (m * n_seg))
            assert abs(ratio - 1.0) < 4.0 * se + 0.01, (axis, lo, hi, ratio, se)


def test_gust_rms_equals_sigma(long_record):
    _check_rms(long_record, "mil-f-8785c")


def test_gust_psd_matches_dryden(long_record):
    _check_welch(long_record, "mil-f-8785c")


def test_gust_statistics_mil_hdbk_1797():
    # the handbook's lateral/vertical filter, at the coarser sample interval only (the
    # discretization is shared with the default model, whose dt-independence is checked above)
    turb = Turbulence(enabled=True, model="mil-hdbk-1797", sample_time_s=0.02, start_s=0.0, seed=11)
    record = generate_gusts(turb, V, RECORD_S)
    _check_rms(record, "mil-hdbk-1797")
    _check_welch(record, "mil-hdbk-1797")


# ----------------------------------------------------------------------------------------------
# gust records: reproducibility, switching, lookup
# ----------------------------------------------------------------------------------------------
def _short(**kw):
    base = dict(enabled=True, start_s=10.0, duration_s=20.0, sample_time_s=0.005)
    base.update(kw)
    return Turbulence(**base)


def test_same_seed_is_bit_identical_and_seeds_differ():
    a = generate_gusts(_short(), V, 20.0)
    b = generate_gusts(_short(), V, 20.0)
    c = generate_gusts(_short(), V, 20.0, seed=2019)
    d = generate_gusts(_short(seed=2019), V, 20.0)
    assert np.array_equal(a.values, b.values)
    assert np.array_equal(c.values, d.values)  # explicit seed == the same seed in the parameters
    assert not np.any(a.values == c.values)


@pytest.mark.parametrize("model", MODELS)
def test_record_covers_window(model):
    rec = generate_gusts(_short(model=model), V, 20.0)
    assert rec.t0_s == 10.0 and rec.t_on_s == 10.0 and rec.t_off_s == 30.0
    assert rec.values.shape[1] == 3 and rec.values.dtype == np.float64
    assert rec.time_s[-1] >= rec.t_off_s + rec.dt_s * 0.999  # at least one sample past the end
    assert np.isfinite(rec.values).all() and rec.values.std() > 0.0


def test_duration_defaults_to_parameters():
    rec = generate_gusts(_short(duration_s=5.0), V)
    assert rec.t_off_s == 15.0


def test_turbulence_disabled_gives_zeros():
    rec = generate_gusts(_short(enabled=False), V, 20.0)
    assert not rec.values.any()
    assert not rec.at(np.linspace(0.0, 40.0, 101)).any()
    assert gust_at(15.0, rec.t0_s, rec.dt_s, rec.values, rec.t_on_s, rec.t_off_s) == (0.0, 0.0, 0.0)


def test_gust_at_window_and_interpolation():
    rec = generate_gusts(_short(), V, 20.0)
    args = (rec.t0_s, rec.dt_s, rec.values, rec.t_on_s, rec.t_off_s)
    for t in (0.0, 9.9999, 30.0, 30.5, 1e6):  # outside [10, 30)
        assert gust_at(t, *args) == (0.0, 0.0, 0.0)
        assert not rec.at(t).any()
    k = np.arange(0, 4000, 37)
    t_samples = rec.t0_s + k * rec.dt_s
    inside = np.array([gust_at(t, *args) for t in t_samples])
    # t0 + k dt, then (t - t0)/dt, loses a few ulp of the time: the interpolation weight is off by
    # ~1e-12 and the value by that times a sample-to-sample change (< 1 m/s): 1e-11 m/s
    np.testing.assert_allclose(inside, rec.values[k], rtol=0, atol=1e-11)
    np.testing.assert_allclose(rec.at(t_samples), rec.values[k], rtol=0, atol=1e-11)
    # midway between samples: the mean of the neighbours
    mid = gust_at(rec.t0_s + 100.5 * rec.dt_s, *args)
    np.testing.assert_allclose(mid, 0.5 * (rec.values[100] + rec.values[101]), rtol=0, atol=1e-11)
    # the numpy lookup and the numba kernel agree at arbitrary times (same arithmetic)
    t_any = np.random.default_rng(3).uniform(9.0, 31.0, 300)
    kernel = np.array([gust_at(t, *args) for t in t_any])
    np.testing.assert_allclose(rec.at(t_any), kernel, rtol=0, atol=1e-14)


def test_gust_at_clamps_at_record_ends():
    values = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    rec = GustRecord(t0_s=1.0, dt_s=0.5, values=values, t_on_s=0.0, t_off_s=10.0)
    assert gust_at(0.2, 1.0, 0.5, values, 0.0, 10.0) == (1.0, 2.0, 3.0)
    assert gust_at(5.0, 1.0, 0.5, values, 0.0, 10.0) == (4.0, 5.0, 6.0)
    np.testing.assert_array_equal(rec.at([0.2, 1.25, 5.0]), [[1, 2, 3], [2.5, 3.5, 4.5], [4, 5, 6]])


# ----------------------------------------------------------------------------------------------
# standard intensities
# ----------------------------------------------------------------------------------------------
# MIL-F-8785C Fig. 7 as tabulated in the MathWorks Aerospace Blockset Dryden blocks (and JSBSim
# FGWinds.cpp), ft/s; probability of exceedance 1e-2 (light), 1e-3 (moderate), 1e-5 (severe).
@pytest.mark.parametrize(
    "altitude_ft, light, moderate, severe",
    [
        (500.0, 6.6, 8.6, 15.6),
        (7500.0, 6.7, 10.1, 23.6),
        (25000.0, 2.7, 6.6, 20.0),
        (45000.0, 0.0, 4.2, 15.1),
    ],
)
def test_standard_intensity_table_values(altitude_ft, light, moderate, severe):
    for level, ft_s in (("light", light), ("moderate", moderate), ("severe", severe)):
        sigma = standard_intensity(level, altitude_ft * FT)
        assert sigma[0] == sigma[1] == sigma[2]  # isotropic above 2000 ft
        assert sigma[0] == pytest.approx(ft_s * FT, rel=RTOL_FLOAT, abs=1e-15)


def test_standard_intensity_interpolates_linearly():
    # halfway between 25 000 ft (6.6 ft/s) and 35 000 ft (5.0 ft/s), moderate
    assert standard_intensity("moderate", 30000.0 * FT)[0] == pytest.approx(5.8 * FT, rel=RTOL_FLOAT)


def test_standard_intensity_monotone_in_level():
    for h in np.linspace(152.4, 24384.0, 97):
        light, moderate, severe = (standard_intensity(lv, h)[0] for lv in ("light", "moderate", "severe"))
        assert 0.0 <= light <= moderate < severe


def test_standard_intensity_errors():
    with pytest.raises(ParameterError) as exc:
        standard_intensity("extreme", 8000.0)
    assert str(exc.value) == "turbulence.intensity = 'extreme': must be one of 'light', 'moderate', 'severe'"
    for h in (100.0, 25000.0, float("nan")):
        with pytest.raises(ParameterError, match=r"\[152\.4, 24384\] m"):
            standard_intensity("light", h)


def test_intensity_preset_in_parameters():
    p = params_from_dict({"turbulence": {"intensity": "severe"}, "flight": {"altitude_m": 7620.0}})
    assert p.turbulence.sigma_m_s == pytest.approx((20.0 * FT,) * 3, rel=RTOL_FLOAT)


def test_cubic_gust_interpolation():
    """The Catmull-Rom reading passes through every sample (to the same 1e-11 m/s time round-off
    as the linear one), has a continuous slope at the samples (one-sided difference quotients over
    1e-7 s agree to 1e-4 of the sample-to-sample slope scale, the quotients' own truncation), and
    the numpy lookup uses the kernel's arithmetic (bit-identical)."""
    rec = generate_gusts(_short(interpolation="cubic"), V, 20.0)
    assert rec.interpolation == "cubic"
    args = (rec.t0_s, rec.dt_s, rec.values, rec.t_on_s, rec.t_off_s, True)
    k = np.arange(2, 3990, 37)
    t_samples = rec.t0_s + k * rec.dt_s
    inside = np.array([gust_at(t, *args) for t in t_samples])
    np.testing.assert_allclose(inside, rec.values[k], rtol=0, atol=1e-11)
    d = 1e-7
    left = (inside - np.array([gust_at(t - d, *args) for t in t_samples])) / d
    right = (np.array([gust_at(t + d, *args) for t in t_samples]) - inside) / d
    scale = np.abs(np.diff(rec.values, axis=0)).max() / rec.dt_s
    assert np.abs(left - right).max() < 1e-4 * scale
    t_any = np.random.default_rng(4).uniform(9.0, 31.0, 300)
    np.testing.assert_array_equal(rec.at(t_any), np.array([gust_at(t, *args) for t in t_any]))


def test_smoothed_record_keeps_the_impulse_and_vanishes_outside():
    """The averaged, windowed record is zero at both ends of its support, and its integral equals
    the windowed gust's (the linear reading's trapezoid sum of the edge-halved samples): a
    symmetric kernel of unit sum conserves it to round-off (1e-12 m of gust displacement)."""
    from hosedrogue.environment.turbulence import smoothed_record

    rec = generate_gusts(_short(), V, 20.0)
    sm = smoothed_record(rec, 0.02)
    assert not sm.values[:2].any() and not sm.values[-2:].any()
    k_off = int(round((rec.t_off_s - rec.t0_s) / rec.dt_s))
    windowed = rec.values[: k_off + 1].copy()
    windowed[0] *= 0.5
    windowed[-1] *= 0.5
    np.testing.assert_allclose(sm.values.sum(axis=0) * sm.dt_s, windowed.sum(axis=0) * rec.dt_s,
                               rtol=0, atol=1e-12)
    assert sm.t_on_s < rec.t_on_s and sm.t_off_s > rec.t_off_s
