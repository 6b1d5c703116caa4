"""Progress bars on stderr for long commands (tqdm), silent when stderr is not a terminal or
when HOSEDROGUE_PROGRESS=0."""

from __future__ import annotations

import os
import sys


def progress_bar(total: int, desc: str, enabled: bool | None = None):
    from tqdm import tqdm

    if enabled is None:
        enabled = sys.stderr.isatty() and os.environ.get("HOSEDROGUE_PROGRESS", "1") != "0"
    return tqdm(total=total, desc=desc, unit="step", disable=not enabled, file=sys.stderr, leave=False)
