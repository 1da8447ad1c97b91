"""What a new user meets (#31, section 3; #30 item 4): no hangs without a display, results that
say when they are worse, trials that say what ran, one-line errors for every bad value, and
`mimic play` that records the torso and ball and says what happened."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest
from _learn_helpers import joint_frame, smooth_motion
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import ModelFileError
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.model_file import describe_model, load_model, save_model
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model

runner = CliRunner()


def _one_line_error(result, code: int, *fragments: str) -> str:
    assert result.exit_code == code, result.output
    assert "Traceback" not in result.output
    lines = result.output.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), lines
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    return lines[0]


@pytest.fixture(scope="module")
def model_path(tmp_path_factory):
    t, q = smooth_motion(30)
    ds = dataset_from_frame(joint_frame(t, q), metadata={"motion": "wave", "team": "mimic"})
    path = tmp_path_factory.mktemp("model") / "wave.mimic"
    return save_model(train_model(ds, TrainConfig(FAST, seed=0, epochs=20)), path)


def _edited(model_path, tmp_path, field, value):
    """A copy of the model whose meta.json has ``field`` set to ``value`` (or removed)."""
    out = tmp_path / "edited.mimic"
    with zipfile.ZipFile(model_path) as src, zipfile.ZipFile(out, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "meta.json":
                meta = json.loads(data)
                if value is _REMOVE:
                    meta.pop(field, None)
                else:
                    meta[field] = value
                data = json.dumps(meta).encode()
            dst.writestr(item, data)
    return out


_REMOVE = object()
_EDITS = [
    (field, value)
    for field in (
        "format_version",
        "robot",
        "joint_names",
        "input_kind",
        "input_offset_s",
        "input_scale_per_s",
        "period_s",
        "duration_s",
        "layout",
        "metrics",
        "source",
        "preset",
    )
    for value in (_REMOVE, "x", [1, 2], True)
] + [
    ("layout", {"in_dim": "1", "out_dim": 23, "hidden": [8]}),
    ("layout", {"in_dim": 1, "out_dim": 23, "hidden": "8"}),
    ("layout", {"in_dim": 1, "out_dim": 23}),
    ("metrics", {"mae_rad_per_joint": [1, 2]}),
    ("joint_names", [1] * 22),
]


@pytest.mark.parametrize("field, value", _EDITS)
def test_an_edited_meta_json_is_one_line_never_a_traceback(model_path, tmp_path, field, value):
    path = _edited(model_path, tmp_path, field, value)
    for read in (load_model, describe_model):
        try:
            read(path)
        except ModelFileError as err:
            assert "\n" not in str(err) and str(path) in str(err)
    for args in (["info", str(path)], ["info", str(path), "--json"]):
        result = runner.invoke(app, args)
        assert result.exception is None or isinstance(result.exception, SystemExit), (
            f"{result.exception!r}: {result.output}"
        )
        if result.exit_code:
            _one_line_error(result, 2, str(path))
