"""Issue 6 on the real thing: the other team's walk, observed, learned and walked again.

A short steady-state recording of the other team's walk (joint states only), a small cyclic
model trained on compensated targets, then the learned copy walks from the own goal line
with the phase-locked start and the balance layer.
"""

import math

import numpy as np
import pytest

from mimic.agents.balance import foot_yaw_shift_rad
from mimic.agents.neural_player import NeuralPlayer
from mimic.agents.registry import AgentSpec
from mimic.learn.presets import get_preset
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.model.model_file import save_model
from mimic.recording.recorder import record
from mimic.robot.joints import joint_index
from mimic.robot.nao import nao
from mimic.tasks.walk import WalkTrialConfig, run_walk_episode
from mimic.world.mujoco_world import MujocoWorld

# The other team's walk reaches its steady speed (full step length) about 4 s after starting.
WARMUP_S = 4.0
PERIODS = 8

NAO_JOINTS = nao().num_joints


@pytest.fixture(scope="module")
def walk_model(tmp_path_factory):
    out = tmp_path_factory.mktemp("walk")
    mcap = out / "other_team_walk.mcap"
    rec = record(
        "other-team-walk", mcap, observe_only=True, warmup_s=WARMUP_S, duration_s=PERIODS * 0.32
    )
    assert rec.info.period_s == pytest.approx(0.32)
    model = train_model(
        training_dataset(mcap, target="compensated"),
        TrainConfig(preset=get_preset("fast"), seed=0, epochs=4000),
    )
    return save_model(model, out / "other_team_walk.mimic")


def test_cyclic_start_blends_from_the_start_pose_into_the_cycle(walk_model):
    player = NeuralPlayer.from_file(walk_model)
    assert player.model.cyclic and player.stance_s > 0 and player.start_ramp_s > 0

    class Obs:  # only what reset reads
        time_s = 0.0
        joint_angles_rad = np.linspace(-0.1, 0.1, NAO_JOINTS)

    player.reset(Obs())
    np.testing.assert_allclose(player.cyclic_reference(0.0)[:NAO_JOINTS], Obs.joint_angles_rad)
    # Right after the stance blend: the cycle's mean pose, no swing yet.
    np.testing.assert_allclose(
        player.cyclic_reference(player.stance_s)[:NAO_JOINTS], player.mean_pose_rad(), atol=1e-9
    )
    # After the ramp: the network's own cycle, phase 0 at the end of the stance blend.
    t = player.stance_s + player.start_ramp_s + 0.1
    np.testing.assert_allclose(player.cyclic_reference(t), player.reference_at(t - player.stance_s))
    # Both times 0: the old behaviour (the cycle from the first cycle on).
    old = NeuralPlayer.from_file(walk_model, stance_s=0.0, start_ramp_s=0.0)
    old.reset(Obs())
    np.testing.assert_allclose(old.cyclic_reference(0.05), old.reference_at(0.05))


def _foot_in_torso(angles: np.ndarray, side: str) -> np.ndarray:
    """(3, 3) orientation of a foot in the torso frame, from the simulator's kinematics."""
    import mujoco

    world = MujocoWorld()
    world.reset()
    world.place_robot(0.0, 0.0, 0.0, angles)
    mujoco.mj_kinematics(world.model, world.data)
    torso = world.data.xmat[world.model.body("torso").id].reshape(3, 3)
    foot = world.data.xmat[world.model.body(f"{side}_foot").id].reshape(3, 3)
    return torso.T @ foot


def test_foot_yaw_shift_yaws_the_feet_without_pitching_them():
    bent = np.zeros(NAO_JOINTS)
    for side in ("left", "right"):
        bent[joint_index(f"{side}_hip_pitch")] = 0.4
        bent[joint_index(f"{side}_knee_pitch")] = -0.8
        bent[joint_index(f"{side}_ankle_pitch")] = 0.4
    shifted = bent + foot_yaw_shift_rad(0.05, -0.03)
    for side, want in (("left", 0.05), ("right", -0.03)):
        rel = _foot_in_torso(bent, side).T @ _foot_in_torso(shifted, side)
        assert math.atan2(rel[1, 0], rel[0, 0]) == pytest.approx(want, abs=2e-3)
        assert abs(math.atan2(-rel[2, 0], rel[2, 2])) < 2e-3  # no pitch
        assert abs(math.atan2(rel[2, 1], rel[2, 2])) < 2e-3  # no roll


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_learned_walk_with_balance_walks_forward_without_falling(walk_model, seed):
    config = WalkTrialConfig(start_x_m=-15.0, finish_x_m=-10.0, timeout_s=25.0)
    spec = AgentSpec("model", str(walk_model), balance=True)
    [row], _ = run_walk_episode(spec, seed=seed, config=config)
    assert not row["fell"], row
    assert row["finished"], row
    # 5 m including the start-up: the other team's walk itself averages ~0.39 m/s here.
    assert row["speed_m_s"] > 0.3, row
    assert abs(row["y_end_m"]) < 0.5, row
