"""Symmetric cycles (``mimic train --symmetric``): a straight walk learned as the mean of each
step and its mirrored twin, so the copy does not replay the recording's own leans and turns.

The T1 other team's walk is recorded in our world (angles and body poses), and a lean to the
left is added to its hip rolls: the kind of one-sided correction a black-box recording holds.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import DatasetError
from mimic.learn.dataset import as_cyclic, dataset_from_frame, symmetric_cycle
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.model.foot_track import FootTrack
from mimic.model.keys import FOOT_TRACK_KEY
from mimic.model.model_file import load_model
from mimic.recording import layout as L
from mimic.recording.recorder import record
from mimic.robot.registry import get_robot

runner = CliRunner()
RECORDINGS = Path(__file__).resolve().parents[1] / "recordings"
#: The lean added to both hip rolls [rad]: the left hip opens, the right one closes.
LEAN_RAD = 0.06


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    from mimic.agents.registry import make_agent

    path = tmp_path_factory.mktemp("sym") / "t1_walk.mcap"
    record(make_agent("other-team-walk", robot="t1"), path, duration_s=6.0)
    return path


def _leaning(ds):
    """The dataset with ``LEAN_RAD`` added to both hip rolls (the same sign on both: a lean
    to one side, not a symmetric stance)."""
    q = ds.angles_rad.copy()
    for name in ds.joint_names:
        if "hip_roll" in name.lower():
            q[:, ds.joint_names.index(name)] += LEAN_RAD
    return ds.with_angles(q)


def _asymmetry_rad(model, joint: str) -> float:
    """Mean over the cycle of the model's ``joint`` and its mirror joint half a cycle later,
    mirrored: 0 for a symmetric cycle [rad]."""
    robot = get_robot(model.robot)
    period = model.period_s
    t = np.linspace(0.0, period, 40, endpoint=False)
    q, later = model.predict(t)[:, :-1], model.predict(t + period / 2)[:, :-1]
    mirrored = robot.mirror_angles(later)
    i = model.joint_names.index(joint)
    return float(np.mean(q[:, i] - mirrored[:, i]))


def test_a_symmetric_copy_does_not_keep_the_recordings_lean(recording):
    robot = get_robot("t1")
    roll = next(j.name for j in robot.joints if "hip_roll" in j.name.lower() and j.mirror_sign < 0)
    ds = training_dataset(recording, L.JOINT_STATES, start_s=2.5, period="auto")
    leaning = _leaning(ds)
    sym = symmetric_cycle(leaning)
    # Every sample and its mirror image half a cycle on, in time order.
    assert sym.n_samples == 2 * leaning.n_samples and np.all(np.diff(sym.time_s) >= 0)
    assert sym.metadata["symmetric"] and sym.period_s == leaning.period_s
    config = TrainConfig(FAST, epochs=400)
    plain, symmetric = train_model(leaning, config), train_model(sym, config)
    # The plain copy replays the lean: its roll differs from the mirrored other hip's by the
    # lean twice over (+lean on one side, the other side's +lean mirrored to -lean).
    assert _asymmetry_rad(plain, roll) == pytest.approx(2 * LEAN_RAD, abs=0.02)
    # The symmetric copy learned the mean of both steps: no lean left.
    assert abs(_asymmetry_rad(symmetric, roll)) < 0.01
    # Its steps are still the walk's: the knee swings as much as the plain copy's does.
    knee = next(j.name for j in robot.joints if "knee" in j.name.lower())
    t = np.linspace(0.0, sym.period_s, 40, endpoint=False)
    k = sym.joint_names.index(knee)
    swing = np.ptp(symmetric.predict(t)[:, k])
    assert swing == pytest.approx(np.ptp(plain.predict(t)[:, k]), rel=0.2) and swing > 0.1


def test_a_symmetric_foot_track_mirrors_each_foot_half_a_cycle_on(recording):
    ds = training_dataset(recording, L.JOINT_STATES, start_s=2.5, period="auto", symmetric=True)
    track = FootTrack.from_metadata(ds.metadata[FOOT_TRACK_KEY])
    for phase in np.linspace(0.0, 1.0, 12, endpoint=False):
        left, right_later = track.at(phase)[0], track.at(phase + 0.5)[1]
        assert left == pytest.approx(right_later * np.array([1.0, -1.0]), abs=0.01)
    # The feet stay on their own sides.
    assert track.left_m[:, 1].min() > 0.03 and track.right_m[:, 1].max() < -0.03


def test_only_a_cycle_can_be_made_symmetric():
    import polars as pl

    robot = get_robot("t1")
    frame = pl.DataFrame(
        {"time_s": np.arange(50) * 0.02, **{j.name: np.zeros(50) for j in robot.joints}}
    )
    one_shot = dataset_from_frame(frame, robot=robot)
    with pytest.raises(DatasetError, match="only a cyclic motion"):
        symmetric_cycle(one_shot)
    # A cycle standing still is its own mirror image: nothing changes but the sample count.
    still = symmetric_cycle(as_cyclic(one_shot, 0.8))
    assert still.n_samples == 100 and np.all(still.angles_rad == 0)


def test_train_symmetric_from_the_command_line(recording, tmp_path):
    out = tmp_path / "walk.mimic"
    said = runner.invoke(
        app,
        ["train", str(recording), "--start", "2.5", "--period", "auto", "--symmetric",
         "--epochs", "200", "-o", str(out)],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    model = load_model(out)
    assert model.cyclic and model.metadata["symmetric"]
    # A kick has no half cycle to mirror: one line, no model written.
    bad, kick = tmp_path / "kick.mimic", RECORDINGS / "kick_right.mcap"
    said = runner.invoke(app, ["train", str(kick), "--symmetric", "-o", str(bad)])
    assert said.exit_code != 0 and "cyclic" in said.output and "Traceback" not in said.output
    assert not bad.exists()
    said = runner.invoke(
        app, ["train", str(recording), str(recording), "--merge", "--symmetric", "-o", str(bad)]
    )
    assert said.exit_code != 0 and "--merge" in said.output and not bad.exists()
