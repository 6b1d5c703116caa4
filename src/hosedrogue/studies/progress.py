"""Progress bars on stderr for long commands (tqdm).

The policy, in one place (:func:`progress_enabled`): a bar is shown only when the caller asks for
one, stderr is a terminal and the environment does not set ``HOSEDROGUE_PROGRESS=0``.
"""

from __future__ import annotations

import os
import sys


def progress_enabled(requested: bool = True) -> bool:
    """Whether to show a progress bar.

    Parameters
    ----------
    requested : bool
        The caller's wish (e.g. not ``--quiet``).

    Returns
    -------
    bool
        ``requested`` and stderr is a terminal and ``HOSEDROGUE_PROGRESS`` is not ``"0"``.
    """
    return bool(requested) and sys.stderr.isatty() and os.environ.get("HOSEDROGUE_PROGRESS", "1") != "0"


def progress_bar(total: int, desc: str, enabled: bool | None = None, unit: str = "step", initial: int = 0,
                 leave: bool = False):
    """A tqdm progress bar on stderr.

    Parameters
    ----------
    total : int
        Number of items [unit].
    desc : str
        Label in front of the bar.
    enabled : bool, optional
        Show it; default :func:`progress_enabled`.
    unit : str
        Name of one item.
    initial : int
        Items already done [unit].
    leave : bool
        Keep the finished bar on screen.

    Returns
    -------
    tqdm.tqdm
    """
    from tqdm import tqdm

    if enabled is None:
        enabled = progress_enabled()
    return tqdm(total=total, initial=initial, desc=desc, unit=unit, disable=not enabled, file=sys.stderr,
                leave=leave)
