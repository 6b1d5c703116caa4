"""Lookup tables of a receiver model: linear in each axis, extrapolated linearly beyond the ends.

This is the interpolation of the F-16 routines of Stevens, Lewis & Johnson (2015, Appendix A.8):
the cell is found by the breakpoints, clamped to the first and last cell, and the value is linear
in each axis within it (bilinear for two axes), so beyond the table it continues the end cell's
slope. Scalar arithmetic, a few microseconds a lookup: the trim and the linearization call each
table thousands of times. ``tests/aircraft/test_tables.py`` compares it with
:class:`scipy.interpolate.RegularGridInterpolator` (``fill_value=None``), the same interpolation
written independently.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field

import numpy as np


def _cell(axis: tuple[float, ...], x: float) -> tuple[int, float]:
    """Index of the cell of ``axis`` holding ``x`` (clamped to the end cells) and the fraction in it."""
    i = min(max(bisect.bisect_right(axis, x) - 1, 0), len(axis) - 2)
    return i, (x - axis[i]) / (axis[i + 1] - axis[i])


def _cell_once(cells: dict, axis: tuple[float, ...], x: float) -> tuple[int, float]:
    """:func:`_cell`, remembered in ``cells`` by the axis (its identity: the dict lives for one
    evaluation, while every table it saw is alive; equal axes of a model file are one object,
    :mod:`.model_file`) and the value."""
    key = (id(axis), x)
    hit = cells.get(key)
    if hit is None:
        hit = cells[key] = _cell(axis, x)
    return hit


@dataclass(frozen=True)
class Table:
    """A table of one or two axes.

    Attributes
    ----------
    name : str
        Its name in the model file.
    axes : tuple of str
        The variables it is a function of, outer index first.
    breakpoints : tuple of tuple of float
        Each axis's breakpoints, strictly increasing.
    values : numpy.ndarray
        The values, shape ``(len(breakpoints[0]), ...)``.
    odd_in : str or None
        An axis the table is odd in: given for that variable >= 0, evaluated at its absolute value
        and multiplied by its sign (the book's CL and CN in sideslip).
    """

    name: str
    axes: tuple[str, ...]
    breakpoints: tuple[tuple[float, ...], ...]
    values: np.ndarray
    odd_in: str | None = None
    #: :attr:`values` as nested lists of Python floats, what :meth:`__call__` reads: the same numbers
    #: and the same arithmetic (nothing fused), at a fraction of numpy scalars' cost per operation
    rows: list = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "rows", np.asarray(self.values, dtype=float).tolist())

    def __call__(self, variables: dict[str, float], cells: dict | None = None) -> float:
        """The table's value at ``variables`` (a mapping holding every name in :attr:`axes`).

        Parameters
        ----------
        variables : dict
            Variable name to value (degrees for angles, as the tables are).
        cells : dict, optional
            Cells already found at these ``variables`` (by breakpoints and value), shared by the
            tables of one evaluation: most of a model's tables have the same breakpoints in angle of
            attack, and each would look up the same cell (the same numbers, found once).

        Returns
        -------
        float
        """
        sign = 1.0
        xs = []
        for name in self.axes:
            x = variables[name]
            if name == self.odd_in:
                sign = 1.0 if x >= 0.0 else -1.0
                x = abs(x)
            xs.append(x)
        v = self.rows
        cells = {} if cells is None else cells
        i, f = _cell_once(cells, self.breakpoints[0], xs[0])
        if len(xs) == 1:
            return sign * (v[i] + f * (v[i + 1] - v[i]))
        j, g = _cell_once(cells, self.breakpoints[1], xs[1])
        row, up = v[i], v[i + 1]
        lo = row[j] + g * (row[j + 1] - row[j])
        hi = up[j] + g * (up[j + 1] - up[j])
        return sign * (lo + f * (hi - lo))


@dataclass(frozen=True)
class Term:
    """One term of a coefficient: ``gain * table(variables) * product of variables[times]``.

    Attributes
    ----------
    table : Table or None
        The table (None: a constant gain).
    gain : float
        The factor.
    times : tuple of str
        Variables multiplied in.
    """

    table: Table | None
    gain: float
    times: tuple[str, ...]

    def __call__(self, variables: dict[str, float], cells: dict | None = None) -> float:
        """The term's value at ``variables``.

        Parameters
        ----------
        variables : dict
            Variable name to value.
        cells : dict, optional
            Cells found at these variables (:meth:`Table.__call__`).

        Returns
        -------
        float
        """
        value = self.gain if self.table is None else self.gain * self.table(variables, cells)
        for name in self.times:
            value *= variables[name]
        return value
