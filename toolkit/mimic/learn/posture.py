"""How a motion starts, read from the torso pose at its first sample.

A black-box recording says nothing of how the robot lay: ``mimic record --server`` sees a
player, not what its motion expects. The torso does: its up axis lies near the ground when
the robot lies (its forward axis pointing down on the front, up on the back), and an
upright torso below the robot's upright height is sitting (or kneeling, squatting).
``mimic train`` keeps the answer as the model's ``start_posture``; ``mimic play`` and the
trials lay the robot down that way (``world.base.POSTURES``; a sitting start is named, not
placed: no world can put a robot down sitting).
"""

from __future__ import annotations

import math

import numpy as np

from mimic.geometry import forward_axis_z
from mimic.robot.model import RobotDescription

__all__ = ["START_POSTURES", "start_posture", "LYING_TILT_RAD"]

#: What ``start_posture`` answers.
START_POSTURES = ("standing", "sitting", "lying_front", "lying_back")
#: A torso tilted more than this from vertical lies [rad].
LYING_TILT_RAD = math.radians(60)


def start_posture(torso_pos_m, torso_quat_wxyz, robot: RobotDescription) -> str:
    """``standing``, ``sitting``, ``lying_front`` or ``lying_back`` for one torso pose: (3,)
    position [m] and (4,) orientation in the field frame."""
    w, x, y, z = (float(v) for v in np.asarray(torso_quat_wxyz, dtype=float))
    norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    up_z = 1 - 2 * (x * x + y * y)
    if up_z < math.cos(LYING_TILT_RAD):
        return "lying_front" if forward_axis_z([w, x, y, z]) < 0 else "lying_back"
    if float(np.asarray(torso_pos_m, dtype=float)[2]) < robot.falls.upright_above_m:
        return "sitting"
    return "standing"
