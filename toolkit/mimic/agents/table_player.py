"""An agent that tracks a table of joint references, one row per cycle (no network)."""

from __future__ import annotations

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.world.base import Observation

__all__ = ["TablePlayer"]


class TablePlayer(Agent):
    """Sends row k of ``references_rad`` ((T, N) [rad], one row per 20 ms cycle) at cycle k,
    the last row after the table ends; done once every row was sent. Set ``robot`` for a
    table of another robot than the NAO."""

    name = "reference table"

    def __init__(self, references_rad: np.ndarray) -> None:
        super().__init__()
        self.references_rad = references_rad
        self._i = 0

    def reset(self, obs: Observation) -> None:
        self._i, self.done = 0, False

    def act(self, obs: Observation) -> JointCommand:
        row = self.references_rad[min(self._i, len(self.references_rad) - 1)]
        self._i += 1
        self.done = self._i >= len(self.references_rad)
        # Exposed, as every reference-playing agent does, for the balance layer to correct.
        self.reference_rad = row
        return JointCommand.references(row)
