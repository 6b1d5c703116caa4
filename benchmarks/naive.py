"""The paper's model written the way a user would without this package: numpy right-hand side,
dense mass matrix, numpy.linalg.solve, scipy.integrate.solve_ivp. Used only as a speed baseline
by realtime.py; it reuses the package's parameters and air fields, not its kernels."""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.integrate

from hosedrogue.constants import G0
from hosedrogue.environment.atmosphere import density
from hosedrogue.environment.turbulence import generate_gusts
from hosedrogue.environment.wake import wake_field


def make_rhs(p):
    n = p.hose.links
    l = p.hose.length_m / n
    rho = density(p.flight.altitude_m)
    V = p.flight.airspeed_m_s
    M = np.full(n, p.hose.mass_per_length_kg_m * l)
    M[-1] += p.drogue.mass_kg
    S = np.cumsum(M[::-1])[::-1]
    Smax = S[np.maximum.outer(np.arange(n), np.arange(n))]
    J = p.hose.link_inertia_kg_m2
    Jd = p.drogue.inertia_kg_m2
    do, di = p.hose.outer_diameter_m, p.hose.inner_diameter_m
    EI = p.hose.elastic_modulus_pa * math.pi * (do**4 - di**4) / 64
    gusts = generate_gusts(p.turbulence, V)

    def air(pts, t):
        vy, vz = wake_field(pts[:, 1], pts[:, 2], p.tanker, p.wake, V, rho)
        g = gusts.at(t) if p.turbulence.enabled else np.zeros(3)
        return np.stack([-V + 0 * vy, vy, vz], axis=1) + g

    def rhs(t, x):
        th1, th2 = x[0 : 2 * n : 2], x[1 : 2 * n : 2]
        d1, d2 = x[2 * n :: 2], x[2 * n + 1 :: 2]
        c1, s1, c2, s2 = np.cos(th1), np.sin(th1), np.cos(th2), np.sin(th2)
        e = np.stack([-c1 * c2, -s2, s1 * c2], 1)
        a = np.stack([s1 * c2, 0 * c1, c1 * c2], 1)
        b = np.stack([c1 * s2, -c2, -s1 * s2], 1)
        r = np.vstack([np.zeros(3), np.cumsum(l * e, 0)])
        v = np.vstack([np.zeros(3), np.cumsum(l * (a * d1[:, None] + b * d2[:, None]), 0)])
        p11, p12 = d1**2 + d2**2, 2 * d1 * d2
        cvec = l * np.stack([c1 * c2 * p11 - s1 * s2 * p12, s2 * d2**2, -s1 * c2 * p11 - c1 * s2 * p12], 1)
        xi = np.cumsum(cvec, 0)
        F = np.zeros((n + 1, 3))
        F[1:, 2] += M * G0
        mid = 0.5 * (r[:-1] + r[1:])
        vt = 0.5 * (v[:-1] + v[1:]) - air(mid, t)
        nk = -e
        vtn = np.sum(vt * nk, 1)
        vn = vt - vtn[:, None] * nk
        D = (-0.5 * rho * (vtn * np.abs(vtn))[:, None] * math.pi * do * l * p.hose.tangential_drag_coefficient * nk
             - 0.5 * rho * np.linalg.norm(vn, axis=1)[:, None] * vn * math.pi * do * l * p.hose.normal_drag_coefficient)
        F[:-1] += 0.5 * D
        F[1:] += 0.5 * D
        vr = v[-1] - air(r[-1:], t)[0]
        F[-1] += -0.5 * rho * np.linalg.norm(vr) * vr * math.pi * p.drogue.diameter_m**2 / 4 * p.drogue.drag_coefficient
        dvec = e[1:] - e[:-1]
        dn = np.linalg.norm(dvec, axis=1)
        gam = 2 * np.arcsin(np.minimum(dn / 2, 1))
        with np.errstate(invalid="ignore", divide="ignore"):
            F[1:n] += np.where(dn[:, None] > 0, 8 * EI * gam[:, None] / l**2 * dvec / dn[:, None], 0.0)
        G = np.cumsum((F[1:] - M[:, None] * xi)[::-1], 0)[::-1]
        g = np.empty((2 * n, 3))
        g[0::2], g[1::2] = l * a, l * b
        Q = np.einsum("ij,ij->i", g, np.repeat(G, 2, axis=0))
        Q[0::2] += 2 * J * c2 * s2 * d1 * d2
        Q[1::2] -= J * c2 * s2 * d1**2
        H = np.repeat(np.repeat(Smax, 2, 0), 2, 1) * (g @ g.T)
        H[np.arange(0, 2 * n, 2), np.arange(0, 2 * n, 2)] += J * c2**2
        H[np.arange(1, 2 * n, 2), np.arange(1, 2 * n, 2)] += J
        H[-2, -2] += Jd
        H[-1, -1] += Jd
        return np.concatenate([x[2 * n :], np.linalg.solve(H, Q)])

    return rhs


def naive_wall_time(p, x0, duration_s):
    rhs = make_rhs(p)
    t0 = time.perf_counter()
    sol = scipy.integrate.solve_ivp(rhs, (0.0, duration_s), x0, method="RK45", rtol=1e-6, atol=1e-8)
    assert sol.success
    return time.perf_counter() - t0, duration_s
