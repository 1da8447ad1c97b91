"""Learning is robot-agnostic: a non-NAO joint set (the league's T1) trains, saves, loads and
exports with its own N + 1 outputs, robot and joint names."""

import json

import numpy as np
import pytest
from _learn_helpers import joint_frame, smooth_motion

from mimic.errors import DatasetError, MimicError
from mimic.learn.bench import synthetic_dataset
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.export import export_onnx
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model, train_models, training_dataset
from mimic.model.model_file import describe_model, load_model, save_model
from mimic.recording import layout as L
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot

T1 = get_robot("t1")


@pytest.fixture(scope="module")
def t1_model():
    t, q = smooth_motion(30, robot="t1")
    ds = dataset_from_frame(
        joint_frame(t, q, robot="t1"), robot="t1", metadata={"motion": "t1_wave"}
    )
    assert ds.robot == "t1" and ds.joint_names == T1.joint_names
    assert ds.targets.shape == (30, T1.num_joints + 1)
    return train_model(ds, TrainConfig(FAST, seed=0, epochs=200))


def test_t1_network_has_its_own_output_size(t1_model):
    n = T1.num_joints
    assert n != get_robot("nao").num_joints  # really another joint set
    assert t1_model.layout.out_dim == n + 1 and t1_model.num_joints == n
    assert t1_model.robot == "t1" and t1_model.joint_names == T1.joint_names
    assert t1_model.predict(np.linspace(0, 0.5, 7)).shape == (7, n + 1)
    assert set(t1_model.metrics["mae_rad_per_joint"]) == set(T1.joint_names)


def test_t1_model_file_round_trip(t1_model, tmp_path):
    path = save_model(t1_model, tmp_path / "t1_wave.mimic")
    back = load_model(path)
    assert back.robot == "t1" and back.joint_names == T1.joint_names
    assert back.layout == t1_model.layout
    t = np.linspace(0, 0.6, 13)
    np.testing.assert_allclose(back.predict(t), t1_model.predict(t), atol=1e-12)
    info = describe_model(path)
    assert info["robot"] == "t1" and info["num_joints"] == T1.num_joints


def test_t1_onnx_export_has_n_plus_1_outputs(t1_model, tmp_path):
    ort = pytest.importorskip("onnxruntime")
    onnx = pytest.importorskip("onnx")
    path = export_onnx(t1_model, tmp_path / "t1_wave.onnx")
    sess = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    times = np.linspace(0.0, 0.6, 31).astype(np.float32)[:, None]
    (out,) = sess.run(None, {"time_s": times})
    assert out.shape == (31, T1.num_joints + 1)
    np.testing.assert_allclose(out, t1_model.predict(times[:, 0].astype(np.float64)), atol=1e-5)
    meta = {p.key: p.value for p in onnx.load(str(path)).metadata_props}
    assert meta["robot"] == "t1" and int(meta["num_joints"]) == T1.num_joints
    assert json.loads(meta["joint_names"]) == list(T1.joint_names)
    assert json.loads(meta["outputs"]) == [*T1.joint_names, "ended"]


def test_nao_and_t1_train_together_each_with_its_shape():
    nao = synthetic_dataset(25, seed=1, name="nao_m")
    t1 = synthetic_dataset(30, seed=2, name="t1_m", robot="t1")
    a, b = train_models([nao, t1], TrainConfig(FAST, seed=0, epochs=20))
    assert (a.robot, a.layout.out_dim) == ("nao", nao.num_joints + 1)
    assert (b.robot, b.layout.out_dim) == ("t1", T1.num_joints + 1)


def test_a_nao_table_is_not_a_t1_dataset():
    t, q = smooth_motion(10)
    with pytest.raises(DatasetError, match="expected the 23 t1 joints in its order"):
        dataset_from_frame(joint_frame(t, q), robot="t1", metadata={"source": "x.mcap"})


def test_t1_recording_learns_reached_angles_and_refuses_compensation(tmp_path):
    t, q = smooth_motion(12, robot="t1")
    path = tmp_path / "t1_wave.mcap"
    info = L.RecordingInfo(motion="t1_wave", agent="test", robot="t1", world="league")
    with RecordingWriter(path, info) as w:
        for k in range(len(t)):
            w.write_joints(int(round(t[k] * L.NS_PER_S)), q[k])
    ds = training_dataset(path, L.JOINT_STATES)  # default target: what the robot allows
    assert ds.robot == "t1" and ds.metadata["target"] == "reached"
    np.testing.assert_allclose(ds.angles_rad, q)
    with pytest.raises(MimicError, match="t1 has PD motors") as err:
        training_dataset(path, L.JOINT_STATES, "compensated")
    assert "\n" not in str(err.value)
