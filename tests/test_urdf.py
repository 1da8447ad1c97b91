"""The URDF twin: well-formed, same links, joints, limits and kinematics as the MJCF robot."""

import math
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

from mimic.robot.description import BODIES
from mimic.robot.joints import JOINTS
from mimic.robot.urdf import robot_urdf
from mimic.world.mujoco_world import MujocoWorld


def _tree():
    return ET.fromstring(robot_urdf())


def test_links_and_revolute_joints_match_the_joint_table():
    root = _tree()
    assert [link.get("name") for link in root.findall("link")] == [b.name for b in BODIES]
    joints = root.findall("joint")
    assert len(joints) == 22
    by_name = {j.get("name"): j for j in joints}
    for joint in JOINTS:
        el = by_name[joint.name]
        assert el.get("type") == "revolute"
        limit = el.find("limit")
        assert math.isclose(float(limit.get("lower")), joint.lower_rad, abs_tol=1e-6)
        assert math.isclose(float(limit.get("upper")), joint.upper_rad, abs_tol=1e-6)


def test_masses_add_up_and_inertias_are_positive():
    root = _tree()
    masses = [float(link.find("inertial/mass").get("value")) for link in root.findall("link")]
    assert math.isclose(sum(masses), sum(b.mass_kg for b in BODIES), rel_tol=1e-6)
    for link in root.findall("link"):
        inertia = link.find("inertial/inertia")
        assert all(float(inertia.get(k)) > 0 for k in ("ixx", "iyy", "izz"))


def _urdf_fk(angles: dict[str, float]) -> dict[str, np.ndarray]:
    """Link origins in the torso frame from the URDF alone (origins are pure translations)."""
    root = _tree()
    pos, rot = {"torso": np.zeros(3)}, {"torso": np.eye(3)}
    for j in root.findall("joint"):
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        origin = np.array([float(v) for v in j.find("origin").get("xyz").split()])
        axis = np.array([float(v) for v in j.find("axis").get("xyz").split()])
        q = angles[j.get("name")]
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        r_joint = np.eye(3) + math.sin(q) * k + (1 - math.cos(q)) * k @ k
        pos[child] = pos[parent] + rot[parent] @ origin
        rot[child] = rot[parent] @ r_joint
    return pos


def test_forward_kinematics_agrees_with_mujoco():
    world = MujocoWorld()
    rng = np.random.default_rng(3)
    angles = np.array([rng.uniform(j.lower_rad, j.upper_rad) for j in JOINTS])
    world.place_robot(0.0, 0.0, 0.0, angles)
    mujoco.mj_kinematics(world.model, world.data)
    d = world.data
    r_torso = d.xmat[world.torso_body_id].reshape(3, 3)
    fk = _urdf_fk({j.name: a for j, a in zip(JOINTS, angles)})
    for body in BODIES:
        in_torso = r_torso.T @ (
            d.xpos[world.model.body(body.name).id] - d.xpos[world.torso_body_id]
        )
        np.testing.assert_allclose(fk[body.name], in_torso, atol=1e-6, err_msg=body.name)
