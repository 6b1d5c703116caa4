"""Shared fixtures. Tests compare independent formulations and invariants; every tolerance
states its physical reason where it is used."""

import numpy as np
import pytest

from hosedrogue.spec.params import PAPER


@pytest.fixture
def rng():
    return np.random.default_rng(20180371)


def free_stream(params=PAPER, **sections):
    """Parameters with the tanker wake off (uniform free stream), plus overrides."""
    sections.setdefault("wake", {})
    sections["wake"] = {**sections["wake"], "enabled": False}
    return params.replace(**sections)
