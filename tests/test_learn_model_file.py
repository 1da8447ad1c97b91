"""Model files: round trip, description, and one clear error for files that are not models."""

import json
import zipfile

import numpy as np
import pytest
from _learn_helpers import joint_frame, smooth_motion

from mimic.errors import ModelFileError
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model
from mimic.model.model_file import describe_model, is_model_file, load_model, save_model


@pytest.fixture(scope="module")
def model():
    t, q = smooth_motion(30)
    ds = dataset_from_frame(
        joint_frame(t, q),
        metadata={"motion": "wave", "team": "mimic", "ball_offset_m": [0.15, -0.05]},
    )
    return train_model(ds, TrainConfig(FAST, seed=0, epochs=100))


def test_round_trip_keeps_weights_mapping_and_metadata(model, tmp_path):
    path = save_model(model, tmp_path / "m" / "wave.mimic")
    back = load_model(path)
    assert np.array_equal(back.params, model.params)
    t = np.linspace(0, 0.6, 13)
    np.testing.assert_allclose(back.predict(t), model.predict(t), atol=1e-12)
    assert back.name == "wave" and back.metadata["ball_offset_m"] == [0.15, -0.05]
    assert back.metrics["epochs"] == 100 and back.preset == "fast"
    assert back.robot == model.robot == "nao" and back.joint_names == model.joint_names
    info = describe_model(path)
    assert info["kind"] == "model" and info["n_params"] == 5123
    assert info["robot"] == "nao" and info["num_joints"] == 22
    assert set(info["metrics"]) >= {"mae_rad", "max_error_rad", "ended_accuracy", "wall_s"}
    json.dumps(info)
    assert is_model_file(path)


def test_not_a_model(tmp_path):
    bad = tmp_path / "notes.mimic"
    bad.write_text("hello")
    assert not is_model_file(bad)
    with pytest.raises(ModelFileError, match="not a mimic model file") as err:
        load_model(bad)
    assert "\n" not in str(err.value)
    with pytest.raises(ModelFileError, match="no such model file"):
        load_model(tmp_path / "missing.mimic")


def test_model_for_another_joint_layout(model, tmp_path):
    path = save_model(model, tmp_path / "wave.mimic")
    other = tmp_path / "other.mimic"
    with zipfile.ZipFile(path) as src, zipfile.ZipFile(other, "w") as dst:
        for item in src.namelist():
            data = src.read(item)
            if item == "meta.json":
                meta = json.loads(data)
                meta["joint_names"] = meta["joint_names"][:20]
                data = json.dumps(meta)
            dst.writestr(item, data)
    with pytest.raises(ModelFileError, match="different joint layout") as err:
        load_model(other)
    assert "\n" not in str(err.value)


def _rewrite_meta(src, dst, change) -> None:
    with zipfile.ZipFile(src) as a, zipfile.ZipFile(dst, "w") as b:
        for item in a.namelist():
            data = a.read(item)
            if item == "meta.json":
                meta = json.loads(data)
                change(meta)
                data = json.dumps(meta)
            b.writestr(item, data)


def test_model_file_without_robot_is_a_nao_model(model, tmp_path):
    """Files written before robots were data have no ``robot`` entry: they are NAO models."""
    path = save_model(model, tmp_path / "wave.mimic")
    old = tmp_path / "old.mimic"
    _rewrite_meta(path, old, lambda meta: meta.pop("robot"))
    back = load_model(old)
    assert back.robot == "nao" and back.num_joints == 22
    np.testing.assert_array_equal(back.params, model.params)


def test_model_of_an_unknown_robot(model, tmp_path):
    path = save_model(model, tmp_path / "wave.mimic")
    other = tmp_path / "robby.mimic"
    _rewrite_meta(path, other, lambda meta: meta.update(robot="robby"))
    with pytest.raises(ModelFileError, match="unknown robot 'robby'") as err:
        load_model(other)
    assert "\n" not in str(err.value)
