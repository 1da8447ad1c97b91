"""Our walk engine in the real world: forward speed, sideways, turning, stop, go-to-pose."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mimic.agents.walk import WalkEngine, make_walk_agent
from mimic.agents.walk.goto import GoToPose, pose_behind_ball, wrap_angle
from mimic.checks.ball_approach import approach_starts, walk_behind_ball
from mimic.robot.nao import nao
from mimic.world.base import World
from mimic.world.mujoco_world import MujocoWorld


@pytest.fixture(scope="module")
def world() -> World:
    return MujocoWorld()


def _start(world: World, x: float = -15.0, y: float = 0.0, yaw: float = 0.0) -> None:
    world.reset()
    world.place_robot(x, y, yaw, nao().stand_pose())


def _run(world: World, agent, seconds: float, reset: bool = True) -> bool:
    """Run; True if the robot never fell."""
    if reset:
        agent.reset(world.observe())
    for _ in range(int(seconds / 0.02)):
        world.step(agent.act(world.observe()))
        if world.fallen():
            return False
    return True


def test_forward_walk_reaches_target_speed(world: World) -> None:
    _start(world)
    agent = make_walk_agent()
    assert _run(world, agent, 3.0), "fell while starting"
    x0, t0 = world.torso_pos_m()[0], world.time_s
    assert _run(world, agent, 6.0, reset=False), "fell while walking"
    speed = (world.torso_pos_m()[0] - x0) / (world.time_s - t0)
    assert speed >= 0.4, f"forward speed {speed:.3f} m/s"


def _walk_forward(world: World, distance_m: float, timeout_s: float) -> tuple[bool, float, float]:
    """Walk from the goal line; (never fell, average speed incl. the start [m/s], |y| [m])."""
    _start(world)
    agent = make_walk_agent()
    agent.reset(world.observe())
    while world.torso_pos_m()[0] < -15.0 + distance_m and world.time_s < timeout_s:
        world.step(agent.act(world.observe()))
        if world.fallen():
            return False, 0.0, 0.0
    p = world.torso_pos_m()
    return True, (p[0] + 15.0) / world.time_s, abs(p[1])


def test_walks_5_m_at_walking_speed(world: World) -> None:
    upright, speed, drift = _walk_forward(world, 5.0, 20.0)
    assert upright, "fell"
    assert speed >= 0.4, f"average speed {speed:.3f} m/s over 5 m (incl. the start)"
    assert drift < 0.3, f"lateral drift {drift:.2f} m"


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(5))
def test_walks_15_m_from_jittered_starts(world: World, seed: int) -> None:
    rng = np.random.default_rng(seed)
    world.reset()
    world.place_robot(
        -15.0 + rng.uniform(-0.01, 0.01),
        rng.uniform(-0.01, 0.01),
        math.radians(rng.uniform(-2, 2)),
        nao().stand_pose() + rng.normal(0, 0.01, nao().num_joints),
    )
    agent = make_walk_agent()
    agent.reset(world.observe())
    (x0, y0, _), yaw0 = world.torso_pos_m(), world.torso_yaw_rad()
    while world.torso_pos_m()[0] < 0.0 and world.time_s < 60.0:
        world.step(agent.act(world.observe()))
        assert not world.fallen()
    p = world.torso_pos_m()
    assert (p[0] + 15.0) / world.time_s >= 0.4
    # Drift: sideways from the line the robot faced at the start (the line it holds).
    drift = -math.sin(yaw0) * (p[0] - x0) + math.cos(yaw0) * (p[1] - y0)
    assert abs(drift) < 0.5, f"drift {drift:.2f} m"


def test_sideways_walk_moves_left(world: World) -> None:
    _start(world)
    agent = WalkEngine()
    agent.set_velocity(0.0, 0.1, 0.0)
    assert _run(world, agent, 6.0)
    assert world.torso_pos_m()[1] > 0.2
    assert abs(world.torso_pos_m()[0] + 15.0) < 0.3


def test_turning_in_place(world: World) -> None:
    _start(world)
    agent = WalkEngine()
    agent.set_velocity(0.0, 0.0, 0.6)
    agent.reset(world.observe())
    turned, last = 0.0, world.torso_yaw_rad()
    for _ in range(int(4.0 / 0.02)):
        world.step(agent.act(world.observe()))
        assert not world.fallen()
        yaw = world.torso_yaw_rad()
        turned += wrap_angle(yaw - last)
        last = yaw
    assert turned > math.radians(45)
    assert np.hypot(*(world.torso_pos_m()[:2] - (-15.0, 0.0))) < 0.3


@pytest.mark.parametrize("speed_m_s", [0.3, 0.45])
def test_stop_comes_to_rest_in_the_stand_pose(world: World, speed_m_s: float) -> None:
    _start(world)
    agent = make_walk_agent(speed_m_s)
    assert _run(world, agent, 2.5)
    agent.stop()
    assert _run(world, agent, 2.5, reset=False)
    assert agent.state == "standing" and agent.done
    obs = world.observe()
    assert np.abs(obs.joint_speeds_rad_s).max() < 0.3
    assert np.abs(obs.joint_angles_rad - nao().stand_pose()).max() < math.radians(6)
    assert world.upright()


def test_pose_behind_ball_puts_ball_at_offset() -> None:
    x, y, h = pose_behind_ball((1.0, 0.5), (15.0, 0.0), (0.15, -0.055))
    c, s = math.cos(h), math.sin(h)
    bx, by = 1.0 - x, 0.5 - y
    assert abs(c * bx + s * by - 0.15) < 1e-12 and abs(-s * bx + c * by + 0.055) < 1e-12
    assert abs(h - math.atan2(-0.5, 14.0)) < 1e-12


def test_go_to_pose_arrives(world: World) -> None:
    _start(world, -12.0, 0.0, 0.0)
    goto = GoToPose(WalkEngine())
    target = (-11.0, 0.3, math.radians(30))
    goto.set_target(*target)
    goto.reset(world.observe())
    for _ in range(int(25 / 0.02)):
        world.step(goto.act(world.observe()))
        assert not world.fallen()
        if goto.arrived:
            break
    assert goto.arrived
    p = world.torso_pos_m()
    assert np.hypot(p[0] - target[0], p[1] - target[1]) < 0.05
    assert abs(wrap_angle(world.torso_yaw_rad() - target[2])) < math.radians(8)


def test_go_to_pose_behind_the_ball_leaves_it_in_place(world: World) -> None:
    """The kick trial's use: end behind the ball facing the goal with the ball where the kick
    wants it, without walking into it. The walk is chaotic (another CPU's last digits change
    which step lands where) and touches the ball from about half of all starts (measured:
    ``python benchmarks/goto_ball.py --near 20 --around 20``), so this is a rate over 30
    starts, 20 just ahead of the ball facing away and 10 from anywhere 0.4-1.0 m from it: at
    least a third succeed (15 of 30 here), and at most one falls."""
    results = [
        walk_behind_ball(world, ball, start)
        for ball, start in approach_starts(np.random.default_rng(1), near=20, around=10)
    ]
    assert sum(r.fell for r in results) <= 1, results
    assert sum(r.ok for r in results) >= 10, [r for r in results if not r.ok]
