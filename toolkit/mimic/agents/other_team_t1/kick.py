"""The T1 team's kick: a kick step inside its walk, the right foot swung along a planned path.

The team kicks the way its walk steps, so the robot balances through the kick as it does
through a step: it starts its walk on the spot, rocks onto the left foot, and in the first
step the right foot swings it adds a path of its own to the swing (lift and wind back, strike
forward through the ball, come back to land beside the left foot). Then it stops walking and
settles into the stand pose. Where the ball must lie for that strike is ``ball_offset_m``.
"""

from __future__ import annotations

import math
from dataclasses import replace

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team_t1.params import KickParams, WalkParams
from mimic.agents.other_team_t1.walk import OtherTeamT1Walk
from mimic.world.base import CYCLE_S, Observation

__all__ = ["OtherTeamT1Kick", "kick_path"]

_KICKER = -1.0  # the right foot kicks


def kick_path(params: KickParams):
    """The kicking foot's offset (dx forward, dz up) [m] by phase of the kick step: zero at
    lift-off, wound back, at the strike, down at touch-down ``land_x_m`` ahead of its usual
    landing (cosine blends)."""
    p = params
    marks = (
        (p.lift_off, 0.0, 0.0),
        (p.windup_phase, p.windup_x_m, p.windup_z_m),
        (p.strike_phase, p.strike_x_m, p.strike_z_m),
        (p.touch_down, p.land_x_m, 0.0),
    )

    def path(phase: float) -> tuple[float, float]:
        for (t0, x0, z0), (t1, x1, z1) in zip(marks, marks[1:]):
            if phase <= t1:
                u = min(1.0, max(0.0, (phase - t0) / max(t1 - t0, 1e-9)))
                w = 0.5 - 0.5 * math.cos(math.pi * u)
                return x0 + (x1 - x0) * w, z0 + (z1 - z0) * w
        return p.land_x_m, 0.0

    return path


class OtherTeamT1Kick(Agent):
    """A one-shot right-foot kick from a stand; ``ball_offset_m`` is where it wants the ball."""

    name = "other_team_kick"
    team = "other_team"
    period_s = None
    robot = "t1"
    # Its IK and foot path are the T1's geometry.
    robot_only = True

    def __init__(
        self, params: KickParams = KickParams(), walk_params: WalkParams = WalkParams()
    ) -> None:
        super().__init__()
        self.params = params
        #: Ball centre relative to the torso, robot frame (x forward, y left) [m].
        self.ball_offset_m = (params.ball_x_m, params.ball_y_m)
        self._walk = OtherTeamT1Walk(
            replace(
                walk_params,
                speed_m_s=0.0,
                lift_off=params.lift_off,
                touch_down=params.touch_down,
                halt_hold_s=params.halt_hold_s,
                halt_blend_s=params.halt_blend_s,
            )
        )
        self._path = kick_path(params)
        self._settle_s = 0.0

    def reset(self, obs: Observation) -> None:
        self._walk.reset(obs)
        self._walk.kick(_KICKER, self._path, self.params.not_before_step)
        self._settle_s = 0.0
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        walk = self._walk
        if (
            walk.kick_step is not None
            and walk.state == "walking"
            and walk.steps_taken > walk.kick_step + self.params.steps_after
        ):
            walk.stop()
        command = walk.act(obs)
        if walk.done:
            self._settle_s += CYCLE_S
            self.done = self._settle_s >= self.params.settle_s
        return command
