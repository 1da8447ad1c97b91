"""Our MuJoCo world made to play like the league's server, for fast searches and checks.

RCSSServerMJ steps the same MJCF with other solver options (Euler integration, pyramidal
friction cones, 100 solver iterations) and applies each command one cycle later than our
world (``command_delay_cycles``). ``LeagueLikeWorld`` does both in our world: a get-up or
kick tuned here meets the league's timing without a server per episode (a server episode
costs 10-20 times the wall time). It is an approximation: contacts still differ in detail.
"""

from __future__ import annotations

import mujoco

from mimic.robot.actuators import JointCommand
from mimic.world.base import LEAGUE_COMMAND_DELAY_CYCLES
from mimic.world.mujoco_world import MujocoWorld

__all__ = ["LeagueLikeWorld"]


class LeagueLikeWorld(MujocoWorld):
    """``MujocoWorld`` with the league server's solver options and one cycle of command delay."""

    command_delay_cycles = LEAGUE_COMMAND_DELAY_CYCLES

    def __init__(self, robot="t1", **kwargs) -> None:
        super().__init__(robot, **kwargs)
        opt = self.model.opt
        opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
        opt.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
        opt.iterations, opt.ls_iterations = 100, 50
        opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_EULERDAMP)
        self._pending: JointCommand | None = None

    def reset(self) -> None:
        super().reset()
        self._pending = None

    def step(self, command: JointCommand) -> None:
        """Apply the command of the cycle before (the first cycle holds the joints)."""
        late = self._pending or JointCommand.references(self.joint_angles_rad())
        self._pending = command
        super().step(late)
