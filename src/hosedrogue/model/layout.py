"""The slot tables of the compiled core: every float array the kernels exchange, declared once,
and the codes their slots hold.

The kernels pass their scalars in flat float64 arrays. Each array's slots are declared here, as a
:class:`Layout`: a sequence of ``(name, width, meaning)`` entries, from which the offsets
and the table's end are computed, never typed by hand. The names stay plain module-level ints,
``(PS_G, PS_RHO, ...) = PS.offsets()``, which numba freezes into the compiled code as constants
(the test suite checks that each name on the left is its entry's offset). A table may continue
after another (``after=``), as the tanker's motion slots (:data:`ENV_M`) continue the air's
(:data:`ENV`) in the one ``env`` array. The codes some slots hold (the reel's law in ``EP_LAW``,
the bending mode in ``PS_BENDING``, ...) and the kernels' status codes (``C_STATUS``) follow
their tables.

The tables, by the array they lay out:

* ``ps``, the model's scalars: :data:`PS` (:mod:`hosedrogue.model.system` packs it);
* ``env``, the air: :data:`ENV` (the wake's scalars: :data:`hosedrogue.environment.wake.WAKE_LAYOUT`),
  continued by the tanker's motion, :data:`ENV_M` (:mod:`hosedrogue.model.frame`), then the
  motion table, :data:`MOTION_HEAD` and a :data:`MOTION_ROW` per ramp;
* ``act``, the drogue's actuator: the ideal actuator, :data:`ACT`
  (:meth:`hosedrogue.spec.sections.Actuator.as_array`), continued by the control surfaces,
  :data:`SURFACES` (:func:`hosedrogue.model.drogue_actuator.actuator_array`);
* ``ep``, the engagement's scalars: :data:`EP` (:func:`hosedrogue.engagement.parameters.engagement_parameters`);
* the engagement's state after the hose's entries: :data:`TAIL`, then the block of the pilot's
  states, :data:`PILOT`, or of the receiver's, :data:`RECEIVER`;
* ``out``, the scalars of one engagement evaluation: :data:`OUT`;
* the sampled-data loops (:mod:`hosedrogue.model.sampled`): a ring row, the raw measurement of a
  state, :data:`RAW`; the measurement a controller reads, :data:`MEAS`
  (:class:`hosedrogue.controllers.sampled.Measurement`); the counters of a stepped run (an int64
  array), :data:`CTR`.

Why one module: the tables are shared by modules that import one another. ``env`` is read by
:mod:`.chain_loads` and :mod:`.frame`, and :mod:`.chain_loads` imports :mod:`.frame`, so
:mod:`.frame` could not continue a table declared in :mod:`.chain_loads`; ``act`` is read by
:mod:`.integrate` (the ideal actuator) and :mod:`.drogue_actuator` (the surfaces); the
engagement's output row is as wide as :data:`MAX_SURFACES` servo rates; ``ep``, the state's tail
and ``out`` are read by every module of :mod:`hosedrogue.model.engagement` and packed by
:mod:`hosedrogue.engagement`. This module imports nothing from ``model`` (only the wake's table
and the bow wave's shape codes from :mod:`hosedrogue.environment`, a layer below), so every
kernel module can import its names without a cycle, and a reader finds every table in one
place. The environment's own tables (the wake's scalars) stay in :mod:`hosedrogue.environment`:
``model`` may import from ``environment``, not the reverse.
"""

from __future__ import annotations

from typing import NamedTuple

from ..environment.bow_wave import SHAPE_LINE, SHAPE_OFF, SHAPE_RANKINE
from ..environment.wake import WAKE_SIZE


class Slot(NamedTuple):
    """One entry of a :class:`Layout`: ``width`` consecutive slots from ``offset``."""

    name: str
    offset: int
    width: int
    meaning: str


class Layout:
    """A slot table: named runs of consecutive slots, their offsets computed in declaration order.

    Parameters
    ----------
    name : str
        The array the table lays out (for :meth:`describe`).
    entries : sequence of (str, int, str)
        ``(name, width, meaning)`` per entry: the constant's name, its number of slots (>= 1) and
        what it holds, with its unit.
    after : Layout, optional
        The table this one continues in the same array: its first slot is ``after.end``.
    """

    def __init__(self, name: str, entries, after: Layout | None = None):
        self.name = name
        self.after = after
        self.start = after.end if after is not None else 0
        slots = []
        offset = self.start
        for key, width, meaning in entries:
            if not (isinstance(width, int) and width >= 1):
                raise ValueError(f"{name}.{key}: width {width!r} must be an int >= 1")
            slots.append(Slot(key, offset, width, meaning))
            offset += width
        names = [s.name for s in slots]
        if len(set(names)) != len(names):
            raise ValueError(f"{name}: a name is declared twice")
        self.slots = tuple(slots)
        self._by_name = {s.name: s for s in slots}
        #: one past the table's last slot (the array's length when nothing follows)
        self.end = offset

    @property
    def size(self) -> int:
        """Number of slots of this table (the sum of its widths; ``end - start``)."""
        return self.end - self.start

    def offsets(self) -> tuple:
        """The offsets of every entry, in declaration order (to unpack into the module's names)."""
        return tuple(s.offset for s in self.slots)

    def slice(self, name: str) -> slice:
        """The slots of entry ``name`` (for packing arrays in Python)."""
        s = self._by_name[name]
        return slice(s.offset, s.offset + s.width)

    def __getitem__(self, name: str) -> Slot:
        return self._by_name[name]

    def __iter__(self):
        return iter(self.slots)

    def __len__(self) -> int:
        return len(self.slots)

    def describe(self) -> str:
        """The table as text: offset, width, name and meaning of every entry."""
        head = f"{self.name}: slots {self.start}..{self.end - 1} ({self.size})"
        rows = [f"{s.offset:4d}  {s.width:2d}  {s.name:14s}  {s.meaning}" for s in self.slots]
        return "\n".join([head] + rows)

    def __repr__(self) -> str:
        return f"Layout({self.name!r}, {len(self.slots)} entries, slots {self.start}..{self.end - 1})"


# --- ps: the model's scalars (chain_loads, chain_dynamics, elastic) -----------------------------
PS = Layout("ps", [
    ("PS_G", 1, "gravity [m/s^2]"),
    ("PS_RHO", 1, "air density [kg/m^3]"),
    ("PS_V", 1, "airspeed [m/s]"),
    ("PS_DO", 1, "hose outer diameter [m]"),
    ("PS_CT", 1, "tangential drag coefficient c_t [-]"),
    ("PS_CN", 1, "normal drag coefficient c_n [-]"),
    ("PS_DROGUE_CDA", 1, "drogue area x drag coefficient [m^2]"),
    ("PS_EI", 1, "bending stiffness E I [N m^2]"),
    ("PS_BENDING", 1, "bending mode: BENDING_OFF 0, BENDING_PAPER 1, BENDING_MOMENT 2"),
    ("PS_DRAG_QUAD", 1, "link drag quadrature: DRAG_MIDPOINT 0, DRAG_GAUSS2 1 (two-point Gauss)"),
    ("PS_BEND_DAMP", 1, "structural bending damping c_b [N m^2 s]"),
    ("PS_M_TOW", 1, "mass lumped at the tow point (joint 0) [kg]: carried by the tanker, it never moves, so "
                    "it enters only the tow-point force (its weight); nonzero for the split lumping"),
    ("PS_EA", 1, "axial stiffness EA [N] of the hose (inf: rigid, inextensible links, the paper's); "
                 "tension EA eps + c_a deps/dt (hosedrogue.model.elastic)"),
    ("PS_CA", 1, "Kelvin-Voigt axial damping c_a [N s]"),
])
(PS_G, PS_RHO, PS_V, PS_DO, PS_CT, PS_CN, PS_DROGUE_CDA, PS_EI, PS_BENDING, PS_DRAG_QUAD, PS_BEND_DAMP, PS_M_TOW,
 PS_EA, PS_CA) = PS.offsets()
PS_SIZE = PS.end
#: codes of PS_BENDING and PS_DRAG_QUAD
BENDING_OFF, BENDING_PAPER, BENDING_MOMENT = 0, 1, 2
DRAG_MIDPOINT, DRAG_GAUSS2 = 0, 1

# --- env: the air (chain_loads) ----------------------------------------------------------------
ENV = Layout("env", [
    ("ENV_V", 1, "airspeed [m/s] (manoeuvring: the evaluation's copy holds the airspeed at its time)"),
    ("ENV_FROZEN", 1, "1.0: the frozen gust field (a point -px behind the tow point meets it -px/V later), "
                      "0.0: the uniform one (the same gust along the hose)"),
    ("ENV_T_ON", 1, "the gust window's start [s] (inf: no turbulence)"),
    ("ENV_T_OFF", 1, "the gust window's end [s]"),
    ("ENV_G_T0", 1, "the gust record's first time [s]"),
    ("ENV_G_DT", 1, "the gust record's time step [s]"),
    ("ENV_WAKE", WAKE_SIZE, "the wake's scalars (hosedrogue.environment.wake.WAKE_LAYOUT; "
                            "manoeuvring: the circulation at the evaluation's load factor and airspeed)"),
    ("ENV_G_CUBIC", 1, "1.0: read the gust record with the cubic interpolant, 0.0: linearly"),
    ("ENV_G_NOW", 1, "scratch of an evaluation's copy of env: 1.0 when ENV_GU..ENV_GW hold the gust at its time "
                     "(the uniform distribution: one lookup per evaluation, not one per link; the same bits)"),
    ("ENV_GU", 1, "the evaluation's gust, x [m/s]"),
    ("ENV_GV", 1, "the evaluation's gust, y [m/s]"),
    ("ENV_GW", 1, "the evaluation's gust, z [m/s]"),
    ("ENV_BW", 1, "the receiver's bow wave (hosedrogue.environment.bow_wave): shape code, 0 none (the model's); "
                  "the engagement writes ENV_BW.. into its evaluations' copies of env, where the probe tip is"),
    ("ENV_BW_X", 1, "the bow wave's source, x in S_p [m]"),
    ("ENV_BW_Y", 1, "the bow wave's source, y in S_p [m]"),
    ("ENV_BW_Z", 1, "the bow wave's source, z in S_p [m]"),
    ("ENV_BW_Q", 1, "the bow wave's flux [m^3/s]"),
    ("ENV_BW_LEN", 1, "the bow wave's line length [m]"),
])
(ENV_V, ENV_FROZEN, ENV_T_ON, ENV_T_OFF, ENV_G_T0, ENV_G_DT, ENV_WAKE, ENV_G_CUBIC, ENV_G_NOW, ENV_GU, ENV_GV,
 ENV_GW, ENV_BW, ENV_BW_X, ENV_BW_Y, ENV_BW_Z, ENV_BW_Q, ENV_BW_LEN) = ENV.offsets()

# --- env continued: the tanker's motion (frame) ------------------------------------------------
#: ENV_M_ON, ENV_M_V0 are the model's; the others are written per evaluation by
#: :func:`hosedrogue.model.frame.frame_terms`. With the motion on, the model's env holds the
#: motion table from ENV_SIZE on (:data:`MOTION_HEAD`, :data:`MOTION_ROW`), and every
#: evaluation's copy of env the frame terms at its time.
ENV_M = Layout("env (tanker's motion)", [
    ("ENV_M_ON", 1, "1.0 when the tanker manoeuvres"),
    ("ENV_M_V0", 1, "the airspeed the gust record and the wake's scalars were made for [m/s]"),
    ("ENV_M_T", 1, "the path flown over V0 [s]"),
    ("ENV_M_G", 3, "the direction of gravity in B [-]"),
    ("ENV_M_A0", 3, "the tow point's acceleration a_0 in B [m/s^2]"),
    ("ENV_M_W", 3, "B's angular velocity Omega [rad/s]"),
    ("ENV_M_D", 3, "B's angular acceleration alpha [rad/s^2]"),
], after=ENV)
ENV_M_ON, ENV_M_V0, ENV_M_T, ENV_M_G, ENV_M_A0, ENV_M_W, ENV_M_D = ENV_M.offsets()
ENV_M_END = ENV_M.end
#: the env scalars (the model's env is longer by the motion table when the tanker manoeuvres)
ENV_SIZE = ENV_M_END

#: the motion table's header, at ``env[ENV_SIZE:]`` (hosedrogue.model.frame.motion_table)
MOTION_HEAD = Layout("motion table head", [
    ("MT_RAMPS", 1, "number of ramps [-]"),
    ("MT_PHI0", 1, "initial bank phi_0 [rad]"),
    ("MT_GAMMA0", 1, "initial flight-path angle gamma_0 [rad]"),
    ("MT_G", 1, "gravity g [m/s^2]"),
])
MT_RAMPS, MT_PHI0, MT_GAMMA0, MT_G = MOTION_HEAD.offsets()
#: one ramp's row of the motion table, after the header (hosedrogue.spec.manoeuvres.Ramp)
MOTION_ROW = Layout("motion table row", [
    ("MR_QUANTITY", 1, "the quantity that changes (hosedrogue.spec.manoeuvres BANK, AIRSPEED or the flight path)"),
    ("MR_START", 1, "the ramp's start [s]"),
    ("MR_RATE", 1, "the rate of change the ramp reaches [quantity/s]"),
    ("MR_RAMP", 1, "the time its rate takes to rise (and to fall) [s]"),
    ("MR_CRUISE", 1, "the time its rate is held [s]"),
])
MR_QUANTITY, MR_START, MR_RATE, MR_RAMP, MR_CRUISE = MOTION_ROW.offsets()
TABLE_HEAD, TABLE_ROW = MOTION_HEAD.end, MOTION_ROW.end

# --- act: the drogue's actuator (integrate, drogue_actuator) ------------------------------------
ACT = Layout("act", [
    ("ACT_U_MAX", 2, "the largest force per axis, lateral and vertical [N] (inf: no limit)"),
    ("ACT_RATE", 1, "the largest rate of the applied force [N/s] (inf: no limit, no lag)"),
    ("ACT_TAU", 1, "the time constant of a rate-limited actuator's lag [s]"),
])
ACT_U_MAX, ACT_RATE, ACT_TAU = ACT.offsets()
#: entries of the ideal actuator at the head of ``act`` (an ``act`` longer than that means an
#: actuated drogue: the surfaces' entries follow)
ACT_IDEAL = ACT.end

#: the surfaces' entries of act, after the ideal actuator's; then (not in the table: their number
#: varies) the surfaces' directions (t_y, t_z per surface) and the anti-windup gain (nc x 2, row-major)
SURFACES = Layout("act (control surfaces)", [
    ("DA_NS", 1, "number of surfaces n_s [-]"),
    ("DA_ORDER", 1, "servo order (1 or 2) [-]"),
    ("DA_OMEGA", 1, "servo frequency [rad/s]"),
    ("DA_ZETA", 1, "servo damping [-]"),
    ("DA_DMAX", 1, "deflection limit [rad]"),
    ("DA_RMAX", 1, "deflection rate limit [rad/s]"),
    ("DA_SCF", 1, "reference area x force slope S C_F [m^2/rad]"),
    ("DA_SKD", 1, "reference area x drag slope S k_D [m^2/rad^2]"),
    ("DA_MODE", 1, "command mode: MODE_FORCE 0, MODE_DEFLECTION 1"),
    ("DA_QMIN", 1, "the smallest dynamic pressure of the inversion [Pa]"),
    ("DA_NC", 1, "number of the controller's states nc [-]"),
], after=ACT)
(DA_NS, DA_ORDER, DA_OMEGA, DA_ZETA, DA_DMAX, DA_RMAX, DA_SCF, DA_SKD, DA_MODE, DA_QMIN, DA_NC) = SURFACES.offsets()
DA_HEAD = SURFACES.end
#: codes of DA_MODE: the controller commands a force [N] (mixed to the surfaces), or the
#: surfaces' deflections [rad] directly (its outputs, one per surface)
MODE_FORCE, MODE_DEFLECTION = 0, 1
#: Most surfaces (the section's range), so the engagement's output row has room for every servo rate.
MAX_SURFACES = 8

# --- ep: the engagement's scalars (hosedrogue.model.engagement) --------------------------------
EP = Layout("ep", [
    # the hose and the drogue
    ("EP_MU", 1, "hose mass per length [kg/m]"),
    ("EP_MD", 1, "drogue mass [kg]"),
    ("EP_SPLIT", 1, "1: split lumping (half of each link's mass at each end joint), 0: aft"),
    ("EP_JLINK", 1, "every link's transverse inertia [kg m^2]; < 0: the rod inertia m l^2 / 12 for link 0"),
    ("EP_L0", 1, "the chain's nominal link length [m]"),
    # the reel
    ("EP_LAW", 1, "the reel's law: LAW_LOCKED, LAW_CONSTANT_TENSION, LAW_RESPONSE, LAW_COMMANDED"),
    ("EP_RD", 1, "drum radius [m]"),
    ("EP_JR", 1, "reel inertia [kg m^2]"),
    ("EP_CR", 1, "drum friction [N m s]"),
    ("EP_TSET", 1, "tension set point [N]"),
    ("EP_TAU_MAX", 1, "motor torque limit [N m]"),
    ("EP_V_IN_MAX", 1, "take-up speed limit [m/s]"),
    ("EP_V_OUT_MAX", 1, "payout speed limit [m/s]"),
    ("EP_K_GOV", 1, "speed governor gain [N s/m]"),
    ("EP_KS", 1, "the response law's take-up gain on the slack [1/s]"),
    ("EP_DB", 1, "the response law's slack dead band [m]"),
    ("EP_KV", 1, "the response law's speed gain [N s/m]"),
    ("EP_PAY_T0", 1, "the locked reel's payout schedule: start [s]"),
    ("EP_PAY_DIST", 1, "payout distance [m] (negative: takes up)"),
    ("EP_PAY_V", 1, "payout top speed [m/s]"),
    ("EP_PAY_A", 1, "payout peak acceleration [m/s^2]"),
    # the probe
    ("EP_PROBE", 1, "1 with a probe"),
    ("EP_P0X", 1, "probe tip's start, x in S_p [m]"),
    ("EP_P0Y", 1, "probe tip's start, y in S_p [m]"),
    ("EP_P0Z", 1, "probe tip's start, z in S_p [m]"),
    ("EP_VC", 1, "closure speed [m/s]"),
    ("EP_PUSH", 1, "probe travel after capture [m]"),
    ("EP_T_STOP", 1, "the probe's stopping ramp [s]"),
    ("EP_KP", 1, "coupling stiffness [N/m]"),
    ("EP_CP", 1, "coupling damping [N s/m]"),
    ("EP_COUPLED", 1, "1 once the probe has captured the drogue"),
    ("EP_T_CAP", 1, "capture time [s] (inf before capture)"),
    ("EP_S_CAP", 1, "probe travel at capture [m]"),
    ("EP_JD", 1, "drogue inertia [kg m^2]"),
    # the receiver's bow wave; EP_BW_D* is the source (the line's forward end) minus the probe tip
    ("EP_BW", 1, "bow-wave shape: BW_OFF, BW_RANKINE, BW_LINE"),
    ("EP_BW_DX", 1, "bow-wave source minus probe tip, x [m]"),
    ("EP_BW_DY", 1, "bow-wave source minus probe tip, y [m]"),
    ("EP_BW_DZ", 1, "bow-wave source minus probe tip, z [m]"),
    ("EP_BW_Q", 1, "bow-wave flux [m^3/s]"),
    ("EP_BW_LEN", 1, "bow-wave line length [m]"),
    # the drogue controller and the pilot
    ("EP_CTRL", 1, "1 with a drogue controller in the loop (its states follow the block after the tail)"),
    ("EP_NPIL", 1, "number of states of the block after the tail (the pilot's PIL_STATES or the receiver's "
                   "RCV_STATES, and the commanded reel's one): the whole block"),
    ("EP_PIL_DELAY", 1, "the pilot's reaction time [s]"),
    ("EP_PIL_LAG", 1, "the pilot's lag [s]"),
    ("EP_PIL_TV", 1, "the pilot's velocity time constant [s]"),
    ("EP_PIL_VMAX", 1, "the pilot's speed bound [m/s]"),
    ("EP_PIL_AMAX", 1, "the pilot's acceleration bound [m/s^2]"),
    ("EP_H", 1, "the RK4 step [s] (the index of the drogue history the pilot's delay reads)"),
    ("EP_L_MIN", 1, "the free hose length's least [m] (the drum's end stop: fully reeled in)"),
    ("EP_L_MAX", 1, "the free hose length's most [m] (fully paid out)"),
    # the sampled-data controllers (docs/controllers.md): the pilot flag, the receiver, the commanded reel
    ("EP_PIL", 1, "1 when the pilot flies the probe (its states open the block after the tail)"),
    ("EP_RCV", 1, "1 when the receiver flies it (its RCV_STATES states open the block)"),
    ("EP_RCV_TV", 1, "the receiver's velocity time constant [s]"),
    ("EP_RCV_VMAX", 3, "the receiver's speed bounds per axis [m/s]"),
    ("EP_RCV_AMAX", 3, "the receiver's acceleration bounds per axis [m/s^2]"),
    ("EP_REEL_SLOT", 1, "1 + the place in the block of the commanded reel's (LAW_COMMANDED) held take-up speed "
                        "command [m/s]; 0 without"),
    ("EP_REEL_TV", 1, "the commanded reel's speed time constant [s]"),
    # the elastic links (docs/model.md §11)
    ("EP_ELASTIC", 1, "1 for elastic links (the hose state [q, qd, lam, lamd], 6n; hosedrogue.model.elastic)"),
    ("EP_SCHEME", 1, "the elastic chain's integrator: SCHEME_RK4 or SCHEME_SDIRK2 (hosedrogue.model.implicit)"),
    ("EP_ITER", 1, "the SDIRK's least corrections per stage"),
    # a probe path fed from outside (the engagement FMU's position input; hosedrogue.engagement.stepper's
    # receiver_pass_through): the receiver's tip is, instead of its response, the cubic in time
    # p(t) = P + V s + A s^2 / 2 + J s^3 / 6, s = t - T0 (tanker frame), evaluated at every stage's time
    # as the prescribed path is (fed_tip)
    ("EP_FEED", 1, "1 when the probe path is fed from outside"),
    ("EP_FEED_T0", 1, "the fed cubic's time origin T0 [s]"),
    ("EP_FEED_P", 3, "its position P [m]"),
    ("EP_FEED_V", 3, "its velocity V [m/s]"),
    ("EP_FEED_A", 3, "its acceleration A [m/s^2]"),
    ("EP_FEED_J", 3, "its jerk J [m/s^3]"),
])
(EP_MU, EP_MD, EP_SPLIT, EP_JLINK, EP_L0,
 EP_LAW, EP_RD, EP_JR, EP_CR, EP_TSET, EP_TAU_MAX, EP_V_IN_MAX, EP_V_OUT_MAX, EP_K_GOV,
 EP_KS, EP_DB, EP_KV,
 EP_PAY_T0, EP_PAY_DIST, EP_PAY_V, EP_PAY_A,
 EP_PROBE, EP_P0X, EP_P0Y, EP_P0Z, EP_VC, EP_PUSH, EP_T_STOP, EP_KP, EP_CP, EP_COUPLED, EP_T_CAP,
 EP_S_CAP, EP_JD,
 EP_BW, EP_BW_DX, EP_BW_DY, EP_BW_DZ, EP_BW_Q, EP_BW_LEN,
 EP_CTRL, EP_NPIL, EP_PIL_DELAY, EP_PIL_LAG, EP_PIL_TV, EP_PIL_VMAX, EP_PIL_AMAX, EP_H,
 EP_L_MIN, EP_L_MAX,
 EP_PIL, EP_RCV, EP_RCV_TV, EP_RCV_VMAX, EP_RCV_AMAX, EP_REEL_SLOT, EP_REEL_TV,
 EP_ELASTIC, EP_SCHEME, EP_ITER,
 EP_FEED, EP_FEED_T0, EP_FEED_P, EP_FEED_V, EP_FEED_A, EP_FEED_J) = EP.offsets()
EP_SIZE = EP.end
#: codes of EP_LAW (the reel's laws), EP_BW (the bow wave's shapes, hosedrogue.environment.bow_wave's)
#: and EP_SCHEME (the elastic chain's integrators: RK4, or the stiff SDIRK of hosedrogue.model.implicit)
LAW_LOCKED, LAW_CONSTANT_TENSION, LAW_RESPONSE, LAW_COMMANDED = 0, 1, 2, 3
BW_OFF, BW_RANKINE, BW_LINE = SHAPE_OFF, SHAPE_RANKINE, SHAPE_LINE
SCHEME_RK4, SCHEME_SDIRK2 = 0, 1

# --- the engagement's state: z = [hose (4n, or 6n for elastic links), tail, block, controller] ---
#: the tail, after the hose entries (hosedrogue.model.engagement.chain.tail_start): L, L' and the
#: work states of the energy balance
TAIL = Layout("z tail", [
    ("Z_L", 1, "free hose length L [m]"),
    ("Z_LD", 1, "its rate L' [m/s]"),
    ("Z_WM", 1, "work of the motor on the drum [J]"),
    ("Z_WF", 1, "heat of the drum's friction [J]"),
    ("Z_WX", 1, "work of the exit on the hose [J]"),
    ("Z_WFLUX", 1, "kinetic energy carried by hose joining or leaving the moving masses [J]"),
    ("Z_WP", 1, "work of the probe on the drogue [J]"),
    ("Z_WAX", 1, "heat of the links' axial damping [J] (elastic links; 0 otherwise)"),
])
Z_L, Z_LD, Z_WM, Z_WF, Z_WX, Z_WFLUX, Z_WP, Z_WAX = TAIL.offsets()
Z_TAIL = TAIL.end

#: after the tail: the pilot's states (if any), then the controller's states and, for a
#: rate-limited actuator, the applied force [N] - the layout of hosedrogue.model.integrate's
#: closed loop with x = everything before the controller
PILOT = Layout("pilot block", [
    ("PIL_Y", 1, "probe tip y [m]"),
    ("PIL_Z", 1, "probe tip z [m]"),
    ("PIL_VY", 1, "its rate y' [m/s]"),
    ("PIL_VZ", 1, "its rate z' [m/s]"),
])
PIL_Y, PIL_Z, PIL_VY, PIL_VZ = PILOT.offsets()
PIL_STATES = PILOT.end

#: or the receiver's states (tanker frame)
RECEIVER = Layout("receiver block", [
    ("RCV_X", 3, "probe tip position [m]"),
    ("RCV_VX", 3, "probe tip velocity [m/s]"),
    ("RCV_CX", 3, "held velocity command [m/s]"),
])
RCV_X, RCV_VX, RCV_CX = RECEIVER.offsets()
RCV_STATES = RECEIVER.end

# --- out: the scalars of one engagement evaluation ---------------------------------------------
OUT = Layout("out", [
    ("O_T0", 1, "exit tension T0 [N]"),
    ("O_LDD", 1, "L'' [m/s^2]"),
    ("O_TAU", 1, "motor torque [N m] (positive reels in)"),
    ("O_SLACK", 1, "slack [m]: the hose's length minus the straight exit-to-drogue distance"),
    ("O_PX", 1, "probe tip, x [m]"),
    ("O_PY", 1, "probe tip, y [m]"),
    ("O_PZ", 1, "probe tip, z [m]"),
    ("O_FPX", 1, "the probe's force on the drogue, x [N]"),
    ("O_FPY", 1, "the probe's force on the drogue, y [N]"),
    ("O_FPZ", 1, "the probe's force on the drogue, z [N]"),
    ("O_VPX", 1, "probe tip velocity, x [m/s]"),
    ("O_VPY", 1, "probe tip velocity, y [m/s]"),
    ("O_VPZ", 1, "probe tip velocity, z [m/s]"),
    ("O_PMOTOR", 1, "the motor's power [W]"),
    ("O_PFRIC", 1, "the drum friction's power [W]"),
    ("O_PEXIT", 1, "the exit's power on the hose [W]"),
    ("O_PFLUX", 1, "the power of the kinetic energy carried by hose joining or leaving the moving masses [W]"),
    ("O_PPROBE", 1, "the probe's power on the drogue [W]"),
    ("O_UY", 1, "control force applied at the drogue, y [N]"),
    ("O_UZ", 1, "control force applied at the drogue, z [N]"),
    ("O_MY", 1, "the measured drogue offset, y [m]"),
    ("O_MZ", 1, "the measured drogue offset, z [m]"),
    ("O_CY", 1, "the commanded force, y [N] (differs from the applied one for a rate-limited actuator)"),
    ("O_CZ", 1, "the commanded force, z [N]"),
    ("O_PAXIAL", 1, "power dissipated by the links' axial damping [W] (elastic links)"),
    ("O_Q", 1, "an actuated drogue's dynamic pressure [Pa]"),
    ("O_EY", 1, "its anti-windup error, y [N]"),
    ("O_EZ", 1, "its anti-windup error, z [N]"),
    ("O_SERVO", 2 * MAX_SURFACES, "an actuated drogue's servo derivatives "
                                  "(hosedrogue.model.drogue_actuator.servo_rates): the surfaces' deflection rates "
                                  "[rad/s] first, then (second order) the servo rates' derivatives [rad/s^2]"),
])
(O_T0, O_LDD, O_TAU, O_SLACK, O_PX, O_PY, O_PZ, O_FPX, O_FPY, O_FPZ, O_VPX, O_VPY, O_VPZ,
 O_PMOTOR, O_PFRIC, O_PEXIT, O_PFLUX, O_PPROBE,
 O_UY, O_UZ, O_MY, O_MZ, O_CY, O_CZ, O_PAXIAL, O_Q, O_EY, O_EZ, O_SERVO) = OUT.offsets()
O_SIZE = OUT.end

# --- the sampled-data loops (sampled) ----------------------------------------------------------
#: the raw measurement of a state (one ring row)
RAW = Layout("raw", [
    ("R_DROGUE", 3, "drogue position [m]"),
    ("R_DROGUE_V", 3, "drogue velocity [m/s]"),
    ("R_PROBE", 3, "probe tip position [m]"),
    ("R_PROBE_V", 3, "probe tip velocity [m/s]"),
    ("R_L", 1, "free hose length [m]"),
    ("R_REEL_V", 1, "reel speed [m/s] (positive reeling in)"),
    ("R_T0", 1, "exit tension [N]"),
    ("R_COUPLED", 1, "coupled flag, 0/1"),
    ("R_Q", 1, "dynamic pressure at an actuated drogue [Pa] (NaN without control surfaces)"),
])
R_DROGUE, R_DROGUE_V, R_PROBE, R_PROBE_V, R_L, R_REEL_V, R_T0, R_COUPLED, R_Q = RAW.offsets()
RAW_SIZE = RAW.end

#: the measurement buffer (read by hosedrogue.controllers.sampled.Measurement)
MEAS = Layout("measurement", [
    ("M_T", 1, "time the quantities are of [s] (the call's time minus the delay)"),
    ("M_DROGUE", 3, "drogue position (with the sensor noise) [m]"),
    ("M_DROGUE_V", 3, "drogue velocity [m/s]"),
    ("M_PROBE", 3, "probe tip position [m] (NaN without a probe)"),
    ("M_PROBE_V", 3, "probe tip velocity [m/s]"),
    ("M_REL", 3, "drogue minus probe tip [m]"),
    ("M_REL_V", 3, "drogue minus probe tip velocity [m/s]"),
    ("M_L", 1, "hose length [m]"),
    ("M_REEL_V", 1, "reel speed [m/s]"),
    ("M_T0", 1, "exit tension [N]"),
    ("M_COUPLED", 1, "coupled flag, 0/1"),
    ("M_BALANCE", 3, "the drogue's balance position at the start [m] (the built-in controllers' reference)"),
    ("M_Q", 1, "dynamic pressure the drogue's control surfaces see [Pa] (NaN without them)"),
])
(M_T, M_DROGUE, M_DROGUE_V, M_PROBE, M_PROBE_V, M_REL, M_REL_V, M_L, M_REEL_V, M_T0, M_COUPLED, M_BALANCE,
 M_Q) = MEAS.offsets()
M_SIZE = MEAS.end

#: the counters of a stepped run (an int64 array the advance kernels update in place)
CTR = Layout("counters", [
    ("C_STEP", 1, "global RK4 step"),
    ("C_SAVED", 1, "saved rows"),
    ("C_SAMPLE", 1, "sample index"),
    ("C_TOTAL", 1, "total steps"),
    ("C_SPC", 1, "RK4 steps per control step"),
    ("C_STATUS", 1, "the last status"),
    ("C_TARGET", 1, "the engagement's step a control step integrates to"),
    ("C_ORIGIN", 1, "the step of the last event (the origin of the times of its compiled segment, as the "
                    "driver counts them)"),
])
C_STEP, C_SAVED, C_SAMPLE, C_TOTAL, C_SPC, C_STATUS, C_TARGET, C_ORIGIN = CTR.offsets()
C_SIZE = CTR.end

# --- the kernels' status codes (what the integrators return; C_STATUS holds the last) ----------
#: the integrators' (STAGE_LIMIT: the elastic chains' SDIRK, hosedrogue.model.implicit)
OK, NONFINITE, YAW_LIMIT, STEP_LIMIT, STAGE_LIMIT = 0, 1, 2, 3, 4
#: the engagement's segment stop codes: a remesh (the exit link split or merged), the probe tip
#: crossing the coupler plane, a link's yaw past the switch angle (its angles change chart)
SPLIT, MERGE, PLANE, CHART = 10, 11, 12, 13
#: failure code: the free hose length left [EP_L_MIN, EP_L_MAX] (the reel reached an end stop)
REEL_END = 20

#: every table, for the docs and the tests
TABLES = (PS, ENV, ENV_M, MOTION_HEAD, MOTION_ROW, ACT, SURFACES, EP, TAIL, PILOT, RECEIVER, OUT, RAW, MEAS, CTR)
