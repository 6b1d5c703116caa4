"""The scenario reference: every table and key a scenario file may hold, with its unit, default,
allowed range and meaning, generated from the sections' field metadata so that it cannot drift
from the code (the documentation's "Scenario reference" page is this module's output).

* :func:`reference_tables` - the tables in the order of the page, each with its rows;
* :func:`problems` - what the metadata lacks (a field without a unit, a range or a ``#:`` comment);
* :func:`scenario_reference_markdown` - the page's body (Markdown);
* :func:`scenario_reference_page` - the whole page, as checked in at ``docs/scenario-reference.md``
  and printed by ``hosedrogue reference``.

The rows of the model's sections (:data:`hosedrogue.spec.params.SECTIONS`) and the run's sections
(:data:`hosedrogue.spec.sections.LOOP_SECTIONS`, :data:`hosedrogue.spec.sections.ENGAGEMENT_SECTIONS`)
come from :func:`hosedrogue.spec.fields.field_table`; ``[scenario]``, ``[model]``, ``[controller]``
and the pseudo-key ``turbulence.intensity`` are not sections of fields, so their rows are built
here from the constants that validate them.
"""

from __future__ import annotations

import ast
import dataclasses
import inspect
import math
import re
import textwrap
from typing import Any

from ..spec.config import preset_names
from ..constants import FT_TO_M
from ..spec.fields import field_table
from ..spec.params import SECTIONS, TURBULENCE_PRESET_KEY
from ..spec.rewards import DockingReward, DockingRewardV1, StationKeepingReward, WhipReward
from . import MAX_DURATION_S, MAX_OFFSET_DEG, SCENARIO_KEYS, Scenario
from ..spec.sections import (CONTROLLER_KEYS, CONTROLLER_OPTIONS, CONTROLLER_TYPES, ENGAGEMENT_SECTIONS, LOOP_SECTIONS,
                       LQR_DESIGNS, MAX_SAMPLE_TIME_S, Controller)
from ..spec.standards import INTENSITY_ALTITUDE_FT, INTENSITY_FT_S, PROBABILITY_OF_EXCEEDANCE

#: The unit shown for a dimensionless number (its ``#:`` comment says ``[-]``) or a non-numeric key.
NO_UNIT = "-"

#: What each ``[controller]`` option is: (type, option) -> (unit, meaning). A new option in
#: :data:`hosedrogue.spec.sections.CONTROLLER_OPTIONS` needs a line here (:func:`problems` says so).
CONTROLLER_OPTION_DOCS = {
    ("pid", "lateral"): ("N/m, N/(m s), N s/m, rad/s",
                         "[K_P, K_I, K_D, N] of the lateral channel (force u_y on the drogue's lateral offset), "
                         "K_P + K_I/s + K_D N s/(s + N) (paper Eq. 33)"),
    ("pid", "vertical"): ("N/m, N/(m s), N s/m, rad/s",
                          "[K_P, K_I, K_D, N] of the vertical channel (force u_z on the drogue's vertical offset)"),
    ("lqr", "design"): (NO_UNIT,
                        "\"balanced\": the paper's Q on the balanced states of each 2nd-order channel, with Kalman "
                        "observers (reproduces Table 3's lateral LQR row); \"integral\": Eq. 34 read as integral "
                        "action on the offsets (docs: Where this project and the paper differ)"),
    ("lqr", "q_diag"): ("1/(m N) (balanced); 1/m^2, 1/(m s)^2 (integral)",
                        "diagonal of Q: the 4 balanced states, lateral then vertical (balanced); the weights on "
                        "[P_ny, P_nz, z_ny, z_nz] (integral)"),
    ("lqr", "r_diag"): ("1/N^2", "diagonal of R: the weights on [u_y, u_z]"),
}

#: What each ``[controller]`` key besides ``type`` and the design options is: key -> (unit,
#: allowed, default, meaning). A new key of :data:`hosedrogue.spec.sections.CONTROLLER_KEYS` needs a line here.
CONTROLLER_KEY_DOCS = {
    "sample_time_s": ("s", f"a finite number in [0, {MAX_SAMPLE_TIME_S:g}] s ('python': > 0)", "0.0",
                      "time between the controller's calls; the command is held in between. 'pid', 'lqr': 0 runs "
                      "the continuous controller compiled in the loop, > 0 its zero-order-hold discretization at "
                      "that sample time; 'python': required (docs: Your own controllers)"),
    "entry": (NO_UNIT, 'an entry point "package.module:factory"', '""',
              "type 'python': the controller's factory, imported by that name when the run starts (a file that "
              "names Python code is as trusted as a script)"),
    "options": (NO_UNIT, "a table ([controller.options])", "{}",
                "type 'python': keyword options of the factory, factory(**options)"),
}

#: Defaults of the ``[controller]`` options (missing entries take the paper's values).
CONTROLLER_OPTION_DEFAULTS = {("lqr", "design"): "balanced"}

#: Meanings of the ``[scenario]`` keys that are not fields of :class:`~hosedrogue.scenarios.Scenario`.
SCENARIO_EXTRA_DOCS = {
    "extends": "a shipped scenario name, or a TOML path relative to this file, to start from: this file's "
               "tables override it key by key (a [controller] of another type replaces the parent's table); "
               "the name is this file's own",
}

#: Introductions of the tables, in the order of the page: table -> one paragraph.
TABLE_DOCS = {
    "scenario": "The run: its name, length and initial state. `duration_s` is the one required key.",
    "model": "A shipped model preset to start from; the file's parameter sections then override it.",
    "tanker": "The tanker aircraft (paper Table 1).",
    "hose": "The hose, modelled as `links` rigid links of equal length (paper Table 1).",
    "drogue": "The drogue (paper Table 1).",
    "flight": "The flight condition (paper Sec. 2.3.3: 150 m/s at 8000 m), straight and level unless "
              "`[tanker_motion]` says otherwise (its airspeed is then the one at the start).",
    "wake": "The tanker's Hallock-Burnham wake vortices. `wake = false` at the top level is short for "
            "`[wake] enabled = false`.",
    "turbulence": "Dryden turbulence and its time window. `turbulence = true` at the top level is short for "
                  "`[turbulence] enabled = true`; `intensity` names a standard intensity instead of `sigma_m_s`.",
    "numerics": "Time integration.",
    "tanker_motion": "The tanker's manoeuvres (docs: The model, section 9): the steady flight at the start (a "
                     "coordinated turn, a climb or descent, at `flight.airspeed_m_s`) and the segments that change "
                     "it, each a `[[tanker_motion.segments]]` table (keys `segments.*` below) flying from its "
                     "`start_s` to the bank angle, flight-path angle and airspeed it names, at its rates; a target "
                     "left out is unchanged, and a segment must end before the next starts. Without the table: "
                     "straight and level flight at constant speed.",
    "controller": "The drogue controller: its `type`, then the options of that type. Options not given take "
                  "the paper's values. Type `\"python\"` runs your own sampled-data controller (docs: Your own "
                  "controllers).",
    "actuator": "Limits on the control force applied to the drogue.",
    "sensor": "Noise on the measured drogue position the controllers read, and the delay of the sampled-data "
              "controllers' measurement.",
    "drogue_actuator": "The drogue steers itself with control surfaces that make the controller's force: their "
                       "force from the local dynamic pressure, deflection and rate limits, servos, drag increment "
                       "(docs/model.md §10). Present (even empty: the defaults) or absent; with it `[actuator]` must "
                       "keep its defaults.",
    "reel": "The hose drum unit. With `[reel]` or `[probe]` the scenario runs the hose of varying length "
            "(the engagement).",
    "probe": "The receiver's probe: its prescribed path, the capture test and the coupling once captured.",
    "bow_wave": "The receiver's forebody flow, moving with the probe tip (needs an enabled `[probe]`).",
    "pilot": "A pilot model flying the probe's lateral and vertical position toward the drogue (needs an "
             "enabled `[probe]`).",
    "receiver": "Your own docking controller flying the probe: a probe-tip velocity command through the "
                "receiver's response (needs an enabled `[probe]`; docs: Your own controllers).",
}


def _dataclass_comments(cls: type) -> dict[str, str]:
    """The ``#:`` comment of each field of a dataclass, above the field or at the end of its line."""
    source = textwrap.dedent(inspect.getsource(cls))
    lines = source.splitlines()
    out = {}
    for node in ast.parse(source).body[0].body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            above, i = [], node.lineno - 2
            while i >= 0 and lines[i].strip().startswith("#:"):
                above.insert(0, lines[i].strip()[2:].strip())
                i -= 1
            line = lines[node.end_lineno - 1]
            trailing = line.split("#:", 1)[1].strip() if "#:" in line else ""
            out[node.target.id] = " ".join(above + ([trailing] if trailing else []))
    return out


def toml_value(value: Any) -> str:
    """A default as a scenario file writes it (``true``, ``"paper"``, ``[1.5, 1.5, 1.5]``, ``inf``).

    Parameters
    ----------
    value : Any
        A field's default (bool, number, string, list or tuple, or None).

    Returns
    -------
    str
        TOML text; ``"(none)"`` for None.
    """
    if value is None:
        return "(none)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return f"{value:.12g}" if value != int(value) or abs(value) >= 1e16 else f"{value:.1f}"
    return str(value)


def _unit(row: dict) -> str:
    if row["unit"]:
        return row["unit"]
    numeric = row["allowed"].startswith(("a finite number", "a number", "an integer", "one number"))
    if not numeric or "[-]" in row["meaning"]:
        return NO_UNIT
    return ""  # a number with no unit and not marked dimensionless: problems() reports it


def section_rows(cls: type) -> list[dict]:
    """The reference rows of a section class.

    Parameters
    ----------
    cls : type
        A :class:`hosedrogue.spec.fields.Section` dataclass.

    Returns
    -------
    list of dict
        Per field: ``key``, ``unit`` (:data:`NO_UNIT` for a dimensionless or non-numeric key;
        "" when a number has no unit and its comment does not mark it ``[-]``), ``default``
        (TOML text), ``allowed`` and ``meaning`` (its ``#:`` comment).
    """
    rows = [{"key": r["name"], "unit": _unit(r), "default": toml_value(r["default"]), "allowed": r["allowed"],
             "meaning": r["meaning"]} for r in field_table(cls)]
    for f in dataclasses.fields(cls):  # a list of sub-tables: its keys as rows "field.key"
        if f.metadata.get("kind") == "records":
            rows += [{**row, "key": f"{f.name}.{row['key']}"} for row in section_rows(f.metadata["section"])]
    return rows


def _scenario_rows() -> list[dict]:
    docs = _dataclass_comments(Scenario)
    fields = {f.name: f for f in dataclasses.fields(Scenario)}
    allowed = {
        "name": ("a string", NO_UNIT, "the file's stem"),
        "description": ("a string", NO_UNIT, '""'),
        "duration_s": (f"a finite number in (0, {MAX_DURATION_S:g}] s", "s", "(required)"),
        "extends": ("a shipped scenario name or a TOML path", NO_UNIT, "(none)"),
        "initial": ("one of 'equilibrium', 'displaced'", NO_UNIT, None),
        "initial_pitch_offset_deg": (f"a finite number in [-{MAX_OFFSET_DEG:g}, {MAX_OFFSET_DEG:g}] deg", "deg", None),
        "initial_yaw_offset_deg": (f"a finite number in [-{MAX_OFFSET_DEG:g}, {MAX_OFFSET_DEG:g}] deg", "deg", None),
    }
    rows = []
    for key in SCENARIO_KEYS:
        text, unit, default = allowed.get(key, ("", "", None))
        if default is None and key in fields:
            default = toml_value(fields[key].default)
        rows.append({"key": key, "unit": unit, "default": default or "", "allowed": text,
                     "meaning": SCENARIO_EXTRA_DOCS.get(key, docs.get(key, ""))})
    return rows


def _model_rows() -> list[dict]:
    return [{"key": "preset", "unit": NO_UNIT, "default": "(none: the paper's model)",
             "allowed": "one of " + ", ".join(repr(n) for n in preset_names()),
             "meaning": "a shipped model preset (its [hose], ... tables) applied before this file's parameter "
                        "sections; 'converged' is the stable model for runs beyond the paper's window"}]


def _controller_rows() -> list[dict]:
    type_doc = _dataclass_comments(Controller)["type"]
    rows = [{"key": "type", "unit": NO_UNIT, "default": toml_value(Controller().type),
             "allowed": "one of " + ", ".join(repr(t) for t in CONTROLLER_TYPES),
             "meaning": f"the controller: {type_doc} (paper Eqs. 33-37)"}]
    for ctype, options in CONTROLLER_OPTIONS.items():
        for key, spec in options.items():
            unit, meaning = CONTROLLER_OPTION_DOCS.get((ctype, key), ("", ""))
            if spec is None:
                allowed = "one of " + ", ".join(repr(d) for d in LQR_DESIGNS)
            else:
                size, lo, strict = spec
                allowed = f"a list of {size} finite numbers {'>' if strict else '>='} {lo:g}"
            default = CONTROLLER_OPTION_DEFAULTS.get((ctype, key))
            rows.append({"key": key, "unit": unit, "type": ctype,
                         "default": toml_value(default) if default else "the paper's",
                         "allowed": f"type {ctype!r}: {allowed}", "meaning": meaning})
    keys = dict.fromkeys(k for ks in CONTROLLER_KEYS.values() for k in ks)
    for key in keys:
        unit, allowed, default, meaning = CONTROLLER_KEY_DOCS.get(key, ("", "", "", ""))
        types = [t for t, ks in CONTROLLER_KEYS.items() if key in ks]
        rows.append({"key": key, "unit": unit, "type": " ".join(types), "default": default,
                     "allowed": f"type {' or '.join(map(repr, types))}: {allowed}", "meaning": meaning})
    return rows


def _intensity_row() -> dict:
    lo, hi = INTENSITY_ALTITUDE_FT[0] * FT_TO_M, INTENSITY_ALTITUDE_FT[-1] * FT_TO_M
    levels = ", ".join(f"{k} {v:g}" for k, v in PROBABILITY_OF_EXCEEDANCE.items())
    return {"key": TURBULENCE_PRESET_KEY, "unit": NO_UNIT, "default": "(none)",
            "allowed": "one of " + ", ".join(repr(k) for k in INTENSITY_FT_S),
            "meaning": f"not a field: sets sigma_m_s to the MIL-F-8785C high-altitude intensity of that level "
                       f"(probability of exceedance {levels}) at flight.altitude_m, tabulated for "
                       f"[{lo:g}, {hi:g}] m; give either intensity or sigma_m_s"}


def reference_tables() -> dict[str, list[dict]]:
    """Every table of a scenario file with its rows, in the order of the reference page.

    Returns
    -------
    dict
        Table name (``"scenario"``, ``"model"``, ``"tanker"``, ..., ``"pilot"``) -> rows as in
        :func:`section_rows` (the ``[controller]`` rows also carry the option's ``type``).
    """
    tables: dict[str, list[dict]] = {"scenario": _scenario_rows(), "model": _model_rows()}
    for name, cls in SECTIONS.items():
        tables[name] = section_rows(cls)
    tables["turbulence"].append(_intensity_row())
    tables["controller"] = _controller_rows()
    for name, cls in {**LOOP_SECTIONS, **ENGAGEMENT_SECTIONS}.items():
        tables[name] = section_rows(cls)
    return tables


def problems(tables: dict[str, list[dict]] | None = None) -> list[str]:
    """What the reference cannot say: ``table.key: no unit`` (a number neither given a unit nor
    marked ``[-]``), ``no range`` or ``no meaning`` (no ``#:`` comment).

    Parameters
    ----------
    tables : dict, optional
        :func:`reference_tables` (computed if missing).

    Returns
    -------
    list of str
        Empty when every key is documented.
    """
    tables = reference_tables() if tables is None else tables
    found = []
    for table, rows in tables.items():
        for row in rows:
            for what in ("unit", "allowed", "meaning"):
                if not str(row[what]).strip():
                    label = {"allowed": "range"}.get(what, what)
                    found.append(f"{table}.{row['key']}: no {label}")
    return found


_ROLE = re.compile(r":[a-z]+:`~?([^`]+)`")


def _cell(text: str) -> str:
    """Table-cell Markdown: Sphinx roles as code, ``|`` escaped, one line."""
    text = _ROLE.sub(r"`\1`", str(text)).replace("``", "`")
    parts = re.split(r"(`[^`]*`)", text)
    return " ".join("".join(p if k % 2 else p.replace("|", "\\|") for k, p in enumerate(parts)).split())


def scenario_reference_markdown() -> str:
    """The scenario reference page's body: one heading and table per scenario-file table.

    Returns
    -------
    str
        Markdown (MyST): per table a ``## [name]`` heading, its introduction and a table of
        key, unit, default, allowed values and meaning.
    """
    out = []
    for table, rows in reference_tables().items():
        out += [f"## `[{table}]`", "", TABLE_DOCS.get(table, ""), ""]
        out += ["| key | unit | default | allowed | meaning |", "|---|---|---|---|---|"]
        for r in rows:
            default = r["default"]
            default = _cell(default) if default.startswith(("(", "the ")) else f"`{default}`"
            out.append(f"| `{r['key']}` | {_cell(r['unit'])} | {default} | {_cell(r['allowed'])} | "
                       f"{_cell(r['meaning'])} |")
        out.append("")
    return "\n".join(out + reward_markdown())


#: The rewards of the Gymnasium environments (hosedrogue.envs, docs/gym.md): environment id -> (its
#: section, what it pays).
REWARDS = {
    "hosedrogue/Docking-v1": (DockingRewardV1, "A capture pays only inside the closure window, less its radial miss "
                              "and the probe's peak load after contact; potential-based shaping (which leaves the optimal "
                              "policy unchanged) guides the approach and a cost per second makes waiting worse than "
                              "trying; a miss, a failed latch, a breakaway or a failed state costs its penalty."),
    "hosedrogue/Docking-v0": (DockingReward, "The distance closed on the drogue, less the control effort, plus the "
                              "capture bonus or minus a penalty at the end (kept unchanged; use v1)."),
    "hosedrogue/StationKeeping-v0": (StationKeepingReward, "The drogue's squared lateral and vertical displacement "
                                     "from its balance position and the force spent, per second; a failed state "
                                     "costs its penalty."),
    "hosedrogue/WhipSuppression-v0": (WhipReward, "The hose's slack and the exit tension's excursion from its value "
                                      "at contact, per second, and the take-up command spent; a failed run costs its "
                                      "penalty."),
}


def reward_markdown() -> list[str]:
    """The reference page's lines of the Gymnasium environments' reward weights (their
    ``reward=`` keyword, a table like a scenario file's, though not in one).

    Returns
    -------
    list of str
        Markdown lines: a ``##`` heading, per environment a ``###`` heading and a table.
    """
    out = ["## Rewards of the Gymnasium environments", "",
           "Not tables of a scenario file: the `reward=` keyword of `gymnasium.make(ID, reward={...})` "
           "(a dict of these keys, the rest default; docs/gym.md, \"Reward\").", ""]
    for env_id, (cls, what) in REWARDS.items():
        out += [f"### `reward` of `{env_id}`", "", what, "",
                "| key | unit | default | allowed | meaning |", "|---|---|---|---|---|"]
        out += [f"| `{r['key']}` | {_cell(r['unit'])} | `{r['default']}` | {_cell(r['allowed'])} | {_cell(r['meaning'])} |"
                for r in section_rows(cls)]
        out.append("")
    return out


#: The page's title and introduction (:func:`scenario_reference_page`).
PAGE_INTRO = """# Scenario reference

Every table and key a scenario file may hold, with its unit, default, allowed values and
meaning. This page is generated from the code (the field metadata of the sections and their
`#:` comments, `hosedrogue.scenarios.reference`): `hosedrogue reference` prints it, `hosedrogue
reference --out docs/scenario-reference.md` writes it, and a test fails when the checked-in copy
differs from what the code generates, or when a field lacks a unit, a range or a meaning.

How the tables combine (`extends`, `[model] preset`, which hose model runs, what is refused) is
in [](scenarios.md). A key not listed here is an error naming the table and the keys it allows.
Defaults are the paper's case (Wu et al. 2018, Table 1 and Sec. 2.3); "inf" means no limit. In
Python the same keys are the fields of `hosedrogue.spec.params.Params` (`PAPER.replace(hose={...})`)
and of the classes of `hosedrogue.spec.sections` (`Reel(law="response")`).
"""


def scenario_reference_page() -> str:
    """The whole scenario reference page: :data:`PAGE_INTRO` and :func:`scenario_reference_markdown`.

    Returns
    -------
    str
        Markdown (MyST), ending in one newline.
    """
    return PAGE_INTRO + "\n" + scenario_reference_markdown().rstrip("\n") + "\n"
