"""The slot tables of the compiled core (hosedrogue.model.layout): each declared once, its offsets
computed; no two slots of a table overlap, a table continued after another starts where that one
ends, every name the kernels read is its entry's offset, and the arrays the Python side packs
are as long as their tables."""

import ast
import math
from pathlib import Path

import numpy as np
import pytest

import hosedrogue
from hosedrogue.model import layout as LY

#: the tables, by their names in layout
KEYS = ("PS", "ENV", "ENV_M", "MOTION_HEAD", "MOTION_ROW", "ACT", "SURFACES", "EP", "TAIL", "PILOT", "RECEIVER", "OUT",
        "RAW", "MEAS", "CTR")
#: each table's name for its end (the array's length, or where the next table starts)
ENDS = {"PS": "PS_SIZE", "ENV_M": "ENV_SIZE", "MOTION_HEAD": "TABLE_HEAD", "MOTION_ROW": "TABLE_ROW",
        "ACT": "ACT_IDEAL", "SURFACES": "DA_HEAD", "EP": "EP_SIZE", "TAIL": "Z_TAIL", "PILOT": "PIL_STATES",
        "RECEIVER": "RCV_STATES", "OUT": "O_SIZE", "RAW": "RAW_SIZE", "MEAS": "M_SIZE", "CTR": "C_SIZE"}


def test_every_table_is_listed():
    assert [t.name for t in LY.TABLES] == [getattr(LY, k).name for k in KEYS]


@pytest.mark.parametrize("key", KEYS)
def test_slots_are_consecutive_and_do_not_overlap(key):
    table = getattr(LY, key)
    taken = set()
    at = table.start
    for slot in table:
        assert slot.offset == at, f"{slot.name} starts at {slot.offset}, not where the one before ends ({at})"
        assert slot.width >= 1
        cells = set(range(slot.offset, slot.offset + slot.width))
        assert not cells & taken, f"{slot.name} overlaps {sorted(cells & taken)}"
        taken |= cells
        at += slot.width
        assert slot.meaning, f"{slot.name} says what it holds"
    assert table.end == at
    assert table.size == sum(s.width for s in table) == len(taken) == table.end - table.start
    assert len({s.name for s in table}) == len(table)


@pytest.mark.parametrize("key", KEYS)
def test_the_names_are_the_offsets(key):
    """Each name on the left of ``(...) = TABLE.offsets()`` is its own entry's offset (a name out
    of order would pass the unpacking and read the wrong slot); the table's end is its size name."""
    table = getattr(LY, key)
    for slot in table:
        value = getattr(LY, slot.name)
        assert type(value) is int and value == slot.offset, (slot.name, value, slot.offset)
    if key in ENDS:
        assert getattr(LY, ENDS[key]) == table.end


def test_the_kernels_read_the_layouts_names():
    """Every module of the compiled core that holds a slot's name holds layout's (it imports it)."""
    import importlib
    import pkgutil

    import hosedrogue.model

    names = {s.name: s.offset for t in LY.TABLES for s in t}
    holders = 0
    for info in pkgutil.walk_packages(hosedrogue.model.__path__, "hosedrogue.model."):
        module = importlib.import_module(info.name)
        for name in names.keys() & vars(module).keys():
            assert vars(module)[name] == names[name], (info.name, name)
            holders += 1
    assert holders > len(names)  # the kernels do read them


def test_continued_tables_start_where_the_first_ends():
    # the tanker's motion continues the air's env (kernels' ENV_* and frame's ENV_M_* never share
    # a slot), and the motion table follows both; the surfaces continue the ideal actuator
    assert LY.ENV_M.after is LY.ENV and LY.ENV_M.start == LY.ENV.end
    assert not set(range(LY.ENV.start, LY.ENV.end)) & set(range(LY.ENV_M.start, LY.ENV_M.end))
    assert LY.ENV_SIZE == LY.ENV_M_END == LY.ENV_M.end == LY.ENV.size + LY.ENV_M.size
    assert LY.SURFACES.after is LY.ACT and LY.SURFACES.start == LY.ACT.end == LY.ACT_IDEAL
    assert LY.DA_HEAD == LY.ACT.size + LY.SURFACES.size
    for key in KEYS:
        table = getattr(LY, key)
        if table.after is None:
            assert table.start == 0, key


def _bound_names(targets):
    """The names an assignment binds (``A = ...``, ``A, B = ...``), not the ones it subscripts."""
    for target in targets:
        if isinstance(target, ast.Name):
            yield target.id
        elif isinstance(target, (ast.Tuple, ast.List)):
            yield from _bound_names(target.elts)
        elif isinstance(target, ast.Starred):
            yield from _bound_names([target.value])


def test_each_slot_name_is_assigned_in_one_place():
    """No module of the package assigns a slot's name (or a table's end) but layout: the other
    modules import them, none types an offset by hand."""
    names = {s.name for t in LY.TABLES for s in t} | set(ENDS.values()) | {"ENV_M_END"}
    root = Path(hosedrogue.__file__).parent
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "layout.py" and path.parent.name == "model":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, (ast.AnnAssign, ast.AugAssign)) else []
            for name in _bound_names(targets):
                if name in names:
                    found.append(f"{path.relative_to(root)}:{node.lineno} {name}")
    assert not found, found


#: the codes slots hold and the kernels' status codes, declared in layout beside their tables
CODES = ("BENDING_OFF", "BENDING_PAPER", "BENDING_MOMENT", "DRAG_MIDPOINT", "DRAG_GAUSS2", "MODE_FORCE",
         "MODE_DEFLECTION", "LAW_LOCKED", "LAW_CONSTANT_TENSION", "LAW_RESPONSE", "LAW_COMMANDED", "BW_OFF",
         "BW_RANKINE", "BW_LINE", "SCHEME_RK4", "SCHEME_SDIRK2", "OK", "NONFINITE", "YAW_LIMIT", "STEP_LIMIT",
         "STAGE_LIMIT", "SPLIT", "MERGE", "PLANE", "CHART", "REEL_END")


def test_each_code_is_assigned_in_one_place():
    """No module of the compiled core but layout assigns one of the codes (report/ has labels of
    its own by some of these names)."""
    root = Path(hosedrogue.__file__).parent / "model"
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "layout.py" and path.parent == root:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, (ast.AnnAssign, ast.AugAssign)) else []
            found += [f"{path.name}:{node.lineno} {name}" for name in _bound_names(targets) if name in CODES]
    assert not found, found
    assert all(type(getattr(LY, name)) is int for name in CODES)


def test_describe_lists_every_slot():
    for table in LY.TABLES:
        text = table.describe()
        for slot in table:
            assert slot.name in text and f"{slot.offset:4d}" in text
    assert LY.EP.slice("EP_FEED_P") == slice(LY.EP_FEED_P, LY.EP_FEED_P + 3)
    assert LY.EP["EP_RCV_VMAX"].width == 3


def test_a_layout_refuses_a_bad_entry():
    with pytest.raises(ValueError, match="width"):
        LY.Layout("x", [("A", 0, "nothing")])
    with pytest.raises(ValueError, match="twice"):
        LY.Layout("x", [("A", 1, "a"), ("A", 1, "again")])


# --- the packing code in Python writes the tables' sizes --------------------------------------


def test_the_model_packs_ps_and_env():
    from hosedrogue.analysis.steady_flight import steady_params
    from hosedrogue.environment.wake import WAKE_SIZE, wake_scalars
    from hosedrogue.model import frame
    from hosedrogue.model.system import HoseModel
    from hosedrogue.spec.params import PAPER
    from hosedrogue.scenarios import load_scenario

    level = HoseModel(PAPER)
    assert level.ps.size == LY.PS_SIZE and level.env.size == LY.ENV_SIZE
    assert level.ps[LY.PS_EA] == PAPER.hose.axial_stiffness_n and level.ps[LY.PS_G] > 9.0
    assert LY.ENV["ENV_WAKE"].width == WAKE_SIZE
    assert np.array_equal(level.env[LY.ENV.slice("ENV_WAKE")],
                          wake_scalars(PAPER.tanker, PAPER.wake, PAPER.flight.airspeed_m_s, level.rho))
    turn = HoseModel(steady_params(PAPER, bank_deg=10.0))
    assert turn.env.size == LY.ENV_SIZE + LY.TABLE_HEAD and turn.env[LY.ENV_M_ON] == 1.0
    # a manoeuvre's motion table: its header, then one row per ramp
    params = load_scenario("turn-entry-30").params
    table = frame.motion_table(params.tanker_motion, params.flight.airspeed_m_s)
    ramps = int(table[LY.MT_RAMPS])
    assert ramps >= 1 and table.size == LY.TABLE_HEAD + LY.TABLE_ROW * ramps
    assert table[LY.MT_G] == pytest.approx(9.80665)
    rows = table[LY.TABLE_HEAD:].reshape(ramps, LY.TABLE_ROW)
    first = params.tanker_motion.ramps(params.flight.airspeed_m_s)[0]
    assert rows[0, LY.MR_QUANTITY] == first.quantity and rows[0, LY.MR_START] == first.start_s
    assert rows[0, LY.MR_RATE] == first.rate and rows[0, LY.MR_RAMP] == first.ramp_s
    assert rows[0, LY.MR_CRUISE] == first.cruise_s


def test_the_actuator_packs_act():
    from hosedrogue.spec.drogue_surfaces import DrogueActuator
    from hosedrogue.model import drogue_actuator as DA
    from hosedrogue.spec.sections import Actuator

    head = Actuator(max_force_n=300.0, max_rate_n_s=900.0, time_constant_s=0.05).as_array()
    assert head.size == LY.ACT_IDEAL
    assert list(head[LY.ACT.slice("ACT_U_MAX")]) == [300.0, 300.0]
    assert head[LY.ACT_RATE] == 900.0 and head[LY.ACT_TAU] == 0.05
    section = DrogueActuator(surfaces=6)
    act = DA.actuator_array(head, section, None, 3)
    assert act.size == LY.DA_HEAD + 2 * 6 + 2 * 3
    assert act[LY.DA_NS] == 6 and act[LY.DA_NC] == 3 and act[LY.DA_ORDER] == section.servo_order
    assert np.array_equal(act[:LY.ACT_IDEAL], head)
    # the engagement's output row has room for the servo rates of the most surfaces a section takes
    bound = DrogueActuator.__dataclass_fields__["surfaces"].metadata["hi"]
    assert LY.MAX_SURFACES == bound and LY.OUT["O_SERVO"].width == 2 * bound


def test_the_engagement_packs_ep_and_the_block_after_the_tail():
    from hosedrogue.engagement.chain import initial_chain
    from hosedrogue.engagement.parameters import engagement_parameters
    from hosedrogue.engagement.loop import extra_states
    from hosedrogue.spec.params import PAPER, Actuator
    from hosedrogue.spec.sections import Pilot, Probe, Receiver, Reel

    chain = initial_chain(PAPER)
    probe = Probe(stiffness_n_m=12345.0, damping_n_s_m=67.0)
    ep = engagement_parameters(PAPER, Reel(law="response"), probe, chain, np.array([-30.0, 1.0, 2.0]))
    assert ep.size == LY.EP_SIZE
    assert ep[LY.EP_KP] == 12345.0 and ep[LY.EP_CP] == 67.0 and math.isinf(ep[LY.EP_T_CAP])
    assert ep[LY.EP_MU] == PAPER.hose.mass_per_length_kg_m and ep[LY.EP_L0] == chain.l_nom
    # the pilot's block, or the receiver's, opens the states after the tail
    pil = extra_states(ep.copy(), None, Actuator(), Pilot(enabled=True))
    assert pil.size == LY.PIL_STATES
    e = ep.copy()
    rcv = extra_states(e, None, Actuator(), None, Receiver(entry="x:y"))
    assert rcv.size == LY.RCV_STATES == e[LY.EP_NPIL]
    assert list(rcv[LY.RECEIVER.slice("RCV_X")]) == [e[LY.EP_P0X], e[LY.EP_P0Y], e[LY.EP_P0Z]]
    assert rcv[LY.RCV_VX] == rcv[LY.RCV_CX] == e[LY.EP_VC]


def test_the_measurement_reads_the_buffer():
    from hosedrogue.controllers.sampled import Measurement

    from hosedrogue.controllers.sampled import _VECTORS

    m = Measurement(np.arange(float(LY.M_SIZE)))
    assert m.t_s == LY.M_T and m.drogue_q_pa == LY.M_Q and m.exit_tension_n == LY.M_T0
    assert list(m.drogue_position_m) == [LY.M_DROGUE, LY.M_DROGUE + 1, LY.M_DROGUE + 2]
    # every vector the measurement shows is an entry of three slots
    widths = {s.offset: s.width for s in LY.MEAS}
    assert all(widths[start] == 3 for start in _VECTORS.values())


def test_codes_are_distinct():
    # the status codes (one C_STATUS slot holds any of them), and each slot's codes
    groups = [("OK", "NONFINITE", "YAW_LIMIT", "STEP_LIMIT", "STAGE_LIMIT", "SPLIT", "MERGE", "PLANE", "CHART",
               "REEL_END"), ("BENDING_OFF", "BENDING_PAPER", "BENDING_MOMENT"), ("DRAG_MIDPOINT", "DRAG_GAUSS2"),
              ("MODE_FORCE", "MODE_DEFLECTION"),
              ("LAW_LOCKED", "LAW_CONSTANT_TENSION", "LAW_RESPONSE", "LAW_COMMANDED"),
              ("BW_OFF", "BW_RANKINE", "BW_LINE"), ("SCHEME_RK4", "SCHEME_SDIRK2")]
    assert sorted(n for g in groups for n in g) == sorted(CODES)
    for group in groups:
        assert len({getattr(LY, name) for name in group}) == len(group), group


def test_the_workspaces_rows_are_named():
    """The rows of the workspace tuples (:data:`hosedrogue.model.chain_dynamics.WS`,
    :data:`hosedrogue.model.elastic.EWS`) are what make_workspace and make_elastic_workspace build,
    and no kernel indexes a workspace by a number typed by hand."""
    from hosedrogue.model import chain_dynamics as CD, elastic as E

    n = 5
    ws, ews = CD.make_workspace(n), E.make_elastic_workspace(n)
    assert len(ws) == CD.WS.end == CD.WS.size and len(ews) == E.EWS.end == E.EWS.size
    for table, module in ((CD.WS, CD), (E.EWS, E)):
        for slot in table:
            assert slot.width == 1 and getattr(module, slot.name) == slot.offset
    shapes = {CD.WS_E: (n, 3), CD.WS_CS: (n, 4), CD.WS_R: (n + 1, 3), CD.WS_F: (n + 1, 3), CD.WS_TAU: (n, 2),
              CD.WS_U: (n, 6), CD.WS_DINV: (n, 4), CD.WS_DRAG: (3,), CD.WS_TOW: (3,), CD.WS_QDD: (2 * n,),
              CD.WS_ENV: (LY.ENV_SIZE,), CD.WS_T0: (1,)}
    assert all(ws[i].shape == shape for i, shape in shapes.items())
    assert ews[E.EWS_U].shape == (n, 9) and ews[E.EWS_T].shape == (n,) and ews[E.EWS_ANG_AUG].shape == (n, 2)
    root = Path(hosedrogue.__file__).parent
    bare = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) \
                    and node.value.id in ("ws", "ws2", "ews") and isinstance(node.slice, ast.Constant):
                bare.append(f"{path.relative_to(root)}:{node.lineno}")
    assert not bare, bare
