"""Parameter sets by name or file: the shipped model presets and TOML config files.

A *preset* is a TOML file shipped in ``hosedrogue/spec/presets`` (``converged``: the stable model for
runs beyond the paper's window, docs/long-runs.md) whose ``[section]`` tables override the
paper's case. Entry points for the command line and for scenarios:

* :func:`preset_names` - the shipped presets;
* :func:`load_preset` - a preset's parameters;
* :func:`resolve_config` - ``--config NAME_OR_PATH``: a bare preset name first, else a TOML file
  (which may itself start from a preset: ``[model] preset = "converged"``);
* :func:`resolve_configs` - several ``--config`` values, applied in order;
* :func:`read_toml`, :func:`load_params` - TOML files with one-line errors.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from .params import PAPER, ParameterError, Params, params_from_dict

_PACKAGE = "hosedrogue.spec.presets"


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, turning I/O and syntax problems into :class:`ParameterError`.

    Parameters
    ----------
    path : str or pathlib.Path
        The TOML file to read.

    Returns
    -------
    dict
        The parsed document, ``{key: value}`` as returned by :func:`tomllib.load`.

    Raises
    ------
    ParameterError
        One line naming the file if it is missing, a directory, not readable, not valid UTF-8
        or not valid TOML.
    """
    p = Path(path)
    try:
        with p.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ParameterError(f"config file {str(p)!r}: not found") from None
    except IsADirectoryError:
        raise ParameterError(f"config file {str(p)!r}: is a directory, expected a TOML file") from None
    except PermissionError:
        raise ParameterError(f"config file {str(p)!r}: not readable (permission denied)") from None
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"config file {str(p)!r}: not valid TOML ({exc})") from None
    except UnicodeDecodeError:
        raise ParameterError(f"config file {str(p)!r}: not valid UTF-8 TOML") from None


def load_params(path: str | Path, base: Params = PAPER) -> Params:
    """Parameters from a TOML file of ``[section]`` tables overriding ``base``; a ``[model]
    preset = "NAME"`` table starts from that shipped preset over ``base`` instead.

    Parameters
    ----------
    path : str or pathlib.Path
        TOML file of ``[section]`` tables (``[hose]``, ``[flight]``, ...) whose fields override
        those of ``base``; fields keep the units of their names (``length_m`` [m], ...).
    base : Params, optional
        The parameters the file overrides; default :data:`~hosedrogue.spec.params.PAPER`, the paper's
        case.

    Returns
    -------
    Params
        ``base`` with the file's fields replaced, validated.

    Raises
    ------
    ParameterError
        If the file cannot be read or parsed (see :func:`read_toml`), or names an unknown section,
        field or preset, or a value of the wrong type or outside its range.
    """
    data = dict(read_toml(path))
    model = data.pop("model", None)
    if model is not None:
        if not isinstance(model, dict) or set(model) - {"preset"}:
            raise ParameterError(f"model = {model!r}: must be a table with the field preset (a shipped model preset)")
        if "preset" in model:
            base = load_preset(model["preset"], base=base)
    return params_from_dict(data, base=base)


def resolve_configs(names_or_paths, base: Params = PAPER) -> Params:
    """Parameters from several ``--config`` values, applied in order (each over the previous).

    Parameters
    ----------
    names_or_paths : sequence of str or pathlib.Path
        Preset names or TOML files (:func:`resolve_config`); empty: ``base``.
    base : Params, optional
        The parameters the first one overrides; default the paper's case.

    Returns
    -------
    Params
    """
    params = base
    for item in names_or_paths:
        params = resolve_config(item, base=params)
    return params


# --- shipped presets ------------------------------------------------------------------------------
def preset_names() -> list[str]:
    """Names of the model presets shipped with the package, sorted."""
    root = resources.files(_PACKAGE)
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))


def preset_data(name: str) -> dict[str, Any]:
    """The raw ``{section: {field: value}}`` table of a shipped preset.

    Parameters
    ----------
    name : str
        A preset name, one of :func:`preset_names` (``"converged"``), without ``.toml``.

    Returns
    -------
    dict
        The preset's ``{section: {field: value}}`` overrides, not yet validated.

    Raises
    ------
    ParameterError
        If ``name`` is not a shipped preset (the message lists them).
    """
    names = preset_names()
    if not isinstance(name, str) or name not in names:
        raise ParameterError(f"preset {name!r}: unknown; allowed: {', '.join(names)}")
    with resources.as_file(resources.files(_PACKAGE) / f"{name}.toml") as path:
        return read_toml(path)


def load_preset(name: str, base: Params = PAPER) -> Params:
    """Parameters of the shipped preset ``name`` (its sections override ``base``).

    Parameters
    ----------
    name : str
        A preset name, one of :func:`preset_names` (``"converged"``).
    base : Params, optional
        The parameters the preset overrides; default :data:`~hosedrogue.spec.params.PAPER`, the
        paper's case.

    Returns
    -------
    Params
        ``base`` with the preset's fields replaced, validated.

    Raises
    ------
    ParameterError
        If ``name`` is not a shipped preset.
    """
    return params_from_dict(preset_data(name), base=base)


def _is_bare_name(text: str) -> bool:
    return "/" not in text and "\\" not in text and not text.endswith(".toml")


def resolve_config(name_or_path: str | Path, base: Params = PAPER) -> Params:
    """Parameters from ``--config``: a shipped preset by bare name (``converged``), else a TOML
    file of ``[section]`` tables overriding ``base``.

    A bare name that is neither a preset nor an existing file is a one-line
    :class:`ParameterError` listing the presets.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        A bare preset name (no ``/`` or ``\\``, not ending in ``.toml``), tried first among
        :func:`preset_names`; otherwise the path of a TOML file.
    base : Params, optional
        The parameters the preset or file overrides; default
        :data:`~hosedrogue.spec.params.PAPER`, the paper's case.

    Returns
    -------
    Params
        ``base`` with the preset's or file's fields replaced, validated.

    Raises
    ------
    ParameterError
        If a bare name is neither a preset nor an existing file, or the file cannot be read,
        parsed or validated (see :func:`load_params`).
    """
    text = str(name_or_path)
    if _is_bare_name(text) and text in preset_names():
        return load_preset(text, base=base)
    if _is_bare_name(text) and not Path(text).exists():
        raise ParameterError(
            f"config {text!r}: no such preset or file; presets: {', '.join(preset_names())}"
        )
    return load_params(text, base=base)
