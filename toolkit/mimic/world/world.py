"""The simulated world: one robot, a ball, a field; stepped in 20 ms agent cycles.

Index arrays into qpos/qvel/ctrl are resolved once from the model's names (never hard-coded)
and are read-only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from mimic.robot.joints import JOINT_NAMES, NUM_JOINTS
from mimic.robot.mjcf import FOOT_SITES, IMU_SITE, MAX_JOINT_SPEED_RAD_S
from mimic.world import field as F
from mimic.world.scene import PhysicsConfig, scene_xml

__all__ = ["World", "Observation", "CYCLE_S", "FallCriteria", "yaw_from_quat"]

#: The agent cycle [s]: agents see the world and send joint speeds at 50 Hz.
CYCLE_S = 0.02


@dataclass(frozen=True)
class FallCriteria:
    """When the robot counts as fallen."""

    # Torso centre below this height [m] (standing: ~0.36).
    min_torso_height_m: float = 0.22
    # Torso z axis tilted more than this from vertical [rad].
    max_tilt_rad: float = math.radians(60)


@dataclass
class Observation:
    """What an agent perceives at the start of a cycle.

    Attributes:
        time_s: simulated time since reset [s].
        joint_angles_rad: (22,) joint angles in joint-table order [rad].
        joint_speeds_rad_s: (22,) joint speeds [rad/s].
        gyro_rad_s: (3,) torso angular velocity in the torso frame [rad/s].
        accelerometer_m_s2: (3,) torso proper acceleration in the torso frame [m/s^2].
        torso_quat_wxyz: (4,) torso orientation in the world frame.
        foot_forces_n: (2,) normal force under the left and right sole [N].
        torso_pos_m: (3,) torso centre in the field frame [m] (a localisation estimate).
        ball_pos_m: (3,) ball centre in the field frame [m] (the vision estimate).
    """

    time_s: float
    joint_angles_rad: np.ndarray
    joint_speeds_rad_s: np.ndarray
    gyro_rad_s: np.ndarray
    accelerometer_m_s2: np.ndarray
    torso_quat_wxyz: np.ndarray
    foot_forces_n: np.ndarray
    torso_pos_m: np.ndarray
    ball_pos_m: np.ndarray

    @property
    def torso_yaw_rad(self) -> float:
        """Heading of the torso x axis in the field frame [rad]."""
        return yaw_from_quat(self.torso_quat_wxyz)


def yaw_from_quat(q_wxyz: np.ndarray) -> float:
    """Heading [rad] of the body x axis projected on the ground."""
    w, x, y, z = q_wxyz
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def _readonly(a) -> np.ndarray:
    a = np.asarray(a, dtype=np.int64)
    a.setflags(write=False)
    return a


@dataclass
class World:
    """MuJoCo model and data plus the named views agents and trials need."""

    physics: PhysicsConfig = field(default_factory=PhysicsConfig)
    fall: FallCriteria = field(default_factory=FallCriteria)

    def __post_init__(self) -> None:
        self.model = mujoco.MjModel.from_xml_string(scene_xml(self.physics))
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.substeps = round(CYCLE_S / m.opt.timestep)
        if abs(self.substeps * m.opt.timestep - CYCLE_S) > 1e-9:
            raise ValueError(f"timestep {m.opt.timestep} s does not divide the {CYCLE_S} s cycle")
        self.qpos_idx = _readonly([m.jnt_qposadr[m.joint(n).id] for n in JOINT_NAMES])
        self.qvel_idx = _readonly([m.jnt_dofadr[m.joint(n).id] for n in JOINT_NAMES])
        self.ctrl_idx = _readonly([m.actuator(n).id for n in JOINT_NAMES])
        root = m.joint("root")
        self._root_q = int(m.jnt_qposadr[root.id])
        self._root_v = int(m.jnt_dofadr[root.id])
        ball = m.joint("ball")
        self._ball_q = int(m.jnt_qposadr[ball.id])
        self._ball_v = int(m.jnt_dofadr[ball.id])
        self._sensor = {name: slice(int(m.sensor(name).adr[0]),
                                    int(m.sensor(name).adr[0] + m.sensor(name).dim[0]))
                        for name in ("gyro", "accelerometer", "torso_quat",
                                     *[f"{s}_touch" for s in FOOT_SITES])}
        self.torso_body_id = m.body("torso").id
        self.ball_body_id = m.body("ball").id
        self.imu_site_id = m.site(IMU_SITE).id
        self._home_qpos = self.data.qpos.copy()
        self._sole_height_m = float(self.data.qpos[self._root_q + 2])
        self.cycle = 0

    # --- placing things -------------------------------------------------------------------
    def reset(self) -> None:
        """Everything back to the start: zero pose, robot at the centre, ball at the spot."""
        mujoco.mj_resetData(self.model, self.data)
        self.cycle = 0
        mujoco.mj_forward(self.model, self.data)

    def beam(self, x_m: float, y_m: float, yaw_rad: float = 0.0,
             joint_angles_rad: np.ndarray | None = None, *, lying: str | None = None) -> None:
        """Place the robot at (x, y) facing ``yaw_rad``, feet on the ground, at rest.

        Args:
            joint_angles_rad: (22,) pose to put the joints in (default: zero pose).
            lying: ``"front"`` or ``"back"`` to lay the robot down instead of standing it.
        """
        d = self.data
        q = np.zeros(NUM_JOINTS) if joint_angles_rad is None else np.asarray(joint_angles_rad)
        d.qpos[self.qpos_idx] = q
        d.qvel[self._root_v:self._root_v + 6] = 0.0
        d.qvel[self.qvel_idx] = 0.0
        rot = np.zeros(4)
        mujoco.mju_euler2Quat(rot, np.array([0.0, 0.0, yaw_rad]), "xyz")
        if lying is not None:
            pitch = math.pi / 2 if lying == "front" else -math.pi / 2
            tilt = np.zeros(4)
            mujoco.mju_euler2Quat(tilt, np.array([0.0, pitch, 0.0]), "xyz")
            mujoco.mju_mulQuat(rot, rot, tilt)
        d.qpos[self._root_q:self._root_q + 3] = (x_m, y_m, 1.0)
        d.qpos[self._root_q + 3:self._root_q + 7] = rot
        mujoco.mj_kinematics(self.model, self.data)
        lowest = self._lowest_robot_point_m()
        d.qpos[self._root_q + 2] = 1.0 - lowest + 0.001
        mujoco.mj_forward(self.model, self.data)

    def _lowest_robot_point_m(self) -> float:
        m, d = self.model, self.data
        lowest = np.inf
        for g in range(m.ngeom):
            if m.geom_bodyid[g] < self.torso_body_id or m.geom_contype[g] == 0:
                continue
            size, pos, mat = m.geom_size[g], d.geom_xpos[g], d.geom_xmat[g].reshape(3, 3)
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
                corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1)
                                    for sz in (-1, 1)]) * size
                z = (corners @ mat.T)[:, 2] + pos[2]
                lowest = min(lowest, z.min())
            else:
                half = size[1] * abs(mat[2, 2]) if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE else 0
                lowest = min(lowest, pos[2] - size[0] - half)
        return float(lowest)

    def place_ball(self, x_m: float, y_m: float) -> None:
        """Put the ball at rest on the ground at (x, y)."""
        d = self.data
        d.qpos[self._ball_q:self._ball_q + 7] = (x_m, y_m, F.BALL_RADIUS_M, 1, 0, 0, 0)
        d.qvel[self._ball_v:self._ball_v + 6] = 0.0
        mujoco.mj_forward(self.model, self.data)

    # --- stepping -------------------------------------------------------------------------
    def step(self, joint_speeds_rad_s: np.ndarray) -> None:
        """Apply joint speed commands (22,) [rad/s], capped, and advance one 20 ms cycle."""
        cmd = np.clip(joint_speeds_rad_s, -MAX_JOINT_SPEED_RAD_S, MAX_JOINT_SPEED_RAD_S)
        self.data.ctrl[self.ctrl_idx] = cmd
        mujoco.mj_step(self.model, self.data, nstep=self.substeps)
        self.cycle += 1

    # --- sensing --------------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return float(self.data.time)

    def joint_angles_rad(self) -> np.ndarray:
        """(22,) joint angles [rad], joint-table order."""
        return self.data.qpos[self.qpos_idx].copy()

    def observe(self) -> Observation:
        d, s = self.data, self._sensor
        return Observation(
            time_s=float(d.time),
            joint_angles_rad=d.qpos[self.qpos_idx].copy(),
            joint_speeds_rad_s=d.qvel[self.qvel_idx].copy(),
            gyro_rad_s=d.sensordata[s["gyro"]].copy(),
            accelerometer_m_s2=d.sensordata[s["accelerometer"]].copy(),
            torso_quat_wxyz=d.sensordata[s["torso_quat"]].copy(),
            foot_forces_n=np.array([d.sensordata[s[f"{f}_touch"]][0] for f in FOOT_SITES]),
            torso_pos_m=d.qpos[self._root_q:self._root_q + 3].copy(),
            ball_pos_m=d.qpos[self._ball_q:self._ball_q + 3].copy(),
        )

    def torso_pos_m(self) -> np.ndarray:
        """(3,) torso centre in the field frame [m]."""
        return self.data.qpos[self._root_q:self._root_q + 3].copy()

    def torso_quat_wxyz(self) -> np.ndarray:
        return self.data.qpos[self._root_q + 3:self._root_q + 7].copy()

    def torso_yaw_rad(self) -> float:
        return yaw_from_quat(self.torso_quat_wxyz())

    def torso_up_z(self) -> float:
        """z component of the torso's up axis: 1 upright, 0 lying."""
        return float(self.data.xmat[self.torso_body_id][8])

    def ball_pos_m(self) -> np.ndarray:
        """(3,) ball centre in the field frame [m]."""
        return self.data.qpos[self._ball_q:self._ball_q + 3].copy()

    def ball_speed_m_s(self) -> float:
        return float(np.linalg.norm(self.data.qvel[self._ball_v:self._ball_v + 3]))

    def centre_of_mass_m(self) -> np.ndarray:
        """(3,) robot centre of mass in the field frame [m]."""
        return self.data.subtree_com[self.torso_body_id].copy()

    # --- events ---------------------------------------------------------------------------
    def fallen(self) -> bool:
        """Torso too low or tilted too far (see ``FallCriteria``)."""
        up = max(-1.0, min(1.0, self.torso_up_z()))
        return (self.torso_pos_m()[2] < self.fall.min_torso_height_m
                or math.acos(up) > self.fall.max_tilt_rad)

    def upright(self) -> bool:
        """Standing: torso high and nearly vertical (the success test of a get-up)."""
        return self.torso_pos_m()[2] > 0.28 and self.torso_up_z() > math.cos(math.radians(25))

    def goal_scored(self) -> bool:
        """Ball wholly behind the opponent goal line, between the posts, under the bar."""
        x, y, z = self.ball_pos_m()
        return (x > F.OPPONENT_GOAL_X_M + F.BALL_RADIUS_M and abs(y) < F.GOAL_WIDTH_M / 2
                and z < F.GOAL_HEIGHT_M)

    def ball_out(self) -> bool:
        """Ball wholly outside the field lines (and not a goal)."""
        x, y, _ = self.ball_pos_m()
        r = F.BALL_RADIUS_M
        return (abs(x) > F.FIELD_LENGTH_M / 2 + r or abs(y) > F.FIELD_WIDTH_M / 2 + r) \
            and not self.goal_scored()
