"""Parameter sets by name or file: the shipped model presets and TOML config files.

A *preset* is a TOML file shipped in ``hosedrogue/presets`` (``converged``: the stable model for
runs beyond the paper's window, docs/long-runs.md) whose ``[section]`` tables override the
paper's case. Entry points for the command line and for scenarios:

* :func:`preset_names` - the shipped presets;
* :func:`load_preset` - a preset's parameters;
* :func:`resolve_config` - ``--config NAME_OR_PATH``: a bare preset name first, else a TOML file;
* :func:`read_toml`, :func:`load_params` - TOML files with one-line errors.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from .params import PAPER, ParameterError, Params, params_from_dict

_PACKAGE = "hosedrogue.presets"


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, turning I/O and syntax problems into :class:`ParameterError`."""
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
    """Parameters from a TOML file of ``[section]`` tables overriding ``base``."""
    return params_from_dict(read_toml(path), base=base)


# --- control hardware: actuator and sensor --------------------------------------------------------
def preset_names() -> list[str]:
    """Names of the model presets shipped with the package, sorted."""
    root = resources.files(_PACKAGE)
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))


def preset_data(name: str) -> dict[str, Any]:
    """The raw ``{section: {field: value}}`` table of a shipped preset."""
    names = preset_names()
    if not isinstance(name, str) or name not in names:
        raise ParameterError(f"preset {name!r}: unknown; allowed: {', '.join(names)}")
    with resources.as_file(resources.files(_PACKAGE) / f"{name}.toml") as path:
        return read_toml(path)


def load_preset(name: str, base: Params = PAPER) -> Params:
    """Parameters of the shipped preset ``name`` (its sections override ``base``)."""
    return params_from_dict(preset_data(name), base=base)


def _is_bare_name(text: str) -> bool:
    return "/" not in text and "\\" not in text and not text.endswith(".toml")


def resolve_config(name_or_path: str | Path, base: Params = PAPER) -> Params:
    """Parameters from ``--config``: a shipped preset by bare name (``converged``), else a TOML
    file of ``[section]`` tables overriding ``base``.

    A bare name that is neither a preset nor an existing file is a one-line
    :class:`ParameterError` listing the presets.
    """
    text = str(name_or_path)
    if _is_bare_name(text) and text in preset_names():
        return load_preset(text, base=base)
    if _is_bare_name(text) and not Path(text).exists():
        raise ParameterError(
            f"--config {text!r}: no such preset or file; presets: {', '.join(preset_names())}"
        )
    return load_params(text, base=base)
