"""The study's central claim on our kick: a learned copy, played by the neural player through
the same tracking, reaches the same joint angles and kicks the ball. And beyond it: a copy
learned from the observed angles only (``/joint_states``) kicks without falling inside the
balance layer, which corrects the support leg only."""

import dataclasses

import numpy as np
import pytest

from mimic.agents.balance import BalancedAgent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.neural_player import NeuralPlayer
from mimic.episode import Episode, FallCounter, Observer, PoseNoise, Scene
from mimic.learn.presets import get_preset
from mimic.learn.train import TARGET_REACHED, TrainConfig, train_model, training_dataset
from mimic.motion.files import load_motion
from mimic.recording.layout import JOINT_STATES
from mimic.recording.recorder import record
from mimic.robot.nao import nao
from mimic.world.mujoco_world import MujocoWorld


def _play(agent, offset_m, *, seed=None, falls=None):
    """Joint angles reached while ``agent`` plays from standing behind the ball, and the
    distance the ball moved [m]. With ``seed``, the start pose gets 0.01 rad of noise; with
    ``falls`` (a FallCounter), the robot also stands for 2 s after the motion ends."""
    world = MujocoWorld()
    noise = PoseNoise(joint_rad=0.01 if seed is not None else 0.0)
    Scene(ball_offset_m=tuple(offset_m), ball_after_settle=True, noise=noise).setup(
        world, np.random.default_rng(seed or 0)
    )
    start = world.ball_pos_m()
    reached = _Reached()
    episode = Episode(world, observers=(reached,), falls=falls or FallCounter())
    episode.run(agent, max_s=6.0, abort_on_fall=False)
    if falls is not None:
        episode.stand_still(max_s=2.0)
    return np.array(reached.angles), float(np.linalg.norm(world.ball_pos_m() - start))


class _Reached(Observer):
    """The joint angles seen every cycle."""

    def __init__(self):
        self.angles = []

    def before_step(self, world, obs, agent, command):
        self.angles.append(obs.joint_angles_rad)


@pytest.fixture(scope="module")
def kick_recording(tmp_path_factory):
    out = tmp_path_factory.mktemp("kick") / "kick_right.mcap"
    record("kick_right", out)
    return out


@pytest.fixture(scope="module")
def learned_kick(kick_recording):
    # The default fast schedule: the ended flag needs the full fit to rise on time.
    return train_model(
        training_dataset(kick_recording), TrainConfig(preset=get_preset("fast"), seed=0)
    )


def test_learned_kick_reaches_the_originals_angles_and_kicks(learned_kick):
    movement = load_motion("kick_right")
    original, _ = _play(KeyframePlayer(movement), movement.ball_offset_m)
    learned, ball_moved_m = _play(NeuralPlayer(learned_kick), movement.ball_offset_m)
    n = min(len(original), len(learned))
    assert abs(len(original) - len(learned)) <= 3, "the ended flag stops it on time"
    assert np.abs(original[:n] - learned[:n]).mean() < 0.03
    assert ball_moved_m > 0.5


def test_balance_leaves_a_one_shot_motions_swing_leg_alone(learned_kick):
    world = MujocoWorld()
    world.reset()
    world.place_robot(0.0, 0.0, 0.0, nao().stand_pose())
    rolled_0_1_rad = np.array([np.cos(0.05), np.sin(0.05), 0.0, 0.0])
    tilted = dataclasses.replace(
        world.observe(), gyro_rad_s=np.zeros(3), torso_quat_wxyz=rolled_0_1_rad
    )
    kick = BalancedAgent(NeuralPlayer(learned_kick))
    assert not kick.swing_feedback
    assert kick.ball_offset_m == NeuralPlayer(learned_kick).ball_offset_m
    shift = kick.tilt_correction_rad(tilted)
    swing = "right" if kick.support > 0 else "left"
    support = "left" if swing == "right" else "right"
    moved = {name for name, d in zip(nao().joint_names, shift) if abs(d) > 1e-9}
    assert moved == {f"{support}_ankle_roll"}, "a pure roll moves the support ankle roll only"
    # A walk keeps the swing-leg correction (its swing foot lands where the hip puts it).
    assert (
        BalancedAgent(NeuralPlayer(learned_kick), swing_feedback=True).tilt_correction_rad(tilted)[
            nao().joint_index(f"{swing}_hip_roll")
        ]
        != 0.0
    )


@pytest.mark.parametrize("seed", [0, 1])
def test_kick_learned_from_joint_states_kicks_without_falling_in_the_balance_layer(
    kick_recording, seed
):
    """Beyond the study: only the angles an observer sees, the study's reached-angle target,
    and the balance layer on the support ankle (network seed 0 and 1; without balance the
    seed-1 copy falls in every kick of our seeded check)."""
    model = train_model(
        training_dataset(kick_recording, JOINT_STATES, TARGET_REACHED), TrainConfig(seed=seed)
    )
    assert model.metadata["topic"] == JOINT_STATES
    offset = load_motion("kick_right").ball_offset_m
    falls = FallCounter()
    _, ball_moved_m = _play(BalancedAgent(NeuralPlayer(model)), offset, seed=seed, falls=falls)
    assert falls.falls == 0
    assert ball_moved_m > 3.0
