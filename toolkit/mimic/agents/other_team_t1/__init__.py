"""The "other team" on the Booster T1: a model-based walk and a kick, written as another team
would write them.

The team plans its walk with a linear inverted pendulum (``lipm``), solves its legs with its
own IK read from the robot description (``ik``, ``body``), feeds the IMU back into foot
placement and the ankles (``walk``) and kicks along a planned foot path (``kick``); its
numbers are frozen dataclasses (``params``). It plays as a league team process
(``python -m mimic.team.other_team_t1 --server HOST:PORT``) that speaks only the protocol,
so a recorder sees it only through the monitor stream. Nothing outside this package relies on
its internals: the agents expose no joint references (``reference_rad`` stays None).
"""

from __future__ import annotations

from dataclasses import replace

from mimic.agents.other_team_t1.kick import OtherTeamT1Kick
from mimic.agents.other_team_t1.params import (
    JITTERY_WALK,
    KickParams,
    PolicyWalkParams,
    WalkParams,
)
from mimic.agents.other_team_t1.policy_walk import OtherTeamT1PolicyWalk
from mimic.agents.other_team_t1.walk import OtherTeamT1Walk

__all__ = [
    "make_walk",
    "make_policy_walk",
    "make_jittery_walk",
    "make_kick",
    "OtherTeamT1Walk",
    "WalkParams",
    "KickParams",
    "PolicyWalkParams",
]


def make_walk(vx_m_s: float | None = None) -> OtherTeamT1Walk:
    """The team's T1 walk heading straight ahead at ``vx_m_s`` [m/s] (default: its speed)."""
    params = WalkParams()
    if vx_m_s is not None:
        params = replace(params, speed_m_s=float(vx_m_s))
    return OtherTeamT1Walk(params)


def make_policy_walk(vx_m_s: float | None = None):
    """The team's walk as a learned policy walks (``policy_walk``): toward a target 20 m
    ahead seen with noise, a step time that adapts every step; forward at ``vx_m_s`` [m/s]
    (default: its command's)."""

    command = PolicyWalkParams()
    if vx_m_s is not None:
        command = replace(command, speed_m_s=float(vx_m_s))
    return OtherTeamT1PolicyWalk(WalkParams(), command)


def make_jittery_walk(vx_m_s: float | None = None) -> OtherTeamT1PolicyWalk:
    """The policy-like walk with a learned policy's action jitter on every joint's reference
    (``params.JITTERY_WALK``); forward at ``vx_m_s`` [m/s] (default: its command's)."""

    command = JITTERY_WALK
    if vx_m_s is not None:
        command = replace(command, speed_m_s=float(vx_m_s))
    return OtherTeamT1PolicyWalk(WalkParams(), command)


def make_kick():
    """The team's T1 right-foot kick; its ``ball_offset_m`` says where it wants the ball."""

    return OtherTeamT1Kick(KickParams())
