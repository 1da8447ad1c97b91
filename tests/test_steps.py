"""A walk's steps from its feet (``learn.steps``), and learning a walk that never repeats.

The policy-like walk (``other-team-policy-walk``) is recorded in our world with the T1, its
steps found and learned as one cycle of its mean step pair (``mimic train --period steps``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import DatasetError
from mimic.learn.steps import find_steps

runner = CliRunner()


def _feet(durations_s, dt_s=0.04, lift_m=0.05):
    """(time, feet heights, true touchdowns) of steps of the given durations: each step's
    swing foot rises on a half sine and lands at the step's end; the first swings the right
    foot (so the first touchdown is the right's)."""
    touchdowns = np.concatenate([[0.0], np.cumsum(durations_s)])
    t = np.arange(-0.2, touchdowns[-1] + 0.2, dt_s)
    z = np.zeros((len(t), 2))
    for i, (a, b) in enumerate(zip(touchdowns[:-1], touchdowns[1:])):
        swing = 1 if i % 2 == 0 else 0  # right, left, right, ...
        at = (t > a + 0.1 * (b - a)) & (t < b)
        u = (t[at] - (a + 0.1 * (b - a))) / (0.9 * (b - a))
        z[at, swing] = lift_m * np.sin(np.pi * u)
    return t, z, touchdowns


def test_steps_of_varying_duration_are_found_and_timed_on_their_own():
    rng = np.random.default_rng(3)
    durations = rng.uniform(0.3, 0.5, 24)
    t, z, truth = _feet(durations)
    steps = find_steps(t, z)
    # Every landing after the first swing is found; a touchdown reads where the foot comes
    # within a fifth of its lift (a fixed, small lead on the true landing).
    found = steps.touchdown_s
    assert len(found) == len(truth) - 1
    lead = truth[1:] - found
    assert np.all(lead >= 0) and np.all(lead < 0.06)
    assert np.ptp(lead) < 0.03
    assert steps.count == len(durations) - 1
    assert steps.durations_s.min() < 0.33 and steps.durations_s.max() > 0.47
    assert steps.period_s == pytest.approx(2 * steps.durations_s.mean())
    # The first touchdown is the right foot's (the first step swung it): phase 0.5.
    assert not steps.left_first
    w = steps.warped_s[steps.keep]
    assert np.all(np.diff(w) > 0)
    phase = (w / steps.period_s) % 1.0
    first = t[steps.keep][0]
    assert first >= found[0] and phase[0] == pytest.approx(0.5, abs=0.1)
    # Samples at the same point of their steps share a phase, whatever the steps' lengths.
    mid = [(a + b) / 2 for a, b in zip(found[:-1], found[1:])]
    near = [int(np.argmin(np.abs(t - m))) for m in mid]
    ph = (steps.warped_s[near] / steps.period_s) % 0.5
    assert np.ptp(ph) < 0.12  # one 40 ms sample of a 0.3-0.5 s step either way
    s = steps.summary()
    assert s["count"] == steps.count and s["min_s"] <= s["mean_s"] <= s["max_s"]
    assert "steps" in steps.describe()


def test_a_step_out_of_turn_is_left_out():
    t, z, _ = _feet([0.4] * 12)
    # The right foot stays down for its fifth swing (1.6-2.0 s): the left touches down twice
    # in a row, and the steps around the missing one are no part of the walk.
    z2 = z.copy()
    z2[(t > 1.6) & (t < 2.0), 1] = 0.0
    clean, bumped = find_steps(t, z), find_steps(t, z2)
    assert bumped.count < clean.count
    assert bumped.period_s == pytest.approx(clean.period_s, rel=0.05)


@pytest.mark.parametrize(
    "feet, says",
    [
        (np.zeros((100, 2)), "never rise"),
        (None, "a walk needs two at least"),
    ],
)
def test_no_walk_is_one_clear_error(feet, says):
    if feet is None:
        t, feet, _ = _feet([0.4])
    else:
        t = np.arange(100) * 0.04
    with pytest.raises(DatasetError, match=says):
        find_steps(t, feet, "rec.mcap")


def test_the_policy_walk_never_repeats_its_steps(policy_walk_recording):
    from mimic.learn.train import training_dataset

    ds = training_dataset(policy_walk_recording, start_s=1, period="steps")
    steps = ds.metadata["steps"]
    # Step times wander within 12 s (the league benchmark measures their whole spread).
    assert steps["count"] >= 20
    assert steps["max_s"] >= 1.15 * steps["min_s"] and steps["std_s"] > 0.01
    assert ds.metadata["step_phase"] and ds.period_s == pytest.approx(2 * steps["mean_s"], abs=1e-3)
    assert 0.2 < ds.metadata["walk_speed_m_s"] < 0.8
    # One fixed period cannot hold it: found in the angles, most samples do not repeat.
    with pytest.raises(DatasetError, match="not one cyclic motion|do not repeat"):
        training_dataset(policy_walk_recording, start_s=1, period="auto")


def test_train_prints_the_steps_and_refuses_a_multiple_of_the_cycle(
    policy_walk_recording, tmp_path
):
    from mimic.learn.train import training_dataset

    cycle_s = training_dataset(policy_walk_recording, start_s=1, period="steps").period_s
    said = runner.invoke(
        app,
        [
            "train", str(policy_walk_recording), "--start", "1", "--period", "steps",
            "--symmetric", "--epochs", "300", "-o", str(tmp_path / "copy.mimic"),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    assert "steps from the feet" in said.output and f"period {cycle_s:.3f} s" in said.output
    assert re.search(r"s, -\d+ %/\+\d+ %\); period", said.output), said.output
    for multiple in (2, 3):
        said = runner.invoke(
            app,
            [
                "train", str(policy_walk_recording), "--start", "1", "--period",
                f"{multiple * cycle_s:.3f}", "-o", str(tmp_path / f"x{multiple}.mimic"),
            ],
        )  # fmt: skip
        assert said.exit_code == 2
        assert f"{multiple}.0 cycles of its steps" in said.output
        assert not (tmp_path / f"x{multiple}.mimic").exists()


def test_the_policy_walk_steers_and_adapts_its_step_time():
    """Its turn command flips sign every few steps and its step time changes step by step,
    at most one cycle at a time (our world, the T1)."""
    from mimic.agents.other_team_t1 import make_policy_walk
    from mimic.episode import Episode
    from mimic.tasks.walk import WalkTrialConfig, walk_scene
    from mimic.world.registry import open_world

    with open_world("mujoco", "t1") as world:
        walk_scene(WalkTrialConfig()).setup(world, np.random.default_rng(5))
        agent = make_policy_walk()
        Episode(world).run(agent, max_s=10.0, abort_on_fall=False)
    steps = np.array(agent.steps)
    cycles = np.round(steps[:, 0] / 0.02).astype(int)
    assert len(steps) >= 15
    assert np.abs(np.diff(cycles)).max() <= 1 and len(set(cycles)) >= 3
    turn = steps[:, 3]
    assert np.abs(turn).max() <= 0.25 + 1e-9 and (np.diff(np.sign(turn)) != 0).sum() >= 3
    assert np.all(steps[:, 1] == pytest.approx(0.45))


def test_a_learned_walk_holds_a_commanded_speed_by_its_phase_rate(policy_walk_recording, tmp_path):
    """A step-phase copy carries the speed its recording walked and holds it (or --vx) by its
    phase rate, the phase continuous; without a command it plays at its learned rate."""
    from mimic.agents.neural_player import RATE_RANGE, NeuralPlayer
    from mimic.model.model_file import load_model

    out = tmp_path / "copy.mimic"
    said = runner.invoke(
        app,
        [
            "train", str(policy_walk_recording), "--start", "1", "--period", "steps",
            "--epochs", "300", "-o", str(out),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    model = load_model(out)
    assert NeuralPlayer(model).speed_m_s == model.metadata["walk_speed_m_s"]
    player = NeuralPlayer(model, speed_m_s=0.3)
    player.reset(_obs(model, 0.0, 0.0))
    before = player.played_s(10.0)
    player.retime(1.1, 10.0)
    assert player.played_s(10.0) == pytest.approx(before)
    assert player.played_s(11.0) == pytest.approx(before + 1.1)
    # Walking too slowly after the start-up: the rate rises, never past its range.
    t = player.stance_s + player.start_ramp_s + 0.01
    for k in range(400):
        player.act(_obs(model, t + k * 0.02, 0.001 * k))
    assert player.speed_rate == pytest.approx(RATE_RANGE[1])
    said = runner.invoke(app, ["trial", "walk", "--compare", "kick_right", str(out), "--vx", "0.3"])
    assert said.exit_code == 2 and "takes no speed command" in said.output


def _obs(model, time_s, x_m):
    from mimic.world.base import Observation

    n = model.num_joints
    return Observation(
        time_s, np.zeros(n), np.zeros(n), np.zeros(3), np.zeros(3), np.array([1.0, 0, 0, 0]),
        np.zeros(2), np.array([x_m, 0.0, 0.6]), np.zeros(3),
    )  # fmt: skip


def test_a_robots_own_behaviour_on_another_robot_is_one_line():
    said = runner.invoke(app, ["trial", "walk", "other-team-policy-walk", "--runs", "1"])
    assert said.exit_code == 2
    assert "behaviour of the T1 only" in said.output and "Traceback" not in said.output
