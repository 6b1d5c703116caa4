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
from ..model import layout as LY
from ..model.system import HoseModel, link_inertias, lumped_masses
from ..spec.params import Params

SPLIT_RATIO = 1.5
MERGE_RATIO = 0.5


@dataclass
class Chain:
    """Arrays of one discretization: lengths (l[0] follows L), joint masses, link inertias."""

    l: np.ndarray  #: (n,) link lengths [m], exit link first (its length follows L in the kernels)
    M: np.ndarray  #: (n,) lumped joint masses [kg], joints 1..n (the last includes the drogue)
    J: np.ndarray  #: (n,) transverse link inertias [kg m^2] (the last includes the drogue's)
    l_nom: float  #: nominal link length [m]: hose length over the initial number of links
    chart: np.ndarray  #: (n,) 0: standard angles, 1: the alternative chart (model.engagement.chain.apply_charts)

    @property
    def n(self) -> int:
        return self.l.size


def chain_arrays(params: Params, lengths: np.ndarray, l_nom: float, chart: np.ndarray | None = None) -> Chain:
    """Masses and inertias for link lengths ``lengths`` (lengths[0] is the exit link's current
    length; it is recomputed from L in the kernels), lumped as ``params.hose.mass_lumping`` says
    by the fixed-length model's own :func:`~hosedrogue.model.system.lumped_masses` (the tow
    point's share of ``split`` is carried by the tanker). The compiled counterpart for the exit
    link as L changes is ``model.engagement.chain.set_variable_link``; ``hose_mass_kg`` of every run
    checks that the two agree (mu L at every output time).

    Parameters
    ----------
    params : Params
        Hose mass per length [kg/m], lumping and link inertia, drogue mass [kg] and inertia [kg m^2].
    lengths : array (n,)
        Link lengths [m], exit link first.
    l_nom : float
        Nominal link length [m].
    chart : array (n,), optional
        Angle chart of each link (0 standard, 1 alternative); default all standard.

    Returns
    -------
    Chain
    """
    l = np.ascontiguousarray(lengths, dtype=np.float64).copy()
    n = l.size
    M, _ = lumped_masses(params, l)
    J = link_inertias(params, l)  # the drogue's inertia is the last link's transverse inertia
    chart = np.zeros(n) if chart is None else np.ascontiguousarray(chart, dtype=np.float64).copy()
    return Chain(l, M, J, l_nom, chart)


def initial_chain(params: Params) -> Chain:
    """The initial mesh: ``hose.links`` links of ``hose.length_m / hose.links`` [m], standard charts.

    Parameters
    ----------
    params : Params
        Hose length [m], links, mass per length [kg/m]; drogue mass [kg] and inertia [kg m^2].

    Returns
    -------
    Chain
    """
    n = params.hose.links
    l_nom = params.hose.length_m / n
    return chain_arrays(params, np.full(n, l_nom), l_nom)


def hose_mass_in_air(chain: Chain, params: Params) -> float:
    """Hose mass carried by the joints (and, for split lumping, the exit's half-link) [kg].

    Parameters
    ----------
    chain : Chain
        The discretization (joint masses [kg], exit link length [m]).
    params : Params
        Drogue mass [kg] (subtracted), hose mass per length [kg/m] and lumping.

    Returns
    -------
    float
        Hose mass in the air [kg]; ``mu L`` for a consistent chain.
    """
    m = float(np.sum(chain.M)) - params.drogue.mass_kg
    if params.hose.mass_lumping == "split":
        m += 0.5 * params.hose.mass_per_length_kg_m * chain.l[0]
    return m


#: A link whose yaw passes this in its chart is moved to the other chart (the angle coordinates
#: are singular at 90 deg); after the switch its yaw is at most 90 - 50 = 40 deg in the new chart.
#: The switch is made between steps, so a link may turn by 35 deg within one before it meets the
#: 85 deg guard (numerics.max_yaw_deg): the locked reel's flail turns links at up to 230 rad/s,
#: 26 deg in its 2 ms step (with 60 deg, 25 deg of room, it stopped there).
SWITCH_YAW_DEG = 50.0


def _rot(v: np.ndarray, chart: float, inverse: bool = False) -> np.ndarray:
    """R v (or R^T v) for the alternative chart, identity for the standard one."""
    if chart == 0.0:
        return v.copy()
    x, y, z = v
    return np.array([x, z, -y]) if inverse else np.array([x, -z, y])


def frame(th1: float, th2: float, chart: float = 0.0):
    """(e, a, b) of a link in S_p.

    Parameters
    ----------
    th1, th2 : float
        Pitch and yaw of the link in its chart [rad].
    chart : float
        0 for the standard chart, 1 for the alternative one.

    Returns
    -------
    e, a, b : array (3,)
        Unit vector along the link (exit to drogue) and its derivatives with respect to th1 and
        th2 (``edot = a thd1 + b thd2``; ``|a| = cos th2``, ``|b| = 1``) [-, 1/rad].
    """
    c1, s1, c2, s2 = math.cos(th1), math.sin(th1), math.cos(th2), math.sin(th2)
    e = np.array([-c1 * c2, -s2, s1 * c2])
    a = np.array([s1 * c2, 0.0, c1 * c2])
    b = np.array([c1 * s2, -c2, -s1 * s2])
    return _rot(e, chart), _rot(a, chart), _rot(b, chart)


def _angles(e: np.ndarray, chart: float = 0.0) -> tuple[float, float]:
    """(pitch, yaw) in the given chart of a unit vector e (S_p)."""
    e = _rot(e, chart, inverse=True)
    th2 = math.asin(max(-1.0, min(1.0, -e[1])))
    th1 = math.atan2(e[2], -e[0])
    return th1, th2


def best_chart(e: np.ndarray) -> float:
    """The chart in which direction e has the smaller |yaw|.

    Parameters
    ----------
    e : array (3,)
        Unit link direction in S_p [-].

    Returns
    -------
    float
        0 (standard) or 1 (alternative).
    """
    return 0.0 if abs(e[1]) <= abs(e[2]) else 1.0


def coordinates(e: np.ndarray, edot: np.ndarray, chart: float) -> tuple[float, float, float, float]:
    """(th1, th2, thd1, thd2) of a link with direction e and rate edot in a chart.

    Parameters
    ----------
    e : array (3,)
        Unit link direction in S_p [-].
    edot : array (3,)
        Its time derivative [1/s].
    chart : float
        0 for the standard chart, 1 for the alternative one.

    Returns
    -------
    tuple of float
        Pitch and yaw [rad] and their rates [rad/s].
    """
    th1, th2 = _angles(e, chart)
    _, a, b = frame(th1, th2, chart)
    c2 = math.cos(th2)
    return th1, th2, float(edot @ a) / (c2 * c2), float(edot @ b)


def switch_charts(z: np.ndarray, chain: Chain, switch_yaw: float) -> tuple[np.ndarray, Chain, list[int]]:
    """Move every link whose |yaw| exceeds switch_yaw [rad] to the other chart (exact remap);
    returns the new state, a new Chain and the links moved.

    Parameters
    ----------
    z : array (4n + Z_TAIL,)
        State: angles [rad], rates [rad/s], L [m], L' [m/s], work states [J]; not modified.
    chain : Chain
        Its discretization; not modified.
    switch_yaw : float
        |yaw| beyond which a link changes chart [rad].

    Returns
    -------
    z : array
        The same configuration in the new charts.
    chain : Chain
        A copy with the new charts.
    moved : list of int
        Indices of the links moved.
    """
    n = chain.n
    z = z.copy()
    chain = Chain(chain.l.copy(), chain.M.copy(), chain.J.copy(), chain.l_nom, chain.chart.copy())
    moved = []
    for k in range(n):
        if abs(z[2 * k + 1]) > switch_yaw:
            e, a, b = frame(z[2 * k], z[2 * k + 1], chain.chart[k])
            edot = a * z[2 * n + 2 * k] + b * z[2 * n + 2 * k + 1]
            new = 1.0 - chain.chart[k]
            z[2 * k], z[2 * k + 1], z[2 * n + 2 * k], z[2 * n + 2 * k + 1] = coordinates(e, edot, new)
            chain.chart[k] = new
            moved.append(k)
    return z, chain, moved


def split(z: np.ndarray, chain: Chain, params: Params) -> tuple[np.ndarray, Chain]:
    """Split the exit link: new exit link ``l_0 - l_nom`` and a fixed link ``l_nom`` on its line.

    Parameters
    ----------
    z : array (4n + Z_TAIL,)
        State: angles [rad], rates [rad/s], L [m], L' [m/s], work states [J].
    chain : Chain
        Its discretization (n links).
    params : Params
        For the masses [kg] and inertias [kg m^2] of the new mesh.

    Returns
    -------
    z : array (4(n+1) + Z_TAIL,)
        The same configuration on n + 1 links (every joint keeps position and velocity).
    chain : Chain
        The new mesh.
    """
    n = chain.n
    q, qd = z[: 2 * n], z[2 * n: 4 * n]
    q2 = np.concatenate([q[:2], q])
    qd2 = np.concatenate([qd[:2], qd])
    lengths = np.concatenate([[chain.l[0] - chain.l_nom, chain.l_nom], chain.l[1:]])
    new = chain_arrays(params, lengths, chain.l_nom, np.r_[chain.chart[0], chain.chart])
    if not params.hose.elastic:
        return np.concatenate([q2, qd2, z[4 * n:]]), new
    lam, lamd, tail = z[4 * n: 5 * n], z[5 * n: 6 * n], z[6 * n:]
    L, Ld = tail[LY.Z_L], tail[LY.Z_LD]
    l0 = L - float(np.sum(chain.l[1:]))
    rho = (l0 - chain.l_nom) / l0  # the new exit link's share of the old one's material
    # the new joint is the material point rho l0 from the exit: the same strain on both sides, its
    # velocity along the line interpolated between the exit's material (L' lam_0 / l_0) and joint 1
    lam_a = rho * lam[0]
    lamd_a = Ld * lam[0] / l0 * (1.0 - rho) + rho * lamd[0]
    lam2 = np.concatenate([[lam_a, lam[0] - lam_a], lam[1:]])
    lamd2 = np.concatenate([[lamd_a, lamd[0] - lamd_a], lamd[1:]])
    return np.concatenate([q2, qd2, lam2, lamd2, tail]), new


def merge(z: np.ndarray, chain: Chain, params: Params) -> tuple[np.ndarray, Chain, float]:
    """Merge links 0 and 1 into a straight exit link to old joint 2; returns (z, chain, delta)
    with delta [m] the free length lost (zero for collinear links).

    Parameters
    ----------
    z : array (4n + Z_TAIL,)
        State: angles [rad], rates [rad/s], L [m], L' [m/s], work states [J]; n >= 2.
    chain : Chain
        Its discretization (n links).
    params : Params
        For the masses [kg] and inertias [kg m^2] of the new mesh.

    Returns
    -------
    z : array (4(n-1) + Z_TAIL,)
        State on n - 1 links: joints 2.. keep position and velocity; L and L' follow.
    chain : Chain
        The new mesh.
    delta : float
        Free hose length lost [m].
    """
    n = chain.n
    assert n >= 2
    if params.hose.elastic:
        return _merge_elastic(z, chain, params)
    q, qd, tail = z[: 2 * n], z[2 * n: 4 * n], z[4 * n:].copy()
    L, Ld = tail[LY.Z_L], tail[LY.Z_LD]
    l0 = L - float(np.sum(chain.l[1:]))
    l1 = chain.l[1]

    e0, a0, b0 = frame(q[0], q[1], chain.chart[0])
    e1, a1, b1 = frame(q[2], q[3], chain.chart[1])
    r2 = l0 * e0 + l1 * e1
    V2 = Ld * e0 + l0 * (a0 * qd[0] + b0 * qd[1]) + l1 * (a1 * qd[2] + b1 * qd[3])
    lam = float(np.linalg.norm(r2))
    e = r2 / lam
    Ld_new = float(V2 @ e)
    edot = (V2 - Ld_new * e) / lam
    ch = best_chart(e)
    th1, th2, d1, d2 = coordinates(e, edot, ch)
    q2 = np.concatenate([[th1, th2], q[4:]])
    qd2 = np.concatenate([[d1, d2], qd[4:]])
    delta = l0 + l1 - lam
    tail[LY.Z_L] = L - delta
    tail[LY.Z_LD] = Ld_new
    lengths = np.concatenate([[lam], chain.l[2:]])
    new = chain_arrays(params, lengths, chain.l_nom, np.r_[ch, chain.chart[2:]])
    return np.concatenate([q2, qd2, tail]), new, delta


def _merge_elastic(z: np.ndarray, chain: Chain, params: Params) -> tuple[np.ndarray, Chain, float]:
    """:func:`merge` of elastic links (docs/model.md §11): the new exit link runs straight to old
    joint 2 (which with everything aft keeps position and velocity), its actual length ``|r_2|``
    and rate ``V_2 . e``; it keeps the two links' mean strain, so it holds the material
    ``|r_2| / (1 + eps)`` and the free length L drops by the rest. L' (the reel's) is unchanged."""
    n = chain.n
    q, qd = z[: 2 * n], z[2 * n: 4 * n]
    lam, lamd, tail = z[4 * n: 5 * n], z[5 * n: 6 * n], z[6 * n:].copy()
    L = tail[LY.Z_L]
    l0 = L - float(np.sum(chain.l[1:]))
    l1 = chain.l[1]
    e0, a0, b0 = frame(q[0], q[1], chain.chart[0])
    e1, a1, b1 = frame(q[2], q[3], chain.chart[1])
    r2 = lam[0] * e0 + lam[1] * e1
    V2 = lamd[0] * e0 + lam[0] * (a0 * qd[0] + b0 * qd[1]) + lamd[1] * e1 + lam[1] * (a1 * qd[2] + b1 * qd[3])
    lam_new = float(np.linalg.norm(r2))
    e = r2 / lam_new
    lamd_new = float(V2 @ e)
    edot = (V2 - lamd_new * e) / lam_new
    ch = best_chart(e)
    th1, th2, d1, d2 = coordinates(e, edot, ch)
    strain = (lam[0] + lam[1]) / (l0 + l1) - 1.0
    delta = l0 + l1 - lam_new / (1.0 + strain)
    tail[LY.Z_L] = L - delta
    lengths = np.concatenate([[lam_new / (1.0 + strain)], chain.l[2:]])
    new = chain_arrays(params, lengths, chain.l_nom, np.r_[ch, chain.chart[2:]])
    znew = np.concatenate([[th1, th2], q[4:], [d1, d2], qd[4:], [lam_new], lam[2:], [lamd_new], lamd[2:], tail])
    return znew, new, delta


def chain_model(params: Params, chain: Chain, duration_s: float | None = None) -> HoseModel:
    """The :class:`~hosedrogue.model.system.HoseModel` of a :class:`Chain` as it is (its link
    lengths; the same masses and inertias), for the equilibrium solver, the linearization and the
    kernels' parameter, environment and gust arrays.

    Parameters
    ----------
    params : Params
        The run's parameters; hose length [m] and links become the chain's.
    chain : Chain
        Link lengths [m].
    duration_s : float, optional
        Length of the run [s] the gust record must cover (see ``HoseModel``).

    Returns
    -------
    HoseModel
    """
    return HoseModel(params, duration_s=duration_s, lengths=chain.l)


def chain_equilibrium(params: Params, chain: Chain, duration_s: float | None = None,
                      statics=None) -> tuple[Equilibrium, HoseModel]:
    """Balance position of the chain as it is (any free length, any mesh), in steady air.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and environment.
    chain : Chain
        The mesh.
    duration_s : float, optional
        Length of the run [s] the model's gust record must cover (see ``HoseModel``).
    statics : callable, optional
        ``statics(model)`` gives the chain's statics for the solver (default: the fixed-length
        chain's evaluation; the engagement's own: :func:`hosedrogue.engagement.balance.engagement_equilibrium`).

    Returns
    -------
    equilibrium : hosedrogue.analysis.equilibrium.Equilibrium
        The balance position (state [rad], drogue position [m]).
    model : HoseModel
        The model it was solved on (:func:`chain_model`).
    """
    model = chain_model(params, chain, duration_s)
    # elastic links: the banded chord, the balance position within its residual tolerance, a
    # third of the time (rigid links keep MINPACK's, their results unchanged to the bit)
    return solve_equilibrium(model.params, model=model, banded=model.elastic,
                             statics=None if statics is None else statics(model)), model


def chain_for_length(params: Params, L: float) -> Chain:
    """The mesh the remesh rules give for free length L grown or shortened from the nominal mesh
    (exit link in [MERGE_RATIO, SPLIT_RATIO) l_nom, every other link l_nom).

    Parameters
    ----------
    params : Params
        Nominal hose length [m] and links (they fix l_nom), masses and inertias.
    L : float
        Free hose length [m].

    Returns
    -------
    Chain
    """
    l_nom = params.hose.length_m / params.hose.links
    m = int(math.floor((L - MERGE_RATIO * l_nom) / l_nom))
    m = max(m, 0)
    l0 = L - m * l_nom
    return chain_arrays(params, np.concatenate([[l0], np.full(m, l_nom)]), l_nom)
