"""Progress bars on stderr for long commands (tqdm), silent when stderr is not a terminal or
when HOSEDROGUE_PROGRESS=0."""

from __future__ import annotations

import os
import sys


def progress_bar(total: int, desc: str, enabled: bool | None = None):
    """A tqdm progress bar on stderr.

    Parameters
    ----------
    total : int
        Number of steps [-].
    desc : str
        Label shown before the bar.
    enabled : bool, optional
        Show it; by default only when stderr is a terminal and ``HOSEDROGUE_PROGRESS`` is not ``0``.

    Returns
    -------
    tqdm.tqdm
    """
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty() and os.environ.get("HOSEDROGUE_PROGRESS", "1") != "0"
    return tqdm(total=total, desc=desc, unit="step", disable=not enabled, file=sys.stderr, leave=False)
