"""Our MuJoCo world: one robot (any ``RobotDescription``), a ball and the field.

The NAO world of the study is this world with the default robot. Index arrays into
qpos/qvel/ctrl are resolved once from the model's names (never hard-coded) and are read-only.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mimic.robot.actuators import JointCommand
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S, BodyPoses, Observation, World, posture_quat
from mimic.world.field import Field, field_for_robot
from mimic.world.physics_scales import NominalPhysics
from mimic.world.scene import FOOT_TOUCH_SENSORS, PhysicsConfig, build_model

__all__ = ["MujocoWorld"]


def _readonly(a) -> np.ndarray:
    a = np.asarray(a, dtype=np.int64)
    a.setflags(write=False)
    return a


class MujocoWorld(World):
    """MuJoCo model and data plus the named views agents and trials need.

    Args:
        robot: a ``RobotDescription`` or a robot name (default: ``nao``).
        physics: simulation settings (default: the robot's, ``PhysicsConfig.for_robot``).
        field: the field and ball (default: the robot's, ``field_for_robot``: the league's
            for league robots, the study's for our NAO).
    """

    def __init__(
        self,
        robot: RobotDescription | str | None = None,
        physics: PhysicsConfig | None = None,
        field: Field | None = None,
    ) -> None:
        self.robot = get_robot(robot)
        self.field = field or field_for_robot(self.robot.world)
        self.physics = physics or PhysicsConfig.for_robot(self.robot)
        self.model = build_model(self.robot, self.physics, self.field)
        self.data = mujoco.MjData(self.model)
        # MjData's arrays never move, but every read of data.qpos makes a new view (a third
        # of a microsecond): the per-cycle reads below share one.
        self._qpos = self.data.qpos
        m, names = self.model, self.robot.joint_names
        self.substeps = round(CYCLE_S / m.opt.timestep)
        if abs(self.substeps * m.opt.timestep - CYCLE_S) > 1e-9:
            raise ValueError(f"timestep {m.opt.timestep} s does not divide the {CYCLE_S} s cycle")
        self.qpos_idx = _readonly([m.jnt_qposadr[m.joint(n).id] for n in names])
        self.qvel_idx = _readonly([m.jnt_dofadr[m.joint(n).id] for n in names])
        self.ctrl_idx = _readonly([m.actuator(n).id for n in names])
        root = m.body(self.robot.root_link)
        root_joint = int(m.body_jntadr[root.id])
        self._root_q = int(m.jnt_qposadr[root_joint])
        self._root_v = int(m.jnt_dofadr[root_joint])
        ball = m.joint("ball")
        self._ball_q = int(m.jnt_qposadr[ball.id])
        self._ball_v = int(m.jnt_dofadr[ball.id])
        self._sensor = {
            name: slice(
                int(m.sensor(name).adr[0]), int(m.sensor(name).adr[0] + m.sensor(name).dim[0])
            )
            for name in ("gyro", "accelerometer", "torso_quat", *FOOT_TOUCH_SENSORS)
        }
        # The first value of each sole's touch sensor: its normal force.
        self._foot_force_idx = _readonly([self._sensor[n].start for n in FOOT_TOUCH_SENSORS])
        self.torso_body_id = root.id
        self.ball_body_id = m.body("ball").id
        self._link_names = tuple(link.name for link in self.robot.links)
        self._link_ids = _readonly([m.body(n).id for n in self._link_names])
        self._robot_geoms = _readonly(
            [
                g
                for g in range(m.ngeom)
                if m.geom_bodyid[g] in set(self._link_ids.tolist()) and m.geom_contype[g] != 0
            ]
        )
        self.cycle = 0
        # Friction and masses as built: what ``scale_physics`` scales.
        self._nominal = NominalPhysics.of(self.model)

    # --- placing things -------------------------------------------------------------------
    def reset(self) -> None:
        mujoco.mj_resetData(self.model, self.data)
        self.cycle = 0
        mujoco.mj_forward(self.model, self.data)

    def place_robot(
        self,
        x_m: float,
        y_m: float,
        yaw_rad: float = 0.0,
        joint_angles_rad: np.ndarray | None = None,
        *,
        posture: str = "standing",
    ) -> None:
        d = self.data
        q = (
            self.robot.zeros()
            if joint_angles_rad is None
            else self.robot.check_vector(joint_angles_rad, "start pose")
        )
        d.qpos[self.qpos_idx] = q
        d.qvel[self._root_v : self._root_v + 6] = 0.0
        d.qvel[self.qvel_idx] = 0.0
        rot = posture_quat(yaw_rad, posture)
        d.qpos[self._root_q : self._root_q + 3] = (x_m, y_m, 1.0)
        d.qpos[self._root_q + 3 : self._root_q + 7] = rot
        mujoco.mj_kinematics(self.model, self.data)
        lowest = self._lowest_robot_point_m()
        d.qpos[self._root_q + 2] = 1.0 - lowest + 0.001
        mujoco.mj_forward(self.model, self.data)

    @property
    def root_qpos_adr(self) -> int:
        """Index in ``data.qpos`` of the root link's free joint (position, then quaternion)."""
        return self._root_q

    @property
    def root_dof_adr(self) -> int:
        """Index in ``data.qvel`` of the root link's free joint (linear, then angular)."""
        return self._root_v

    def set_robot_state(
        self,
        torso_pos_m: np.ndarray,
        torso_quat_wxyz: np.ndarray,
        joint_angles_rad: np.ndarray,
        torso_vel_m_s: np.ndarray = np.zeros(3),
        torso_omega_rad_s: np.ndarray = np.zeros(3),
        joint_speeds_rad_s: np.ndarray | None = None,
    ) -> None:
        """Put the robot in a full state: the root link's pose and velocity (linear in the
        field frame, angular in the link's own frame, as MuJoCo's free joint) and every
        joint's angle and speed (a recorded instant to continue from)."""
        d, rq, rv = self.data, self._root_q, self._root_v
        d.qpos[rq : rq + 3] = torso_pos_m
        d.qpos[rq + 3 : rq + 7] = np.asarray(torso_quat_wxyz) / np.linalg.norm(torso_quat_wxyz)
        d.qpos[self.qpos_idx] = self.robot.check_vector(joint_angles_rad, "joint angles")
        d.qvel[rv : rv + 3] = torso_vel_m_s
        d.qvel[rv + 3 : rv + 6] = torso_omega_rad_s
        d.qvel[self.qvel_idx] = 0.0 if joint_speeds_rad_s is None else joint_speeds_rad_s
        mujoco.mj_forward(self.model, self.data)

    def _lowest_robot_point_m(self) -> float:
        m, d = self.model, self.data
        lowest = np.inf
        for g in self._robot_geoms:
            size, pos, mat = m.geom_size[g], d.geom_xpos[g], d.geom_xmat[g].reshape(3, 3)
            kind = m.geom_type[g]
            if kind == mujoco.mjtGeom.mjGEOM_BOX:
                corners = (
                    np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
                    * size
                )
                lowest = min(lowest, (corners @ mat.T)[:, 2].min() + pos[2])
            elif kind == mujoco.mjtGeom.mjGEOM_MESH:
                lowest = min(lowest, pos[2] - m.geom_rbound[g])
            else:  # sphere, capsule, cylinder: radius, plus the half length along z if any
                half = (
                    size[1] * abs(mat[2, 2])
                    if kind in (mujoco.mjtGeom.mjGEOM_CAPSULE, mujoco.mjtGeom.mjGEOM_CYLINDER)
                    else 0
                )
                lowest = min(lowest, pos[2] - size[0] - half)
        return float(lowest)

    def place_ball(self, x_m: float, y_m: float) -> None:
        d = self.data
        d.qpos[self._ball_q : self._ball_q + 7] = (x_m, y_m, self.field.ball_radius_m, 1, 0, 0, 0)
        d.qvel[self._ball_v : self._ball_v + 6] = 0.0
        mujoco.mj_forward(self.model, self.data)

    # --- disturbances ----------------------------------------------------------------------
    can_disturb_physics = True

    def scale_physics(self, friction_scale: float, link_mass_scales: np.ndarray) -> None:
        self._nominal.apply(self.model, self._link_ids, friction_scale, link_mass_scales)

    def push_torso(self, force_n: np.ndarray) -> None:
        self.data.xfrc_applied[self.torso_body_id, :3] = force_n

    def robot_mass_kg(self) -> float:
        return float(self.model.body_subtreemass[self.torso_body_id])

    def describe(self) -> str:
        return f"MuJoCo world ({self.robot.name})"

    # --- stepping -------------------------------------------------------------------------
    def step(self, command: JointCommand) -> None:
        """Turn the command into controls (the robot's actuator model), advance one cycle."""
        angles = self._qpos[self.qpos_idx]
        self.data.ctrl[self.ctrl_idx] = self.robot.actuator.controls(
            command, angles, self.robot.name
        )
        mujoco.mj_step(self.model, self.data, nstep=self.substeps)
        self.cycle += 1

    # --- sensing --------------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return float(self.data.time)

    def joint_angles_rad(self) -> np.ndarray:
        return self._qpos[self.qpos_idx]  # an index array copies

    def observe(self) -> Observation:
        d, s = self.data, self._sensor
        # Each read of an MjData array makes a new view: read each once. Index arrays copy.
        qpos, sensors = self._qpos, d.sensordata
        return Observation(
            time_s=float(d.time),
            joint_angles_rad=qpos[self.qpos_idx],
            joint_speeds_rad_s=d.qvel[self.qvel_idx],
            gyro_rad_s=sensors[s["gyro"]].copy(),
            accelerometer_m_s2=sensors[s["accelerometer"]].copy(),
            torso_quat_wxyz=sensors[s["torso_quat"]].copy(),
            foot_forces_n=sensors[self._foot_force_idx],
            torso_pos_m=qpos[self._root_q : self._root_q + 3].copy(),
            ball_pos_m=qpos[self._ball_q : self._ball_q + 3].copy(),
        )

    def torso_pos_m(self) -> np.ndarray:
        return self._qpos[self._root_q : self._root_q + 3].copy()

    def torso_quat_wxyz(self) -> np.ndarray:
        return self._qpos[self._root_q + 3 : self._root_q + 7].copy()

    def _torso_height_and_quat(self) -> tuple[float, list[float]]:
        z, *quat = self._qpos[self._root_q + 2 : self._root_q + 7].tolist()
        return z, quat

    def ball_pos_m(self) -> np.ndarray:
        return self._qpos[self._ball_q : self._ball_q + 3].copy()

    def ball_speed_m_s(self) -> float:
        return float(np.linalg.norm(self.data.qvel[self._ball_v : self._ball_v + 3]))

    def centre_of_mass_m(self) -> np.ndarray:
        """(3,) robot centre of mass in the field frame [m]."""
        return self.data.subtree_com[self.torso_body_id].copy()

    def ball_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The ball's centre and orientation now, its spin included."""
        mujoco.mj_kinematics(self.model, self.data)  # xpos lags qpos after mj_step
        b = self.ball_body_id
        return self.data.xpos[b].copy(), self.data.xquat[b].copy()

    def body_poses(self) -> BodyPoses:
        mujoco.mj_kinematics(self.model, self.data)  # xpos lags qpos after mj_step
        return BodyPoses(
            self._link_names,
            self.data.xpos[self._link_ids].copy(),
            self.data.xquat[self._link_ids].copy(),
        )
