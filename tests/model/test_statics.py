"""An independent static force balance, written separately from the dynamics code.

Each link is a massless two-force member (masses and loads are lumped at the joints), so at rest
link k lies along the resultant C_k of every external force on the joints aft of it. Marching
from the drogue to the tow point, each link's direction is solved from ``e_k = C_k / |C_k|``
(C_k depends on e_k through the link's own drag and the bending force at its aft joint). Joint
positions, needed for the wake, are taken from the previous march until the drogue position
stops changing. Nothing here calls the package's kernels or its generalized forces.
"""

import math

import numpy as np
import pytest
import scipy.optimize

from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.constants import G0
from hosedrogue.environment.atmosphere import density
from hosedrogue.spec.params import PAPER


def unit_along(th1, th2):
    return np.array([-math.cos(th1) * math.cos(th2), -math.sin(th2), math.sin(th1) * math.cos(th2)])


def wake_air(p, rho, y, z):
    """Hallock-Burnham wake, written out from docs/model.md §4 (independent of the package)."""
    if not p.wake.enabled:
        return np.zeros(3)
    b = p.tanker.span_m
    b0 = p.wake.vortex_spacing_over_span * b
    gamma = p.tanker.mass_kg * G0 / (rho * p.flight.airspeed_m_s * b0)
    rc = p.wake.core_radius_over_span * b
    y_tow = p.wake.tow_point_y_over_span * b
    out = np.zeros(3)
    for y_v, sense in ((b0 / 2 - y_tow, 1.0), (-b0 / 2 - y_tow, -1.0)):
        dy, dz = y - y_v, z - p.wake.vertical_offset_m
        r2 = dy * dy + dz * dz
        vt = gamma / (2 * math.pi) / (r2 + rc * rc)  # v_theta / r
        out[1] += sense * vt * dz
        out[2] -= sense * vt * dy
    return out


def static_march(p):
    n, L = p.hose.links, p.hose.length_m
    l = L / n
    rho = density(p.flight.altitude_m)
    V = p.flight.airspeed_m_s
    do, di = p.hose.outer_diameter_m, p.hose.inner_diameter_m
    EI = p.hose.elastic_modulus_pa * math.pi * (do**4 - di**4) / 64
    # mass[k]: joint k+1's load; "split" puts half a link at each end (docs/model.md §2), and the half
    # link at the tow point adds its weight to the tow-point force only
    link_mass = p.hose.mass_per_length_kg_m * l
    if p.hose.mass_lumping == "aft":
        mass, tow_mass = np.full(n, link_mass), 0.0
    else:
        mass, tow_mass = np.full(n, link_mass), link_mass / 2
        mass[-1] = link_mass / 2
    mass[-1] += p.drogue.mass_kg
    area_d = math.pi * p.drogue.diameter_m**2 / 4

    def air(pt):
        return np.array([-V, 0.0, 0.0]) + wake_air(p, rho, pt[1], pt[2])

    def link_drag(e, mid):
        vrel = -air(mid)  # hose at rest
        n_k = -e
        vt = vrel @ n_k
        vn = vrel - vt * n_k
        return (-0.5 * rho * vt * abs(vt) * math.pi * do * l * p.hose.tangential_drag_coefficient * n_k
                - 0.5 * rho * np.linalg.norm(vn) * vn * math.pi * do * l * p.hose.normal_drag_coefficient)

    def bending(e_k, e_next):
        if p.hose.bending == "off":
            return np.zeros(3)
        d = e_next - e_k
        dn = np.linalg.norm(d)
        if dn == 0:
            return np.zeros(3)
        gamma = math.acos(max(-1.0, min(1.0, e_k @ e_next)))
        return 8 * EI * gamma / l**2 * d / dn

    drogue = np.array([-L, 0.0, 0.0])
    for _ in range(60):
        vr = -air(drogue)
        carried = -0.5 * rho * np.linalg.norm(vr) * vr * area_d * p.drogue.drag_coefficient
        r_aft = drogue.copy()
        # carried = C_{k+1}, the resultant on everything aft of joint k (first: the drogue's drag)
        e_next, drag_next = None, np.zeros(3)
        es = [None] * n
        th_prev = [0.3, 0.0]
        for k in range(n - 1, -1, -1):
            def resultant(th, k=k, r_aft=r_aft, e_next=e_next):
                e = unit_along(*th)
                c = carried + mass[k] * G0 * np.array([0, 0, 1.0]) + 0.5 * drag_next
                c = c + 0.5 * link_drag(e, r_aft - 0.5 * l * e)
                if e_next is not None:
                    c = c + bending(e, e_next)
                return e, c

            def residual(th):
                _, c = resultant(th)
                c = c / np.linalg.norm(c)
                return [math.atan2(c[2], -c[0]) - th[0], math.asin(-c[1]) - th[1]]

            th = scipy.optimize.fsolve(residual, th_prev, xtol=1e-11)
            th_prev = th
            e, c = resultant(th)
            es[k] = e
            carried = c  # C_k: every external force on joints k..n
            drag_next = link_drag(e, r_aft - 0.5 * l * e)  # its other half acts on joint k-1
            r_aft = r_aft - l * e
            e_next = e
        new_drogue = sum(l * e for e in es)
        if np.linalg.norm(new_drogue - drogue) < 1e-12:
            # link 1 pulls the tow point with C_1; the other half of its drag acts there too
            return new_drogue, carried + 0.5 * drag_next + tow_mass * G0 * np.array([0, 0, 1.0])
        drogue = new_drogue
    raise AssertionError("static march did not converge")


@pytest.mark.parametrize(
    "overrides",
    [
        {},
        {"wake": {"enabled": False}},
        {"hose": {"bending": "off"}},
        {"flight": {"altitude_m": 2000.0, "airspeed_m_s": 100.0}},
        {"flight": {"altitude_m": 12000.0, "airspeed_m_s": 220.0}, "hose": {"links": 12}},
        {"hose": {"mass_lumping": "split"}},
        {"hose": {"mass_lumping": "split", "bending": "off", "links": 7}},
    ],
)
def test_equilibrium_matches_independent_force_balance(overrides):
    """Drogue positions agree to 1 mm (the brief's bound; both solutions are converged far
    below it, so a disagreement means the two force models differ), and the tow-point force
    to 1e-6 of its size (a 1 mm shape error changes it by ~1e-4)."""
    p = PAPER.replace(**overrides)
    eq = solve_equilibrium(p)
    drogue, tow = static_march(p)
    assert np.max(np.abs(eq.drogue_position_m - drogue)) < 1e-3
    assert np.linalg.norm(eq.tow_force_n - tow) < 1e-6 * np.linalg.norm(tow)
