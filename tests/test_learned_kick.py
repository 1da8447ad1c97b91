"""The study's central claim on our kick: a learned copy, played by the neural player through
the same tracking, reaches the same joint angles and kicks the ball."""

import numpy as np
import pytest

from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.neural_player import NeuralPlayer
from mimic.learn.presets import get_preset
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.motion.files import load_motion
from mimic.recording.recorder import record
from mimic.trials.episode import FallCounter, stand_pose_rad, stand_still
from mimic.world.world import World


def _play(agent, offset_m):
    world = World()
    world.reset()
    world.beam(0.0, 0.0, 0.0, stand_pose_rad())
    world.place_ball(0.0, 9.0)
    stand_still(world, max_s=0.5, falls=FallCounter())
    torso = world.torso_pos_m()
    world.place_ball(torso[0] + offset_m[0], torso[1] + offset_m[1])
    start = world.ball_pos_m()
    agent.reset(world.observe())
    reached = []
    for _ in range(300):
        obs = world.observe()
        speeds = agent.act(obs)
        reached.append(obs.joint_angles_rad)
        if agent.done:
            break
        world.step(speeds)
    return np.array(reached), float(np.linalg.norm(world.ball_pos_m() - start))


@pytest.fixture(scope="module")
def learned_kick(tmp_path_factory):
    out = tmp_path_factory.mktemp("kick") / "kick_right.mcap"
    record("kick_right", out)
    # The default fast schedule: the ended flag needs the full fit to rise on time.
    return train_model(training_dataset(out), TrainConfig(preset=get_preset("fast"), seed=0))


def test_learned_kick_reaches_the_originals_angles_and_kicks(learned_kick):
    movement = load_motion("kick_right")
    original, _ = _play(KeyframePlayer(movement), movement.ball_offset_m)
    learned, ball_moved_m = _play(NeuralPlayer(learned_kick), movement.ball_offset_m)
    n = min(len(original), len(learned))
    assert abs(len(original) - len(learned)) <= 3, "the ended flag stops it on time"
    assert np.abs(original[:n] - learned[:n]).mean() < 0.03
    assert ball_moved_m > 0.5
