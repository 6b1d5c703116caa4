"""Receiver bow wave: the potential-flow invariants of the forebody flow (no flow through the
body, stagnation point, divergence-free, 1/r^2 decay), each checked against the field the module
computes, with independent formulas for the body and the line."""

import math

import numpy as np
import pytest
import scipy.integrate

from hosedrogue.environment.bow_wave import BowWaveField
from hosedrogue.errors import ParameterError

V = 150.0  # the paper's airspeed [m/s]
TIP = np.array([-15.0, 0.4, 5.5])  # a probe tip near the paper's balance position [m]


@pytest.fixture(params=["rankine", "source-line"])
def bow(request):
    return BowWaveField(V, forebody_radius_m=0.8, probe_offset_m=(2.0, 0.3, -0.4), shape=request.param,
                   nose_length_m=1.5)


def test_no_flow_through_the_rankine_body():
    bw = BowWaveField(V, forebody_radius_m=0.8, probe_offset_m=(2.0, 0.3, -0.4))
    theta = np.linspace(0.05, 3.0, 60)
    s = bw.source_position_m(TIP)
    for phi in (0.0, 1.1, 2.9):
        pts = bw.rankine_surface_m(theta, TIP, phi)
        u = np.array([-V, 0.0, 0.0]) + bw.velocity(pts, TIP)
        # normal: gradient of F = V rho^2 / 2 + Q xi / (4 pi r), constant on the dividing surface
        d = pts - s
        r = np.linalg.norm(d, axis=1)
        xi = d[:, 0]
        grad = V * (d - np.outer(xi, [1.0, 0.0, 0.0]))
        grad += bw.flux_m3_s / (4 * math.pi) * (np.outer(1 / r, [1.0, 0.0, 0.0]) - (xi / r**3)[:, None] * d)
        cosang = np.abs(np.sum(u * grad, axis=1)) / (np.linalg.norm(u, axis=1) * np.linalg.norm(grad, axis=1))
        assert cosang.max() < 1e-12  # round-off of O(1) quantities


def test_stagnation_point_at_the_nose(bow):
    nose = TIP - np.array(bow.probe_offset_m)
    u = np.array([-V, 0.0, 0.0]) + bow.velocity(nose, TIP)
    assert np.linalg.norm(u) < 1e-9 * V  # round-off (the line's nose is found by a root solve)
    if bow.shape == "rankine":
        s = bow.source_position_m(TIP)
        assert nose[0] - s[0] == pytest.approx(bow.forebody_radius_m / 2, rel=1e-14)


def test_divergence_free(bow, rng):
    pts = TIP + rng.uniform(-3.0, 3.0, size=(40, 3))
    s = bow.source_position_m(TIP)
    h = 1e-4  # central differences: truncation error (h / r)^2 ~ 1e-8 of |w| / r at r > 0.3 m
    for p in pts:
        if np.linalg.norm(p - s) < 0.3 or (bow.shape == "source-line" and np.hypot(*(p - s)[1:]) < 0.3):
            continue
        div = 0.0
        for i in range(3):
            e = np.zeros(3)
            e[i] = h
            div += (bow.velocity(p + e, TIP)[i] - bow.velocity(p - e, TIP)[i]) / (2 * h)
        scale = np.linalg.norm(bow.velocity(p, TIP)) / np.linalg.norm(p - s)
        assert abs(div) < 1e-6 * scale


def test_far_field_decays_as_inverse_square(bow):
    s = bow.source_position_m(TIP)
    direction = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    for r in (50.0, 100.0, 200.0):
        w = np.linalg.norm(bow.velocity(s + r * direction, TIP))
        # a point source exactly; the line (length 1.5 m) to O((length / r)) of the point source
        tol = 1e-12 if bow.shape == "rankine" else 2 * bow.nose_length_m / r
        assert w * r**2 == pytest.approx(bow.flux_m3_s / (4 * math.pi), rel=tol)


def test_line_source_matches_a_quadrature_of_point_sources():
    bw = BowWaveField(V, forebody_radius_m=0.8, shape="source-line", nose_length_m=1.5)
    s = bw.source_position_m(TIP)
    sigma = bw.flux_m3_s / bw.nose_length_m
    p = s + np.array([0.7, 0.4, -0.2])
    expected = []
    for i in range(3):
        def integrand(lam):
            d = p - (s - np.array([lam, 0.0, 0.0]))
            return sigma / (4 * math.pi) * d[i] / np.linalg.norm(d) ** 3

        expected.append(scipy.integrate.quad(integrand, 0.0, bw.nose_length_m, epsabs=0, epsrel=1e-13)[0])
    assert np.allclose(bw.velocity(p, TIP), expected, rtol=1e-10, atol=0)  # quadrature accuracy


def test_bad_input_names_the_field():
    with pytest.raises(ParameterError, match=r"bow_wave.forebody_radius_m = -1"):
        BowWaveField(V, forebody_radius_m=-1)
    with pytest.raises(ParameterError, match=r"bow_wave.shape = 'cone'"):
        BowWaveField(V, shape="cone")
