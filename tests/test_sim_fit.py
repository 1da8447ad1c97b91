"""A walk's references fitted in a simulation of the copy (``improve.sim_fit``,
``mimic train --fit-in-sim``).

The T1 other team's policy-like walk is recorded in our world, learned step by step, and the copy
walked again in our world (where the recording was made) until its joints follow the recording.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.improve.sim_fit import (
    SENSITIVITY_RANGE,
    FitCheck,
    SimFit,
    SimFitConfig,
    SimFitRound,
    _binned,
    _periodic_interp,
    _sensitivity,
    _smooth,
    fit_in_simulation,
    fitted_dataset,
    sim_fit_world,
)
from mimic.model.keys import SIM_FIT_KEY
from mimic.robot.registry import get_robot
from mimic.world.registry import LEAGUE_LIKE, MUJOCO
from tests._cli_helpers import one_line_error

runner = CliRunner()


def test_the_cycle_tables_bin_smooth_and_interpolate_around_the_cycle():
    phase = np.linspace(0, 1, 400, endpoint=False)
    values = np.stack([np.sin(2 * np.pi * phase), np.cos(2 * np.pi * phase)], axis=1)
    table = _binned(phase, values, 20)
    centres = (np.arange(20) + 0.5) / 20
    assert np.allclose(table[:, 0], np.sin(2 * np.pi * centres), atol=0.02)
    # A bin no sample fell in is NaN, not zero.
    assert np.isnan(_binned(np.array([0.01, 0.02]), values[:2], 4)[2]).all()
    # Smoothing keeps a constant and the mean, and spreads a spike to its neighbours.
    weights = SimFitConfig().smoothing
    assert np.allclose(_smooth(np.ones((10, 2)), weights), 1.0)
    spike = np.zeros((10, 1))
    spike[0] = 1.0
    smoothed = _smooth(spike, weights)
    assert smoothed.sum() == pytest.approx(1.0) and smoothed[0, 0] == pytest.approx(0.4)
    assert smoothed[9, 0] == pytest.approx(0.2) and smoothed[1, 0] == pytest.approx(0.2)
    # Between bin centres the table is linear, and it wraps from the last bin to the first.
    assert np.allclose(_periodic_interp(table, centres), table)
    at_edge = _periodic_interp(table, np.array([0.0, 1.0, 2.0]))
    assert np.allclose(at_edge, 0.5 * (table[0] + table[-1]))
    fit = SimFit(table, (SimFitRound(0, 0.1, 0.4, False, 10.0),), 0, MUJOCO)
    assert np.allclose(fit.at_phase(centres + 3), table)


def test_the_sensitivity_is_the_share_of_a_step_that_a_joint_followed():
    step = np.random.default_rng(0).normal(0, 0.02, (50, 4))
    followed = np.array([0.5, 0.1, 1.3, 0.8])
    # The error shrinks by what each joint followed of the step.
    seen = _sensitivity(step, -step * followed, np.full(4, 0.7))
    low, high = SENSITIVITY_RANGE
    assert seen == pytest.approx([0.5, low, high, 0.8])
    # A step too small to tell keeps what was known; a bin the walk never reached (NaN)
    # counts as no change.
    assert _sensitivity(step * 1e-3, -step * 1e-3, np.full(4, 0.7)) == pytest.approx(0.7)
    change = -step * 0.5
    change[0] = np.nan
    assert _sensitivity(step, change, np.ones(4))[0] == pytest.approx(0.5, abs=0.05)


def test_a_fitted_copy_is_kept_when_it_falls_no_more_and_walks_no_slower():
    def check(falls, speed):
        return FitCheck((1, 2, 3), falls, speed)

    assert check((0, 0), (0.38, 0.40)).fitted_better
    assert check((2, 1), (0.30, 0.30)).fitted_better
    assert not check((0, 1), (0.38, 0.45)).fitted_better  # faster, but it fell
    assert not check((0, 0), (0.40, 0.39)).fitted_better
    said = check((0, 2), (0.4, 0.41)).describe()
    assert "fell 0 of 3" in said and "fell 2 of 3" in said and "kept the copy as learned" in said
    assert check((0, 0), (0.38, 0.4)).summary()["fitted_kept"] is True


def test_a_config_that_cannot_fit_is_refused():
    with pytest.raises(MimicError, match="1 round at least"):
        SimFitConfig(rounds=0)
    with pytest.raises(MimicError, match="gain"):
        SimFitConfig(gain=1.5)
    with pytest.raises(MimicError, match="1 walk at least"):
        SimFitConfig(check_walks=0)


@pytest.fixture(scope="module")
def walk(policy_walk_recording, tmp_path_factory):
    """(recording, the copy learned step by step) of the T1's policy-like walk in our world."""
    rec, copy = policy_walk_recording, tmp_path_factory.mktemp("simfit") / "copy.mimic"
    said = runner.invoke(
        app,
        [
            "train", str(rec), "--start", "1", "--period", "steps", "--symmetric",
            "--epochs", "400", "-o", str(copy),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    return rec, copy


def test_the_fit_brings_the_copys_joints_closer_to_the_recording(walk):
    from mimic.learn.train import TARGET_REACHED, training_dataset
    from mimic.model.model_file import load_model

    rec, copy = walk
    model = load_model(copy)
    recorded = training_dataset(
        rec, start_s=1, period="steps", symmetric=True, topic="/joint_states",
        target=TARGET_REACHED,
    )  # fmt: skip
    assert recorded.period_s == pytest.approx(model.period_s)
    # Recorded in our world, so fitted there (a league recording is fitted league-like).
    assert sim_fit_world(recorded) == MUJOCO
    league = replace(recorded, metadata={**recorded.metadata, "recording_world": "league"})
    assert sim_fit_world(league) == LEAGUE_LIKE
    seen = []
    # At the learned rate (the speed hold off): the copy's step timing stays the recording's,
    # so what the rounds change is the correction alone.
    config = SimFitConfig(rounds=3, speed_hold=False)
    fit = fit_in_simulation(model, recorded, config, progress=seen.append)
    assert [r.index for r in seen] == [0, 1, 2, 3] and fit.rounds == tuple(seen)
    assert fit.world == MUJOCO
    # The kept round is one that walked, and it follows the recording more closely than the
    # copy as learned did.
    assert fit.kept > 0 and not fit.best.fell
    assert fit.best.rms_rad < 0.8 * fit.first.rms_rad
    assert fit.correction_rad.shape == (SimFitConfig().phase_bins, model.num_joints)
    assert 0 < np.abs(fit.correction_rad).max() < 0.3
    # Symmetric: the correction half a cycle on is the mirrored one.
    half = np.roll(fit.correction_rad, -25, axis=0)
    mirrored = get_robot(model.robot).mirror_angles(half)
    largest = np.abs(fit.correction_rad).max()
    assert np.abs(mirrored - fit.correction_rad).max() < 0.05 * largest + 1e-3
    # The training data takes the correction at each sample's phase.
    train = training_dataset(rec, start_s=1, period="steps", symmetric=True)
    fitted = fitted_dataset(train, fit)
    phase = (train.time_s % train.period_s) / train.period_s
    moved = fitted.targets[:, :-1] - train.targets[:, :-1]
    assert np.allclose(moved, fit.at_phase(phase))
    assert fitted.metadata[SIM_FIT_KEY]["kept_round"] == fit.kept


def test_train_fit_in_sim_prints_the_fit_and_records_it(walk, tmp_path):
    from mimic.model.model_file import load_model

    rec, _ = walk
    out = tmp_path / "fitted.mimic"
    said = runner.invoke(
        app,
        [
            "train", str(rec), "--start", "1", "--period", "steps", "--symmetric",
            "--epochs", "300", "--fit-in-sim", "2", "-o", str(out),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    assert "fitted in the mujoco world, 2 rounds" in said.output, said.output
    # The network trained on the fitted references and the copy as learned walk from three
    # other starts; the one that fell less (and then walked faster) is written.
    assert "check walks from 3 other starts" in said.output, said.output
    facts = load_model(out).metadata[SIM_FIT_KEY]
    assert facts["world"] == MUJOCO and facts["rounds"] == 2
    assert facts["rms_rad"][1] <= facts["rms_rad"][0]
    check = facts["check"]
    assert check["seeds"] == [1, 2, 3] and len(check["falls"]) == 2
    falls, speed = check["falls"], check["speed_m_s"]
    assert check["fitted_kept"] == (falls[1] <= falls[0] and speed[1] >= speed[0])
    said_kept = "kept the fitted copy" if check["fitted_kept"] else "kept the copy as learned"
    assert said_kept in said.output


def test_fit_in_sim_refuses_what_it_cannot_fit(tmp_path):
    rec = tmp_path / "stand.mcap"
    said = runner.invoke(app, ["record", "stand", "--duration", "0.5", "-o", str(rec)])
    assert said.exit_code == 0, said.output
    out = tmp_path / "x.mimic"
    said = runner.invoke(app, ["train", str(rec), "--fit-in-sim", "2", "-o", str(out)])
    one_line_error(said, 2, "--fit-in-sim fits a walk")
    said = runner.invoke(
        app, ["train", str(rec), "--period", "0.5", "--fit-in-sim", "-1", "-o", str(out)]
    )
    one_line_error(said, 2, "--fit-in-sim")
    assert not out.exists()
