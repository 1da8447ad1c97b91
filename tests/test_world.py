"""The world: standing still, the ball rolling to a stop, events."""

import pytest

from mimic.agents.keyframe_player import KeyframePlayer
from mimic.episode import run
from mimic.motion.files import load_motion
from mimic.robot.actuators import JointCommand
from mimic.world import field as F
from mimic.world.base import CYCLE_S
from mimic.world.mujoco_world import MujocoWorld


@pytest.fixture()
def world():
    w = MujocoWorld()
    w.reset()
    return w


def test_cycle_is_whole_number_of_physics_steps(world):
    assert world.substeps * world.model.opt.timestep == pytest.approx(CYCLE_S)


def test_kicked_ball_rolls_and_stops_between_5_and_20_m(world):
    world.place_robot(-5.0, 5.0)
    world.place_ball(0.0, 0.0)
    ball_v = world.model.jnt_dofadr[world.model.joint("ball").id]
    world.data.qvel[ball_v] = 3.0
    world.data.qvel[ball_v + 4] = 3.0 / F.BALL_RADIUS_M  # rolling, not sliding
    for _ in range(int(20 / CYCLE_S)):
        world.step(JointCommand.speeds(world.robot.zeros()))
        if world.ball_speed_m_s() < 0.005:
            break
    assert world.ball_speed_m_s() < 0.005, "ball still rolling after 20 s"
    assert 5.0 <= world.ball_pos_m()[0] <= 20.0


def test_stand_motion_stands_for_60_s(world):
    world.place_robot(0.0, 0.0)
    world.place_ball(3.0, 0.0)
    run(world, KeyframePlayer(load_motion("stand")), max_s=60.0, stop_when_done=False)
    assert not world.fallen()
    assert world.upright()


def test_lying_robot_is_detected_as_fallen(world):
    world.place_robot(1.0, 1.0, 0.3, posture="lying_front")
    for _ in range(25):
        world.step(JointCommand.speeds(world.robot.zeros()))
    assert world.fallen() and not world.upright()


def test_beam_places_robot_and_heading(world):
    world.place_robot(-3.0, 2.0, 1.0)
    assert world.torso_pos_m()[:2] == pytest.approx([-3.0, 2.0])
    assert world.torso_yaw_rad() == pytest.approx(1.0)


def test_goal_and_ball_out(world):
    world.place_robot(0.0, 5.0)
    world.place_ball(F.OPPONENT_GOAL_X_M + 0.3, 0.0)
    assert world.goal_scored() and not world.ball_out()
    world.place_ball(0.0, F.FIELD_WIDTH_M / 2 + 0.1)
    assert world.ball_out() and not world.goal_scored()
    world.place_ball(F.OPPONENT_GOAL_X_M + 0.3, 3.0)
    assert world.ball_out()
