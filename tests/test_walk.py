"""Our walk engine in the real world: forward speed, sideways, turning, stop, go-to-pose."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mimic.agents.walk import WalkEngine, make_walk_agent, stand_pose_rad
from mimic.agents.walk.goto import GoToPose, pose_behind_ball, wrap_angle
from mimic.world.world import World


@pytest.fixture(scope="module")
def world() -> World:
    return World()


def _start(world: World, x: float = -15.0, y: float = 0.0, yaw: float = 0.0) -> None:
    world.reset()
    world.beam(x, y, yaw, stand_pose_rad())


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


@pytest.mark.xfail(strict=True, reason="known gap (issue 4): the walk still falls within a few "
                   "seconds at 0.3 m/s, before stop() takes effect")
def test_stop_comes_to_rest_in_the_stand_pose(world: World) -> None:
    _start(world)
    agent = make_walk_agent(0.3)
    assert _run(world, agent, 2.5)
    agent.stop()
    assert _run(world, agent, 2.5, reset=False)
    assert agent.state == "standing" and agent.done
    obs = world.observe()
    assert np.abs(obs.joint_speeds_rad_s).max() < 0.3
    assert np.abs(obs.joint_angles_rad - stand_pose_rad()).max() < math.radians(6)
    assert world.upright()


def test_pose_behind_ball_puts_ball_at_offset() -> None:
    x, y, h = pose_behind_ball((1.0, 0.5), (15.0, 0.0), (0.15, -0.055))
    c, s = math.cos(h), math.sin(h)
    bx, by = 1.0 - x, 0.5 - y
    assert abs(c * bx + s * by - 0.15) < 1e-12 and abs(-s * bx + c * by + 0.055) < 1e-12
    assert abs(h - math.atan2(-0.5, 14.0)) < 1e-12


@pytest.mark.xfail(strict=True, reason="known gap (issue 4): the walk under go-to-pose falls "
                   "before it arrives")
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
