"""Where a get-up copy's stand window goes (``mimic improve --window auto``), read off the
copy's own runs.

A get-up copy searched over the whole motion can rise to standing height and topple; a
search over the stand alone (``--window START,END``) can fix the topple, but where the stand
begins differs from copy to copy, and reading it off a trace by hand is not a method. ``stand_window``
plays the copy as it is in the get-up trial (the objective's world and settings, the search's
own first episodes) and places the window from ``lead_s`` before the time it was first
upright (``GetupRun.first_upright_s``; a run never upright: when its torso was highest,
``max_torso_height_s``), the median over the runs, to the motion's end (a window to the end
holds its correction over the trial's last pose).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.agents.registry import AgentSpec
from mimic.errors import MimicError
from mimic.tasks.getup import GetupTrialConfig, run_getup_episode
from mimic.trials.parallel import derive_seed

__all__ = ["StandWindow", "stand_window", "STAND_LEAD_S", "AUTO"]

#: ``--window auto``.
AUTO = "auto"
#: The window starts this long before the copy is first upright [s] (the fade-in's length,
#: ``model.windowed.WINDOW_RAMP_S``: the correction is whole by the time it is up).
STAND_LEAD_S = 0.2
#: The window starts at least this long before the motion's end [s] (a copy upright only
#: after its end, in the trial's hold, still gets a window inside the motion).
MIN_WINDOW_S = 0.5


@dataclass(frozen=True)
class StandWindow:
    """The window placed, and what placed it."""

    # The window [s of the motion].
    start_s: float
    end_s: float
    # The median over the runs of when each was first upright (or highest) [s].
    stand_s: float
    # Runs played, and how many were ever upright.
    runs: int
    upright_runs: int

    @property
    def window_s(self) -> tuple[float, float]:
        return self.start_s, self.end_s

    def describe(self) -> str:
        """One line: the window and why."""
        if self.upright_runs == self.runs:
            what = f"first upright at {self.stand_s:.2f} s"
        elif self.upright_runs == 0:
            what = f"never upright; torso highest at {self.stand_s:.2f} s"
        else:
            what = (
                f"first upright, or highest in the {self.runs - self.upright_runs} runs never "
                f"upright, at {self.stand_s:.2f} s"
            )
        return (
            f"--window auto: {self.start_s:.2f},{self.end_s:.2f} s ({what}, median of "
            f"{self.runs} runs)"
        )


def stand_window(
    spec: AgentSpec,
    duration_s: float,
    config: GetupTrialConfig,
    *,
    seed: int,
    runs: int,
    lead_s: float = STAND_LEAD_S,
) -> StandWindow:
    """The stand window of the one-shot get-up ``spec`` (``duration_s`` long [s]) from ``runs``
    get-up trial episodes in ``config``'s world, seeded as the search's first
    (``derive_seed(seed, i)``); module docstring.

    Raises:
        MimicError: runs < 1, a motion too short for a window.
    """
    if runs < 1:
        raise MimicError(f"--window auto plays the copy at least once, got {runs} runs")
    if duration_s <= MIN_WINDOW_S:
        raise MimicError(
            f"--window auto: the motion is {duration_s:.2f} s long, too short for a stand "
            f"window (more than {MIN_WINDOW_S} s)"
        )
    times, upright = [], 0
    for i in range(runs):
        rows, _ = run_getup_episode(spec, derive_seed(seed, i), config)
        row = rows[0]
        if row["first_upright_s"] is not None:
            upright += 1
            times.append(row["first_upright_s"])
        else:
            times.append(row["max_torso_height_s"])
    stand = float(np.median(times))
    start = min(max(0.0, stand - lead_s), duration_s - MIN_WINDOW_S)
    return StandWindow(round(start, 2), float(duration_s), stand, runs, upright)
