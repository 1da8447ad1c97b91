"""`mimic train` / `mimic export` through the real CLI: files written, exit codes, one-line errors."""

import numpy as np
import pytest
from _learn_helpers import PAPER_DATA, smooth_motion
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.model.model_file import load_model

runner = CliRunner()


@pytest.fixture()
def study_table(tmp_path):
    """A small table in the study's '::' format (synthetic values)."""
    t, q = smooth_motion(20)
    names = (
        "neckYaw neckPitch leftShoulderPitch leftShoulderYaw leftArmRoll leftArmYaw "
        "rightShoulderPitch rightShoulderYaw rightArmRoll rightArmYaw leftHipYawPitch "
        "leftHipRoll leftHipPitch leftKneePitch leftFootPitch leftFootRoll rightHipYawPitch "
        "rightHipRoll rightHipPitch rightKneePitch rightFootPitch rightFootRoll"
    ).split()
    head = "::".join(["timestep", *names, "hasEnded"])
    path = tmp_path / "wave.txt"
    rows = ["::".join(f"{v:.6f}" for v in [t[k], *q[k], float(k == 19)]) for k in range(20)]
    path.write_text("\n".join([head, *rows]) + "\n")
    return path


def _paper_kick():
    path = PAPER_DATA / "kick_itandroids.txt"
    if not path.is_file():
        pytest.skip(f"study data absent ({path})")
    return path


def test_train_and_export_study_kick(tmp_path):
    kick = _paper_kick()
    out = tmp_path / "models" / "kick.mimic"
    res = runner.invoke(app, ["train", str(kick), "-o", str(out), "--epochs", "300", "--seed", "3"])
    assert res.exit_code == 0, res.output
    assert "mean abs error" in res.output and out.is_file()
    again = tmp_path / "again.mimic"
    runner.invoke(app, ["train", str(kick), "-o", str(again), "--epochs", "300", "--seed", "3"])
    assert np.array_equal(load_model(out).params, load_model(again).params)
    res = runner.invoke(app, ["export", str(out), "--onnx", str(tmp_path / "kick.onnx")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "kick.onnx").is_file()


def test_several_inputs_train_into_a_folder(tmp_path, study_table):
    other = tmp_path / "wave2.txt"
    other.write_text(study_table.read_text())
    res = runner.invoke(
        app,
        [
            "train",
            str(study_table),
            str(other),
            "-o",
            str(tmp_path / "m"),
            "--epochs",
            "50",
            "--preset",
            "paper",
        ],
    )
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "m" / "wave.mimic").metrics["batch_size"] == 2
    assert (tmp_path / "m" / "wave2.mimic").is_file()


@pytest.mark.parametrize(
    "args, words",
    [
        (["train", "{missing}", "-o", "{out}"], "no such file"),
        (["train", "{table}", "-o", "{out}", "--preset", "slow"], "unknown preset"),
        (["train", "{table}", "-o", "{out}", "--target", "magic"], "unknown target"),
        (["train", "{table}", "{table}", "-o", "{out}"], "must be a folder"),
        (["export", "{table}", "--onnx", "{out}"], "not a mimic model file"),
    ],
)
def test_bad_input_gives_one_error_line(tmp_path, study_table, args, words):
    fill = {
        "missing": str(tmp_path / "nope.mcap"),
        "out": str(tmp_path / "o.mimic"),
        "table": str(study_table),
    }
    res = runner.invoke(app, [a.format(**fill) for a in args])
    assert res.exit_code == 2
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert any(words in ln for ln in lines) and len(lines) <= 2, res.output
