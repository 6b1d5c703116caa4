"""A measurement copies and pickles (an environment holding one can be copied mid-episode,
docs/gym.md "Snapshots"): the copy reads its own copy of the buffer, read-only as the original."""

import copy
import pickle

import numpy as np
import pytest

from hosedrogue.controllers.sampled import Measurement
from hosedrogue.model.sampled import M_DROGUE, M_SIZE


@pytest.mark.parametrize("clone", [copy.deepcopy, lambda m: pickle.loads(pickle.dumps(m))])
def test_a_copied_measurement_reads_its_own_copy_of_the_buffer(clone):
    buf = np.arange(M_SIZE, dtype=np.float64)
    holder = {"buf": buf, "m": Measurement.reading(buf)}
    twin = clone(holder)
    assert np.array_equal(twin["m"].drogue_position_m, buf[M_DROGUE:M_DROGUE + 3])
    twin["buf"][M_DROGUE] = -1.0  # the copied run writes its buffer: its measurement sees it, the original's not
    assert twin["m"].drogue_position_m[0] == -1.0 and holder["m"].drogue_position_m[0] == M_DROGUE
    with pytest.raises(AttributeError, match="read-only"):
        twin["m"].t_s = 0.0
