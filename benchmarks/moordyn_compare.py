"""The towed hose in MoorDyn against hosedrogue: accuracy of the steady drogue position and
real-time factors, printed as figures (never asserted).

MoorDyn (https://moordyn.readthedocs.io; PyPI ``moordyn``, the MoorDyn-C v2 Python bindings;
written against 2.7.2) is an axially elastic lumped-mass line model for moorings in water. This
script sets it up for the paper's hose in air and compares it with hosedrogue's rigid-link Kane
model on the same case: ``PAPER`` with bending off, wake off, turbulence off (16 m hose, 4.4 kg/m,
outer diameter 0.067 m, c_n 0.28, c_t 0.001; drogue 29 kg, 0.61 m, c_d 0.712; 150 m/s at 8000 m).

Run:  .venv/bin/python benchmarks/moordyn_compare.py [--segments 1 2 3 5 10 20 40 80 160]
(one core: NUMBA/OMP/OPENBLAS threads are set to 1 here; MoorDyn itself is single-threaded.)
About 100-140 s in all (2-core machine shared with other jobs), most of it MoorDyn at N = 80
and 160. MoorDyn is an optional extra (``pip install -e '.[bench]'``); without it the script
says so and exits 0, as it does when MoorDyn fails. Its input files live in a temporary
directory that is removed afterwards.

MoorDyn set-up (every value MoorDyn needed; derived from ``PAPER`` at run time)
--------------------------------------------------------------------------------
* **Air as the fluid.** Options ``rho`` = ICAO density at 8000 m (0.52517 kg/m^3), ``g`` =
  9.80665 m/s^2 (hosedrogue's G0; MoorDyn-C's default is 9.81), ``WaveKin 0``.
* **Free stream as a current.** ``Currents 1`` (steady current grid) reads
  ``current_profile.txt``: -150 m/s along x at every depth. The tow point is fixed. (Moving the
  fairlead at 150 m/s instead would carry the model 150 m per simulated second away from its
  start; the current gives the tow-point frame directly.) MoorDyn applies the current to the line
  nodes and to the drogue point.
* **Frames.** MoorDyn's z points up, its water surface is z = 0 and a line node above it gets no
  fluid forces; so the tow point is a ``Fixed`` point at (0, 0, -100 m) with ``WtrDpth`` 1000 m,
  far from surface and seabed. MoorDyn (x, y, z) = hosedrogue S_p (x, -y, -z) + (0, 0, -100 m).
* **Line type** (one line, ``NumSegs`` N, ``UnstrLen`` 16 m, end A at the tow point, end B at
  the drogue):
  ``Diam`` 0.067 m, the outer diameter (MoorDyn uses it for buoyancy and as drag diameter).
  ``Mass/m`` = 4.4 + rho_air pi d^2 / 4 = 4.40185 kg/m: MoorDyn subtracts the buoyancy
  rho (pi d^2 / 4) g per metre from the weight and hosedrogue has none, so the buoyant mass is
  added back and the net weight is exactly 4.4 g per metre (checked with
  ``GetLineNodeWeight``); the inertia is 0.04 % higher.
  ``Cd`` = pi c_n = 0.8796: MoorDyn's transverse drag refers to the frontal area d l, the
  paper's c_n to pi d l. ``CdAx`` = c_t = 0.001: MoorDyn's tangential drag refers to pi d l, as
  the paper's does. Both are 1/2 rho C A |v| v of the relative velocity split along and across
  the local tangent, as in hosedrogue (MoorDyn evaluates them at the nodes, hosedrogue at the
  link midpoints).
  ``Ca`` = ``CaAx`` = 0: no added mass (hosedrogue has none; in air it would be 0.002 kg/m).
  ``EI`` = 0: bending off in both models.
  ``EA`` = 5e6 N: the hose is near-inextensible; at the 1.4-1.5 kN tension it stretches 4.4 mm,
  and the printed check (N = 20 again at 10 EA) shows that this moves the steady drogue by
  4.4 mm: within the required 1 cm with a factor 2 to spare. A stiffer line costs MoorDyn time
  step (dt ~ dl sqrt(mu / EA)); this stretch is also MoorDyn's error floor below.
  ``BA/-zeta`` = -1: axial damping at the critical ratio of each segment's axial mode (MoorDyn's
  option; it damps axial ringing and does not change the steady state).
* **Drogue**: a ``Free`` point at line end B: ``Mass`` 29 kg, ``Volume`` 0 (no buoyancy, no
  added mass), ``CdA`` = c_d pi d_d^2 / 4 = 0.2081 m^2 (MoorDyn applies 1/2 rho CdA |v| v of the
  relative velocity, hosedrogue's drogue drag law). Its rotational inertia (hosedrogue: 1.349
  kg m^2) has no counterpart: a MoorDyn point does not rotate.
* **Time integration.** ``tScheme RK2`` (MoorDyn-C's default); ``TmaxIC 0``: no initial-condition
  relaxation (MoorDyn-C builds the IC without currents, useless here); the steady state comes from
  a dynamic run. ``dtM`` = 0.9 dt_max, dt_max being the largest step whose 3 s run from the
  displaced start ends within 1 mm of the same run at 0.3 dl/c (bisection in log dt; dl/c: the
  segment length over the axial wave speed c = sqrt(EA / mu) = 1066 m/s). A finite-only test is
  not enough: near the limit RK2 leaves an axial oscillation that never decays (seen at N = 1).
  Found: dt_max = 0.99-1.01 dl/c for N >= 10 (MoorDyn's own CFL number of dtM: 0.142),
  0.8-1.6 dl/c at N <= 5; dtM = 6.7e-4 s at N = 20, 1.7e-4 s at N = 80, 8.4e-5 s at N = 160.
  The step is pinned by the axial wave: it halves with each doubling of N, so MoorDyn's cost
  grows as N^2. RK4 allows 1.4 dl/c by the same test, at twice the cost per step: its real-time
  factor at N = 10-40 was 20-35 % below RK2's, so RK2 is the faster scheme here (checked while
  writing this benchmark, not re-run).
* **Starts.** MoorDyn's drogue starts at 0.99 L from the tow point (a slightly slack line, laid
  out by MoorDyn as a catenary). From a taut straight start (drogue at exactly L) the
  bending-free line at N >= 20 often falls into a large flapping motion (metres) that it keeps,
  for any dt and axial damping: a second attractor beside the stable steady state, not a
  numerical instability. hosedrogue's bending-free chain shows the same kind of motion (links
  snaking past the 85 deg yaw limit) from larger displacements at n >= 80 with the paper's link
  inertia.

Steady positions
----------------
hosedrogue: ``solve_equilibrium`` at n = 20, 40, 80, 160, 320 links. Its lumping (each link's
mass at the link's aft joint) converges at first order (the printed observed order is 1.00), so
the reference is the Richardson extrapolation 2 r(320) - r(160). MoorDyn: a dynamic run from
the slightly slack line along the reference chord, in 1 s chunks, until the drogue stays within
0.05 mm over 5 s (about 70 s simulated; the hose's pendulum mode, damped only by the air, decays
with a time constant of about 7 s). Errors are Euclidean distances from the reference (the
motion stays in the x-z plane). MoorDyn's half-segment end masses converge much faster: its
error is the 4.4 mm stretch from N = 5 on, and the stiff run at N = 20 lands 0.46 mm from
hosedrogue's reference (0.44 mm of it stretch) -- an independent check of hosedrogue's statics.

Real-time factors
-----------------
Simulated seconds per wall second of a dynamic run from a displaced start (a straight hose 0.05
rad below and 0.05 rad beside the reference chord, at rest), best of 3 runs interleaved between
the models (so a change of machine load hits both). hosedrogue: the compiled RK4 loop
(``rk4_run``, h = 0.005 s, as ``realtime.py`` times it), 20 s; compile time reported apart.
For n > 20 the dynamic runs use ``link_inertia = "rod"`` (m l^2 / 12): the paper's 2.816
kg m^2 belongs to its 0.8 m links, and keeping it per link multiplies the hose's rotational
inertia by n / 20 (the cost per step is the same either way). MoorDyn: ``moordyn.Step`` in 0.5 s
chunks (MoorDyn sub-steps at dtM internally, so the Python call overhead is negligible), 20 s
for N <= 40 and one 5 s run above (the cost of an explicit step does not depend on the state);
``Create`` + ``Init`` reported apart. The last column (distance of the drogue from the model's
own steady position at the end) shows that no run went astray: about 0.1 m is left after 20 s
in both models, about 1.1 m after MoorDyn's 5 s runs.

Caveats: wall times depend on the machine's load. The steady drogue position is one measure of
accuracy only, and it strongly rewards MoorDyn's lumping: N = 2 segments (one free node besides
the drogue) already beat hosedrogue's 20 links there, but cannot represent the hose's dynamics.
So the ratio at equal resolution (N = n) is printed as well.
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from hosedrogue.analysis.equilibrium import solve_equilibrium  # noqa: E402
from hosedrogue.constants import G0  # noqa: E402
from hosedrogue.controllers.linear import LinearController  # noqa: E402
from hosedrogue.environment.atmosphere import density  # noqa: E402
from hosedrogue.model.integrate import rk4_run  # noqa: E402
from hosedrogue.model.system import HoseModel  # noqa: E402
from hosedrogue.spec.params import PAPER, Actuator  # noqa: E402
from hosedrogue.simulation.simulate import loop_arrays, output_arrays  # noqa: E402

#: The compared case: the paper's hose without bending, wake and turbulence.
CASE = PAPER.replace(hose={"bending": "off"}, wake={"enabled": False}, turbulence={"enabled": False})

HOSE_LINKS = (20, 40, 80, 160)  # hosedrogue resolutions compared
REFERENCE_LINKS = 320  # with 160: the Richardson reference
MOORDYN_SEGMENTS = (1, 2, 3, 5, 10, 20, 40, 80, 160)

#: Axial stiffness of the MoorDyn line [N]: stretch ~ T L / EA ~ 4.4 mm at the 1.4-1.5 kN tension.
EA_N = 5.0e6
#: MoorDyn's BA/-zeta: -1 is the critical damping ratio of each segment's axial mode.
AXIAL_DAMPING = -1.0
TIME_SCHEME = "RK2"
TOW_DEPTH_M = 100.0  # below MoorDyn's water surface (z = 0): nodes above it get no fluid forces
WATER_DEPTH_M = 1000.0
#: Fraction of the largest stable step actually used.
DT_MARGIN = 0.9
#: Length of the stability probe [s]: an axial instability grows in far fewer steps than this.
STABILITY_PROBE_S = 3.0
#: A probe counts as stable if it ends this close [m] to the probe at REFERENCE_STEP_FACTOR dl/c.
STABILITY_TOLERANCE_M = 1e-3
REFERENCE_STEP_FACTOR = 0.3
#: MoorDyn starts with the drogue at this fraction of the hose length from the tow point: a
#: slightly slack line (MoorDyn lays it out as a catenary). From a taut straight start the
#: bending-free line at N >= 20 often falls into a large (metres) flapping motion that it keeps
#: (it coexists with the stable steady state; see the notes in the module docstring).
SLACK_START = 0.99
#: Steady when the drogue stays within this distance [m] over SETTLE_WINDOW_S: well below the
#: errors compared (>= 4 mm, the stretch).
SETTLE_TOLERANCE_M = 5e-5
SETTLE_WINDOW_S = 5.0
SETTLE_MAX_S = 150.0
#: Displaced start: [pitch, yaw] offsets from the reference chord [rad].
DISPLACEMENT_RAD = (0.05, 0.05)
DYNAMIC_S = 20.0
RTF_REPEATS = 3
CHUNK_S = 0.5


# --------------------------------------------------------------------------------------------
# the case in both models' terms
# --------------------------------------------------------------------------------------------


def air_density(p=CASE) -> float:
    """Air density [kg/m^3] of the case (ICAO atmosphere)."""
    return density(p.flight.altitude_m) * p.flight.density_scale


def chord_direction(pitch_rad: float, yaw_rad: float) -> np.ndarray:
    """Unit vector in S_p of a link with these angles (docs/model.md: e = [-c1 c2, -s2, s1 c2])."""
    c1, s1, c2, s2 = math.cos(pitch_rad), math.sin(pitch_rad), math.cos(yaw_rad), math.sin(yaw_rad)
    return np.array([-c1 * c2, -s2, s1 * c2])


def chord_angles(r_sp: np.ndarray) -> tuple[float, float]:
    """[pitch, yaw] [rad] of the straight line from the tow point to r_sp (S_p)."""
    e = r_sp / np.linalg.norm(r_sp)
    yaw = math.asin(-e[1])
    return math.atan2(e[2], -e[0]), yaw


def sp_to_moordyn(r_sp: np.ndarray) -> np.ndarray:
    """S_p (x fwd, y right, z down; origin tow point) -> MoorDyn global (z up, tow point below 0)."""
    return np.array([r_sp[0], -r_sp[1], -r_sp[2] - TOW_DEPTH_M])


def moordyn_to_sp(r_md) -> np.ndarray:
    r = np.asarray(r_md, dtype=float)
    return np.array([r[0], -r[1], -(r[2] + TOW_DEPTH_M)])


# --------------------------------------------------------------------------------------------
# MoorDyn
# --------------------------------------------------------------------------------------------


class MoorDynError(RuntimeError):
    """MoorDyn failed; the message carries what it printed."""


@contextlib.contextmanager
def captured_c_output(sink: Path):
    """Send the C library's stdout/stderr to ``sink`` (MoorDyn prints its banner and log there)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(sink, "ab") as fh:
        os.dup2(fh.fileno(), 1)
        os.dup2(fh.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


def _f(x) -> str:
    """A number as MoorDyn reads it (``repr`` of a numpy float is not a number to MoorDyn)."""
    return format(float(x), ".17g")


def moordyn_input(segments: int, dt_s: float, drogue_sp: np.ndarray, ea_n: float, p=CASE) -> str:
    """The MoorDyn v2 input file of the towed hose (see the module docstring)."""
    rho = air_density(p)
    hose, drogue = p.hose, p.drogue
    area = math.pi * hose.outer_diameter_m**2 / 4
    mass_per_length = hose.mass_per_length_kg_m + rho * area  # buoyancy added back
    cd_frontal = math.pi * hose.normal_drag_coefficient  # paper: pi d l reference; MoorDyn: d l
    cda = drogue.drag_coefficient * math.pi * drogue.diameter_m**2 / 4
    d0 = sp_to_moordyn(drogue_sp)
    # Diam, Mass/m, EA, BA/-zeta, EI, Cd, Ca, CdAx, CaAx
    line_type = " ".join(_f(v) for v in (hose.outer_diameter_m, mass_per_length, ea_n, AXIAL_DAMPING, 0.0,
                                         cd_frontal, 0.0, hose.tangential_drag_coefficient, 0.0))
    return f"""--------------------- MoorDyn Input File ------------------------------------
hosedrogue benchmark: towed refuelling hose in air (benchmarks/moordyn_compare.py)
---------------------- LINE TYPES ------------------------------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
hose {line_type}
---------------------- POINTS ----------------------------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word/ID) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0.0 0.0 {_f(-TOW_DEPTH_M)} 0.0 0.0 0.0 0.0
2 Free {_f(d0[0])} {_f(d0[1])} {_f(d0[2])} {_f(drogue.mass_kg)} 0.0 {_f(cda)} 0.0
---------------------- LINES -----------------------------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 hose 1 2 {_f(hose.length_m)} {segments} -
---------------------- OPTIONS ---------------------------------------------------------
0 writeLog
{_f(dt_s)} dtM
{TIME_SCHEME} tScheme
{_f(G0)} g
{_f(rho)} rho
{_f(WATER_DEPTH_M)} WtrDpth
0 WaveKin
1 Currents
0 TmaxIC
1 disableOutput
1 disableOutTime
------------------------- need this line -----------------------------------------------
"""


def current_profile(p=CASE) -> str:
    """``current_profile.txt``: the free stream, -V along x at every depth (3 header lines)."""
    v = p.flight.airspeed_m_s
    return ("--- uniform current: the free stream relative to the tow point\n"
            "depth-independent\nz (m), ux (m/s), uy (m/s), uz (m/s)\n"
            f"{_f(-WATER_DEPTH_M)} {_f(-v)} 0.0 0.0\n0.0 {_f(-v)} 0.0 0.0\n")


class MoorDynHose:
    """One MoorDyn system of the towed hose, living in a temporary directory."""

    def __init__(self, segments: int, dt_s: float, drogue_sp: np.ndarray, ea_n: float = EA_N):
        import moordyn

        self.md = moordyn
        self.segments = segments
        self._tmp = tempfile.TemporaryDirectory(prefix="hosedrogue-moordyn-")
        folder = Path(self._tmp.name)
        self.log = folder / "console.txt"
        path = folder / "hose.txt"
        path.write_text(moordyn_input(segments, dt_s, drogue_sp, ea_n))
        (folder / "current_profile.txt").write_text(current_profile())
        self.system = None
        t0 = time.perf_counter()
        try:
            with captured_c_output(self.log):
                self.system = moordyn.Create(str(path))
                moordyn.SetVerbosity(self.system, moordyn.LEVEL_NONE)
                status = moordyn.Init(self.system, [], [])
                self.init_s = time.perf_counter() - t0
                self.drogue = moordyn.GetPoint(self.system, 2)
                self.line = moordyn.GetLine(self.system, 1)
        except Exception as exc:  # the bindings raise RuntimeError; keep the library's own words
            printed = self._tail()
            self.close()
            raise MoorDynError(f"MoorDyn set-up failed ({type(exc).__name__}: {exc}); it printed: "
                               f"{printed}") from None
        if status != moordyn.ERRCODE_SUCCESS:
            printed = self._tail()
            self.close()
            raise MoorDynError(f"MoorDyn Init returned {status}; it printed: {printed}")
        self.t = 0.0

    def _tail(self) -> str:
        try:
            text = self.log.read_text(errors="replace").strip().splitlines()
        except OSError:
            return "(nothing)"
        return " | ".join(text[-4:]) or "(nothing)"

    def advance(self, duration_s: float, chunk_s: float = CHUNK_S) -> None:
        """Integrate ``duration_s`` in calls of ``chunk_s`` (MoorDyn sub-steps at dtM)."""
        end = self.t + duration_s
        while self.t < end - 1e-9:
            step = min(chunk_s, end - self.t)
            try:
                self.md.Step(self.system, [], [], self.t, step)
            except RuntimeError as exc:
                raise MoorDynError(f"MoorDyn Step at t = {self.t:g} s failed: {exc}") from None
            self.t += step

    def drogue_sp(self) -> np.ndarray:
        return moordyn_to_sp(self.md.GetPointPos(self.drogue))

    def stretched_length_m(self) -> float:
        nodes = np.array([self.md.GetLineNodePos(self.line, i) for i in range(self.segments + 1)])
        return float(np.sum(np.linalg.norm(np.diff(nodes, axis=0), axis=1)))

    def cfl_and_dt(self) -> tuple[float, float]:
        """MoorDyn's CFL number for its step, and the step it uses [s].

        Read from the compiled module: moordyn 2.7.2's ``GetCFL``/``GetDt`` wrappers drop the
        value (they call ``cmoordyn.get_cfl``/``get_dt`` without returning it).
        """
        import cmoordyn

        return float(cmoordyn.get_cfl(self.system)), float(cmoordyn.get_dt(self.system))

    def close(self) -> None:
        if self.system is not None:
            with contextlib.suppress(Exception), captured_c_output(self.log):
                self.md.Close(self.system)
            self.system = None
        self._tmp.cleanup()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def axial_step_scale(segments: int, ea_n: float = EA_N, p=CASE) -> float:
    """dl / c [s]: the time the axial wave (c = sqrt(EA / mu)) needs to cross one segment."""
    return (p.hose.length_m / segments) / math.sqrt(ea_n / p.hose.mass_per_length_kg_m)


def moordyn_probe(segments: int, dt_s: float, start_sp: np.ndarray, ea_n: float = EA_N) -> np.ndarray:
    """Drogue position S_p [m] after STABILITY_PROBE_S from ``start_sp`` (MoorDynError if MoorDyn
    fails or the position is not finite)."""
    with MoorDynHose(segments, dt_s, start_sp, ea_n) as m:
        m.advance(STABILITY_PROBE_S)
        r = m.drogue_sp()
    if not np.all(np.isfinite(r)):
        raise MoorDynError(f"non-finite drogue position after {STABILITY_PROBE_S:g} s")
    return r


def moordyn_largest_stable_dt(segments: int, start_sp: np.ndarray, ea_n: float = EA_N,
                              iterations: int = 7) -> float:
    """Bisect (in log dt) the largest step whose probe ends within STABILITY_TOLERANCE_M of the
    probe at REFERENCE_STEP_FACTOR dl/c [s]. Divergence fails this, and so does an axial
    oscillation that does not decay (RK2 at a marginal step), which a finite-only test would pass.
    """
    scale = axial_step_scale(segments, ea_n)
    try:
        reference = moordyn_probe(segments, REFERENCE_STEP_FACTOR * scale, start_sp, ea_n)
    except MoorDynError as exc:
        raise MoorDynError(f"N = {segments}, dt = {REFERENCE_STEP_FACTOR * scale:.3g} s: {exc}") from None

    def stable(dt):
        try:
            r = moordyn_probe(segments, dt, start_sp, ea_n)
        except MoorDynError:
            return False
        return np.linalg.norm(r - reference) < STABILITY_TOLERANCE_M

    lo, hi = REFERENCE_STEP_FACTOR * scale, 4.0 * scale
    if stable(hi):
        return hi
    for _ in range(iterations):
        mid = math.sqrt(lo * hi)
        if stable(mid):
            lo = mid
        else:
            hi = mid
    return lo


def moordyn_steady(segments: int, dt_s: float, reference_sp: np.ndarray, ea_n: float = EA_N):
    """Run from a slightly slack straight line along the reference chord until the drogue is
    steady (or SETTLE_MAX_S). Returns (drogue position S_p [m], simulated time [s], residual
    motion over the last SETTLE_WINDOW_S [m], stretch [m], wall time [s]).
    """
    start = SLACK_START * CASE.hose.length_m * reference_sp / np.linalg.norm(reference_sp)
    samples = []
    per_window = int(round(SETTLE_WINDOW_S)) + 1  # one sample per simulated second
    t0 = time.perf_counter()
    with MoorDynHose(segments, dt_s, start, ea_n) as m:
        residual = math.inf
        while m.t < SETTLE_MAX_S - 1e-9:
            m.advance(1.0)
            samples.append(m.drogue_sp())
            if len(samples) >= per_window and m.t >= 20.0:
                window = np.array(samples[-per_window:])
                residual = float(np.max(np.linalg.norm(window - window.mean(axis=0), axis=1)))
                if residual < SETTLE_TOLERANCE_M:
                    break
        stretch = m.stretched_length_m() - CASE.hose.length_m
        return samples[-1], m.t, residual, stretch, time.perf_counter() - t0


def moordyn_real_time_factor(segments: int, dt_s: float, start_sp: np.ndarray, duration_s: float):
    """Simulated/wall ratio of ``duration_s`` from ``start_sp``, the Create + Init time [s], and
    the drogue position S_p [m] at the end."""
    with MoorDynHose(segments, dt_s, start_sp) as m:
        t0 = time.perf_counter()
        m.advance(duration_s)
        wall = time.perf_counter() - t0
        return duration_s / wall, m.init_s, m.drogue_sp()


# --------------------------------------------------------------------------------------------
# hosedrogue
# --------------------------------------------------------------------------------------------


def hose_params(links: int, dynamic: bool = False):
    """The case at ``links`` links. For dynamic runs with more than 20 links the link inertia is
    the rod's m l^2 / 12: the paper's 2.816 kg m^2 belongs to its 0.8 m links, and keeping it per
    link multiplies the hose's rotational inertia by n / 20 (with it, a straight hose released
    0.05 rad off the chord snakes up to 23 deg of link yaw at n = 160, and from 0.1/0.15 rad past
    the 85 deg yaw limit at n >= 80). Neither the cost per step nor the statics depend on it.
    """
    hose = {"links": links}
    if dynamic and links > 20:
        hose["link_inertia"] = "rod"
    return CASE.replace(hose=hose)


def straight_hose_state(links: int, pitch_rad: float, yaw_rad: float) -> np.ndarray:
    """State [q, qd] of a straight hose at rest with every link at these angles."""
    q = np.empty(2 * links)
    q[0::2], q[1::2] = pitch_rad, yaw_rad
    return np.concatenate([q, np.zeros(2 * links)])


def hose_rk4_wall(model: HoseModel, x0: np.ndarray, duration_s: float, repeats: int = 3):
    """Best wall time [s] of the compiled RK4 loop over ``duration_s``, and the final state."""
    h = model.params.numerics.step_s
    nsteps = int(round(duration_s / h))
    ctrl = LinearController.static_zero()
    ts, zs, us = np.empty(2), np.empty((2, x0.size)), np.empty((2, 2))
    loop = loop_arrays(ctrl, np.zeros(2), Actuator(), np.zeros((1, 2)), 1.0)
    args = (x0, h, nsteps, nsteps, *model.kernel_args(), *loop,
            math.radians(model.params.numerics.max_yaw_deg), ts, zs, us, *output_arrays(2, model.n))
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        status, saved, _ = rk4_run(*args)
        best = min(best, time.perf_counter() - t0)
        if status != 0:
            raise RuntimeError(f"hosedrogue RK4 run stopped with status {status}")
    return best, zs[saved - 1].copy()


# --------------------------------------------------------------------------------------------
# the comparison
# --------------------------------------------------------------------------------------------


def mm(x: float) -> str:
    """A length [m] printed in millimetres."""
    return f"{x * 1e3:8.2f} mm"


def hose_steady_positions():
    """hosedrogue's balance positions of the drogue (S_p) [m] by links, and the reference."""
    t0 = time.perf_counter()
    pos = {n: solve_equilibrium(hose_params(n)).drogue_position_m for n in (*HOSE_LINKS, REFERENCE_LINKS)}
    t_eq = time.perf_counter() - t0
    ref = 2 * pos[REFERENCE_LINKS] - pos[REFERENCE_LINKS // 2]  # first-order Richardson extrapolation
    fine = [REFERENCE_LINKS // 4, REFERENCE_LINKS // 2, REFERENCE_LINKS]
    order = math.log2(np.linalg.norm(pos[fine[0]] - pos[fine[1]]) / np.linalg.norm(pos[fine[1]] - pos[fine[2]]))
    err = {n: float(np.linalg.norm(pos[n] - ref)) for n in HOSE_LINKS}
    print(f"\nhosedrogue balance position of the drogue (S_p: x fwd, z down), solve_equilibrium "
          f"({t_eq:.2f} s for all, incl. compile or cache load):")
    for n in pos:
        note = f"error {mm(err[n])}" if n in err else "(enters the reference)"
        print(f"  n = {n:4d}: x = {pos[n][0]:9.5f} m, z = {pos[n][2]:8.5f} m   {note}")
    print(f"  reference 2 r({REFERENCE_LINKS}) - r({REFERENCE_LINKS // 2}): x = {ref[0]:9.5f} m, "
          f"z = {ref[2]:8.5f} m (observed order of convergence {order:.2f}: first order, as the aft-joint "
          f"lumping implies)")
    return pos, ref, err


def moordyn_steady_table(segments, ref: np.ndarray, start_sp: np.ndarray) -> dict:
    """Step search and steady state for each N; prints one entry per N and returns them."""
    print(f"\nMoorDyn {TIME_SCHEME}, EA = {EA_N:.3g} N, BA/-zeta = {AXIAL_DAMPING:g}. dt_max: largest step "
          f"whose {STABILITY_PROBE_S:g} s run from the displaced start ends within "
          f"{STABILITY_TOLERANCE_M * 1e3:g} mm of the run at {REFERENCE_STEP_FACTOR} dl/c (bisection; "
          f"dl/c = segment / axial wave speed); dtM = {DT_MARGIN} dt_max. Steady drogue: run from the "
          f"reference chord until it moves < {SETTLE_TOLERANCE_M * 1e3:g} mm over {SETTLE_WINDOW_S:g} s:")
    md = {}
    for N in segments:
        t0 = time.perf_counter()
        dt_max = moordyn_largest_stable_dt(N, start_sp)
        dt = DT_MARGIN * dt_max
        t_search = time.perf_counter() - t0
        note = ""
        try:
            r, t_settle, resid, stretch, wall = moordyn_steady(N, dt, ref)
            settled = resid < SETTLE_TOLERANCE_M
        except MoorDynError:
            settled = False
        if not settled:  # the long run misbehaved where the short probe did not: step down once
            dt *= 0.5
            note = f" (dtM halved: the settling run did not settle at {DT_MARGIN} dt_max)"
            r, t_settle, resid, stretch, wall = moordyn_steady(N, dt, ref)
        with MoorDynHose(N, dt, start_sp) as m:
            cfl, dt_used = m.cfl_and_dt()
        if not math.isclose(dt_used, dt, rel_tol=1e-9):
            note += f" (MoorDyn reports dtM = {dt_used:.3e} s, not the {dt:.3e} s given)"
        err = float(np.linalg.norm(r - ref))
        md[N] = {"dt": dt, "err": err, "pos": r, "steady": resid < SETTLE_TOLERANCE_M}
        print(f"  N = {N:4d}: dt_max = {dt_max:.3e} s = {dt_max / axial_step_scale(N):.2f} dl/c, "
              f"dtM = {dt:.3e} s (MoorDyn CFL {cfl:.3g}){note}\n"
              f"            x = {r[0]:9.5f} m, z = {r[2]:8.5f} m, error {mm(err)}, stretch {mm(stretch)}, "
              f"{'steady' if md[N]['steady'] else 'NOT steady'} at {t_settle:.0f} s (residual "
              f"{resid * 1e3:.3f} mm); wall {t_search:.1f} s step search + {wall:.1f} s settling", flush=True)
    return md


def stretch_check(md: dict, ref: np.ndarray, start_sp: np.ndarray) -> None:
    """Print how far the stretch at EA_N moves the steady drogue: N = 20 again at 10 EA_N."""
    N = 20 if 20 in md else max(md)
    ea = 10 * EA_N
    dt = DT_MARGIN * moordyn_largest_stable_dt(N, start_sp, ea)
    r, t_end, resid, stretch, _ = moordyn_steady(N, dt, ref, ea)
    shift = float(np.linalg.norm(md[N]["pos"] - r)) * 10 / 9  # the stretch scales as 1 / EA
    print(f"  stretch check, N = {N} at EA = {ea:.3g} N (dtM {dt:.3e} s): x = {r[0]:9.5f} m, "
          f"z = {r[2]:8.5f} m, error {mm(float(np.linalg.norm(r - ref)))}, stretch {mm(stretch)} "
          f"(residual {resid * 1e3:.3f} mm at {t_end:.0f} s)\n"
          f"            => the stretch at EA = {EA_N:.3g} N moves the steady drogue by {mm(shift)}")


def real_time_factors(md: dict, hose_pos: dict, angles: tuple[float, float], start_sp: np.ndarray) -> dict:
    """Best real-time factors of both models from the displaced start, the runs interleaved so
    that a change of the machine's load hits both. Fills md[N]["rtf"]; returns hosedrogue's by n."""
    t0 = time.perf_counter()
    models = {n: HoseModel(hose_params(n, dynamic=True)) for n in HOSE_LINKS}
    starts = {n: straight_hose_state(n, *angles) for n in HOSE_LINKS}
    hose_rk4_wall(models[HOSE_LINKS[0]], starts[HOSE_LINKS[0]], 0.01, repeats=1)
    t_compile = time.perf_counter() - t0
    md_duration = {N: DYNAMIC_S if N <= 40 else 5.0 for N in md}
    hd_rtf, hd_end = {n: 0.0 for n in HOSE_LINKS}, {}
    md_init = {N: math.inf for N in md}
    for rep in range(RTF_REPEATS):
        for N in md:
            if rep > 0 and N > 40:
                continue  # one run: long enough in wall time to be steady
            rtf, init, r_end = moordyn_real_time_factor(N, md[N]["dt"], start_sp, md_duration[N])
            md[N]["rtf"] = max(md[N].get("rtf", 0.0), rtf)
            md[N]["end"] = float(np.linalg.norm(r_end - md[N]["pos"]))
            md_init[N] = min(md_init[N], init)
        for n, model in models.items():
            wall, x_end = hose_rk4_wall(model, starts[n], DYNAMIC_S, repeats=1)
            hd_rtf[n] = max(hd_rtf[n], DYNAMIC_S / wall)
            hd_end[n] = float(np.linalg.norm(model.joint_positions(x_end[: 2 * n])[-1] - hose_pos[n]))
    print(f"\nreal-time factors of a dynamic run from the displaced start (straight hose "
          f"+{DISPLACEMENT_RAD[0]:g} rad pitch and {DISPLACEMENT_RAD[1]:g} rad yaw off the reference chord, at "
          f"rest; MoorDyn's drogue at {SLACK_START} L), best of {RTF_REPEATS} interleaved runs "
          f"(MoorDyn N > 40: one run); last column: the drogue's distance from the model's own steady position at the end")
    for N in md:
        print(f"  MoorDyn    N = {N:4d}: {md_duration[N]:4.0f} s simulated, real-time factor "
              f"{md[N]['rtf']:10,.1f}  (Create + Init {md_init[N] * 1e3:5.1f} ms)   {mm(md[N]['end'])}")
    print(f"  hosedrogue: first RK4 call (compile or cache load) {t_compile:.2f} s")
    for n, model in models.items():
        print(f"  hosedrogue n = {n:4d}: {DYNAMIC_S:4.0f} s simulated, real-time factor {hd_rtf[n]:10,.1f}  "
              f"(RK4, h = {model.params.numerics.step_s} s, link inertia "
              f"{model.params.hose.link_inertia!r})   {mm(hd_end[n])}")
    return hd_rtf


def print_comparison(md: dict, hd_rtf: dict, hd_err: dict) -> None:
    """Ratios of real-time factors at matched steady accuracy and at equal resolution."""
    print("\nat matched accuracy of the steady drogue position (coarsest MoorDyn N at least as accurate):")
    for n in HOSE_LINKS:
        ok = [N for N in sorted(md) if md[N]["steady"] and md[N]["err"] <= hd_err[n]]
        if not ok:
            print(f"  hosedrogue n = {n:3d} (error {mm(hd_err[n])}): no tested MoorDyn N is as accurate")
            continue
        N = ok[0]
        print(f"  hosedrogue n = {n:3d} (error {mm(hd_err[n])}, RTF {hd_rtf[n]:9,.1f})  vs  MoorDyn N = {N:3d} "
              f"(error {mm(md[N]['err'])}, RTF {md[N]['rtf']:9,.1f}):  hosedrogue / MoorDyn = "
              f"{hd_rtf[n] / md[N]['rtf']:6.3f}")
    common = [n for n in HOSE_LINKS if n in md]
    if common:
        print("at equal resolution (N = n: the same number of lumped masses along the hose):")
    for n in common:
        print(f"  n = N = {n:3d}: hosedrogue error {mm(hd_err[n])}, RTF {hd_rtf[n]:9,.1f};  MoorDyn error "
              f"{mm(md[n]['err'])}, RTF {md[n]['rtf']:9,.1f};  hosedrogue / MoorDyn = "
              f"{hd_rtf[n] / md[n]['rtf']:6.1f}")


def moordyn_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("moordyn")
    except PackageNotFoundError:
        return "?"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--segments", type=int, nargs="+", default=list(MOORDYN_SEGMENTS),
                    help="MoorDyn segment counts N (default: %(default)s)")
    args = ap.parse_args(argv)
    wall0 = time.perf_counter()
    try:
        import moordyn  # noqa: F401
    except ImportError as exc:
        print(f"moordyn is not installed ({exc}); this optional benchmark needs the 'bench' extra: "
              f"pip install -e '.[bench]'. Nothing to compare.")
        return 0
    print(f"case: PAPER, bending off, wake off, turbulence off; rho = {air_density():.5f} kg/m^3, "
          f"g = {G0} m/s^2, V = {CASE.flight.airspeed_m_s:g} m/s; moordyn {moordyn_version()}")

    hose_pos, ref, hd_err = hose_steady_positions()
    pitch_ref, _ = chord_angles(ref)
    angles = (pitch_ref + DISPLACEMENT_RAD[0], DISPLACEMENT_RAD[1])
    displaced_sp = SLACK_START * CASE.hose.length_m * chord_direction(*angles)
    try:
        md = moordyn_steady_table(args.segments, ref, displaced_sp)
        stretch_check(md, ref, displaced_sp)
        hd_rtf = real_time_factors(md, hose_pos, angles, displaced_sp)
    except MoorDynError as exc:
        print(f"MoorDyn failed: {exc}\nno comparison printed (moordyn is an optional extra).")
        return 0
    print_comparison(md, hd_rtf, hd_err)
    print(f"\ntotal wall time {time.perf_counter() - wall0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
