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


@pytest.fixture
def default_sigint():
    """Python's default SIGINT handler for the test, as the ``hosedrogue`` command's own process has
    it (a pytest-xdist worker ignores SIGINT): a test of how user code's KeyboardInterrupt is told
    from the user's Ctrl-C (hosedrogue.controllers.sampled.CtrlC) runs the command as it runs."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can be set in the main thread only")
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)
