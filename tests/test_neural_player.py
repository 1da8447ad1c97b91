"""A learned motion played in the World follows the original trajectory."""

import numpy as np
import pytest
from _learn_helpers import joint_frame

from mimic.agents.base import Agent, JointCommand
from mimic.agents.neural_player import NeuralPlayer
from mimic.episode import Observer, run
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model
from mimic.model.model_file import save_model
from mimic.motion.files import load_motion
from mimic.robot.nao import nao
from mimic.world.mujoco_world import MujocoWorld

N = 50  # one second of 20 ms cycles


def _arm_wave() -> np.ndarray:
    """(N, J) references: the stand pose with both shoulders swinging forward and back."""
    stand = load_motion("stand").steps[-1].angles_rad
    t = np.arange(N) * 0.02
    q = np.tile(stand, (N, 1))
    for name in ("left_shoulder_pitch", "right_shoulder_pitch"):
        q[:, nao().joint_index(name)] += 0.6 * np.sin(np.pi * t)
    return q


class _Replay(Agent):
    """Tracks the original reference table (the 'keyframe' side of the comparison)."""

    def __init__(self, refs):
        super().__init__()
        self.refs, self.k = refs, 0

    def reset(self, obs):
        self.k = 0

    def act(self, obs):
        self.reference_rad = self.refs[min(self.k, len(self.refs) - 1)]
        self.k += 1
        self.done = self.k >= len(self.refs)
        return JointCommand.references(self.reference_rad)


def _play(agent, start):
    world = MujocoWorld()
    world.reset()
    world.place_robot(0.0, 0.0, 0.0, start)
    reached = _Reached()
    run(world, agent, max_s=2 * N * 0.02, observers=(reached,))
    return np.array(reached.angles)


class _Reached(Observer):
    def __init__(self):
        self.angles = []

    def before_step(self, world, obs, agent, command):
        self.angles.append(obs.joint_angles_rad.copy())


def test_learned_arm_wave_follows_the_original(tmp_path):
    refs = _arm_wave()
    ds = dataset_from_frame(joint_frame(np.arange(N) * 0.02, refs), metadata={"motion": "arm_wave"})
    model = train_model(ds, TrainConfig(FAST, seed=0, epochs=3000))
    assert model.metrics["mae_rad"] < 0.01
    player = NeuralPlayer.from_file(save_model(model, tmp_path / "arm_wave.mimic"))
    assert player.name == "arm_wave" and player.period_s is None
    learned = _play(player, refs[0])
    original = _play(_Replay(refs), refs[0])
    assert player.done and player.reference_rad.shape == (nao().num_joints,)
    n = min(len(learned), len(original))
    assert n >= N - 2
    shoulder = nao().joint_index("left_shoulder_pitch")
    assert np.ptp(original[:n, shoulder]) > 0.5  # the arm really moved
    assert np.abs(learned[:n] - original[:n]).max() < 0.05


def test_cyclic_player_loops_and_scales_phase():
    t = np.arange(25) * 0.02
    q = np.zeros((25, 22))
    q[:, 0] = 0.3 * np.sin(2 * np.pi * t / 0.5)
    ds = dataset_from_frame(joint_frame(t, q), period_s=0.5, metadata={"motion": "nod"})
    model = train_model(ds, TrainConfig(FAST, seed=0, epochs=500))
    player = NeuralPlayer(model, speed_rate=2.0)
    assert player.period_s == pytest.approx(0.25)
    np.testing.assert_allclose(player.reference_at(0.05), player.reference_at(0.30), atol=1e-9)
    np.testing.assert_allclose(player.reference_at(0.05), model.predict(0.10), atol=1e-9)


def test_learned_get_up_starts_lying_and_stands_the_robot_up(tmp_path):
    from mimic.learn.train import training_dataset
    from mimic.recording.reader import read_tf
    from mimic.recording.recorder import RecordConfig, record

    source = tmp_path / "getup_front.mcap"
    record("getup_front", source, config=RecordConfig(tf_every=5))
    model = train_model(training_dataset(source))
    player = NeuralPlayer(model)
    assert player.start_posture == "lying_front"
    replay = tmp_path / "learned_getup.mcap"
    record(player, replay, config=RecordConfig(tf_every=5))
    torso_z = read_tf(replay)["torso"].pos_m[:, 2]
    assert torso_z[0] < 0.15 and torso_z[-1] > 0.28
