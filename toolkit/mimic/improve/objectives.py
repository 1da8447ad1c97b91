"""What ``mimic improve`` maximises: each trial task's ``Objective`` (``tasks.kick``,
``tasks.walk``, ``tasks.getup``): a score from trial episodes, with the trials' own scenes,
seeds and statistics. Validation plays the trials unchanged (``trial_config``)."""

from __future__ import annotations

from mimic.errors import MimicError
from mimic.tasks.registry import TASKS

__all__ = ["make_objective", "OBJECTIVES"]

#: Every objective class, by its task's name.
OBJECTIVES = {name: task.Objective for name, task in TASKS.items()}


def make_objective(name: str, episodes: int | None = None, **settings):
    """The objective of the task ``name`` with ``episodes`` per evaluation (default: its
    own) and ``settings``.

    Raises:
        MimicError: unknown name, episodes < 1.
    """
    if name not in OBJECTIVES:
        raise MimicError(f"unknown objective {name!r}; objectives: {', '.join(OBJECTIVES)}")
    if episodes is not None:
        if episodes < 1:
            raise MimicError(f"--episodes must be >= 1, got {episodes}")
        settings["episodes"] = episodes
    return OBJECTIVES[name](**settings)
