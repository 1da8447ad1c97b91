"""Foot placement for learned walks: the foot track a cyclic model learns from a recording,
the joint shifts that move a foot, and the balance layer's capture-point rule.

The T1 other team's walk is recorded in our world (angles and body poses); a cyclic copy is
learned from its steady part.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from mimic.agents.balance import BalancedAgent, default_gains, gains_with, with_balance_gains
from mimic.agents.neural_player import NeuralPlayer
from mimic.errors import MimicError
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.model.foot_track import FootTrack
from mimic.model.keys import FOOT_TRACK_KEY
from mimic.recording import layout as L
from mimic.recording.recorder import record
from mimic.world.kinematics import FootKinematics
from mimic.world.mujoco_world import MujocoWorld

PLACE = {"place_y": 0.25, "place_y_rate_s": 0.2, "place_x": 0.2}


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """(the recording, a cyclic copy of its steady part) of the T1 other team's walk."""
    from mimic.agents.registry import make_agent

    path = tmp_path_factory.mktemp("place") / "t1_walk.mcap"
    record(make_agent("other-team-walk", robot="t1"), path, duration_s=6.0)
    ds = training_dataset(path, L.JOINT_STATES, start_s=2.5, period="auto")
    return path, ds, train_model(ds, TrainConfig(FAST, epochs=300))


def test_a_cyclic_copy_carries_where_its_recording_had_the_feet(walk):
    _, ds, model = walk
    track = FootTrack.from_metadata(model.metadata[FOOT_TRACK_KEY])
    phases = np.arange(40) / 40
    feet = np.stack([track.at(p) for p in phases])  # (40, side, xy)
    # The left foot walks left of the torso, the right one right of it, ~0.1 m out each.
    assert np.all(feet[:, 0, 1] > 0.05) and np.all(feet[:, 1, 1] < -0.05)
    # Each foot travels back under the torso and swings ahead again: a stride's worth.
    assert np.ptp(feet[:, 0, 0]) > 0.15 and np.ptp(feet[:, 1, 0]) > 0.15
    # The legs alternate: the right foot's path is the left one's half a cycle later.
    half = np.roll(feet[:, 0, 0], 20)
    assert np.abs(half - feet[:, 1, 0]).mean() < 0.3 * np.ptp(feet[:, 0, 0])
    # A one-shot cut of the same recording carries none (a kick has no cycle to follow).
    assert FOOT_TRACK_KEY not in training_dataset(walk[0], start_s=2.5).metadata


def test_joint_shifts_move_one_foot_by_what_was_asked(walk):
    kin = FootKinematics("t1")
    q = NeuralPlayer(walk[2]).mean_pose_rad()
    upright = (1.0, 0.0, 0.0, 0.0)
    before = kin.feet_m(q, upright)
    maps = kin.shift_map(q)
    for side, k in ((1.0, 0), (-1.0, 1)):
        for step in ((0.02, 0.0), (0.0, -0.02), (-0.015, 0.01)):
            after = kin.feet_m(q + maps[side] @ np.array(step), upright)
            np.testing.assert_allclose(after[k] - before[k], step, atol=1.5e-3)
            np.testing.assert_allclose(after[1 - k], before[1 - k], atol=1e-9)


def test_a_torso_leaning_left_puts_the_swing_foot_left(walk):
    """Rolled left, the feet sit right of where the recording had them under the torso: the
    swing foot is sent left; rolled right, right. Outward it goes as far as
    ``place_limit_m``, inward (toward the support foot) only ``place_inward_m``."""
    world = MujocoWorld("t1")
    world.reset()
    strong = {**PLACE, "place_y": 1.0}  # a 0.25 rad lean moves the feet ~0.15 m: clipped
    g = gains_with(default_gains("t1"), strong)
    model = with_balance_gains(walk[2], strong)
    # A positive turn about the torso's x axis leans it right.
    for roll, side in ((-0.25, 1.0), (0.25, -1.0)):
        agent = BalancedAgent(NeuralPlayer(model, stance_s=0.0, start_ramp_s=0.0))
        assert agent.placement
        obs = world.observe()
        agent.reset(obs)
        quat = np.array([math.cos(roll / 2), math.sin(roll / 2), 0.0, 0.0])
        leaning = replace(obs, torso_quat_wxyz=quat, gyro_rad_s=np.zeros(3))
        # The clock held: one phase, one support foot; 30 cycles finish the step's blend and
        # let the error's rate settle to 0.
        for _ in range(30):
            agent.act(leaning)
        sup = agent.support
        shift_y = agent._place[-sup][1]
        outward = side == -sup  # the swing foot is on the side the torso leans to
        assert shift_y == pytest.approx(
            side * (g.place_limit_m if outward else g.place_inward_m), abs=1e-6
        )
        assert np.all(agent._place[sup] == 0.0)  # the support foot keeps where it stood


def test_placement_is_off_unless_its_gains_are_set(walk):
    model = walk[2]
    assert not BalancedAgent(NeuralPlayer(model)).placement  # every robot's default: off
    assert BalancedAgent(NeuralPlayer(with_balance_gains(model, PLACE))).placement
    # A model without a track (learned before tracks, or a one-shot motion) cannot place.
    bare = replace(model, metadata={k: v for k, v in model.metadata.items() if k != FOOT_TRACK_KEY})
    assert not BalancedAgent(NeuralPlayer(with_balance_gains(bare, PLACE))).placement


def test_a_bad_track_is_one_line():
    with pytest.raises(MimicError, match="foot track"):
        FootTrack.from_metadata({"left_m": [[0.1, 0.1]]})
    with pytest.raises(MimicError, match="foot track"):
        FootTrack.from_metadata({"left_m": "x"})


@pytest.mark.parametrize("lean", ["forward", "left"])
def test_the_support_hip_turns_a_leaning_torso_back_over_the_leg(walk, lean):
    """Torso attitude (``torso_pitch``, ``torso_roll``): a torso leaning forward over a
    planted leg stands at a flexed hip; the support hip extends, which in the torso's frame
    moves the foot back (planted, the torso turns back up). Leaning left, the foot moves
    right. The swing leg is left to the rest of the layer."""
    world = MujocoWorld("t1")
    world.reset()
    kin = FootKinematics("t1")
    model = with_balance_gains(walk[2], {"torso_pitch": 0.8, "torso_roll": 0.8})
    agent = BalancedAgent(NeuralPlayer(model, stance_s=0.0, start_ramp_s=0.0))
    obs = world.observe()
    agent.reset(obs)
    angle = 0.1
    quat = (
        np.array([math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0])  # nose down
        if lean == "forward"
        else np.array([math.cos(angle / 2), -math.sin(angle / 2), 0.0, 0.0])  # leaning left
    )
    leaning = replace(obs, torso_quat_wxyz=quat, gyro_rad_s=np.zeros(3))
    agent.act(leaning)
    with_attitude = agent.tilt_correction_rad(leaning)
    no_attitude = with_balance_gains(walk[2], {"torso_pitch": 0.0, "torso_roll": 0.0})
    without = BalancedAgent(NeuralPlayer(no_attitude, stance_s=0.0, start_ramp_s=0.0))
    without.reset(obs)
    without.act(leaning)
    assert without.support == agent.support
    q = NeuralPlayer(walk[2]).mean_pose_rad()
    upright = (1.0, 0.0, 0.0, 0.0)
    k = 0 if agent.support > 0 else 1
    moved = (
        kin.feet_m(q + with_attitude, upright)[k]
        - kin.feet_m(q + without.tilt_correction_rad(leaning), upright)[k]
    )
    axis = 0 if lean == "forward" else 1
    # About leg length (0.5 m) x hip turn (0.8 x 0.1 rad): 4 cm; at least 1 cm.
    assert moved[axis] < -0.01
    # The swing leg gets the same as without the attitude terms.
    other = kin.feet_m(q + with_attitude, upright)[1 - k]
    np.testing.assert_allclose(
        other, kin.feet_m(q + without.tilt_correction_rad(leaning), upright)[1 - k], atol=1e-9
    )
