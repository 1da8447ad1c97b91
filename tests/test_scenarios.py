"""The scenario tasks: registry, configs, scenes and outcomes (the physical outcomes are
asserted through their callers: tests/test_motions.py, tests/test_other_team*.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mimic.agents.hold import HoldPose
from mimic.errors import MimicError
from mimic.tasks import kick_from_stand, stand
from mimic.tasks.kick_from_stand import After, KickFromStandConfig, KickFromStandOutcome, Standing
from mimic.tasks.scenarios import SCENARIOS, get_scenario
from mimic.tasks.straight_walk import StraightWalkConfig
from mimic.world.mujoco_world import MujocoWorld


def test_every_scenario_is_registered_by_name_with_a_default_config():
    assert set(SCENARIOS) == {"kick-from-stand", "stand", "straight-walk"}
    for name, scenario in SCENARIOS.items():
        assert scenario.name == name and get_scenario(name) is scenario
        scenario.config()  # the defaults are a valid config


def test_an_unknown_scenario_names_the_known_ones():
    with pytest.raises(MimicError, match="kick-from-stand"):
        get_scenario("penalty")


def test_configs_check_their_fields():
    assert KickFromStandConfig(after="stand", standing="never-fell").after is After.STAND
    with pytest.raises(MimicError, match="settle_s"):
        KickFromStandConfig(settle_s=-0.1)
    with pytest.raises(ValueError):
        KickFromStandConfig(after="sit")
    with pytest.raises(MimicError, match="distance_m"):
        StraightWalkConfig(distance_m=0.0)


def test_the_kick_scene_puts_the_robot_behind_the_ball_or_where_told():
    config = KickFromStandConfig(ball_start_m=(-8.0, 1.0))
    assert kick_from_stand.scene(config, (0.25, -0.05)).robot_xy_m == (-8.25, 1.05)
    told = KickFromStandConfig(robot_xy_m=(0.0, 0.0))
    assert kick_from_stand.scene(told, (0.25, -0.05)).robot_xy_m == (0.0, 0.0)


def test_the_outcome_measures_the_ball_in_the_robots_heading():
    left = KickFromStandOutcome((1.0, 1.0, 0.05), (1.0, 3.0, 0.05), math.pi / 2, True, 0, "done")
    assert left.distance_m == pytest.approx(2.0)
    assert left.forward_m == pytest.approx(2.0) and left.lateral_m == pytest.approx(0.0)
    assert left.direction_error_rad == pytest.approx(0.0)
    np.testing.assert_allclose(left.moved_xy_m, [0.0, 2.0])
    short = KickFromStandOutcome((0, 0, 0), (0.01, 0, 0), 0.0, False, 1, "fell")
    assert math.isnan(short.direction_error_rad)


def test_a_kick_needs_a_ball_offset():
    world = MujocoWorld()
    with pytest.raises(MimicError, match="not a kick"):
        kick_from_stand.play(world, HoldPose(world.robot.stand_pose()), 0)


def test_the_nao_stands_and_standing_has_the_configured_meaning():
    world = MujocoWorld()
    assert stand.play(world, None, 0, stand.StandConfig(duration_s=1.0)).stood
    assert Standing("upright") is Standing.UPRIGHT
