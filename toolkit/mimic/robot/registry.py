"""Robots by name: ``nao`` (ours, the study's simulator) and the league's ``t1`` and ``k1``.

League robots are read from the MJCF files the ``rcsssmj`` package ships, only when asked
for, so listing names is cheap.
"""

from __future__ import annotations

from mimic.errors import MimicError
from mimic.robot.league import league_robot
from mimic.robot.model import RobotDescription
from mimic.robot.nao import nao

__all__ = ["get_robot", "robot_names", "DEFAULT_ROBOT", "UnknownRobotError"]

#: The robot of every command that is not told otherwise.
DEFAULT_ROBOT = "nao"
_LEAGUE = ("t1", "k1")


class UnknownRobotError(MimicError):
    """A robot name mimic does not know."""


def robot_names() -> list[str]:
    """Every name ``get_robot`` accepts."""
    return ["nao", *_LEAGUE]


def get_robot(name: str | RobotDescription | None = None) -> RobotDescription:
    """The robot called ``name`` (default ``nao``); a description is passed through."""
    if isinstance(name, RobotDescription):
        return name
    key = (name or DEFAULT_ROBOT).lower()
    if key in ("nao", "nao_type0"):  # nao_type0: what older recordings call it
        return nao()
    if key in _LEAGUE:
        return league_robot(key)
    raise UnknownRobotError(f"unknown robot {name!r}; known robots: {', '.join(robot_names())}")
