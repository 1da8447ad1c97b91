"""ONNX export: same outputs as the numpy model (time and cyclic phase models)."""

import json

import numpy as np
import pytest
from _learn_helpers import NAO, joint_frame, smooth_motion

from mimic.learn.dataset import dataset_from_frame
from mimic.learn.export import export_onnx
from mimic.learn.presets import FAST, PAPER
from mimic.learn.train import TrainConfig, train_model

ort = pytest.importorskip("onnxruntime")


@pytest.mark.parametrize("preset, period_s", [(FAST, None), (PAPER, None), (FAST, 0.4)])
def test_onnx_matches_numpy_model(tmp_path, preset, period_s):
    t, q = smooth_motion(25)
    ds = dataset_from_frame(joint_frame(t, q), period_s=period_s, metadata={"motion": "wave"})
    model = train_model(ds, TrainConfig(preset, seed=0, epochs=150))
    path = export_onnx(model, tmp_path / "wave.onnx")
    sess = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    times = np.linspace(0.0, 1.2, 61).astype(np.float32)[:, None]
    (out,) = sess.run(None, {"time_s": times})
    assert out.shape == (61, 23)
    np.testing.assert_allclose(out, model.predict(times[:, 0].astype(np.float64)), atol=1e-5)
    meta = {p.key: p.value for p in __import__("onnx").load(str(path)).metadata_props}
    assert json.loads(meta["joint_names"]) == list(NAO.joint_names)
    assert meta["robot"] == "nao" and meta["num_joints"] == "22"
    assert meta["input_kind"] == ("phase" if period_s else "time")
