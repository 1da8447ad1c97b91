"""Robots as data: the registry and `mimic robots`, mirror maps, the league's T1 and K1
read from RCSSServerMJ's MJCF files, standing on our field under their PD motors, and their
URDF twins."""

import json
import math
import subprocess
import sys
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.robot.actuators import JointCommand
from mimic.robot.registry import get_robot, robot_names
from mimic.world.mujoco_world import MujocoWorld

rcsssmj = pytest.importorskip("rcsssmj")
LEAGUE = ("t1", "k1")
runner = CliRunner()


def _mjcf_model(name: str) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(get_robot(name).mjcf_path))


def _mjcf_hinges(name: str) -> list[str]:
    m = _mjcf_model(name)
    return [m.joint(j).name for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]


@pytest.fixture(scope="module", params=LEAGUE)
def standing(request):
    """(world, torso heights, tilts, fallen flags) over 10 s of holding the stand pose."""
    world = MujocoWorld(request.param)
    robot = world.robot
    world.reset()
    world.place_robot(0, 0, 0, robot.stand_pose())
    world.place_ball(0.0, 3.0)  # the league's ball (0.11 m) would sit between the feet
    heights, tilts, fallen = [world.torso_pos_m()[2]], [], []
    command = JointCommand.references(robot.stand_pose())
    for _ in range(500):
        world.step(command)
        heights.append(world.torso_pos_m()[2])
        tilts.append(math.acos(min(1.0, world.torso_up_z())))
        fallen.append(world.fallen())
    return world, np.array(heights), np.array(tilts), np.array(fallen)


# --- registry and CLI ---------------------------------------------------------------------
def test_mimic_robots_lists_nao_t1_k1_with_their_joint_counts():
    result = runner.invoke(app, ["robots", "--json"])
    assert result.exit_code == 0, result.output
    rows = {row["name"]: row for row in json.loads(result.output)}
    assert list(rows) == robot_names() == ["nao", "t1", "k1"]
    assert rows["nao"]["joints"] == 22 and rows["nao"]["world"] == "nao"
    assert rows["t1"]["joints"] == 23 and rows["t1"]["world"] == "league"
    assert rows["k1"]["joints"] == len(_mjcf_hinges("k1")) == 22
    assert rows["t1"]["actuator"] == rows["k1"]["actuator"] == "PD motors"
    assert rows["nao"]["actuator"] == "speed servos"
    assert rows["t1"]["mass_kg"] == pytest.approx(_mjcf_model("t1").body_mass.sum(), abs=1e-3)


def test_mimic_robots_table_fits_80_columns():
    result = runner.invoke(app, ["robots"], terminal_width=80)
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert all(len(line) <= 80 for line in lines)
    assert "mass kg" in lines[0] and "world" in lines[0]
    for name, joints in (("nao", 22), ("t1", 23), ("k1", 22)):
        row = next(line for line in lines if line.split()[0] == name)
        assert row.split()[1] == str(joints)


def test_league_robot_without_rcsssmj_is_one_line_saying_what_to_install():
    code = (
        "import sys; sys.modules['rcsssmj'] = None\n"  # as if it were not installed
        "from mimic.robot.registry import get_robot\n"
        "get_robot('t1')\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode != 0
    assert "MimicError" in done.stderr and "pip install rcsssmj" in done.stderr


# --- descriptions read from the MJCF ----------------------------------------------------
@pytest.mark.parametrize("name", LEAGUE)
def test_league_joints_links_and_limits_are_the_mjcfs(name):
    robot, m = get_robot(name), _mjcf_model(name)
    assert robot.joint_names == tuple(_mjcf_hinges(name))
    for j in robot.joints:
        mj = m.joint(j.name)
        assert (j.lower_rad, j.upper_rad) == pytest.approx(tuple(mj.range))
        assert j.child_link == m.body(mj.bodyid[0]).name
        assert j.parent_link == m.body(m.body_parentid[mj.bodyid[0]]).name
    assert [link.name for link in robot.links] == [m.body(b).name for b in range(1, m.nbody)]
    assert robot.links[0].parent is None and robot.root_link == "torso"
    assert robot.mass_kg == pytest.approx(m.body_mass.sum())
    assert robot.actuator.max_torque_nm == pytest.approx(
        [m.jnt_actfrcrange[m.joint(n).id, 1] for n in robot.joint_names]
    )
    assert robot.foot_links == ("left_foot_link", "right_foot_link")
    assert robot.imu_site == "torso" and robot.world == "league"
    groups = {j.group for j in robot.joints}
    assert {"head", "left_arm", "right_arm", "left_leg", "right_leg"} <= groups
    assert [j.name for j in robot.joints if j.group == "left_leg"][-1] == "Left_Ankle_Roll"


def test_t1_has_23_joints_with_a_waist_and_pd_gains_in_range():
    t1 = get_robot("t1")
    assert t1.num_joints == 23
    assert t1.joints[t1.joint_index("Waist")].group == "waist"
    kp, kd = t1.actuator.kp_nm_rad, t1.actuator.kd_nm_s_rad
    legs = [t1.joint_index(n) for n in t1.joint_names if "Hip" in n or "Knee" in n]
    arms = [t1.joint_index(n) for n in t1.joint_names if "Shoulder" in n or "Elbow" in n]
    assert np.all((kp[legs] >= 100) & (kp[legs] <= 200))
    assert np.all((kp[arms] >= 20) & (kp[arms] <= 40))
    assert np.all((kd >= 0.3) & (kd <= 5))


@pytest.mark.parametrize("name", ["nao", *LEAGUE])
def test_mirroring_twice_is_the_identity_and_the_stand_pose_is_symmetric(name):
    robot = get_robot(name)
    q = np.random.default_rng(0).uniform(-1, 1, size=(5, robot.num_joints))
    assert robot.mirror_angles(robot.mirror_angles(q)) == pytest.approx(q)
    assert robot.mirror_angles(robot.stand_pose()) == pytest.approx(robot.stand_pose())
    for j in robot.joints:
        other = robot.joints[robot.joint_index(j.mirror)]
        assert other.mirror == j.name and other.mirror_sign == j.mirror_sign
        # The mirror joint's stops, mirrored, are this joint's stops.
        assert sorted(
            [other.lower_rad * j.mirror_sign, other.upper_rad * j.mirror_sign]
        ) == pytest.approx([j.lower_rad, j.upper_rad])
        if j.group.startswith("left_"):
            assert other.group == "right_" + j.group.removeprefix("left_")


@pytest.mark.parametrize("name", LEAGUE)
def test_roll_and_yaw_joints_flip_sign_in_the_mirror_pitch_joints_keep_it(name):
    robot = get_robot(name)
    for j in robot.joints:
        kind = j.name.lower()
        expected = (
            +1
            if "pitch" in kind
            else -1
            if ("roll" in kind or "yaw" in kind or kind == "waist")
            else None
        )
        assert j.mirror_sign == expected, j.name
        swapped = j.name.replace("Left", "@").replace("Right", "Left").replace("@", "Right")
        assert j.mirror == swapped


@pytest.mark.parametrize("name", LEAGUE)
def test_fall_thresholds_scale_with_the_standing_torso_height(name):
    world = MujocoWorld(name)
    world.reset()
    world.place_robot(0, 0, 0, world.robot.stand_pose())
    height, falls = world.torso_pos_m()[2], world.robot.falls
    assert falls.fallen_below_m == pytest.approx(0.6 * height, rel=0.02)
    assert falls.upright_above_m == pytest.approx(0.8 * height, rel=0.02)
    assert world.upright() and not world.fallen()
    world.place_robot(0, 0, 0, world.robot.stand_pose(), posture="lying_back")
    assert world.fallen() and not world.upright()


# --- the attached model ---------------------------------------------------------------
@pytest.mark.parametrize("name", LEAGUE)
def test_attached_model_has_one_pd_position_actuator_per_joint_and_our_sensors(name):
    world = MujocoWorld(name)
    m, robot = world.model, world.robot
    assert m.opt.timestep == 0.005 and world.substeps == 4
    assert m.nu == robot.num_joints
    assert not any(m.actuator(i).name.endswith(("_tau", "_pos", "_vel")) for i in range(m.nu))
    for i, name_ in enumerate(robot.joint_names):
        act = m.actuator(name_)
        assert act.trnid[0] == m.joint(name_).id
        kp, kd, limit = (
            robot.actuator.kp_nm_rad[i],
            robot.actuator.kd_nm_s_rad[i],
            robot.actuator.max_torque_nm[i],
        )
        assert act.gainprm[0] == kp and tuple(act.biasprm[:3]) == (0, -kp, -kd)
        assert tuple(act.forcerange) == (-limit, limit)
    for sensor in ("gyro", "accelerometer", "torso_quat", "left_sole_touch", "right_sole_touch"):
        assert m.sensor(sensor).dim[0] > 0
    assert m.nexclude == len(ET.parse(robot.mjcf_path).getroot().findall("./contact/exclude"))


def test_position_actuators_apply_the_league_pd_law():
    """torque = kp (q_ref - q) + kd (0 - dq), limited: RCSSServerMJ's law with dq_ref = tau = 0."""
    world = MujocoWorld("t1")
    m, d, robot = world.model, world.data, world.robot
    world.reset()
    world.place_robot(0, 0, 0, robot.stand_pose())
    rng = np.random.default_rng(3)
    ref = robot.stand_pose() + rng.uniform(-0.3, 0.3, robot.num_joints)
    d.qvel[world.qvel_idx] = rng.uniform(-2, 2, robot.num_joints)
    d.ctrl[world.ctrl_idx] = robot.actuator.targets(JointCommand.references(ref))
    mujoco.mj_forward(m, d)
    q, dq = d.qpos[world.qpos_idx], d.qvel[world.qvel_idx]
    pd = robot.actuator.kp_nm_rad * (ref - q) - robot.actuator.kd_nm_s_rad * dq
    limit = robot.actuator.max_torque_nm
    assert d.actuator_force[world.ctrl_idx] == pytest.approx(np.clip(pd, -limit, limit))


def test_speed_commands_are_refused_by_pd_motors():
    world = MujocoWorld("t1")
    world.reset()
    with pytest.raises(MimicError, match="PD motors"):
        world.step(JointCommand.speeds(np.zeros(world.robot.num_joints)))
    with pytest.raises(MimicError, match="t1 has PD motors"):
        world.robot.actuator.targets(JointCommand.speeds(np.zeros(23)), "t1")


def test_robot_touches_the_ball_and_the_ground():
    world = MujocoWorld("t1")
    m, d = world.model, world.data
    world.reset()
    world.place_robot(0, 0, 0, world.robot.stand_pose())
    for _ in range(10):  # placed 1 mm up: let it settle onto its soles
        world.step(JointCommand.references(world.robot.stand_pose()))
    foot = m.geom("left_foot")
    # The ball resting on the instep: 2 mm into the top of the foot box.
    x, y, z = d.geom_xpos[foot.id]
    world.place_ball(x, y)
    radius = world.field.ball_radius_m
    d.qpos[m.jnt_qposadr[m.joint("ball").id] + 2] = z + foot.size[2] + radius - 0.002
    mujoco.mj_forward(m, d)
    pairs = {frozenset((m.geom(c.geom1).name, m.geom(c.geom2).name)) for c in d.contact[: d.ncon]}
    assert frozenset(("ball", "left_foot")) in pairs
    for sole in ("left_foot", "right_foot"):
        assert frozenset(("ground", sole)) in pairs


# --- standing -------------------------------------------------------------------------
def test_league_robot_stands_10_s_under_its_pd_motors(standing):
    world, heights, tilts, fallen = standing
    robot = world.robot
    assert not fallen.any()
    assert np.abs(heights - heights[0]).max() < 0.03, robot.name  # no sagging or sinking
    assert tilts.max() < 0.1 and tilts[-1] < 0.03
    assert np.abs(world.torso_pos_m()[:2]).max() < 0.03  # no sliding or stepping
    seen = world.observe()
    assert np.abs(seen.joint_angles_rad - robot.stand_pose()).max() < 0.05
    # At rest the soles carry the robot, evenly, and the IMU feels gravity upward.
    assert seen.foot_forces_n.sum() == pytest.approx(robot.mass_kg * 9.81, rel=0.05)
    assert seen.foot_forces_n[0] == pytest.approx(seen.foot_forces_n[1], rel=0.1)
    assert seen.accelerometer_m_s2 == pytest.approx([0, 0, 9.81], abs=0.2)
    assert np.abs(seen.gyro_rad_s).max() < 0.05


# --- URDF twins -----------------------------------------------------------------------
def _rpy_matrix(rpy) -> np.ndarray:
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


@pytest.mark.parametrize("name", LEAGUE)
def test_urdf_has_the_mjcfs_links_and_revolute_joints_and_its_kinematics(name):
    robot, m = get_robot(name), _mjcf_model(name)
    root = ET.fromstring(robot.urdf())
    joints = [j for j in root.findall("joint") if j.get("type") == "revolute"]
    assert [j.get("name") for j in joints] == list(robot.joint_names) == _mjcf_hinges(name)
    assert len(joints) == (23 if name == "t1" else robot.num_joints)
    assert [link.get("name") for link in root.findall("link")] == [k.name for k in robot.links]
    masses = [float(link.find("inertial/mass").get("value")) for link in root.findall("link")]
    assert sum(masses) == pytest.approx(robot.mass_kg, rel=1e-4)
    # Forward kinematics of the URDF at the zero pose lands every link where MuJoCo has it.
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    pose = {robot.root_link: (d.xpos[1], d.xmat[1].reshape(3, 3))}
    for j in root.findall("joint"):  # parents come before children
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        origin = j.find("origin")
        xyz = np.array(origin.get("xyz").split(), dtype=float)
        rpy = np.array(origin.get("rpy").split(), dtype=float)
        p_pos, p_rot = pose[parent]
        pose[child] = (p_pos + p_rot @ xyz, p_rot @ _rpy_matrix(rpy))
        b = m.body(child).id
        assert pose[child][0] == pytest.approx(d.xpos[b], abs=1e-6)
        assert pose[child][1] == pytest.approx(d.xmat[b].reshape(3, 3), abs=1e-5)
        if j.get("type") == "revolute":
            limit = j.find("limit")
            assert float(limit.get("lower")) == pytest.approx(m.joint(j.get("name")).range[0])
            assert float(limit.get("effort")) == m.jnt_actfrcrange[m.joint(j.get("name")).id, 1]


def test_rerun_reads_the_t1_urdf(tmp_path, rerun_cli):
    import rerun as rr

    urdf, rrd = tmp_path / "t1.urdf", tmp_path / "t1.rrd"
    urdf.write_text(get_robot("t1").urdf())
    rec = rr.RecordingStream("urdf_check")
    rec.save(rrd)
    rec.log_file_from_path(urdf)
    rec.flush()
    del rec
    printed = subprocess.run(
        [rerun_cli, "rrd", "print", str(rrd)],
        check=True,
        capture_output=True,
        text=True,
        timeout=120,
        env={"RERUN_ANALYTICS": "off", "PATH": "/usr/bin:/bin"},
    ).stdout
    for link in ("torso", "left_foot_link", "Shank_Right", "left_hand_link"):
        assert f"/visual_geometries/{link}/" in printed
