"""The variable-length link chain in Python: its arrays, its remesh (split and merge of the exit
link) and its balance position at any free length.

Link 0 runs from the hose exit to joint 1 and has the variable length ``l_0 = L - sum l_k``; the
other links keep their length (the nominal ``l_nom = hose.length_m / hose.links`` unless a merge
made them otherwise). When ``l_0`` passes ``SPLIT_RATIO l_nom`` the exit link is split into a new
exit link ``l_0 - l_nom`` and a fixed link ``l_nom`` along the same line (exact: every joint keeps
its position and velocity, L and L' are unchanged). Below ``MERGE_RATIO l_nom`` links 0 and 1 are
merged into one straight exit link from the exit to old joint 2: joint 2 and everything aft keep
position and velocity exactly, which fixes the new link's length ``|r_2|`` and the new L'
``V_2 . e``; unless links 0 and 1 are collinear, L drops by ``delta = l_0 + l_1 - |r_2|`` (of order
``l gamma^2``) and L' changes - both are recorded per event (docs/engagement.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..model import engagement_kernels as EK
from ..model.system import HoseModel
from ..params import Params

SPLIT_RATIO = 1.5
MERGE_RATIO = 0.5
LUMPINGS = ("split", "aft")


@dataclass
class Chain:
    """Arrays of one discretization: lengths (l[0] follows L), joint masses, link inertias."""

    l: np.ndarray
    M: np.ndarray
    J: np.ndarray
    l_nom: float

    @property
    def n(self) -> int:
        return self.l.size


def chain_arrays(params: Params, lengths: np.ndarray, lumping: str, l_nom: float) -> Chain:
    """Masses and inertias for link lengths ``lengths`` (lengths[0] is the exit link's current
    length; it is recomputed from L in the kernels)."""
    if lumping not in LUMPINGS:
        raise ValueError(f"lumping = {lumping!r}: must be one of {LUMPINGS}")
    hose = params.hose
    mu = hose.mass_per_length_kg_m
    l = np.ascontiguousarray(lengths, dtype=np.float64).copy()
    n = l.size
    M = np.empty(n)
    if lumping == "split":
        for k in range(n - 1):
            M[k] = 0.5 * mu * (l[k] + l[k + 1])
        M[n - 1] = 0.5 * mu * l[n - 1]
    else:
        M[:] = mu * l
    M[n - 1] += params.drogue.mass_kg
    J = mu * l**3 / 12.0 if hose.link_inertia == "rod" else np.full(n, hose.link_inertia_kg_m2)
    return Chain(l, M, J, l_nom)


def initial_chain(params: Params, lumping: str) -> Chain:
    n = params.hose.links
    l_nom = params.hose.length_m / n
    return chain_arrays(params, np.full(n, l_nom), lumping, l_nom)


def hose_mass_in_air(chain: Chain, params: Params, lumping: str) -> float:
    """Hose mass carried by the joints (and, for split lumping, the exit's half-link) [kg]."""
    m = float(np.sum(chain.M)) - params.drogue.mass_kg
    if lumping == "split":
        m += 0.5 * params.hose.mass_per_length_kg_m * chain.l[0]
    return m


def _angles(e: np.ndarray) -> tuple[float, float]:
    """(pitch, yaw) of a unit vector e = [-c1 c2, -s2, s1 c2]."""
    th2 = math.asin(max(-1.0, min(1.0, -e[1])))
    th1 = math.atan2(e[2], -e[0])
    return th1, th2


def split(z: np.ndarray, chain: Chain, params: Params, lumping: str) -> tuple[np.ndarray, Chain]:
    """Split the exit link: new exit link ``l_0 - l_nom`` and a fixed link ``l_nom`` on its line."""
    n = chain.n
    q, qd, tail = z[: 2 * n], z[2 * n: 4 * n], z[4 * n:]
    q2 = np.concatenate([q[:2], q])
    qd2 = np.concatenate([qd[:2], qd])
    lengths = np.concatenate([[chain.l[0] - chain.l_nom, chain.l_nom], chain.l[1:]])
    new = chain_arrays(params, lengths, lumping, chain.l_nom)
    return np.concatenate([q2, qd2, tail]), new


def merge(z: np.ndarray, chain: Chain, params: Params, lumping: str) -> tuple[np.ndarray, Chain, float]:
    """Merge links 0 and 1 into a straight exit link to old joint 2; returns (z, chain, delta)
    with delta [m] the free length lost (zero for collinear links)."""
    n = chain.n
    assert n >= 2
    q, qd, tail = z[: 2 * n], z[2 * n: 4 * n], z[4 * n:].copy()
    L, Ld = tail[EK.Z_L], tail[EK.Z_LD]
    l0 = L - float(np.sum(chain.l[1:]))
    l1 = chain.l[1]

    def frame(th1, th2):
        c1, s1, c2, s2 = math.cos(th1), math.sin(th1), math.cos(th2), math.sin(th2)
        e = np.array([-c1 * c2, -s2, s1 * c2])
        a = np.array([s1 * c2, 0.0, c1 * c2])
        b = np.array([c1 * s2, -c2, -s1 * s2])
        return e, a, b

    e0, a0, b0 = frame(q[0], q[1])
    e1, a1, b1 = frame(q[2], q[3])
    r2 = l0 * e0 + l1 * e1
    V2 = Ld * e0 + l0 * (a0 * qd[0] + b0 * qd[1]) + l1 * (a1 * qd[2] + b1 * qd[3])
    lam = float(np.linalg.norm(r2))
    e = r2 / lam
    th1, th2 = _angles(e)
    _, a, b = frame(th1, th2)
    Ld_new = float(V2 @ e)
    edot = (V2 - Ld_new * e) / lam
    c2 = math.cos(th2)
    rates = np.array([edot @ a / (c2 * c2), edot @ b])
    q2 = np.concatenate([[th1, th2], q[4:]])
    qd2 = np.concatenate([rates, qd[4:]])
    delta = l0 + l1 - lam
    tail[EK.Z_L] = L - delta
    tail[EK.Z_LD] = Ld_new
    lengths = np.concatenate([[lam], chain.l[2:]])
    new = chain_arrays(params, lengths, lumping, chain.l_nom)
    return np.concatenate([q2, qd2, tail]), new, delta


class ChainModel(HoseModel):
    """A :class:`HoseModel` whose arrays are those of a :class:`Chain` (for the equilibrium
    solver, the linearization and the fixed-length kernels at L' = 0)."""

    def __init__(self, params: Params, chain: Chain):
        L = float(np.sum(chain.l))
        params = params.replace(hose={"length_m": L, "links": chain.n})
        super().__init__(params)
        self.l = chain.l.copy()
        self.M = chain.M.copy()
        self.S = np.cumsum(self.M[::-1])[::-1].copy()
        self.J = chain.J.copy()


def chain_equilibrium(params: Params, chain: Chain) -> tuple[Equilibrium, ChainModel]:
    """Balance position of the chain as it is (any free length, any mesh), in steady air."""
    model = ChainModel(params, chain)
    return solve_equilibrium(model.params, model=model), model


def chain_for_length(params: Params, L: float, lumping: str) -> Chain:
    """The mesh the remesh rules give for free length L grown or shortened from the nominal mesh
    (exit link in [MERGE_RATIO, SPLIT_RATIO) l_nom, every other link l_nom)."""
    l_nom = params.hose.length_m / params.hose.links
    m = int(math.floor((L - MERGE_RATIO * l_nom) / l_nom))
    m = max(m, 0)
    l0 = L - m * l_nom
    return chain_arrays(params, np.concatenate([[l0], np.full(m, l_nom)]), lumping, l_nom)
