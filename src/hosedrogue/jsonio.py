"""Strict JSON: the one conversion of the package's numbers to JSON types.

JSON has no NaN and no infinities (``JSON.parse`` and other strict readers refuse Python's
``NaN``/``Infinity``): :func:`plain` turns them into ``null``, numpy scalars and arrays into
Python numbers and lists, tuples into lists; :func:`dumps` writes the result with
``allow_nan=False``, so a value it missed is an error, never a non-standard file.
"""

from __future__ import annotations

import json
import math

import numpy as np

__all__ = ["plain", "dumps", "fallback"]


def plain(value):
    """``value`` in strict JSON types.

    Parameters
    ----------
    value : object
        Numbers, strings, bools, None, and dicts, lists, tuples and numpy arrays of them.

    Returns
    -------
    object
        The same structure: dict keys as strings, arrays and tuples as lists, numpy scalars as
        Python's, NaN and infinities as None.
    """
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [plain(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def fallback(value):
    """A value strict JSON does not know, for ``json.dumps(default=...)``: a number as a float (null
    if not finite), anything else (an option of a user's controller given from Python) as its text.

    Parameters
    ----------
    value : object
        What ``json`` could not write.

    Returns
    -------
    float, None or str
    """
    try:
        return plain(float(value))
    except (TypeError, ValueError):
        return repr(value)


def dumps(value, **kwargs) -> str:
    """:func:`plain` ``value`` as strict JSON text.

    Parameters
    ----------
    value : object
        As :func:`plain` takes.
    **kwargs
        Passed to :func:`json.dumps` (``indent``, ``separators``, ...).

    Returns
    -------
    str
    """
    return json.dumps(plain(value), allow_nan=False, **kwargs)
