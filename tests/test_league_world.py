"""``LeagueWorld``: the world interface on a server mimic hosts itself; episodes run on it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mimic.agents.registry import make_agent
from mimic.episode import PoseTrace, Scene, run
from mimic.world.league_field import league_field
from mimic.world.league_server import LeagueWorld, LeagueWorldConfig


@pytest.fixture(scope="module")
def world():
    before = set(Path.cwd().iterdir())
    w = LeagueWorld("t1", config=LeagueWorldConfig(team="worldtest", player=3))
    yield w
    workdir, server = w.server.workdir, w.server
    w.close()
    assert not server.running and not workdir.exists()
    assert set(Path.cwd().iterdir()) == before  # no console.log or MuJoCo log left here


def test_the_hosted_server_runs_in_a_temporary_folder(world):
    assert world.server.running
    assert (world.server.workdir / "console.log").is_file()
    assert world.field == league_field() and world.field.length_m > 30


def test_a_scene_and_a_motion_run_unchanged(world):
    scene = Scene(robot_xy_m=(-1.0, 0.5), robot_yaw_rad=0.3, ball_offset_m=(0.3, 0.0), settle_s=0.4)
    placement = scene.setup(world, np.random.default_rng(0))
    t0 = world.time_s
    assert np.hypot(*(world.torso_pos_m()[:2] - (-1.0, 0.5))) < 0.05
    assert abs(world.torso_yaw_rad() - 0.3) < 0.05
    np.testing.assert_allclose(world.ball_pos_m()[:2], placement.ball_xy_m, atol=0.01)
    trace = PoseTrace(every_cycles=5)
    outcome = run(world, make_agent("stand", robot="t1"), max_s=1.0, observers=(trace,))
    assert outcome.end == "done" and world.time_s == pytest.approx(t0 + 0.62, abs=0.021)
    assert world.upright() and not world.fallen()
    obs = world.observe()
    assert np.abs(obs.joint_angles_rad - world.robot.stand_pose()).max() < 0.1
    assert obs.foot_forces_n.shape == (2,) and np.isfinite(obs.gyro_rad_s).all()
    poses = world.body_poses()
    assert poses.names[0] == world.robot.root_link
    np.testing.assert_allclose(poses.pos_m[0], world.torso_pos_m(), atol=0.01)
    assert len(trace.trace().times_s) >= 5
    assert world.ball_speed_m_s() < 0.05


@pytest.mark.parametrize("posture,side", [("lying_front", "front"), ("lying_back", "back")])
def test_the_robot_can_be_laid_down(world, posture, side):
    world.place_robot(2.0, -2.0, 0.0, world.robot.stand_pose(), posture=posture)
    run(world, make_agent("stand", robot="t1"), max_s=0.3)
    assert world.fallen() and world.lying_side() == side
