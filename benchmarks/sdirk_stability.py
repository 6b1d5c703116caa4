"""Linear stability of the stiff SDIRK of the elastic chains (docs/model.md §11), printed as figures.

The scheme of :mod:`hosedrogue.model.implicit` (Alexander's two-stage SDIRK, each stage
corrected ``corrections`` times from the previous stage's slope, the stiff part taken implicitly
through the recursion's augmentation) applied to the scalar second-order test equation

    x'' = -omega^2 x - K x - C x'

with the spring-damper ``K``, ``C`` implicit (each link's axial spring-damper, exact) and
``omega^2 x`` either explicit (``alpha = 0``: the scheme before bending and the string stiffness
were augmented) or augmented by ``alpha omega^2`` (``elastic.angle_stiff_terms``: alpha = 2 is the
bending's Gershgorin bound on its highest mode, alpha = 1 the exact string stiffness; a fixed
number of corrections, as the tolerance-driven iteration does in calm motion). One step maps (x,
x', the carried slope guess) linearly; its spectral radius is printed against ``omega h`` (a
value below 1: the step damps that mode). The same arithmetic as ``implicit.stage_point``,
``elastic.stiff_terms`` and ``elastic.angle_stiff_terms``, written out for one degree of
freedom.

Run:  .venv/bin/python benchmarks/sdirk_stability.py
"""

from __future__ import annotations

import numpy as np

from hosedrogue.model.implicit import SDIRK2_GAMMA as G


def step(x, v, a_guess, h, w, K, C, corrections, alpha=0.0):
    """One step of the scheme on the test equation; returns (x, v, the next guess)."""

    def stage(xh, vh, a0):
        a = a0
        aug = h * G * C + (h * G) ** 2 * (K + alpha * w * w)
        for _ in range(corrections):
            X = xh + h * G * vh + (h * G) ** 2 * a  # the stage's state at the guess
            V = vh + h * G * a
            Q = -w * w * X - K * X - C * V
            a = (Q + aug * a) / (1.0 + aug)  # the augmented solve (unit mass)
        return xh + h * G * vh + (h * G) ** 2 * a, vh + h * G * a, a

    X1, V1, a1 = stage(x, v, a_guess)
    X2, V2, a2 = stage(x + h * (1 - G) * V1, v + h * (1 - G) * a1, a1)
    return X2, V2, a2


def spectral_radius(wh, corrections, Kh2=0.0, Ch=0.0, alpha=0.0):
    """Spectral radius of one step for omega h, K h^2 and C h (h = 1), omega^2 augmented by alpha."""
    cols = [step(*e, 1.0, wh, Kh2, Ch, corrections, alpha) for e in np.eye(3)]
    return float(max(abs(np.linalg.eigvals(np.array(cols).T))))


def main():
    whs = (0.1, 0.3, 0.6, 1.0, 1.5, 2.0, 2.5, 3.0)
    print("spectral radius of one step on x'' = -omega^2 x (explicit part), against omega h:")
    print("corrections " + " ".join(f"{wh:>8g}" for wh in whs))
    for c in (1, 2, 3):
        print(f"{c:>11d} " + " ".join(f"{spectral_radius(wh, c):8.5f}" for wh in whs))
    whs_aug = (0.6, 1.0, 2.0, 3.0, 5.0, 10.0, 30.0)
    for alpha in (1.0, 2.0):
        print(f"omega^2 augmented by {alpha:g} omega^2 (elastic.angle_stiff_terms), against omega h:")
        print("corrections " + " ".join(f"{wh:>8g}" for wh in whs_aug))
        for c in (2, 3, 6):
            print(f"{c:>11d} " + " ".join(f"{spectral_radius(wh, c, alpha=alpha):8.5f}" for wh in whs_aug))
    print("with a stiff axial spring (K h^2) and damper (C h), omega h = 0.6, two corrections:")
    for Kh2, Ch in ((1e2, 0.0), (1e4, 0.0), (1e6, 0.0), (1e4, 1e2), (0.0, 1e3)):
        print(f"  K h^2 = {Kh2:g}, C h = {Ch:g}: {spectral_radius(0.6, 2, Kh2, Ch):.4f}")


if __name__ == "__main__":
    main()
