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
