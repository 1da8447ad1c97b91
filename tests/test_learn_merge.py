"""`mimic train A B --merge`: one motion learned from recordings of it that a 25 Hz monitor
sampled on other cycles, aligned and pooled."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import DatasetError
from mimic.learn.dataset import dataset_from_file
from mimic.learn.merge import align_shift_s, merged_training_dataset
from mimic.model.model_file import describe_model, load_model
from mimic.recording import layout as L
from mimic.recording.reader import read_recording
from mimic.recording.writer import RecordingWriter

runner = CliRunner()
SHIPPED = Path(__file__).parents[1] / "recordings" / "kick_right.mcap"
#: How long the second recording shows the robot standing before its kick [s].
WAIT_S = 0.4


def _write(path: Path, info, time_s: np.ndarray, angles_rad: np.ndarray) -> Path:
    with RecordingWriter(path, info) as w:
        for t, q in zip(time_s, angles_rad):
            w.write_joints(int(round(t * L.NS_PER_S)), q)
    return path


@pytest.fixture(scope="module")
def halves(tmp_path_factory):
    """The shipped kick's observed angles (50 Hz, from our simulator) as two 25 Hz recordings:
    the even cycles from the kick's start, and the odd cycles after WAIT_S of standing."""
    folder = tmp_path_factory.mktemp("merge")
    full = dataset_from_file(SHIPPED, L.JOINT_STATES)
    info = read_recording(SHIPPED).info
    t, q = full.time_s, full.angles_rad
    even = _write(folder / "even.mcap", info, t[::2], q[::2])
    wait = np.arange(0.0, WAIT_S - 1e-9, 0.04)
    odd = _write(
        folder / "odd.mcap",
        info,
        np.concatenate([wait, t[1::2] - t[1] + WAIT_S]),
        np.concatenate([np.tile(q[0], (len(wait), 1)), q[1::2]]),
    )
    return full, even, odd


def test_the_second_half_is_found_on_the_first_ones_clock(halves):
    full, even, odd = halves
    a = align_shift_s(
        dataset_from_file(even, L.JOINT_STATES), dataset_from_file(odd, L.JOINT_STATES)
    )
    # odd.mcap shows cycle 1 at WAIT_S: its clock runs WAIT_S - 20 ms ahead of the first's.
    assert a.shift_s == pytest.approx(WAIT_S - 0.02)
    assert a.rms_rad < 0.02


def test_the_pooled_recordings_are_the_motion_at_50_hz(halves):
    full, even, odd = halves
    merged, alignments = merged_training_dataset([even, odd], L.JOINT_STATES, "reached")
    n = len(merged.time_s)
    assert n >= len(full.time_s) - 1
    np.testing.assert_allclose(merged.time_s, full.time_s[:n], atol=1e-6)
    np.testing.assert_allclose(merged.angles_rad, full.angles_rad[:n], atol=1e-6)
    assert merged.targets[-1, -1] == 1.0 and merged.targets[:-2, -1].sum() == 0
    assert merged.metadata["merged_from"] == [str(even), str(odd)]
    assert merged.metadata["ball_offset_m"] == pytest.approx([0.16, -0.069])


def test_a_cut_is_on_the_first_recordings_clock(halves):
    full, even, odd = halves
    merged, _ = merged_training_dataset(
        [even, odd], L.JOINT_STATES, "reached", start_s=0.4, end_s=1.2
    )
    assert merged.time_s[0] == 0.0 and merged.time_s[-1] == pytest.approx(0.8)
    on_full = (full.time_s >= 0.4 - 1e-9) & (full.time_s <= 1.2 + 1e-9)
    np.testing.assert_allclose(merged.angles_rad, full.angles_rad[on_full], atol=1e-6)
    assert merged.targets[-1, -1] == 1.0 and merged.targets[:-2, -1].sum() == 0


def _odd_cycle_error(model_path: Path, full) -> float:
    """Largest error [rad] of a model at the cycles only odd.mcap shows."""
    model = load_model(model_path)
    t = full.time_s[1::2]
    return float(np.abs(model.predict(t)[:, : full.num_joints] - full.angles_rad[1::2]).max())


def test_train_merge_learns_the_cycles_one_recording_lacks(halves, tmp_path):
    full, even, odd = halves
    merged, alone = tmp_path / "merged.mimic", tmp_path / "even.mimic"
    common = ["--target", "reached", "--epochs", "8000"]
    res = runner.invoke(app, ["train", str(even), str(odd), "--merge", "-o", str(merged), *common])
    assert res.exit_code == 0, res.output
    assert "aligned odd.mcap: +0.38 s" in res.output
    res = runner.invoke(app, ["train", str(even), "-o", str(alone), *common])
    assert res.exit_code == 0, res.output
    assert describe_model(merged)["source"]["merged_from"] == [str(even), str(odd)]
    # The kick's sharpest moves fall between the even cycles: learned from them alone the
    # network guesses there (0.081 rad off at worst when written); with the odd recording
    # pooled in it has seen them (0.045).
    assert _odd_cycle_error(merged, full) < 0.75 * _odd_cycle_error(alone, full)


def test_a_recording_that_strays_from_the_others_is_left_out(halves, tmp_path):
    full, even, odd = halves
    info = read_recording(SHIPPED).info
    t, q = full.time_s[::2], full.angles_rad[::2].copy()
    again = _write(tmp_path / "again.mcap", info, t, q + 0.005)  # the kick once more
    q[t > 1.5] += 0.3  # the robot fell: every joint elsewhere from 1.5 s on
    fell = _write(tmp_path / "fell.mcap", info, t, q)
    merged, alignments = merged_training_dataset([even, odd, fell, again], L.JOINT_STATES)
    assert [a.kept for a in alignments] == [True, True, False, True]
    assert merged.metadata["merge_left_out"] == [str(fell)]
    assert str(fell) not in merged.metadata["merged_from"]
    with pytest.raises(DatasetError, match="Put a recording of the motion first"):
        merged_training_dataset([fell, even, odd, again], L.JOINT_STATES)
    res = runner.invoke(
        app,
        ["train", str(even), str(odd), str(fell), "--merge", "--epochs", "200",
         "-o", str(tmp_path / "m.mimic")],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "left out" in res.output and "fell.mcap" in res.output


def test_recordings_of_another_robot_are_refused(halves, tmp_path):
    _, even, _ = halves
    other = _write(
        tmp_path / "t1.mcap",
        L.RecordingInfo(motion="kick", agent="test", robot="t1", world="league"),
        np.arange(0, 1, 0.04),
        np.zeros((25, 23)),
    )
    with pytest.raises(DatasetError, match="same robot"):
        merged_training_dataset([even, other])


@pytest.mark.parametrize(
    "extra, words",
    [
        ([], "give at least two"),
        (["{odd}", "--period", "1.0"], "one-shot motions"),
        (["{odd}", "-o", "{folder}"], "must end in .mimic"),
    ],
)
def test_bad_merges_give_one_error_line(halves, tmp_path, extra, words):
    _, even, odd = halves
    fill = {"odd": str(odd), "folder": str(tmp_path / "models")}
    args = ["train", str(even), "--merge", *(a.format(**fill) for a in extra)]
    if "-o" not in extra:
        args += ["-o", str(tmp_path / "m.mimic")]
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert any(words in ln for ln in lines) and len(lines) <= 2, res.output
