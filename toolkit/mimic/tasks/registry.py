"""The trial tasks by name: what ``mimic trial NAME`` and ``mimic improve --objective NAME``
play. A new trial is a ``TrialTask`` in its own module plus one line here."""

from __future__ import annotations

from mimic.errors import MimicError
from mimic.tasks.base import TrialTask
from mimic.tasks.getup import GetupTask
from mimic.tasks.kick import KickTask
from mimic.tasks.walk import WalkTask

__all__ = ["TASKS", "get_task"]

#: Every trial task, by name.
TASKS: dict[str, type[TrialTask]] = {task.name: task for task in (KickTask, WalkTask, GetupTask)}


def get_task(name: str) -> type[TrialTask]:
    """The trial task called ``name``.

    Raises:
        MimicError: an unknown name, with the known ones.
    """
    try:
        return TASKS[name]
    except KeyError:
        raise MimicError(f"unknown trial {name!r}; trials: {', '.join(TASKS)}") from None
