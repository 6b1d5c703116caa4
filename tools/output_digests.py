"""Digests of every shipped scenario's outputs, for byte-comparing a refactor against the code before it.

Runs each shipped scenario (``hosedrogue.scenarios``' TOML files) as ``hosedrogue simulate`` does and
writes it into ``OUT/NAME/``; prints one line per scenario: the SHA-256 of ``timeseries.csv`` and of
the arrays of ``hose.npz`` (their names, dtypes, shapes and bytes: the zip's own bytes carry a
time stamp). Run it on the commit before a change and after it and compare the two listings
(``diff``): a refactor that changes no physics leaves every line the same.

Run:  .venv/bin/python tools/output_digests.py OUT [NAME ...] > digests.txt
"""

from __future__ import annotations

import hashlib
import sys
from importlib.resources import files
from pathlib import Path

import numpy as np


def npz_digest(path):
    """SHA-256 of the arrays in an ``.npz`` (names, dtypes, shapes, bytes), not of the zip."""
    h = hashlib.sha256()
    with np.load(path) as data:
        for name in sorted(data.files):
            a = np.ascontiguousarray(data[name])
            h.update(f"{name} {a.dtype.str} {a.shape}".encode())
            h.update(a.tobytes())
    return h.hexdigest()


def main(argv):
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run, write

    if not argv:
        print("usage: output_digests.py OUT [NAME ...]", file=sys.stderr)
        raise SystemExit(2)
    out = Path(argv[0])
    names = argv[1:] or sorted(p.name[:-5] for p in files("hosedrogue").joinpath("scenarios").iterdir()
                               if p.name.endswith(".toml"))
    from hosedrogue.errors import ParameterError

    try:
        scenarios = [load_scenario(name) for name in names]  # every name checked before a run
    except ParameterError as exc:
        print(f"output_digests.py: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    for name, scenario in zip(names, scenarios):
        folder = out / name
        folder.mkdir(parents=True, exist_ok=True)
        write(run(scenario), folder, plot=False)
        csv = hashlib.sha256((folder / "timeseries.csv").read_bytes()).hexdigest()
        hose = folder / "hose.npz"
        print(f"{name:36s} csv {csv[:16]}  hose {npz_digest(hose)[:16] if hose.exists() else '-'}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
