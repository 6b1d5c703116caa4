"""The reward weights of the Gymnasium environments on the scenario reference page (docs/gym.md
"Reward"): every field of both rewards, with a unit, a range and a meaning."""

import dataclasses
import re

from hosedrogue.scenarios import reference
from hosedrogue.spec.rewards import DockingReward, DockingRewardV1


def test_every_reward_field_is_on_the_reference_page_with_every_column():
    text = reference.scenario_reference_markdown()
    for env_id, cls in (("hosedrogue/Docking-v1", DockingRewardV1), ("hosedrogue/Docking-v0", DockingReward)):
        part = text.split(f"### `reward` of `{env_id}`")[1].split("###")[0]
        rows = dict(re.findall(r"^\| `(\w+)` \|(.*)\|$", part, re.M))
        assert list(rows) == [f.name for f in dataclasses.fields(cls)]
        assert all(len(cells.split(" | ")) == 4 and all(c.strip() for c in cells.split(" | ")) for cells in rows.values())
    assert reference.problems({"reward": reference.section_rows(DockingRewardV1)}) == []
    assert reference.problems({"reward": reference.section_rows(DockingReward)}) == []
