"""The "other team": a fast walk and a kick written as if by another team.

The study copies other teams' motions from the joint angles it observes, without knowing how
they are made. This package plays that team: its own leg IK, walk engine, kick and
parameters. Nothing outside this package may rely on its internals; the recorder sees only
the ``Agent`` interface (and ``ball_offset_m`` on the kick), and the agents never expose
their joint references (``reference_rad`` stays None).
"""

from __future__ import annotations

from dataclasses import replace

from mimic.agents.other_team.kick import OtherTeamKick
from mimic.agents.other_team.params import KickParams, WalkParams
from mimic.agents.other_team.walk import OtherTeamWalk

__all__ = ["make_walk", "make_kick", "OtherTeamWalk", "WalkParams", "KickParams"]


def make_walk(vx_m_s: float | None = None) -> OtherTeamWalk:
    """The team's walk heading straight ahead at ``vx_m_s`` [m/s] (default: its best speed)."""
    params = WalkParams()
    if vx_m_s is not None:
        params = replace(params, speed_m_s=float(vx_m_s))
    return OtherTeamWalk(params)


def make_kick():
    """The team's right-foot kick; its ``ball_offset_m`` says where it wants the ball."""

    return OtherTeamKick(KickParams())
