"""Turbulence seeds of a campaign's runs.

Run ``i`` of a campaign with seed ``S`` uses the turbulence seed (:func:`run_seed`)::

    numpy.random.SeedSequence([S, i]).generate_state(1, dtype=numpy.uint64)[0] % 2**63

It depends on ``(S, i)`` only, not on the number of workers, the order in which runs finish or
whether the campaign was interrupted and resumed, so ``runs.csv`` sorted by run index is identical
for any of these. ``SeedSequence`` hashes its entropy, so neighbouring indices give unrelated
seeds, and its output is stable across numpy versions (numpy's documented guarantee). The value is
reduced modulo 2**63 because ``turbulence.seed`` is limited to [0, 2**63 - 1].
"""

from __future__ import annotations

import numpy as np

#: The rule of :func:`run_seed` as recorded in campaign.json.
SEED_RULE = "numpy.random.SeedSequence([seed, run]).generate_state(1, dtype=uint64)[0] % 2**63"


def run_seed(campaign_seed: int, index: int) -> int:
    """Turbulence seed of one run of a campaign (the module's rule).

    Parameters
    ----------
    campaign_seed : int
        The campaign's seed, >= 0.
    index : int
        The run's index, >= 0.

    Returns
    -------
    int
        A seed in [0, 2**63 - 1].
    """
    state = np.random.SeedSequence([int(campaign_seed), int(index)]).generate_state(1, dtype=np.uint64)
    return int(state[0]) % 2**63
