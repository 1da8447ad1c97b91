"""Disturbances: pushes, physics spreads, start delays and sensor noise in real episodes."""

import math
from dataclasses import replace

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.agents.registry import AgentSpec
from mimic.cli.main import app
from mimic.episode.disturbance import (
    DISTURB_LEVELS,
    GAME_PUSH_SPEED_M_S,
    ORIGINAL_PUSH_SPEED_M_S,
    EpisodeDisturbances,
    NoisySensors,
)
from mimic.errors import MimicError
from mimic.robot.actuators import JointCommand
from mimic.stats import ratio_interval
from mimic.tasks.walk import WalkTask, WalkTrialConfig, run_walk_episode
from mimic.trials.api import check_trial, walk_trial
from mimic.world.mujoco_world import MujocoWorld

# A short course (5 m of the study's 15 m) keeps each run a few seconds of wall time.
SHORT = dict(start_x_m=-15.0, finish_x_m=-12.0)
GAME = WalkTrialConfig(disturb="game", **SHORT)


def _standing_nao() -> MujocoWorld:
    world = MujocoWorld("nao")
    world.reset()
    world.place_robot(0.0, 0.0, 0.0, world.robot.stand_pose())
    return world


def test_a_push_changes_the_whole_robots_speed_by_its_size():
    world = _standing_nao()
    from mimic.agents.hold import HoldPose
    from mimic.episode import run

    run(world, HoldPose(world.robot.stand_pose(), "nao"), max_s=0.5, stop_when_done=False)
    mass = world.robot_mass_kg()
    before = world.data.subtree_com[world.torso_body_id].copy()
    dv = 0.2
    world.push_torso(np.array([0.0, mass * dv / 0.1, 0.0]))  # sideways, 0.1 s
    for _ in range(5):
        world.step(JointCommand.references(world.robot.stand_pose()))
    world.push_torso(np.zeros(3))
    # Momentum: the centre of mass moves sideways at about dv (the feet's friction takes a
    # share, the push's own 0.1 s moves it dv * 0.05 m).
    vel = (world.data.subtree_com[world.torso_body_id] - before) / 0.1
    assert 0.3 * dv < vel[1] < 1.1 * dv
    assert abs(vel[0]) < 0.3 * dv


def test_physics_scales_do_not_compound_and_move_the_mass():
    world = MujocoWorld("nao")
    nominal = world.robot_mass_kg()
    friction = world.model.geom_friction[:, 0].copy()
    scales = np.full(len(world.robot.links), 1.1)
    for _ in range(2):  # twice: from the nominal values each time
        world.scale_physics(0.9, scales)
    assert world.robot_mass_kg() == pytest.approx(1.1 * nominal, rel=1e-9)
    np.testing.assert_allclose(world.model.geom_friction[:, 0], 0.9 * friction)
    world.scale_physics(1.0, np.ones(len(world.robot.links)))
    assert world.robot_mass_kg() == pytest.approx(nominal, rel=1e-9)


def test_game_draws_repeat_per_seed_and_none_draws_nothing():
    world = MujocoWorld("nao")
    a, b = (EpisodeDisturbances("game", 5, world) for _ in range(2))
    assert a.friction_scale == b.friction_scale and 0.9 <= a.friction_scale <= 1.1
    np.testing.assert_array_equal(a.link_mass_scales, b.link_mass_scales)
    assert a.push_speed_m_s == GAME_PUSH_SPEED_M_S["nao"]
    c = EpisodeDisturbances("game", 6, world)
    assert c.friction_scale != a.friction_scale
    none = EpisodeDisturbances("none", 5, world)
    assert none.columns()["friction_scale"] == 1.0 and none.columns()["mass_scale"] == 1.0


def test_game_runs_get_pushed_and_differ_more_than_undisturbed_ones():
    spec = AgentSpec("behaviour", "walk")
    game = [run_walk_episode(spec, s, GAME)[0][0] for s in range(3)]
    calm = [
        run_walk_episode(spec, s, WalkTrialConfig(disturb="none", **SHORT))[0][0] for s in range(3)
    ]
    assert all(r["disturb"] == "game" for r in game)
    assert sum(r["pushes"] for r in game) >= 1, "no push in 3 runs of ~8 s at one per 3 s"
    assert all(r["pushes"] == 0 and r["start_delay_s"] == 0 for r in calm)
    assert all(0 <= r["start_delay_s"] <= DISTURB_LEVELS["game"].start_delay_s for r in game)
    # The same seed with and without disturbances starts from the same scene; the
    # disturbances move where the robot ends.
    for g, c in zip(game, calm, strict=True):
        assert (
            abs(g["y_end_m"] - c["y_end_m"]) > 0.005 or abs(g["speed_m_s"] - c["speed_m_s"]) > 0.002
        )
    # The same seed repeats exactly.
    again = run_walk_episode(spec, 1, GAME)[0][0]
    assert again == game[1]


def test_hard_level_feeds_the_agent_noisy_sensors_but_measures_the_truth():
    world = _standing_nao()
    level = DISTURB_LEVELS["hard"]

    class Seen:
        name, team, period_s, start_posture, robot, robot_only = "seen", "t", None, "x", "nao", 0
        done, reference_rad = False, None

        def reset(self, obs):
            self.seen = [obs]

        def act(self, obs):
            self.seen.append(obs)
            return None

    inner = Seen()
    agent = NoisySensors(inner, level, np.random.default_rng(0))
    truth = world.observe()
    agent.reset(truth)
    for _ in range(200):
        agent.act(truth)
    joints = np.array([o.joint_angles_rad for o in inner.seen]) - truth.joint_angles_rad
    assert joints.std() == pytest.approx(level.joint_noise_rad, rel=0.1)
    gyro = np.array([o.gyro_rad_s for o in inner.seen]) - truth.gyro_rad_s
    assert gyro.std() == pytest.approx(level.gyro_noise_rad_s, rel=0.15)
    tilts = [
        math.acos(min(1.0, abs(float(np.dot(o.torso_quat_wxyz, truth.torso_quat_wxyz)))))
        for o in inner.seen
    ]
    assert 0 < np.mean(tilts) < 3 * level.tilt_noise_rad
    np.testing.assert_array_equal(world.observe().joint_angles_rad, truth.joint_angles_rad)


def test_a_trial_reports_each_ratio_with_its_interval_and_the_level():
    spec = AgentSpec("behaviour", "walk")
    result = walk_trial([spec, spec], runs=3, seed=2, workers=1, config=GAME)
    row = result.summary.row(1, named=True)
    assert row["disturb"] == "game"
    # The same variant twice on the same seeds: the same runs, a ratio of exactly 1.
    assert row["mean_speed_m_s_ratio_ci_low"] == pytest.approx(1.0)
    assert row["mean_speed_m_s_ratio_ci_high"] == pytest.approx(1.0)
    assert {"pushes", "push_times_s", "friction_scale", "mass_scale"} <= set(result.rows.columns)
    # Pushed as hard as the original (the first variant) survives most of the time: our walk
    # engine takes more than the NAO's game push.
    assert set(result.rows["push_speed_m_s"]) == {ORIGINAL_PUSH_SPEED_M_S[("nao", "walk")]}
    assert ORIGINAL_PUSH_SPEED_M_S[("nao", "walk")] > GAME_PUSH_SPEED_M_S["nao"]


def test_every_variant_is_pushed_as_hard_as_the_original_survives():
    engine, other = AgentSpec("behaviour", "walk"), AgentSpec("behaviour", "other-team-walk")
    result = walk_trial([other, engine], runs=2, seed=3, workers=1, config=GAME)
    assert set(result.rows["push_speed_m_s"]) == {GAME_PUSH_SPEED_M_S["nao"]}
    # The same seeds draw the same push times for both (a longer run gets more of them); only
    # their size follows the original.
    times = result.rows.group_by("variant", maintain_order=True).agg("push_times_s")
    for a, b in zip(*(times["push_times_s"][i].to_list() for i in (0, 1)), strict=True):
        n = min(len(a), len(b))
        assert n >= 1 and a[:n] == b[:n]
    # A motion or a model as the original: the robot's game push; the level's scale applies.
    kick = AgentSpec("motion", "kick_right")
    assert WalkTask.for_original(GAME, kick).push_speed_m_s == GAME_PUSH_SPEED_M_S["nao"]
    assert WalkTask.for_original(WalkTrialConfig(), engine).push_speed_m_s is None
    hard = WalkTask.for_original(replace(GAME, disturb="hard"), engine)
    world = MujocoWorld("nao")
    pushed = EpisodeDisturbances("hard", 1, world, hard.push_speed_m_s).push_speed_m_s
    assert pushed == DISTURB_LEVELS["hard"].push_scale * ORIGINAL_PUSH_SPEED_M_S[("nao", "walk")]


def test_ratio_interval_covers_the_true_ratio_about_95_percent_of_the_time():
    rng = np.random.default_rng(0)
    hits_paired = hits_unpaired = 0
    widths = []
    for _ in range(400):
        shared = rng.normal(0.0, 0.05, 20)  # the seed's disturbance, the same for both
        base = 0.5 + shared + rng.normal(0.0, 0.01, 20)
        copy = 0.45 + shared + rng.normal(0.0, 0.01, 20)
        lo, hi = ratio_interval(copy, base, paired=True)
        hits_paired += lo <= 0.9 <= hi
        ulo, uhi = ratio_interval(copy, base)
        hits_unpaired += ulo <= 0.9 <= uhi
        widths.append((hi - lo, uhi - ulo))
    assert 0.9 <= hits_paired / 400 <= 0.99
    assert hits_unpaired / 400 >= 0.9
    paired_w, unpaired_w = np.mean(widths, axis=0)
    assert paired_w < 0.5 * unpaired_w, "pairing by seed removes the shared disturbance"
    assert all(math.isnan(v) for v in ratio_interval([1.0], [1.0, 2.0]))


def test_a_league_server_refuses_pushes_in_one_line():
    spec = AgentSpec("behaviour", "other-team-walk", robot="t1")
    with pytest.raises(MimicError, match="--disturb none"):
        check_trial(
            "walk", [spec], runs=1, config=WalkTrialConfig(world="league-server", disturb="game")
        )
    check_trial(
        "walk", [spec], runs=1, config=WalkTrialConfig(world="league-server", disturb="none")
    )
    check_trial("walk", [spec], runs=1, config=WalkTrialConfig(world="league", disturb="game"))
    check_trial("walk", [spec], runs=1, config=WalkTrialConfig(world="league-like", disturb="game"))


def test_unknown_level_is_one_clear_line():
    result = CliRunner().invoke(app, ["trial", "walk", "--runs", "1", "--disturb", "windy"])
    assert result.exit_code != 0
    assert "unknown disturbance level 'windy'; levels: none, game, hard" in result.output
    assert "Traceback" not in result.output


def test_the_cli_defaults_to_game_where_it_can_push_and_none_on_a_league_server():
    from mimic.cli.trial import _disturb

    assert _disturb(None, "mujoco") == "game" and _disturb(None, "league-like") == "game"
    assert _disturb(None, "league") == "game"  # in process
    assert _disturb(None, "league-server") == "none"
    assert _disturb("hard", "mujoco") == "hard"


def test_the_dashboard_shows_each_push_of_the_replayed_run(tmp_path, rerun_cli):
    import subprocess

    from mimic.viz.trials import save_trial_dashboard

    spec = AgentSpec("behaviour", "walk")
    config = WalkTrialConfig(disturb="hard", start_x_m=-15.0, finish_x_m=-11.0)
    result = walk_trial([spec], runs=1, seed=4, workers=1, config=config, trace=True)
    trace = result.traces["walk"]
    assert len(trace.pushes) == result.rows["pushes"][0] >= 1
    start_s, force_n, duration_s = trace.pushes[0]
    assert np.linalg.norm(force_n) > 0 and force_n[2] == 0
    assert duration_s == DISTURB_LEVELS["hard"].push_duration_s
    rrd = tmp_path / "walk.rrd"
    save_trial_dashboard(result, rrd)
    text = subprocess.run(
        [rerun_cli, "rrd", "print", str(rrd)], check=True, capture_output=True, text=True
    ).stdout
    assert "/world/replay/walk/push - data columns: [Arrows3D" in text


def test_the_league_world_in_process_takes_pushes_and_the_physics_spreads():
    from mimic.world.league_inprocess import LeagueInProcessWorld

    with LeagueInProcessWorld("t1") as world:
        nominal = world.robot_mass_kg()
        world.scale_physics(1.1, np.full(len(world.robot.links), 0.9))
        assert world.robot_mass_kg() == pytest.approx(0.9 * nominal, rel=1e-9)
        world.reset()
        world.place_robot(0.0, 0.0, 0.0, world.robot.stand_pose())
        hold = JointCommand.references(world.robot.stand_pose())
        for _ in range(25):
            world.step(hold)
        before = world.torso_pos_m()
        world.push_torso(np.array([0.0, world.robot_mass_kg() * 0.3 / 0.1, 0.0]))
        for _ in range(5):
            world.step(hold)
        world.push_torso(np.zeros(3))
        for _ in range(5):
            world.step(hold)
        moved = world.torso_pos_m() - before
        assert moved[1] > 0.01 and abs(moved[0]) < moved[1], "pushed to its left"
    spec = AgentSpec("behaviour", "other-team-walk", robot="t1")
    config = WalkTrialConfig(world="league", disturb="game", start_x_m=-5.0, finish_x_m=-3.0)
    row = run_walk_episode(spec, 3, config)[0][0]
    assert row["world"] == "league" and row["disturb"] == "game"
    assert row["friction_scale"] != 1.0 and row["mass_scale"] != 1.0


def test_the_same_seed_gives_the_same_disturbed_table_whatever_the_workers(tmp_path):
    from mimic.tasks.kick import KickTrialConfig
    from mimic.trials.api import kick_trial

    spec = AgentSpec("behaviour", "walk")
    one, two = tmp_path / "one.parquet", tmp_path / "two.parquet"
    walk_trial([spec], runs=3, seed=9, workers=1, config=GAME, out=one)
    walk_trial([spec], runs=3, seed=9, workers=2, config=GAME, out=two)
    assert one.read_bytes() == two.read_bytes()
    kick = AgentSpec("motion", "kick_right")
    config = KickTrialConfig(disturb="game")
    a = kick_trial([kick], minutes=0.5, seed=9, workers=1, config=config, out=tmp_path / "a.pq")
    kick_trial([kick], minutes=0.5, seed=9, workers=2, config=config, out=tmp_path / "b.pq")
    assert (tmp_path / "a.pq").read_bytes() == (tmp_path / "b.pq").read_bytes()
    assert set(a.rows["disturb"]) == {"game"} and "pushes_during_kick" in a.rows.columns


def test_a_getup_trial_is_disturbed_too():
    from mimic.tasks.getup import GetupTrialConfig
    from mimic.trials.api import getup_trial

    config = GetupTrialConfig(disturb="hard")
    result = getup_trial(
        [AgentSpec("motion", "getup_front")], runs=2, seed=3, workers=1, config=config
    )
    rows = result.rows
    assert set(rows["disturb"]) == {"hard"} and (rows["friction_scale"] != 1.0).all()
    assert (rows["start_delay_s"] > 0).all()
    assert result.summary["disturb"][0] == "hard"
