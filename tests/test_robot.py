"""The robot model against the simulator's published numbers."""

import math

import mujoco
import numpy as np
import pytest

from mimic.robot import joints as J
from mimic.robot.description import BODIES, total_mass_kg
from mimic.world.mujoco_world import MujocoWorld


@pytest.fixture(scope="module")
def world():
    return MujocoWorld()


def test_total_mass_is_the_simulators(world):
    robot_bodies = range(world.torso_body_id, world.model.nbody)
    mass = sum(world.model.body_mass[b] for b in robot_bodies)
    assert mass == pytest.approx(4.6071, rel=0.02)
    assert total_mass_kg() == pytest.approx(4.6071, abs=1e-6)


def test_22_actuated_hinges_with_simulator_limits(world):
    m = world.model
    hinges = [m.joint(i) for i in range(m.njnt) if m.jnt_type[i] == mujoco.mjtJoint.mjJNT_HINGE]
    assert len(hinges) == 22 and m.nu == 22
    for joint in J.JOINTS:
        mj = m.joint(joint.name)
        assert mj.range == pytest.approx([joint.lower_rad, joint.upper_rad])
        actuator = m.actuator(joint.name)
        assert actuator.trnid[0] == mj.id
        assert actuator.ctrlrange == pytest.approx([-6.1395, 6.1395])
    assert J.joint_index("llj4") == J.joint_index("left_knee_pitch")
    assert math.degrees(J.JOINTS[J.joint_index("rlj2")].lower_rad) == pytest.approx(-45)


def test_thirteen_body_kinds():
    kinds = {b.name.removeprefix("left_").removeprefix("right_") for b in BODIES}
    assert len(kinds) == 13 and len(BODIES) == 23


def _body_positions(world, angles):
    world.place_robot(0.0, 0.0, 0.0, angles)
    return {
        world.model.body(i).name: world.data.xpos[i] - world.torso_pos_m()
        for i in range(world.torso_body_id, world.model.nbody)
    }


def test_mirrored_command_gives_mirrored_pose(world):
    rng = np.random.default_rng(3)
    lo, hi = J.lower_limits_rad(), J.upper_limits_rad()
    # Stay inside both a joint's range and its mirror's range.
    lo_m, hi_m = J.mirror_angles(lo), J.mirror_angles(hi)
    lo2, hi2 = np.maximum(lo, np.minimum(lo_m, hi_m)), np.minimum(hi, np.maximum(lo_m, hi_m))
    angles = rng.uniform(lo2, hi2)
    pose = _body_positions(world, angles)
    mirrored = _body_positions(world, J.mirror_angles(angles))
    for name, pos in pose.items():
        twin = name.replace("left_", "#").replace("right_", "left_").replace("#", "right_")
        assert mirrored[twin] == pytest.approx(pos * [1, -1, 1], abs=1e-9), name


@pytest.mark.parametrize(
    "joint, expect",
    [
        ("left_hip_pitch", "foot forward"),
        ("left_knee_pitch", "foot back"),
        ("left_shoulder_pitch", "hand down"),
    ],
)
def test_sign_conventions(world, joint, expect):
    angles = np.zeros(J.NUM_JOINTS)
    angles[J.joint_index(joint)] = -0.5 if joint != "left_hip_pitch" else 0.5
    if joint == "left_shoulder_pitch":
        angles[J.joint_index(joint)] = -math.pi / 2
    pos = _body_positions(world, angles)
    if expect == "foot forward":
        assert pos["left_foot"][0] > 0.1
    elif expect == "foot back":
        assert pos["left_foot"][0] < -0.03
    else:
        assert pos["left_lower_arm"][2] < -0.01 and abs(pos["left_lower_arm"][0]) < 0.02


def test_resolve_joint_names_accepts_simulator_names_in_any_order():
    names = list(reversed(J.SIM_NAMES))
    perm = J.resolve_joint_names(names)
    assert [names[i] for i in perm] == list(J.SIM_NAMES)
    with pytest.raises(J.UnknownJointError, match="missing joints: head_yaw"):
        J.resolve_joint_names(list(J.JOINT_NAMES[1:]))
