"""Entity paths and the timeline: one place that names where things live in Rerun."""

from __future__ import annotations

import numpy as np
import rerun as rr

from mimic.robot.model import RobotDescription

__all__ = [
    "TIMELINE",
    "WORLD",
    "ROBOT",
    "BALL",
    "JOINTS_ROOT",
    "GROUPS",
    "joint_group",
    "joint_path",
    "time_column",
]

#: The timeline every time series uses: simulated time since the recording started.
TIMELINE = "sim_time"
WORLD = "world"
ROBOT = "world/robot"
BALL = "world/ball"
JOINTS_ROOT = "joints"
#: Curve groups shown as one plot each.
GROUPS = ("head", "arms", "legs")


def joint_group(joint_group_name: str) -> str:
    """Plot group of a robot's joint group (``left_leg`` -> ``legs``; a waist plots with the
    legs, the hips it turns)."""
    if joint_group_name == "head":
        return "head"
    return "arms" if joint_group_name.endswith("arm") else "legs"


def joint_path(robot: RobotDescription, joint_name: str, series: str) -> str:
    """Entity path of one joint's curve, e.g. ``joints/legs/left_knee_pitch/reached``."""
    joint = robot.joints[robot.joint_index(joint_name)]
    return f"{JOINTS_ROOT}/{joint_group(joint.group)}/{joint_name}/{series}"


def time_column(times_s: np.ndarray) -> rr.TimeColumn:
    """A Rerun time column of simulated seconds."""
    return rr.TimeColumn(TIMELINE, duration=np.asarray(times_s, dtype=float))
