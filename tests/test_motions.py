"""Our own team's keyframe motions: the files parse, and in the simulator they do their job."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from mimic.checks.motions import run_getup, run_kick, run_stand
from mimic.errors import MotionFileError
from mimic.motion.files import format_motion, list_motions, load_motion, parse_motion
from mimic.robot.joints import lower_limits_rad, mirror_angles, upper_limits_rad
from mimic.robot.nao import nao

#: Kick target: ball at least this far forward, robot standing 2 s after the motion [m].
KICK_TARGET_M = 3.0


def test_stand_holds_for_60_s():
    assert run_stand(60.0)


@pytest.mark.parametrize("name", list_motions())
def test_every_shipped_motion_parses_within_joint_limits(name):
    movement = load_motion(name)
    assert movement.name == name
    assert movement.duration_s > 0
    tolerance_rad = 1e-6
    for step in movement.steps:
        assert np.all(step.angles_rad >= lower_limits_rad() - tolerance_rad), name
        assert np.all(step.angles_rad <= upper_limits_rad() + tolerance_rad), name


@pytest.mark.parametrize("name", list_motions())
def test_format_then_parse_gives_the_same_motion(name):
    movement = load_motion(name)
    assert parse_motion(format_motion(movement), f"{name}.txt") == movement


def test_round_trip_keeps_a_ball_offset_and_a_speed_rate():
    movement = dataclasses.replace(
        load_motion("stand"), ball_offset_m=(0.18, -0.055), speed_rate=1.25
    )
    back = parse_motion(format_motion(movement))
    assert back == movement
    assert back != dataclasses.replace(movement, ball_offset_m=(0.18, 0.055))


def test_kick_left_is_the_mirror_of_kick_right():
    right, left = load_motion("kick_right"), load_motion("kick_left")
    assert left.ball_offset_m == (right.ball_offset_m[0], -right.ball_offset_m[1])
    for r, mirrored in zip(right.steps, left.steps, strict=True):
        assert r.time_s == mirrored.time_s
        np.testing.assert_allclose(mirrored.angles_rad, mirror_angles(r.angles_rad))


@pytest.mark.parametrize(
    "text, line, words",
    [
        ("motion x\nstep 0.5\nleft_knee_pich -40\n", 3, "unknown joint"),
        ("motion x\nstep 0.5\nleft_knee_pitch forty\n", 3, "needs a number"),
        ("motion x\nspeed_rate 1\n", None, "no 'step'"),
        ("motion x\nball_offset 0.2\nstep 0.5\n", 2, "cannot read"),
        ("motion x\nstep -1\n", 2, "step time"),
    ],
)
def test_bad_motion_files_name_the_file_and_line(text, line, words):
    with pytest.raises(MotionFileError) as err:
        parse_motion(text, "bad.txt")
    message = str(err.value)
    assert message.startswith(f"bad.txt:{line}:" if line else "bad.txt:")
    assert words in message


def _assert_good_kick(name, seed):
    outcome = run_kick(load_motion(name), seed)
    assert outcome.forward_m >= KICK_TARGET_M, outcome
    assert abs(outcome.direction_error_rad) < math.radians(30), outcome
    assert outcome.standing_after, outcome


@pytest.mark.parametrize("name, seed", [("kick_right", 1), ("kick_right", 2), ("kick_left", 3)])
def test_kick_moves_the_ball_forward_along_the_heading(name, seed):
    outcome = run_kick(load_motion(name), seed)
    assert outcome.forward_m >= 1.0, outcome
    assert abs(outcome.direction_error_rad) < math.radians(15), outcome


@pytest.mark.parametrize("seed", [0, 1])
def test_kick_right_sends_the_ball_3_m_and_stays_standing(seed):
    _assert_good_kick("kick_right", seed)


def test_kick_left_sends_the_ball_3_m_and_stays_standing():
    _assert_good_kick("kick_left", 2)


def test_a_kick_without_ball_offset_is_refused():
    with pytest.raises(MotionFileError, match="ball_offset"):
        run_kick(load_motion("stand"), 0)


@pytest.mark.parametrize("side", ["front", "back"])
@pytest.mark.parametrize("seed", [0, 1])
def test_getup_stands_the_robot_up(side, seed):
    movement = load_motion(f"getup_{side}")
    outcome = run_getup(movement, side, seed)
    assert outcome.upright, outcome
    assert outcome.time_to_upright_s <= movement.duration_s + 1.0


@pytest.mark.parametrize("side", ["front", "back"])
def test_getup_ends_in_the_stand_pose(side):
    # So that ``stand`` or a walk can take over from the last keyframe.
    last = load_motion(f"getup_{side}").steps[-1].angles_rad
    np.testing.assert_allclose(last, nao().stand_pose(), rtol=0.0, atol=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["kick_right", "kick_left"])
def test_kick_rate_is_at_least_9_in_10(name):
    movement = load_motion(name)
    outcomes = [run_kick(movement, seed) for seed in range(10)]
    good = [o.forward_m >= KICK_TARGET_M and o.standing_after for o in outcomes]
    assert sum(good) >= 9, outcomes


@pytest.mark.slow
@pytest.mark.parametrize("side", ["front", "back"])
def test_getup_rate_is_at_least_9_in_10(side):
    movement = load_motion(f"getup_{side}")
    outcomes = [run_getup(movement, side, seed) for seed in range(10)]
    assert sum(o.upright for o in outcomes) >= 9, outcomes
