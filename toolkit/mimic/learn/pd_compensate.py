"""Compensated targets for PD motors: references that reproduce an *observed* motion.

A robot with PD motors (the league's T1 and K1) reaches its reference only where no torque is
needed: every motor applies ``tau = kp (r - q) - kd dq``, so the joint sags under load and lags
when it moves. Angles seen from outside (``/joint_states``, the league's monitor stream) are
what the robot *reached*; replayed as references they sag and lag a second time, and a T1
walk or kick copied that way falls within a second. The reference that reproduces the motion
is ``r = q + (tau + kd dq) / kp`` with ``tau`` the torque each joint needed, and that torque
follows from the observed motion by inverse dynamics:

1. The motion is smoothed and differentiated by local polynomial fits (``half_window_s``
   each side, order ``poly_order``): joint angles, the torso position and its
   orientation (the floating base, from ``/tf``), so every sample has positions, velocities
   and accelerations of every degree of freedom.
2. MuJoCo's inverse dynamics, with all constraints off, gives the generalised force the whole
   motion needs, ``M qacc + c``. Its six floating-base rows cannot come from motors: they are
   the ground's push on the feet.
3. Each foot within ``contact_height_m`` of the lowest the feet get carries a wrench (force
   and moment at the foot link's origin). Under one foot the six rows fix the wrench; under two
   the split is chosen as the least-squares solution in which a foot moment costs
   ``moment_weight`` [1/m^2] times a force (the load then moves to the foot under the body
   rather than into ankle torques).
4. The joint rows, less the feet's share, are the joint torques; clipped to the motors' limits
   they give the references.

Lying, kneeling and sitting (a get-up) the ground holds more than the feet, so every link can
touch it (issue 35):

5. Each collision shape's lowest point is found (exact for spheres and capsules, a corner of
   its bounding box otherwise); a link whose lowest point lies within
   ``body_contact_height_m`` of the ground (z = 0) may push there with a force (no moment).
   A foot carries a wrench as in step 3 only when it stands flat (tilted less than
   ``flat_foot_tilt_rad``, its sole within ``sole_height_m`` of the ground); while another
   link touches, a foot on its heel or toes pushes at its lowest point like the rest.
6. The floating-base rows are split over all the contacts. With ``friction`` set (an option,
   off by default: it rolled one recording's T1 back get-up copy and not two others',
   docs/getups.md): each point force lies in its friction cone (a nonnegative sum of the four edges
   of a pyramid, coefficient ``friction``), except where the point slides (its velocity along
   the ground above ``slide_m_s``): there the ground pushes only along the cone's edge that
   opposes the sliding (kinetic friction); a flat foot's wrench is free. The split is the
   nonnegative least-squares fit of the six rows with a small cost on every force. So static
   friction holds the links that stay put and the sliding ones only brake: a waist that twists
   the pelvis and legs over the ground while the torso lies still gets more of the torque it
   needed (``tests/test_pd_compensate.py``: 0.060 against 0.085 rad rms). ``friction=None`` (the
   default): the least-squares split in which a point force costs as much as a foot's force, a link that
   would pull on the ground dropped and the split solved again (at most 8 times).
7. Saturation at the joint stops: a joint within ``stop_margin_rad`` of a stop sits at it. The
   stop pushes only back into the range, so it gives every share of the torque that points
   that way, and the motor gives only what points into the stop. So a joint that rests
   against its stop under load (a knee folded by the body's weight) gets its observed angle
   as the reference, and one that the motion drives into its stop (a keyframe commanding an
   angle past it) gets a reference beyond the stop by the torque the motion needs there, over
   kp. The torque the motion needs is what steps 2-6 give; a motor that pushed harder into
   its stop than that leaves no trace in the angles and cannot be recovered.

8. Saturation of the motors: where the torque a joint needs reaches ``saturation_share`` of
   its motor's limit, the motor pushed at its limit and the reference lay somewhere beyond
   ``q + (limit + kd dq) / kp``: the angles bound it, they do not give it. A keyframe commands
   where the push should end and the joint lags behind it, so over each push (a run of one
   sign of torque) from its first to its last saturated sample the reference is the farthest
   the push reaches from there on (its look-ahead envelope). A copy that lags a little stays
   saturated, as the original did, rather than falling back to a torque the lag lowers.
   ``saturation_share=None`` (the default, as with ``friction``): the bound itself.

The references are returned at the sample times; a world that applies a command a cycle late
(the league server) needs them ``lead_s`` early, which ``pd_references`` leaves to its caller
(``training_dataset`` shifts league recordings by one cycle).

Measured (``tests/test_pd_compensate.py``; the T1 other team's walk recorded in our world at
50 Hz; from six recorded instants 40-140 cycles in, the robot is set to the recorded state and
continues open loop, no feedback at all): the reached angles replayed as references fall after
30-38 cycles, 0.057-0.064 rad mean tracking error over the first half second; these references
walk on to the recording's end from 3 of the 6 instants (the others 205-221 of 213-253
cycles), 0.009 rad. T1 kicks seen as the league's monitor gives them (25 Hz) and tracked from
the table inside the balance layer, 10 seeds (``benchmarks/t1_copyable_kick.py``): one kicks
3.06 m from references built on smoothed angles (7-sample fits), 3.54 m on 5-sample fits and
3.75 m on the observed angles (7-sample derivatives; the original: 3.78 m); another 3.78 m
on the observed angles with 7-sample derivatives and 4.37 m with 5-sample ones, the default at
25 Hz (the original: 4.70 m).

What it cannot see: in double support, torques that press the legs against each other move
nothing and leave no trace in the angles (a keyframe motion may hold such a squeeze). Lying
on several links the split of the load between them is not in the angles either: the
friction split is a choice (the smallest forces in the cones), and a motion that pushes one
limb hard against the ground
(a T1 get-up's arms, referenced 1 rad past where the ground stops them) gets less push than
it had. Measured on our T1 ``getup_front`` recorded in our world at 50 Hz against its own
references: 0.004-0.09 rad mean error per joint, largest on the shoulders while the arms
press on the ground; replayed open loop it falls back from its kneel-sit, as does the
original with 0.02 rad of random reference bias per joint in 2 of 4 runs (``docs/getups.md``).
Our T1 ``getup_back`` seen at 25 Hz from the league's monitor: on one recording the
least-squares split's copy never rolls from its back onto its front and the friction split's
always does; on a second recording of the same play (angles within 0.0055 rad) it is the
other way round, and on a third neither rolls by the friction split: the references over the
roll move by up to 0.04 rad rms between recordings, and the roll hangs on that
(``docs/getups.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from mimic.errors import MimicError
from mimic.geometry import one_hemisphere, quat_mul
from mimic.robot.actuators import PDMotors
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.mujoco_world import MujocoWorld

__all__ = [
    "PdCompensationConfig",
    "PdCompensation",
    "body_rates_rad_s",
    "local_polynomial",
    "pd_references",
]


@dataclass(frozen=True)
class PdCompensationConfig:
    """How references are reconstructed from an observed motion of a PD-motor robot."""

    # Local polynomial fits: how far each side of the centre they reach [s] (rounded up to
    # whole samples: 3 at our 50 Hz, 2 at the league monitor's 25 Hz; a kick's strike lasts
    # about 0.1 s, and a wider fit flattens it), and the polynomial's order.
    half_window_s: float = 0.06
    poly_order: int = 3

    def half_window(self, dt_s: float) -> int:
        """Samples each side of the centre for samples every ``dt_s`` [s]."""
        return max(1, math.ceil(self.half_window_s / dt_s - 1e-6))

    # A foot touches the ground when its link is within this of the lowest it gets [m].
    contact_height_m: float = 0.015
    # Cost of a foot moment [N m] relative to a force [N] when two feet share the load [1/m^2].
    moment_weight: float = 100.0
    # Any other link (knees, hands, back, hips) touches the ground when the lowest point of
    # its collision shapes is within this of the ground (z = 0) [m]; it can push there, not
    # pull, with a force and no moment.
    body_contact_height_m: float = 0.03
    # A foot carries a wrench only when tilted less than this [rad] and its sole is within
    # this of the ground [m] (lying, a foot rests on its heel or toes: a point).
    flat_foot_tilt_rad: float = math.radians(30)
    sole_height_m: float = 0.05
    # A joint within this of a stop sits at the stop [rad].
    stop_margin_rad: float = 0.03
    # Friction coefficient of a point contact (step 6): its force lies in the friction cone
    # (a pyramid of four edges), or, where the point slides faster than ``slide_m_s``, on the
    # cone's edge against the sliding. None: the least-squares split, no cone.
    friction: float | None = None
    slide_m_s: float = 0.05
    # A motor whose needed torque is at least this share of its limit pushed saturated: over
    # each push (torque of one sign) from its first to its last saturated sample the reference
    # is the farthest the push reaches from there on (step 8). None: the saturation bound.
    saturation_share: float | None = None


@dataclass(frozen=True)
class PdCompensation:
    """References and what they were made from, one row per sample.

    Attributes:
        references_rad: (T, N) references that reproduce the motion [rad].
        torques_nm: (T, N) joint torques the motors apply, clipped to their limits [N m] (at a
            stop: only the share the stop cannot give).
        contacts: (T, 2) whether the left and right foot carried load.
        base_residual: (T,) largest floating-base force or moment the contacts could not
            supply [N or N m] (0 whenever the ground holds the robot; large in flight).
        body_contacts: (T, B) whether each of ``contact_bodies`` pushed on the ground.
        contact_bodies: the B links other than the feet that may touch the ground.
        at_stop: (T, N) whether each joint sat at a stop.
    """

    references_rad: np.ndarray
    torques_nm: np.ndarray
    contacts: np.ndarray
    base_residual: np.ndarray
    body_contacts: np.ndarray | None = None
    contact_bodies: tuple[str, ...] = ()
    at_stop: np.ndarray | None = None


def local_polynomial(
    y: np.ndarray, dt_s: float, half_window: int, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Value, first and second derivative of ``y`` (T, ...) sampled every ``dt_s`` [s], each
    from a polynomial of ``order`` fitted to the ``half_window`` samples each side (fewer at
    the ends, the order lowered to fit)."""
    y = np.asarray(y, dtype=float)
    flat = y.reshape(len(y), -1)
    out = np.zeros((3, *flat.shape))
    n = len(flat)
    for k in range(n):
        lo, hi = max(0, k - half_window), min(n, k + half_window + 1)
        deg = min(order, hi - lo - 1)
        x = (np.arange(lo, hi) - k) * dt_s
        coef, *_ = np.linalg.lstsq(np.vander(x, deg + 1, increasing=True), flat[lo:hi], rcond=None)
        out[0, k] = coef[0]
        if deg >= 1:
            out[1, k] = coef[1]
        if deg >= 2:
            out[2, k] = 2.0 * coef[2]
    return tuple(o.reshape(y.shape) for o in out)


def body_rates_rad_s(quat_wxyz: np.ndarray, dquat_per_s: np.ndarray) -> np.ndarray:
    """(T, 3) angular velocity in the body's own frame [rad/s] (MuJoCo's free joint) from
    (T, 4) unit quaternions and their time derivatives: w = 2 conj(q) dq/dt."""
    conj = np.asarray(quat_wxyz, dtype=float) * np.array([1.0, -1.0, -1.0, -1.0])
    return 2.0 * quat_mul(conj, np.asarray(dquat_per_s, dtype=float))[:, 1:]


def pd_motors(robot: RobotDescription) -> PDMotors:
    """The robot's PD motors, or one clear line for a robot without them."""
    if not isinstance(robot.actuator, PDMotors):
        raise MimicError(
            f"PD compensation needs PD motors; the {robot.name} has {robot.actuator.kind}"
        )
    return robot.actuator


def pd_references(
    time_s: np.ndarray,
    angles_rad: np.ndarray,
    torso_pos_m: np.ndarray,
    torso_quat_wxyz: np.ndarray,
    robot: str | RobotDescription,
    config: PdCompensationConfig = PdCompensationConfig(),
) -> PdCompensation:
    """References that reproduce an observed motion through ``robot``'s PD motors.

    Args:
        time_s: (T,) sample times [s], evenly spaced.
        angles_rad: (T, N) observed joint angles in the robot's joint order [rad].
        torso_pos_m, torso_quat_wxyz: (T, 3) and (T, 4) pose of the robot's root link in the
            field frame at the same times.

    Raises:
        MimicError: the robot has no PD motors, the arrays disagree in shape, or the samples
            are too few or unevenly spaced.
    """

    robot = get_robot(robot)
    motors = pd_motors(robot)
    t = np.asarray(time_s, dtype=float)
    q = np.asarray(angles_rad, dtype=float)
    pos = np.asarray(torso_pos_m, dtype=float)
    quat = np.asarray(torso_quat_wxyz, dtype=float)
    T = len(t)
    if q.shape != (T, robot.num_joints) or pos.shape != (T, 3) or quat.shape != (T, 4):
        raise MimicError(
            f"PD compensation: {T} times, angles {q.shape}, torso positions {pos.shape} and "
            f"orientations {quat.shape} for the {robot.num_joints} {robot.name} joints"
        )
    if T < 3:
        raise MimicError(f"PD compensation needs at least 3 samples, got {T}")
    steps = np.diff(t)
    dt = float(np.median(steps))
    if not (dt > 0 and np.all(np.abs(steps - dt) < 0.25 * dt)):
        k = int(np.argmax(np.abs(steps - dt)))
        raise MimicError(
            f"PD compensation needs evenly spaced samples: {steps[k]:.3f} s between "
            f"{t[k]:.2f} s and {t[k + 1]:.2f} s, every {dt:.3f} s elsewhere (resample the "
            "motion: learn.window)"
        )
    h, order = config.half_window(dt), config.poly_order
    if T < 2 * h + 1:
        raise MimicError(f"PD compensation needs at least {2 * h + 1} samples, got {T}")

    world = MujocoWorld(robot)
    m, d = world.model, world.data
    # Free motion: no contacts, limits or friction loss; the feet's share is solved below.
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)

    q_s, dq, ddq = local_polynomial(q, dt, h, order)
    p_s, dp, ddp = local_polynomial(pos, dt, h, order)
    quat_s, dquat, _ = local_polynomial(one_hemisphere(quat), dt, h, order)
    quat_s /= np.linalg.norm(quat_s, axis=1, keepdims=True)
    omega = body_rates_rad_s(quat_s, dquat)
    _, domega, _ = local_polynomial(omega, dt, h, min(order, 2))

    rq, rv = world.root_qpos_adr, world.root_dof_adr
    jq, jv = np.asarray(world.qpos_idx), np.asarray(world.qvel_idx)
    base = np.arange(rv, rv + 6)
    feet = [m.body(name).id for name in robot.foot_links]

    def pose(k: int) -> None:
        d.qpos[:] = m.qpos0
        d.qpos[rq : rq + 3], d.qpos[rq + 3 : rq + 7], d.qpos[jq] = p_s[k], quat_s[k], q_s[k]

    shapes = _contact_shapes(m, m.body(robot.root_link).id)
    bodies = sorted({b for b, _ in shapes if b not in feet}) + list(feet)
    foot_z = np.zeros((T, len(feet)))
    foot_up = np.ones((T, len(feet)))  # z of each foot's up axis: 1 flat
    low_z = np.full((T, len(bodies)), np.inf)
    low_point = np.zeros((T, len(bodies), 3))
    for k in range(T):
        pose(k)
        mujoco.mj_kinematics(m, d)
        foot_z[k] = [d.xpos[b][2] for b in feet]
        foot_up[k] = [d.xmat[b][8] for b in feet]
        for b, g in shapes:
            point = _lowest_point(m, d, g)
            i = bodies.index(b)
            if point[2] < low_z[k, i]:
                low_z[k, i], low_point[k, i] = point[2], point
    # A foot stands on the ground (a wrench: it can tilt the body) when it is near the lowest
    # the feet get, flat, and its sole near the ground; a foot on its heel or toes pushes at
    # one point, like the other links.
    contacts = (
        (foot_z < foot_z.min() + config.contact_height_m)
        & (foot_up > math.cos(config.flat_foot_tilt_rad))
        & (low_z[:, -len(feet) :] < config.sole_height_m)
    )
    # Links other than the feet on the ground: the robot lies, kneels or sits, and a foot
    # that touches without standing flat (toes tucked) pushes at its lowest point too.
    touching = low_z < config.body_contact_height_m
    others = touching[:, : -len(feet)].any(axis=1)
    touching[:, -len(feet) :] &= others[:, None] & ~contacts

    kp, kd, limit = motors.kp_nm_rad, motors.kd_nm_s_rad, motors.max_torque_nm
    torques = np.zeros_like(q)
    residual = np.zeros(T)
    jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    weights = np.r_[np.ones(3), np.full(3, config.moment_weight)]
    for k in range(T):
        pose(k)
        d.qvel[:] = 0.0
        d.qacc[:] = 0.0
        d.qvel[rv : rv + 3], d.qvel[rv + 3 : rv + 6], d.qvel[jv] = dp[k], omega[k], dq[k]
        d.qacc[rv : rv + 3], d.qacc[rv + 3 : rv + 6], d.qacc[jv] = ddp[k], domega[k], ddq[k]
        mujoco.mj_inverse(m, d)
        force = d.qfrc_inverse.copy()
        columns = []
        for i, body in enumerate(feet):
            if contacts[k, i]:
                mujoco.mj_jacBody(m, d, jacp, jacr, body)
                columns.append(np.vstack([jacp, jacr]).T)  # generalised force of a wrench
        points = []
        for i, body in enumerate(bodies):
            if touching[k, i]:
                mujoco.mj_jac(m, d, jacp, None, low_point[k, i], body)
                points.append(jacp.T.copy())  # generalised force of a force at the point
        if points and config.friction is not None:
            touching[k], force = _share_load_cone(
                force, base, columns, points, weights, touching[k], d.qvel, config
            )
        elif points:
            touching[k], force = _share_load(force, base, columns, points, weights, touching[k])
        elif columns:
            jac = np.hstack(columns)
            a = jac[base]
            w_inv = 1.0 / np.tile(weights, len(columns))
            wrench = w_inv * (a.T @ np.linalg.solve((a * w_inv) @ a.T, force[base]))
            force -= jac @ wrench
        residual[k] = np.abs(force[base]).max()
        torques[k] = force[jv]
    # Saturation: a joint at a stop is held there by the stop as far as the stop can push
    # (back into the range); the motor gives only the torque toward the stop, which then puts
    # the reference beyond it.
    lower = np.array([j.lower_rad for j in robot.joints])
    upper = np.array([j.upper_rad for j in robot.joints])
    at_upper = q > upper - config.stop_margin_rad
    at_lower = q < lower + config.stop_margin_rad
    torques = np.where(at_upper, np.maximum(torques, 0.0), torques)
    torques = np.where(at_lower, np.minimum(torques, 0.0), torques)
    needed = torques.copy()
    torques = np.clip(torques, -limit, limit)
    # The observed angle itself, not its smoothed value: the fit is there for the derivatives,
    # and a smoothed angle cuts a kick's strike short (see "Measured" above).
    references = q + (torques + kd * dq) / kp
    if config.saturation_share is not None:
        saturated = np.abs(needed) >= config.saturation_share * limit
        references = _saturation_envelope(references, needed, saturated)
    names = tuple(m.body(b).name for b in bodies)
    return PdCompensation(
        references, torques, contacts, residual, touching, names, at_upper | at_lower
    )


def _saturation_envelope(
    references: np.ndarray, torques: np.ndarray, saturated: np.ndarray
) -> np.ndarray:
    """``references`` (T, N) with each saturated push replaced by its look-ahead envelope.

    A push is a run of samples whose ``torques`` (T, N) keep one sign; where it has samples
    ``saturated`` (T, N, bool), from its first to its last such sample each reference becomes
    the farthest (in the push's direction) from there to that last sample."""
    out = references.copy()
    sign = np.sign(torques)
    for j in range(references.shape[1]):
        k = 0
        while k < len(sign):
            end = k
            while end + 1 < len(sign) and sign[end + 1, j] == sign[k, j]:
                end += 1
            hits = k + np.nonzero(saturated[k : end + 1, j])[0]
            if sign[k, j] != 0 and len(hits):
                lo, hi = hits[0], hits[-1] + 1
                run = sign[k, j] * references[lo:hi, j]
                out[lo:hi, j] = sign[k, j] * np.maximum.accumulate(run[::-1])[::-1]
            k = end + 1
    return out


def _contact_shapes(m, root_body: int) -> list[tuple[int, int]]:
    """(body, geom) of every collision shape of the robot rooted at ``root_body``."""
    root = m.body_rootid[root_body]
    return [
        (int(m.geom_bodyid[g]), g)
        for g in range(m.ngeom)
        if m.body_rootid[m.geom_bodyid[g]] == root and (m.geom_contype[g] or m.geom_conaffinity[g])
    ]


def _lowest_point(m, d, g: int) -> np.ndarray:
    """(3,) the lowest point of geom ``g`` in the field frame [m]: exact for spheres and
    capsules, a corner of its bounding box otherwise."""
    rot = d.geom_xmat[g].reshape(3, 3)
    centre = d.geom_xpos[g]
    if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE:
        return centre - np.array([0.0, 0.0, m.geom_size[g][0]])
    if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE:
        axis = rot[:, 2] * m.geom_size[g][1]
        end = centre - axis if axis[2] > 0 else centre + axis
        return end - np.array([0.0, 0.0, m.geom_size[g][0]])
    half = m.geom_aabb[g][3:]
    centre = centre + rot @ m.geom_aabb[g][:3]
    return centre - rot @ (np.sign(rot[2]) * half)


def _share_load_cone(force, base, columns, points, weights, touching, qvel, config):
    """As ``_share_load``, each point force in its friction cone: a nonnegative sum of the
    cone's edges (a pyramid of four), or where the point slides, of the one edge that opposes
    the sliding (kinetic friction); the feet's wrenches free. The split is the nonnegative
    least-squares fit of the floating-base rows with a small cost on every force (the
    smallest forces that hold the body). Returns (the links that push, the force left)."""
    mu = config.friction
    square = [
        np.array([1.0, 0.0]),
        np.array([0.0, 1.0]),
        np.array([-1.0, 0.0]),
        np.array([0.0, -1.0]),
    ]
    blocks, owner = [], []
    for col in columns:  # a foot's wrench: each component either sign
        blocks += [col, -col]
        owner += [-1] * (2 * col.shape[1])
    for i, jac in enumerate(points):
        slide = (jac.T @ qvel)[:2]
        speed = float(np.linalg.norm(slide))
        edges = [-slide / speed] if speed > config.slide_m_s else square
        for e in edges:
            blocks.append((jac @ np.array([mu * e[0], mu * e[1], 1.0]))[:, None])
            owner.append(i)
    gen = np.hstack(blocks)  # (nv, edges): generalised force of each edge
    cost = np.ones(gen.shape[1])
    cost[: 2 * 6 * len(columns)] = np.tile(np.sqrt(weights), 2 * len(columns))
    reg = 1e-3
    a = np.vstack([gen[base], reg * np.diag(cost)])
    b = np.r_[force[base], np.zeros(gen.shape[1])]
    lam = _nnls(a, b)
    owner = np.array(owner)
    where = np.nonzero(touching)[0]
    pushing = np.array([lam[owner == i].sum() > 1e-6 for i in range(len(points))], bool)
    touching = touching.copy()
    touching[:] = False
    touching[where[pushing]] = True
    return touching, force - gen @ lam


def _nnls(a: np.ndarray, b: np.ndarray, max_iter: int = 500) -> np.ndarray:
    """x >= 0 minimising |a x - b| (Lawson and Hanson's active set method)."""
    n = a.shape[1]
    x = np.zeros(n)
    free = np.zeros(n, bool)
    for _ in range(max_iter):
        grad = a.T @ (b - a @ x)
        if free.all() or grad[~free].max(initial=-np.inf) <= 1e-10 * (1 + np.abs(grad).max()):
            break
        free[np.argmax(np.where(free, -np.inf, grad))] = True
        while True:
            z = np.zeros(n)
            z[free] = np.linalg.lstsq(a[:, free], b, rcond=None)[0]
            if (z[free] > 0).all():
                x = z
                break
            neg = free & (z <= 0)
            alpha = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + alpha * (z - x)
            free &= x > 1e-12
            x[~free] = 0.0
    return x


def _share_load(force, base, columns, points, weights, touching, max_rounds: int = 8):
    """The ground's share of ``force`` (generalised, (nv,)) under the feet's wrenches
    (``columns``) and the other links' point forces (``points``, one (nv, 3) Jacobian each
    for the links ``touching``): the least-squares split (a foot moment costs ``weights`` as
    in ``pd_references``, a point force as much as a foot's), links that would pull on the
    ground dropped one at a time. Returns (the links that push, the force left)."""
    touching = touching.copy()
    where = np.nonzero(touching)[0]
    active = list(range(len(points)))
    while True:
        blocks = columns + [points[i] for i in active]
        if not blocks:
            touching[:] = False
            return touching, force
        jac = np.hstack(blocks)
        a = jac[base]
        w_inv = 1.0 / np.r_[np.tile(weights, len(columns)), np.ones(3 * len(active))]
        wrench = w_inv * (a.T @ np.linalg.lstsq((a * w_inv) @ a.T, force[base], rcond=1e-9)[0])
        pushes = wrench[6 * len(columns) :].reshape(-1, 3)[:, 2]
        if not active or pushes.min() >= 0 or max_rounds == 0:
            break
        active.pop(int(np.argmin(pushes)))
        max_rounds -= 1
    touching[:] = False
    touching[where[active]] = True
    return touching, force - jac @ wrench
