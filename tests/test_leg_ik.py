"""Leg IK: our forward kinematics matches MuJoCo; IK inverts it; unreachable targets clamp."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from mimic.robot.leg_ik import (
    leg_fk,
    leg_geometry,
    leg_ik,
    leg_ik_floats,
    leg_joint_indices,
    rpy_matrix,
    sole_to_ankle,
)
from mimic.world.base import World
from mimic.world.mujoco_world import MujocoWorld

SIDES = ("left", "right")


@pytest.fixture(scope="module")
def world() -> World:
    return MujocoWorld()


def _angles_in_limits(side: str, u: list[float]) -> np.ndarray:
    g = leg_geometry(side)
    return g.lower_rad + np.asarray(u) * (g.upper_rad - g.lower_rad)


@pytest.mark.parametrize("side", SIDES)
def test_fk_matches_mujoco_bodies(world: World, side: str) -> None:
    rng = np.random.default_rng(7)
    m, d = world.model, world.data
    foot = m.body(f"{side}_foot").id
    for _ in range(20):
        q = _angles_in_limits(side, rng.uniform(0, 1, 6))
        d.qpos[:] = 0.0
        d.qpos[3] = 1.0  # torso at the origin, identity orientation (qpos 0..6 = root)
        full = np.zeros(world.robot.num_joints)
        full[leg_joint_indices(side)] = q
        d.qpos[world.qpos_idx] = full
        mujoco.mj_kinematics(m, d)
        p, r = leg_fk(side, q)
        np.testing.assert_allclose(p, d.xpos[foot], atol=1e-9)
        np.testing.assert_allclose(r, d.xmat[foot].reshape(3, 3), atol=1e-9)


def test_stand_pose_foot_is_flat_under_the_hip() -> None:
    q = np.radians([0, 0, 19, -40, 21, 0])
    p, r = leg_fk("left", q)
    np.testing.assert_allclose(r, np.eye(3), atol=1e-12)
    assert abs(p[1] - leg_geometry("left").hip[1]) < 1e-12
    assert -0.33 < p[2] < -0.32


# Reachable workspace: random angles well inside the stops, away from the straight knee, and
# with the hip no more than 60 deg off the foot's vertical (seen from the foot, a leg lying
# along the sole leaves the ankle roll undefined: the roll singularity of this chain).
@settings(max_examples=300, deadline=None)
@given(
    side=st.sampled_from(SIDES),
    u=st.lists(st.floats(0.02, 0.98), min_size=6, max_size=6),
    knee=st.floats(-2.0, -0.15),
)
def test_ik_inverts_fk(side: str, u: list[float], knee: float) -> None:
    q = _angles_in_limits(side, u)
    q[3] = knee
    p, r = leg_fk(side, q)
    up = r.T @ (leg_geometry(side).hip - p)
    assume(up[2] > 0.5 * np.linalg.norm(up))
    q2 = leg_ik(side, p, r, clip_to_limits=False)
    p2, r2 = leg_fk(side, q2)
    assert np.abs(p2 - p).max() < 1e-3
    # Rotation error angle.
    cos = (np.trace(r2.T @ r) - 1) / 2
    assert math.acos(max(-1.0, min(1.0, cos))) < 0.01


@settings(max_examples=200, deadline=None)
@given(
    side=st.sampled_from(SIDES),
    pos=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
    rpy=st.lists(st.floats(-math.pi, math.pi), min_size=3, max_size=3),
)
def test_any_target_gives_finite_angles_within_limits(side, pos, rpy) -> None:
    q = leg_ik(side, np.array(pos), rpy_matrix(*rpy))
    g = leg_geometry(side)
    assert np.all(np.isfinite(q))
    assert np.all(q >= g.lower_rad - 1e-12) and np.all(q <= g.upper_rad + 1e-12)


def test_out_of_reach_target_is_clamped_toward_it() -> None:
    g = leg_geometry("left")
    q = leg_ik("left", g.hip + np.array([0.0, 0.0, -1.0]))  # far below the hip
    p, _ = leg_fk("left", q)
    assert p[2] < g.hip[2] - 0.21  # leg (almost) straight, pointing down
    assert abs(p[0] - g.hip[0]) < 0.02


def test_sole_target_round_trip() -> None:
    r = rpy_matrix(0.05, -0.1, 0.2)
    sole = np.array([0.02, 0.06, -0.36])
    ankle = sole_to_ankle("left", sole, r)
    q = leg_ik("left", ankle, r)
    p, r2 = leg_fk("left", q)
    np.testing.assert_allclose(p + r2 @ leg_geometry("left").sole, sole, atol=1e-3)


@pytest.mark.parametrize("side", SIDES)
def test_the_float_path_gives_leg_ik_bit_for_bit(side: str) -> None:
    """The walk engine's ``leg_ik_floats`` is ``leg_ik`` on plain floats: the same numbers,
    to the last bit (a walk's trial tables must not change with it)."""
    rng = np.random.default_rng(3)
    for k in range(300):
        pos = np.array([0.0, 0.05 if side == "left" else -0.05, -0.28]) + rng.normal(0, 0.08, 3)
        rot = rpy_matrix(*rng.normal(0, 0.3, 3))
        passes = 1 + k % 3
        q = leg_ik(side, pos, rot, passes=passes)
        q_floats = leg_ik_floats(side, pos.tolist(), rot.tolist(), passes=passes)
        assert np.array(q_floats).tobytes() == q.tobytes()


def _solve_every_pass_in_full(side: str, ankle, rot, passes: int) -> list[float]:
    """The solver as first written: each pass solves all six angles, the next pass's anchor
    placed by the last roll angle (the reference for the solver that solves only the roll
    angle of a pass before the last)."""
    g = leg_geometry(side)
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rot
    hx, hy, hz = g.hip_f
    ax, az = g.ankle_f[0], g.ankle_f[2]
    tx, ty, tz = ankle
    q = [0.0] * 6
    for _ in range(passes):
        c6, s6 = math.cos(q[5]), math.sin(q[5])
        ox, oy, oz = ax, s6 * az, c6 * az
        apx = tx - (r00 * ox + r01 * oy + r02 * oz)
        apy = ty - (r10 * ox + r11 * oy + r12 * oz)
        apz = tz - (r20 * ox + r21 * oy + r22 * oz)
        vx, vy, vz = apx - hx, apy - hy, apz - hz
        rx = r00 * vx + r10 * vy + r20 * vz
        ry = r01 * vx + r11 * vy + r21 * vz
        rz = r02 * vx + r12 * vy + r22 * vz
        q6 = math.atan2(-ry, -rz)
        dist = min(max(math.sqrt(vx * vx + vy * vy + vz * vz), g.reach_min_m), g.reach_max_m)
        c = (g.l_squares - dist * dist) / g.l_twice_product
        q4 = _wrap(g.knee_offset_rad - (math.pi - math.acos(max(-1.0, min(1.0, c)))))
        c6, s6 = math.cos(q6), math.sin(q6)
        px, pz = rx, s6 * ry + c6 * rz
        (thx, _, thz), (shx, _, shz) = g.thigh_f, g.shank_f
        c4, s4 = math.cos(q4), math.sin(q4)
        mx = c4 * thx + s4 * thz + shx
        mz = -s4 * thx + c4 * thz + shz
        q5 = _wrap(math.atan2(px, pz) - math.atan2(mx, mz))
        a = q4 + q5
        ca, sa = math.cos(a), math.sin(a)
        b0x, b0y, b0z = ca, -s6 * sa, -c6 * sa
        b1x, b1y, b1z = 0.0, c6, -s6
        b2x, b2y, b2z = sa, s6 * ca, c6 * ca
        rot0_b1 = r00 * b1x + r01 * b1y + r02 * b1z
        rot1_b0 = r10 * b0x + r11 * b0y + r12 * b0z
        rot1_b1 = r10 * b1x + r11 * b1y + r12 * b1z
        rot1_b2 = r10 * b2x + r11 * b2y + r12 * b2z
        rot2_b0 = r20 * b0x + r21 * b0y + r22 * b0z
        rot2_b1 = r20 * b1x + r21 * b1y + r22 * b1z
        rot2_b2 = r20 * b2x + r21 * b2y + r22 * b2z
        cs, ss = g.cos_sigma, g.sin_sigma
        m11 = cs * rot1_b1 + ss * rot2_b1
        m20 = -ss * rot1_b0 + cs * rot2_b0
        m21 = -ss * rot1_b1 + cs * rot2_b1
        m22 = -ss * rot1_b2 + cs * rot2_b2
        phi = math.asin(max(-1.0, min(1.0, m21)))
        theta, psi = math.atan2(-m20, m22), math.atan2(-rot0_b1, m11)
        q = [g.hyp_sign * psi, phi + g.sigma_rad, -theta, q4, q5, q6]
    return [min(max(a, lo), hi) for a, lo, hi in zip(q, g.lower_f, g.upper_f)]


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize("side", SIDES)
def test_solving_only_the_roll_of_early_passes_changes_no_bit(side: str) -> None:
    """A pass before the last only places the next anchor: solving just its roll angle gives
    the numbers of solving every pass in full (the walk's trial tables depend on it), also
    far out of reach and with the foot turned hard."""
    rng = np.random.default_rng(11)
    for k in range(600):
        spread = (0.08, 0.3)[k % 2]
        pos = np.array([0.0, 0.05 if side == "left" else -0.05, -0.28]) + rng.normal(0, spread, 3)
        rot = rpy_matrix(*rng.normal(0, (0.3, 2.0)[k % 3 == 0], 3)).tolist()
        passes = 1 + k % 3
        expected = _solve_every_pass_in_full(side, pos.tolist(), rot, passes)
        got = leg_ik_floats(side, pos.tolist(), rot, passes)
        assert np.array(got).tobytes() == np.array(expected).tobytes()
