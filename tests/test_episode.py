"""The episode layer: scenes from an explicit generator, one run loop, observers."""

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.agents.hold import HoldPose, Limp
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.registry import make_agent
from mimic.cli.main import app
from mimic.episode import Episode, FallCounter, Observer, PoseNoise, PoseTrace, Scene, run
from mimic.errors import MimicError
from mimic.motion.files import load_motion
from mimic.world.mujoco_world import MujocoWorld


def _placed(seed, noise=PoseNoise(0.01, 0.03, 0.02, 0.01)):
    world = MujocoWorld()
    placement = Scene(ball_offset_m=(0.2, 0.0), noise=noise, settle_s=0.2).setup(
        world, np.random.default_rng(seed)
    )
    return world, placement


def test_same_generator_seed_same_scene_and_state():
    (w1, p1), (w2, p2) = _placed(3), _placed(3)
    np.testing.assert_array_equal(p1.pose_rad, p2.pose_rad)
    np.testing.assert_array_equal(w1.data.qpos, w2.data.qpos)
    _, p3 = _placed(4)
    assert not np.array_equal(p1.pose_rad, p3.pose_rad)


def test_uniform_noise_stays_within_its_half_widths():
    noise = PoseNoise(position_m=0.05, yaw_rad=0.1, joint_rad=0.02, distribution="uniform")
    for seed in range(5):
        world, p = _placed(seed, noise)
        assert abs(p.robot_xy_m[0]) <= 0.05 and abs(p.robot_xy_m[1]) <= 0.05
        assert abs(p.robot_yaw_rad) <= 0.1
        stand = world.robot.stand_pose()
        assert np.all(np.abs(p.pose_rad - world.robot.clip(stand)) <= 0.02 + 1e-12)


def test_ball_goes_to_the_offset_in_the_robot_frame():
    world = MujocoWorld()
    p = Scene(
        robot_xy_m=(1.0, 2.0), robot_yaw_rad=math.pi / 2, ball_offset_m=(0.3, 0.0), settle_s=0.0
    ).setup(world, np.random.default_rng(0))
    assert p.ball_xy_m == pytest.approx((1.0, 2.3))
    assert world.ball_pos_m()[:2] == pytest.approx([1.0, 2.3])


def test_bad_noise_is_refused():
    with pytest.raises(ValueError, match="finite"):
        PoseNoise(position_m=float("nan"))
    with pytest.raises(ValueError, match="normal or uniform"):
        PoseNoise(distribution="gaussian")


class _Count(Observer):
    def __init__(self):
        self.before, self.after, self.started = 0, 0, 0

    def start(self, world, agent):
        self.started += 1

    def before_step(self, world, obs, agent, command):
        self.before += 1

    def after_step(self, world):
        self.after += 1


def test_run_ends_for_each_reason_and_shows_every_cycle():
    world, _ = _placed(0)
    count = _Count()
    kick = KeyframePlayer(load_motion("kick_right"))
    outcome = run(world, kick, max_s=10.0, observers=(count,))
    assert outcome.end == "done" and count.started == 1
    # The last cycle is seen (the agent says done) but not stepped.
    assert count.before == outcome.cycles + 1 and count.after == outcome.cycles
    assert run(world, HoldPose(world.joint_angles_rad()), max_s=0.2).end == "timeout"
    assert run(world, Limp(), max_s=1.0, stop=lambda w: w.time_s > 0.0).end == "stop"
    world.place_robot(0.0, 0.0, 0.0, posture="lying_back")
    assert run(world, Limp(), max_s=1.0, abort_on_fall=True).end == "fell"


def test_episode_counts_falls_and_traces_every_run():
    world = MujocoWorld()
    trace = PoseTrace(every_cycles=1)
    episode = Episode(world, observers=(trace,), falls=FallCounter())
    Scene(posture="lying_front", settle_s=0.2).setup(
        world, np.random.default_rng(0), observers=episode.watchers
    )
    assert episode.falls.falls == 1
    assert episode.get_up()
    assert episode.falls.getups == 1 and world.upright()
    poses = trace.trace()
    assert poses.body_pos_m.shape[1:] == (len(world.robot.links), 3)
    assert len(poses.times_s) > 100 and np.all(np.diff(poses.times_s) > 0)


def test_a_nao_only_controller_refuses_another_robot():
    world = MujocoWorld("t1")
    with pytest.raises(MimicError, match="NAO-only controller; it cannot drive the T1"):
        run(world, make_agent("walk"), max_s=0.1)
    with pytest.raises(MimicError, match="made for the NAO"):
        run(world, KeyframePlayer(load_motion("kick_right")), max_s=0.1)


def test_record_a_nao_only_controller_on_the_t1_is_one_line(tmp_path):
    result = CliRunner().invoke(
        app, ["record", "walk", "--robot", "t1", "-o", str(tmp_path / "x.mcap")]
    )
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert "NAO-only controller" in result.output
    assert not (tmp_path / "x.mcap").exists()
