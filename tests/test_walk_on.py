"""A game goes on after a fall: under ``game`` a walk run that falls gets up and walks on, and a
walk that resumes turns back to its course (``Agent.resume``)."""

from __future__ import annotations

import math
from dataclasses import replace

import polars as pl
import pytest

from mimic.agents.registry import AgentSpec, agent_spec
from mimic.episode import run
from mimic.episode.disturbance import DISTURB_LEVELS
from mimic.tasks.walk import WalkTrialConfig, run_walk_episode
from mimic.trials.api import walk_trial
from mimic.world.registry import open_world

# 4 m of the study's 15 m course; a minute at most.
SHORT = dict(start_x_m=-15.0, finish_x_m=-11.0, timeout_s=40.0)


@pytest.fixture
def shove(monkeypatch):
    """A level like ``game`` whose pushes are twice as large and twice as frequent, so the
    NAO's walk falls within a few metres; and the same with a fall ending the run."""
    game = DISTURB_LEVELS["game"]
    harder = replace(game, push_scale=2.0, push_interval_s=2.0)
    monkeypatch.setitem(DISTURB_LEVELS, "shove", harder)
    monkeypatch.setitem(DISTURB_LEVELS, "shove-once", replace(harder, get_up_after_fall=False))


def test_game_and_hard_go_on_after_a_fall_and_none_does_not():
    assert DISTURB_LEVELS["game"].get_up_after_fall and DISTURB_LEVELS["hard"].get_up_after_fall
    assert not DISTURB_LEVELS["none"].get_up_after_fall


def test_a_walk_run_that_falls_gets_up_and_walks_on_to_the_finish(shove):
    spec = AgentSpec("behaviour", "walk")
    seed = 1
    on = run_walk_episode(spec, seed, WalkTrialConfig(disturb="shove", **SHORT))[0][0]
    once = run_walk_episode(spec, seed, WalkTrialConfig(disturb="shove-once", **SHORT))[0][0]
    calm = run_walk_episode(spec, seed, WalkTrialConfig(disturb="none", **SHORT))[0][0]
    # Without the rule the first fall ends the run where it happened.
    assert once["end"] == "fell" and once["fell"] and once["getups"] == 0
    assert once["distance_m"] < 4.0
    # With it the robot gets up (each fall it got up from counted), walks on and finishes,
    # back near its course, and the time on the ground costs it speed.
    assert on["end"] == "finished" and on["finished"] and on["fell"]
    assert on["getups"] >= 1 and on["falls"] >= on["getups"]
    assert abs(on["y_end_m"]) < 1.0
    assert on["walk_time_s"] > once["walk_time_s"] + 3.0
    assert calm["getups"] == 0 and not calm["fell"] and calm["end"] == "finished"
    assert on["speed_m_s"] < 0.7 * calm["speed_m_s"]


def test_the_table_counts_the_runs_that_fell_and_every_fall(shove):
    spec = AgentSpec("behaviour", "walk")
    result = walk_trial(
        [spec], runs=2, seed=1, workers=1, config=WalkTrialConfig(disturb="shove", **SHORT)
    )
    row, runs = result.summary.row(0, named=True), result.rows
    # The share's interval is of runs that fell; a run that fell got up and may fall again.
    assert row["runs_fell"] == runs["fell"].sum() >= 1
    assert row["falls"] == runs["falls"].sum() >= row["runs_fell"]
    assert row["fall_rate_pct"] == pytest.approx(100.0 * row["runs_fell"] / 2)


@pytest.mark.parametrize(
    "world, robot, walk",
    [
        ("mujoco", "nao", "walk"),
        ("mujoco", "nao", "other-team-walk"),
        ("league", "t1", "other-team-walk"),
    ],
)
def test_a_resumed_walk_turns_back_to_its_course(world, robot, walk):
    """Walk 3 s, stand the robot up again turned 40 deg off its course (as a get-up leaves
    it), then resume: the walk turns back to its heading; a reset keeps the new one."""
    turned_rad = math.radians(40)
    end_yaw_deg = {}
    for how in ("resume", "reset"):
        with open_world(world, robot) as w:
            w.reset()
            stand = w.robot.stand_pose()
            w.place_robot(-4.0, 0.0, 0.0, stand)
            agent = agent_spec(walk, robot=robot).build()
            assert run(w, agent, max_s=3.0).end == "timeout"  # walking on its line
            x, y = w.torso_pos_m()[:2]
            w.place_robot(float(x), float(y), turned_rad, stand)
            assert abs(w.torso_yaw_rad() - turned_rad) < 0.01
            getattr(agent, how)(w.observe())
            yaw_deg = []  # every 0.2 s over 10 s: the T1's torso swings +-15 deg with its steps
            for _ in range(50):
                assert run(w, agent, max_s=0.2, reset=False).end == "timeout"
                yaw_deg.append(math.degrees(w.torso_yaw_rad()))
            assert not w.fallen()
            end_yaw_deg[how] = sum(yaw_deg[-20:]) / 20  # over the last 4 s
    assert abs(end_yaw_deg["resume"]) < 10.0, end_yaw_deg
    assert end_yaw_deg["reset"] > 25.0, end_yaw_deg


def test_a_run_that_gets_up_plays_the_same_on_one_worker_and_two(tmp_path):
    # The T1 in the league's simulation, 4 m under game: on this seed its third run falls,
    # gets up and walks on; the table must not depend on where the runs played.
    config = WalkTrialConfig(
        disturb="game", world="league", start_x_m=-5.0, finish_x_m=-1.0, timeout_s=40.0
    )
    spec = agent_spec("other-team-walk", robot="t1")
    one, two = tmp_path / "one.parquet", tmp_path / "two.parquet"
    walk_trial([spec], runs=3, seed=5, workers=1, config=config, out=one)
    walk_trial([spec], runs=3, seed=5, workers=2, config=config, out=two)
    assert one.read_bytes() == two.read_bytes()
    runs = pl.read_parquet(one)
    assert runs["getups"].sum() >= 1 and runs["finished"].all()
