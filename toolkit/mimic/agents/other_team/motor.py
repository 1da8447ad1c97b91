"""The other team's body layer: foot targets to the NAO's joint targets, targets to speed commands."""

from __future__ import annotations

import numpy as np

from mimic.agents.other_team.ik import leg_ik
from mimic.agents.other_team.params import ServoParams
from mimic.geometry import torso_pitch_roll
from mimic.robot.joints import joint_index
from mimic.robot.nao import nao
from mimic.world.base import CYCLE_S

__all__ = ["LEG_IDX", "ARM_IDX", "legs_to_joints", "servo_speeds", "torso_pitch_roll"]

_LEG_PARTS = ("hip_yaw_pitch", "hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch", "ankle_roll")
#: Joint-table indices of each leg's six joints, keyed by side (+1 left, -1 right).
LEG_IDX = {
    s: np.array([joint_index(f"{n}_{p}") for p in _LEG_PARTS])
    for s, n in ((1.0, "left"), (-1.0, "right"))
}
#: Joint-table indices of (shoulder pitch, shoulder roll), keyed by side.
ARM_IDX = {
    s: np.array([joint_index(f"{n}_shoulder_pitch"), joint_index(f"{n}_shoulder_roll")])
    for s, n in ((1.0, "left"), (-1.0, "right"))
}


def legs_to_joints(
    feet: dict[float, tuple[np.ndarray, np.ndarray]],
    shoulder_pitch_rad: float,
    shoulder_roll_rad: float,
) -> np.ndarray:
    """(N,) joint targets [rad] for foot poses {side: (ankle point (3,), rotation (3, 3))}.

    The poses are in the torso frame; the head is held straight and the arms still.
    """
    q = nao().zeros()
    for side, (pos, rot) in feet.items():
        q[LEG_IDX[side]] = leg_ik(side, pos, rot)
        q[ARM_IDX[side]] = (shoulder_pitch_rad, side * shoulder_roll_rad)
    # Both yaw-pitch hinges stay equal on the real robot; here each leg keeps its own.
    return nao().clip(q)


def servo_speeds(
    target_next_rad: np.ndarray,
    angles_rad: np.ndarray,
    servo: ServoParams,
    target_now_rad: np.ndarray | None = None,
) -> np.ndarray:
    """(N,) speeds [rad/s] that close ``gain`` of the gap to next cycle's targets, capped.

    With ``target_now_rad`` (this cycle's planned targets) the plan's own speed
    (target_next - target_now) / cycle is added, scaled by ``servo.feedforward``, so a moving
    target is followed without the lag of a purely proportional command.
    """
    speed = servo.gain * (target_next_rad - angles_rad) / CYCLE_S
    if target_now_rad is not None and servo.feedforward:
        speed = speed + servo.feedforward * (target_next_rad - target_now_rad) / CYCLE_S
    cap = nao().actuator.max_speed_rad_s
    return np.clip(speed, -cap, cap)
