"""Datasets from joint tables: layout, ended flag, phase, and one clear error for bad input."""

import numpy as np
import polars as pl
import pytest
from _learn_helpers import NAO, PAPER_DATA, joint_frame, smooth_motion

from mimic.errors import DatasetError
from mimic.learn.dataset import dataset_from_file, dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import input_mapping
from mimic.model.motion_model import MotionModel
from mimic.model.network import Layout


def test_targets_have_22_joints_and_flag_on_last_sample():
    t, q = smooth_motion(20)
    ds = dataset_from_frame(joint_frame(t + 3.0, q))
    assert ds.targets.shape == (20, 23)
    assert ds.robot == "nao" and ds.joint_names == NAO.joint_names and ds.num_joints == 22
    assert ds.time_s[0] == 0.0
    np.testing.assert_array_equal(ds.targets[:, :22], q)
    assert ds.targets[-1, 22] == 1.0 and ds.targets[:-1, 22].sum() == 0.0


def test_table_is_cut_where_the_motion_ended():
    t, q = smooth_motion(20)
    ended = np.zeros(20)
    ended[12:] = 1.0
    ds = dataset_from_frame(joint_frame(t, q, ended))
    assert ds.n_samples == 13 and ds.targets[-1, 22] == 1.0


def test_cyclic_motion_uses_phase_input():
    t, q = smooth_motion(30)
    ds = dataset_from_frame(joint_frame(t, q), period_s=0.3)
    assert ds.targets[:, 22].sum() == 0.0  # a cyclic motion never ends
    layout = Layout.for_joints(ds.num_joints, in_dim=2)
    m = MotionModel(layout, np.zeros(layout.n_params, np.float32), **input_mapping(ds, FAST))
    x = m.network_inputs(np.array([0.0, 0.075, 0.3]))
    np.testing.assert_allclose(x, [[0, 1], [1, 0], [0, 1]], atol=1e-12)


@pytest.mark.parametrize(
    "make, words",
    [
        (lambda t, q: joint_frame(t[:0], q[:0]), "empty"),
        (lambda t, q: joint_frame(t[:1], q[:1]), "single sample"),
        (lambda t, q: joint_frame(t, np.where(np.arange(22) == 5, np.nan, q)), "NaN"),
        (lambda t, q: joint_frame(t, q).drop(NAO.joint_names[3]), "21 joint columns"),
        (
            lambda t, q: joint_frame(t, q).with_columns(pl.lit(0.0).alias("tail_wag")),
            "unexpected tail_wag",
        ),
        (lambda t, q: joint_frame(t[::-1].copy(), q), "time does not increase"),
    ],
)
def test_bad_tables_raise_one_clear_line(make, words):
    t, q = smooth_motion(10)
    with pytest.raises(DatasetError) as err:
        dataset_from_frame(make(t, q), metadata={"source": "x.mcap"})
    msg = str(err.value)
    assert words in msg and "\n" not in msg and msg.startswith("x.mcap")


def test_unknown_suffix_and_missing_file(tmp_path):
    with pytest.raises(DatasetError, match="no such file"):
        dataset_from_file(tmp_path / "nope.mcap")
    (tmp_path / "a.csv").write_text("x")
    with pytest.raises(DatasetError, match="unknown input kind"):
        dataset_from_file(tmp_path / "a.csv")


def test_study_kick_text_file():
    path = PAPER_DATA / "kick_itandroids.txt"
    if not path.is_file():
        pytest.skip(f"study data absent ({path})")
    ds = dataset_from_file(path)
    assert ds.n_samples == 77 and ds.targets[-1, 22] == 1.0
    assert ds.metadata["motion"] == "kick_itandroids"
