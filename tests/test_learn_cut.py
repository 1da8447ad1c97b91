"""Black-box recordings hold more than the motion: cut them, find a walk's period, and find
where a kick wanted the ball, from the recording alone."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import DatasetError
from mimic.learn.dataset import (
    NON_REPEATING_RAD,
    as_cyclic,
    average_jittery_joints,
    cut_dataset,
    dataset_from_frame,
    detect_period_s,
    drop_non_repeating,
)
from mimic.learn.train import training_dataset
from mimic.model.model_file import load_model
from mimic.recording import layout as L
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot

T1 = get_robot("t1")
NAO = get_robot("nao")


def _gait(period_s: float, seconds: float, dt: float = 0.04, robot=NAO, seed: int = 0):
    """Angles of a two-step gait: legs in antiphase (the left leg's cycle is the right's
    shifted by half a period), plus a little noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, dt)
    q = np.tile(np.asarray(robot.stand_pose_rad), (len(t), 1))
    phase = 2 * math.pi * t / period_s
    for i, name in enumerate(robot.joint_names):
        side = 1.0 if name.lower().startswith("left") else -1.0
        if "knee" in name.lower() or "hip_pitch" in name.lower():
            q[:, i] += 0.2 * np.sin(phase + (0 if side > 0 else math.pi))
            q[:, i] += 0.05 * np.sin(2 * phase)  # each step alike: a half-period part
    return t, q + rng.normal(0, 0.002, q.shape)


@pytest.mark.parametrize("period_s", [0.5, 0.84, 1.3])
def test_the_period_of_a_gait_is_its_two_step_cycle(period_s):
    t, q = _gait(period_s, 8.0)
    assert detect_period_s(t, q) == pytest.approx(period_s, rel=0.01)


def test_no_period_in_motion_that_does_not_repeat_or_is_too_short():
    t = np.arange(0, 6, 0.04)
    q = np.cumsum(np.random.default_rng(1).normal(0, 0.01, (len(t), 22)), axis=0)
    with pytest.raises(DatasetError, match="do not repeat"):
        detect_period_s(t, q)
    with pytest.raises(DatasetError, match="needs at least 0.6 s"):
        detect_period_s(t[:10], q[:10])


def test_a_cycle_leaves_out_what_does_not_repeat_it():
    """A black-box walk ends however the other team's process ends: here the robot, no longer
    driven, sags over its last second. Those samples, and a single glitch, are left out; the
    cycle's own samples all stay."""
    import polars as pl

    t, q = _gait(0.84, 9.0)
    q[-25:] += np.linspace(0, 0.6, 25)[:, None]  # the fall
    q[100, 3] += 0.2  # a glitch
    frame = pl.DataFrame({"time_s": t, **{n: q[:, i] for i, n in enumerate(NAO.joint_names)}})
    ds = as_cyclic(dataset_from_frame(frame, metadata={"source": "rec.mcap"}), 0.84)
    kept = drop_non_repeating(ds)
    dropped = np.setdiff1d(np.round(t, 4), np.round(kept.time_s, 4))
    assert kept.metadata["non_repeating"] == len(dropped)
    assert round(t[100], 4) in dropped  # the glitch
    assert np.all(dropped[dropped != round(t[100], 4)] > t[-25] - 1e-9)  # the fall's part
    # The fall's first samples stay within the limit (0.025 rad more each): the rest is out.
    within = int(NON_REPEATING_RAD / 0.025)
    assert 25 - within - 2 <= len(dropped) - 1 <= 25 - within + 1
    # One-shot motions are what they are; a motion that is not one cycle is refused.
    one_shot = dataset_from_frame(frame)
    assert drop_non_repeating(one_shot) is one_shot
    with pytest.raises(DatasetError, match="not one cyclic motion"):
        drop_non_repeating(as_cyclic(dataset_from_frame(frame), 0.61))


def test_a_cycle_of_jittery_joints_is_still_one_cycle():
    """A learned policy's joints jitter from one sample to the next (here two joints, 0.3 rad
    at 25 Hz): nearly every sample is off the cycle by more than 0.1 rad, and none of them is
    a glitch. The limit grows with each joint's own jitter: the cycle is kept, a glitch in a
    steady joint and the fall are still left out, and a wrong period is still refused."""
    import polars as pl

    t, q = _gait(0.84, 12.0)
    rng = np.random.default_rng(3)
    jitter = np.zeros((len(t), 2))
    for k in range(1, len(t)):  # AR(1), 0.4 kept per sample
        jitter[k] = 0.4 * jitter[k - 1] + math.sqrt(1 - 0.16) * rng.normal(0, 0.3, 2)
    q[:, :2] += jitter
    q[-25:] += np.linspace(0, 0.6, 25)[:, None]  # the fall
    q[100, 3] += 0.2  # a glitch
    frame = pl.DataFrame({"time_s": t, **{n: q[:, i] for i, n in enumerate(NAO.joint_names)}})
    ds = as_cyclic(dataset_from_frame(frame, metadata={"source": "rec.mcap"}), 0.84)
    with pytest.raises(DatasetError, match="not one cyclic motion"):
        drop_non_repeating(ds, jitters=0.0)  # the fixed limit alone: refused
    kept = drop_non_repeating(ds)
    dropped = np.setdiff1d(np.round(t, 4), np.round(kept.time_s, 4))
    assert round(t[100], 4) in dropped  # the glitch
    assert np.all(np.isin(np.round(t[-15:], 4), dropped))  # the fall, past 5 jitters
    assert len(kept.time_s) > 0.7 * len(t)
    with pytest.raises(DatasetError, match="not one cyclic motion"):
        drop_non_repeating(as_cyclic(dataset_from_frame(frame), 0.61))
    # What is learned of a jittery joint is its cycle's mean: a network fitted to the cloud
    # learns wiggles of its own. The steady joints stay as they are.
    mean = average_jittery_joints(kept)
    assert mean.metadata["jittery_joints"] == list(NAO.joint_names[:2])
    np.testing.assert_array_equal(mean.targets[:, 2:], kept.targets[:, 2:])
    np.testing.assert_array_equal(mean.time_s, kept.time_s)

    # The jitter (0.3 rad) averaged over the cycles at each phase (14 here).
    def head_rms(d):
        return float(np.sqrt(np.mean((d.targets[:, :2] - NAO.stand_pose_rad[:2]) ** 2)))

    assert head_rms(kept) > 0.25 and head_rms(mean) < 0.12
    steady = drop_non_repeating(as_cyclic(dataset_from_frame(pl.DataFrame({
        "time_s": t, **{n: _gait(0.84, 12.0)[1][:, i] for i, n in enumerate(NAO.joint_names)}
    })), 0.84))  # fmt: skip
    assert average_jittery_joints(steady) is steady


def test_a_cut_keeps_its_samples_timed_from_zero_and_ends_the_motion_there():
    t, q = _gait(1.0, 4.0)
    import polars as pl

    frame = pl.DataFrame({"time_s": t, **{n: q[:, i] for i, n in enumerate(NAO.joint_names)}})
    ds = dataset_from_frame(frame, metadata={"source": "rec.mcap"})
    cut = cut_dataset(ds, 1.0, 2.5)
    assert cut.time_s[0] == 0.0 and cut.time_s[-1] == pytest.approx(1.48)
    np.testing.assert_allclose(cut.angles_rad, q[(t >= 1.0 - 1e-9) & (t <= 2.5 + 1e-9)])
    assert cut.targets[-1, -1] == 1.0 and cut.targets[:-1, -1].sum() == 0
    assert cut.metadata["cut_s"] == [1.0, 2.48]
    cyclic = as_cyclic(cut, 1.0)
    assert cyclic.period_s == 1.0 and cyclic.targets[:, -1].sum() == 0
    for start, end, match in (
        (3.0, 2.0, "before --end"),
        (-1, 2, "before --end"),
        (3.95, None, "keeps 1"),
    ):
        with pytest.raises(DatasetError, match=match) as err:
            cut_dataset(ds, start, end)
        assert "\n" not in str(err.value) and "rec.mcap" in str(err.value)


def _black_box_kick(path, offset_xy=(0.3, -0.12), yaw=0.6):
    """A league-like recording: joint states, the torso pose and the ball on /tf, no motion
    metadata but the robot; the robot stands still 1 s, then 'kicks' (a knee swing)."""
    info = L.RecordingInfo(motion="others_5", agent="league player", robot="t1", world="league")
    t = np.arange(0.0, 3.0, 0.04)
    q = np.tile(np.asarray(T1.stand_pose_rad), (len(t), 1))
    knee = T1.joint_names.index("Right_Knee_Pitch")
    q[:, knee] += np.where(t > 1.0, 0.5 * np.sin(np.clip(t - 1.0, 0, None) * 3.0), 0.0)
    torso = np.array([2.0, -1.0, 0.65])
    quat = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    c, s = math.cos(yaw), math.sin(yaw)
    ball = torso[:2] + np.array(
        [c * offset_xy[0] - s * offset_xy[1], s * offset_xy[0] + c * offset_xy[1]]
    )
    with RecordingWriter(path, info) as w:
        for k, tk in enumerate(t):
            ns = int(round(tk * L.NS_PER_S))
            w.write_joints(ns, q[k])
            w.write_tf(
                ns,
                [L.WORLD_FRAME, L.WORLD_FRAME],
                [T1.root_link, L.BALL_FRAME],
                np.array([torso, [*ball, 0.07]]),
                np.array([quat, [1.0, 0, 0, 0]]),
            )
    return t, q


def test_training_cuts_a_black_box_kick_and_finds_where_it_wanted_the_ball(tmp_path):
    path = tmp_path / "seen.mcap"
    _, q = _black_box_kick(path)
    ds = training_dataset(path, L.JOINT_STATES, "reached", start_s=0.8, end_s=2.6)
    assert ds.time_s[0] == 0.0 and ds.time_s[-1] == pytest.approx(1.8)
    assert ds.metadata["ball_offset_m"] == pytest.approx([0.3, -0.12], abs=1e-3)
    # From the command line: the model carries the cut and the ball offset.
    out = tmp_path / "seen.mimic"
    res = CliRunner().invoke(
        app,
        [
            "train",
            str(path),
            "--start",
            "0.8",
            "--end",
            "2.6",
            "--target",
            "reached",
            "-o",
            str(out),
            "--epochs",
            "300",
        ],
    )
    assert res.exit_code == 0, res.output
    assert "interrupted" not in res.output and "never ends" not in res.output  # a chosen piece
    meta = load_model(out).metadata
    assert meta["cut_s"] == [0.8, 2.6] and meta["ball_offset_m"] == pytest.approx(
        [0.3, -0.12], abs=1e-3
    )
    res = CliRunner().invoke(
        app, ["train", str(path), "--period", "x", "-o", str(tmp_path / "x.mimic")]
    )
    assert (
        res.exit_code == 2
        and "--period must be a number of seconds, 'auto' or 'steps'" in res.output
    )


def test_a_ball_lying_aside_is_not_a_kicks_ball(tmp_path):
    path = tmp_path / "aside.mcap"
    _black_box_kick(path, offset_xy=(0.1, -3.0))  # where our recorder puts an unused ball
    ds = training_dataset(path, L.JOINT_STATES, "reached", start_s=0.8, end_s=2.6)
    assert "ball_offset_m" not in ds.metadata
