"""A get-up copy fitted until it follows its recording (``mimic improve --follow``), and the
offset track of a windowed correction it is written as."""

from __future__ import annotations

import numpy as np
import pytest
from test_getups import _black_box_getup
from test_improve import N, _tiny_model
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.improve.correction import WINDOW_RAMP_S, windowed_model
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.model.model_file import load_model, save_model
from mimic.model.windowed import WindowedModel, window_weight
from mimic.recording import layout as L


def test_an_offset_track_acts_in_its_window_between_its_knots_and_its_file_keeps_it(tmp_path):
    """A windowed correction with a track: the offsets vary linearly between the knots, held
    beyond the last, faded in with the window; the file loads back to the same references."""
    model = _tiny_model()
    knots = np.array([0.6, 0.8, 1.0])
    values = np.zeros((3, N))
    values[:, 2] = [0.1, -0.1, 0.05]
    fixed = windowed_model(model, 1.0, (0.6, 2.0), np.zeros(N), np.ones(N), track=(knots, values))
    t = np.array([0.3, 0.7, 0.9, 1.2])
    shift = fixed.predict(t)[:, :N] - model.predict(t)[:, :N]
    want = window_weight(t, 0.6, 2.0) * np.array([0.1, 0.0, -0.025, 0.05])
    assert np.allclose(shift[:, 2], want, atol=1e-12)
    assert np.allclose(np.delete(shift, 2, axis=1), 0.0, atol=1e-12)
    assert shift[0, 2] == 0.0 and 0.0 < window_weight(np.array([0.7]), 0.6, 2.0)[0] < 1.0
    written = load_model(save_model(fixed, tmp_path / "track.mimic"))
    assert isinstance(written, WindowedModel)
    grid = np.linspace(0.0, fixed.duration_s, 41)
    assert np.allclose(written.predict(grid), fixed.predict(grid), atol=1e-9)
    with pytest.raises(ValueError, match="increase"):
        windowed_model(model, 1.0, (0.6, 2.0), np.zeros(N), np.ones(N), track=(knots[::-1], values))


def test_follow_fits_a_black_box_get_up_copy_from_just_after_it_faces_the_ground(tmp_path):
    """``mimic improve COPY --objective getup --follow REC``: the copy of a get-up that starts
    on its front is played in the league-like trial; the window starts 0.2 s after it first
    faced the ground, the references before it stay as learned, the track is a correction of
    the legs only, and the file written plays on."""
    rec, copy, out = tmp_path / "seen.mcap", tmp_path / "copy.mimic", tmp_path / "fit.mimic"
    _black_box_getup(rec)
    ds = training_dataset(rec, L.JOINT_STATES, "reached", start_s=0.0, end_s=3.9)
    save_model(train_model(ds, TrainConfig(epochs=40)), copy)
    said = CliRunner().invoke(
        app,
        [
            "improve", str(copy), "--objective", "getup", "--follow", str(rec), "--budget", "2",
            "--episodes", "1", "--world", "league-like", "-o", str(out),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    assert "round 1: followed to" in said.output and "--follow: window from" in said.output
    fitted, learned = load_model(out), load_model(copy)
    assert isinstance(fitted, WindowedModel) and fitted.track_s is not None
    start = fitted.window_s[0]
    assert 0.2 <= start < 1.0  # lying on its front from the start: after 0.2 s and a little
    early = np.linspace(0.0, start, 7)
    assert np.allclose(fitted.predict(early), learned.predict(early), atol=1e-12)
    legs = [
        i
        for i, n in enumerate(learned.joint_names)
        if any(k in n for k in ("Hip", "Knee", "Ankle"))
    ]
    others = np.delete(fitted.track_offsets_rad, legs, axis=1)
    assert np.all(others == 0.0)
    assert fitted.track_s[0] == pytest.approx(start - WINDOW_RAMP_S)
    # The recording's own speed from the window on: the copy is not warped, so no change.
    assert fitted.warp_rate == pytest.approx(1.0)
    with pytest.raises(MimicError, match="window"):
        from mimic.improve.follow import follow_recording
        from mimic.tasks.getup import GetupTrialConfig

        follow_recording(fitted, rec, legs, GetupTrialConfig(world="league-like"))


def test_follow_refuses_the_search_options_it_would_ignore(tmp_path):
    copy, rec, out = tmp_path / "copy.mimic", tmp_path / "seen.mcap", tmp_path / "fit.mimic"
    save_model(_tiny_model(), copy)
    rec.write_bytes(b"")
    for extra, name in (
        (["--save", str(tmp_path / "f.rrd")], "--save"),
        (["--validate", "4"], "--validate"),
        (["--pick", "mean", "--sigma", "0.5"], "--pick, --sigma"),
    ):
        said = CliRunner().invoke(
            app,
            [
                "improve", str(copy), "--objective", "getup", "--follow", str(rec), "--budget",
                "2", "-o", str(out), *extra,
            ],
        )  # fmt: skip
        assert said.exit_code == 2, said.output
        assert f"drop {name}" in said.output and "Traceback" not in said.output
        assert not out.exists()
    # The recording is an input: it is never the output, even with --force.
    said = CliRunner().invoke(
        app,
        [
            "improve", str(copy), "--objective", "getup", "--follow", str(rec), "--budget", "2",
            "-o", str(rec), "--force",
        ],
    )  # fmt: skip
    assert said.exit_code == 2 and rec.read_bytes() == b"", said.output


def test_a_hip_pitch_about_its_axis_turns_the_standing_torso_up_as_the_torso_term_assumes():
    """The torso term adds the torso's pitch error to the hip pitch joints with the sign of
    their axis's y: in the league-like world, the T1 standing with its hip pitch references
    0.15 rad higher (both +y) ends with its forward axis higher than with its stand pose."""
    from mimic.improve.follow import _hip_pitch_signs
    from mimic.robot.actuators import JointCommand
    from mimic.robot.registry import get_robot
    from mimic.world.registry import open_world

    t1 = get_robot("t1")
    legs = [i for i, n in enumerate(t1.joint_names) if "Hip" in n or "Knee" in n]
    signs = _hip_pitch_signs("t1", legs, t1.num_joints)
    hips = [t1.joint_names.index(n) for n in ("Left_Hip_Pitch", "Right_Hip_Pitch")]
    assert np.flatnonzero(signs).tolist() == hips and np.all(signs[hips] == 1.0)
    ends = []
    for offset in (0.0, 0.15):
        with open_world("league-like", "t1") as world:
            world.reset()
            world.place_robot(0, 0, 0, t1.stand_pose())
            world.place_ball(0.0, 3.0)
            command = JointCommand.references(np.asarray(t1.stand_pose()) + offset * signs)
            for _ in range(25):  # 0.5 s
                world.step(command)
            ends.append(world.torso_forward_z())
    assert ends[1] > ends[0] + 0.05, ends


def test_the_torso_term_moves_the_fitted_hips_toward_the_recordings_lean(tmp_path):
    """A recording whose torso is pitched up 0.25 rad more than its joints make the copy's:
    the follow fits joints only, then with the torso term, and keeps the torso term's fit on
    a tie; its hip pitch track is higher than the joints-only fit's (``torso_gain`` 0) where
    the term acted, and only the hips' tracks differ."""
    from mimic.improve.follow import FollowConfig, follow_recording
    from mimic.tasks.getup import GetupTrialConfig

    rec, lean = tmp_path / "seen.mcap", tmp_path / "lean.mcap"
    _black_box_getup(rec)
    ds = training_dataset(rec, L.JOINT_STATES, "reached", start_s=0.0, end_s=3.9)
    copy = train_model(ds, TrainConfig(epochs=40))
    _leaning_back(rec, lean, 0.25)
    legs = [i for i, n in enumerate(copy.joint_names) if any(k in n for k in ("Hip", "Knee"))]
    hips = [copy.joint_names.index(n) for n in ("Left_Hip_Pitch", "Right_Hip_Pitch")]
    trial = GetupTrialConfig(world="league-like")
    plain, torso = (
        follow_recording(
            copy, lean, legs, trial, FollowConfig(rounds=2, runs=1, torso_gain=g, short_front_s=0)
        )
        for g in (0.0, 1.0)
    )
    assert [r.torso_gain for r in plain.rounds] == [0.0, 0.0] and plain.torso_gain == 0.0
    assert [r.torso_gain for r in torso.rounds] == [0.0, 0.0, 1.0, 1.0]
    assert torso.best_followed_s == plain.best_followed_s  # a tie: the torso term's fit
    assert (
        torso.torso_gain == 1.0
        and "2 rounds with the torso term, the further of 2 fits" in torso.describe()
    )
    more = torso.model.track_offsets_rad[:, hips] - plain.model.track_offsets_rad[:, hips]
    assert np.all(more >= -1e-12) and more.max() > 0.1, more.max()
    others = [i for i in range(copy.num_joints) if i not in hips]
    assert np.array_equal(
        torso.model.track_offsets_rad[:, others], plain.model.track_offsets_rad[:, others]
    )
    with pytest.raises(MimicError, match="torso"):
        FollowConfig(torso_gain=-1.0)


def test_the_short_front_fits_are_kept_only_where_they_follow_further(tmp_path):
    """The follow's two short-front fits (each run mending the front before its own followed
    time) run after the 2 s fits, from the same start; one is kept only if it follows
    further by more than the tolerance, else the fitted copy is the one without them, the
    same to the bit (copies whose 2 s fits already stand keep them); and a copy whose 2 s
    fit rises to standing height does not try them."""
    from mimic.improve.follow import FollowConfig, follow_recording
    from mimic.tasks.getup import GetupTrialConfig

    rec = tmp_path / "seen.mcap"
    _black_box_getup(rec)
    ds = training_dataset(rec, L.JOINT_STATES, "reached", start_s=0.0, end_s=3.9)
    copy = train_model(ds, TrainConfig(epochs=40))
    legs = [i for i, n in enumerate(copy.joint_names) if any(k in n for k in ("Hip", "Knee"))]
    trial = GetupTrialConfig(world="league-like")
    base, short = (
        follow_recording(copy, rec, legs, trial, FollowConfig(rounds=2, runs=2, short_front_s=f))
        for f in (0.0, 0.5)
    )
    fits = [(r.torso_gain, r.front_s, r.per_run) for r in short.rounds]
    assert (
        fits
        == [(0.0, 2.0, False)] * 2
        + [(0.5, 2.0, False)] * 2
        + [(0.0, 0.5, True)] * 2
        + [(0.5, 0.5, True)] * 2
    )
    assert short.rounds[:4] == base.rounds  # the 2 s fits as without the short ones
    ran = _best_followed_of(short, True)
    if short.per_run:
        assert ran > base.best_followed_s + FollowConfig().tolerance_s
        assert "each run's own 0.5 s front" in short.describe()
    else:
        assert ran <= base.best_followed_s + FollowConfig().tolerance_s
        assert np.array_equal(short.model.track_offsets_rad, base.model.track_offsets_rad)
        assert short.front_s == 2.0 and "the further of 4 fits" in short.describe()
    with pytest.raises(MimicError, match="short front"):
        FollowConfig(short_front_s=-1.0)
    # A copy whose 2 s fit rises (here: any height counts) never tries the short fits.
    risen = follow_recording(
        copy, rec, legs, trial, FollowConfig(rounds=2, runs=2, short_front_below_m=0.0)
    )
    assert risen.rounds == base.rounds and not risen.per_run
    assert np.array_equal(risen.model.track_offsets_rad, base.model.track_offsets_rad)


def _best_followed_of(result, per_run):
    return max(r.followed for r in result.rounds if r.per_run == per_run and r.kept)


def _leaning_back(src, out, lean_rad):
    """``src``'s joints and torso, the torso pitched up ``lean_rad`` more throughout."""
    from test_getups import T1, _pitch_quat

    from mimic.geometry import forward_axis_z
    from mimic.learn.dataset import dataset_from_file
    from mimic.learn.train import recorded_torso
    from mimic.recording.writer import RecordingWriter

    seen = dataset_from_file(src, L.JOINT_STATES)
    pos, quat = recorded_torso(src, seen)
    info = L.RecordingInfo(motion="others_3", agent="league player", robot="t1", world="league")
    with RecordingWriter(out, info) as w:
        for k, tk in enumerate(seen.time_s):
            ns = int(round(tk * L.NS_PER_S))
            w.write_joints(ns, seen.angles_rad[k])
            pitch = -np.arcsin(forward_axis_z(quat[k]))  # positive: leaning forward
            turned = np.array([_pitch_quat(pitch - lean_rad)])
            w.write_tf(ns, [L.WORLD_FRAME], [T1.root_link], pos[k][None], turned)
