"""Tasks as objects (issue 32): a new trial is one task class plus its registration, and
every trial's table, files and dashboard come from its task."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import polars as pl
import pyarrow.parquet as pq
import pytest
import typer
from typer.testing import CliRunner

from mimic.agents.hold import HoldPose
from mimic.agents.registry import AgentSpec
from mimic.cli import trial as cli_trial
from mimic.cli.main import app
from mimic.episode import Episode, PoseNoise, Scene
from mimic.stats import wilson_interval
from mimic.tasks import registry
from mimic.tasks.base import Column, Dashboard, EpisodeBatch, TaskOption, TrialTask, ci_columns
from mimic.trials.api import run_trial
from mimic.world.registry import open_world

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class StandConfig:
    # How long the robot holds its stand [s].
    hold_s: float = 1.0
    # Start-pose noise of the joints [rad].
    joint_noise_rad: float = 0.02
    world: str = "mujoco"
    disturb: str = "none"
    trace: bool = False


def run_stand_episode(spec: AgentSpec, seed: int, config: StandConfig):
    with open_world(config.world, spec.robot) as world:
        scene = Scene(robot_xy_m=(0.0, 0.0), noise=PoseNoise(joint_rad=config.joint_noise_rad))
        episode = Episode(world)
        scene.setup(world, np.random.default_rng(seed), observers=episode.watchers)
        robot = world.robot
        outcome = episode.run(HoldPose(robot.stand_pose(), robot.name), max_s=config.hold_s)
        row = dict(
            seed=seed,
            stood=outcome != "fell",
            torso_height_m=float(world.torso_pos_m()[2]),
            duration_s=world.time_s,
            falls=int(outcome == "fell"),
            world=config.world,
        )
        return [row], row


def stand_summary(label: str, batch: EpisodeBatch) -> dict:
    runs = pl.DataFrame(batch.rows)
    stood = int(runs["stood"].sum())
    return dict(
        variant=label,
        runs=runs.height,
        stood_pct=100.0 * stood / runs.height,
        **ci_columns("stood_pct", wilson_interval(stood, runs.height), 100.0),
        mean_height_m=runs["torso_height_m"].mean(),
        world=runs["world"][0],
    )


class StandTask(TrialTask):
    """A task written in a test, as a user would add one: hold the stand pose."""

    name = "stand"
    summary = "Stand trial: hold the stand pose from a noisy start."
    Config = StandConfig
    Objective = None
    options = (TaskOption("hold_s", "--hold-s", "Time to hold the stand [s]."),)
    columns = (
        Column("variant", "variant"),
        Column("runs", "runs"),
        Column("stood_pct", "stood %", "stood_pct", "range"),
        Column("mean_height_m", "height m"),
    )
    legend = "stood: runs that did not fall in {hold_s:g} s."
    ratio_columns = ("mean_height_m",)
    ratio_sources = {"mean_height_m": "torso_height_m"}
    dashboard = Dashboard(
        curves=("torso_height_m",), histogram="torso_height_m", histogram_bins=(0.0, 1.0, 0.05)
    )
    run_episode = staticmethod(run_stand_episode)
    summarise = staticmethod(stand_summary)

    @classmethod
    def default_variant(cls, robot: str, config: StandConfig) -> str:
        return "stand"


def test_a_new_trial_is_one_task_class_and_its_registration(tmp_path, monkeypatch):
    """The runner, the command, its table, its parquet and its dashboard come from the task."""
    monkeypatch.setitem(registry.TASKS, StandTask.name, StandTask)
    result = run_trial("stand", [AgentSpec("behaviour", "stand")], runs=2, seed=4, workers=1)
    assert result.summary["runs"].to_list() == [2] and result.rows.height == 2
    assert result.summary["stood_pct"].to_list() == [100.0]

    one = typer.Typer()
    one.command("stand")(cli_trial._trial_command(StandTask))
    one.command("other")(lambda: None)  # two commands: the name is the subcommand
    out, rrd = tmp_path / "stand.parquet", tmp_path / "stand.rrd"
    done = CliRunner().invoke(
        one,
        ["stand", "--runs", "2", "--hold-s", "0.5", "--workers", "1", "-o", str(out)]
        + ["--save", str(rrd)],
    )
    assert done.exit_code == 0, done.output
    text = " ".join(done.output.split())  # the table wraps at the test console's width
    assert "stand trial, 2 runs per variant, seed 0" in text
    assert "stood: runs that did not fall in 0.5 s." in text
    meta = pq.read_schema(out).metadata[b"mimic"].decode()
    assert '"kind": "stand"' in meta and '"hold_s": 0.5' in meta
    printed = subprocess.run(
        [str(Path(sys.executable).parent / "rerun"), "rrd", "print", str(rrd)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert printed.returncode == 0, printed.stderr
    assert "trial/torso_height_m/stand" in printed.stdout


def test_the_getup_trial_saves_its_own_dashboard(tmp_path):
    """Each task's dashboard draws its own rows (a get-up has no speed to plot)."""
    rrd = tmp_path / "getup.rrd"
    done = CliRunner().invoke(
        app,
        ["trial", "getup", "--runs", "1", "--workers", "1", "--disturb", "none"]
        + ["--save", str(rrd)],
    )
    assert done.exit_code == 0, done.output
    printed = subprocess.run(
        [str(Path(sys.executable).parent / "rerun"), "rrd", "print", str(rrd)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert printed.returncode == 0, printed.stderr
    assert "trial/time_to_stand_s/getup_front" in printed.stdout


@pytest.mark.parametrize("name", sorted(registry.TASKS))
def test_every_registered_task_is_complete(name):
    """What the runner, improve, the CLI and the viewer ask of a task, every task has."""
    task = registry.TASKS[name]
    config = task.Config()
    assert task.summary and task.legend.format_map(vars(config))
    assert task.default_variant("nao", config)
    assert task.Objective is not None and task.Objective().trial_config == config
    for column in task.columns:
        assert column.ci is None or column.ci_how in ("half", "range", "range %")
    assert set(task.ratio_sources) <= set(task.ratio_columns)
    assert task.dashboard.histogram and task.dashboard.series


def test_no_trial_code_outside_tasks_asks_which_task_it_runs():
    """Trials, improve, the CLI and the viewer never switch on a task's kind."""
    found = subprocess.run(
        ["grep", "-rn", "-e", 'kind == "', "-e", 'kind != "', "-e", 'name == "kick"', "."],
        cwd=ROOT / "toolkit" / "mimic",
        capture_output=True,
        text=True,
    ).stdout.splitlines()
    trial_switches = [
        line
        for line in found
        if not line.startswith(("./tasks/", "./world/"))
        and any(k in line for k in ('"kick"', '"walk"', '"getup"'))
    ]
    assert trial_switches == []
