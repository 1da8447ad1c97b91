"""Recordings carry their robot: metadata, joint order, tables in that robot's order, old files."""

import numpy as np
import pytest

from mimic.errors import RecordingError
from mimic.recording import layout as L
from mimic.recording.reader import describe_recording, read_joint_table, read_recording
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S


def _write(path, info, rows, names=None):
    cycle_ns = int(round(info.cycle_s * L.NS_PER_S))
    with RecordingWriter(path, info) as w:
        for k, row in enumerate(rows):
            w.write_joints(k * cycle_ns, row, names=names)


def test_info_defaults_come_from_the_robot_and_the_world():
    nao, t1 = get_robot("nao"), get_robot("t1")
    info = L.RecordingInfo(motion="m", agent="a")
    assert info.robot == "nao" and info.world == "nao" and info.joint_order == nao.joint_names
    assert info.cycle_s == CYCLE_S and info.control_rate_hz == pytest.approx(1.0 / CYCLE_S)
    other = L.RecordingInfo(motion="m", agent="a", robot="t1")
    assert other.joint_order == t1.joint_names
    meta = other.to_metadata()
    assert meta["robot"] == "t1" and meta["control_rate_hz"] == "50.0"
    assert L.RecordingInfo.from_metadata(meta) == other


def test_old_metadata_names_the_nao_robot_model():
    old = {
        "motion": "kick",
        "agent": "KeyframePlayer",
        "robot_model": "nao_type0",
        "control_rate_hz": "50.0",
        "cycle_s": "0.02",
    }
    info = L.RecordingInfo.from_metadata(old)
    assert info.robot == "nao" and info.joint_order == get_robot("nao").joint_names


def test_old_file_reads_as_nao(tmp_path):
    class OldInfo(L.RecordingInfo):
        def to_metadata(self):  # what files written before robots were data hold
            meta = super().to_metadata()
            del meta["robot"], meta["world"]
            return {**meta, "robot_model": "nao_type0"}

    nao = get_robot("nao")
    path = tmp_path / "old.mcap"
    rows = np.tile(nao.stand_pose(), (3, 1))
    _write(path, OldInfo(motion="stand", agent="old"), rows)
    rec = read_recording(path)
    assert "robot" not in rec.metadata[L.METADATA_NAME]
    assert rec.info.robot == "nao" and rec.robot is nao
    table = read_joint_table(rec)
    assert table.columns == [L.TIME_COLUMN, *nao.joint_names, L.ENDED_COLUMN]
    assert describe_recording(path)["robot"] == "nao"


def test_league_robot_recording_reads_in_its_own_order(tmp_path):
    t1 = get_robot("t1")
    rng = np.random.default_rng(0)
    rows = rng.normal(size=(4, t1.num_joints))
    order = rng.permutation(t1.num_joints)  # any order on the wire
    path = tmp_path / "t1.mcap"
    _write(
        path,
        L.RecordingInfo(motion="wave", agent="test", robot="t1", world="league"),
        rows[:, order],
        names=[t1.joint_names[i] for i in order],
    )
    table = read_joint_table(path)
    assert table.columns == [L.TIME_COLUMN, *t1.joint_names, L.ENDED_COLUMN]
    np.testing.assert_allclose(table.select(t1.joint_names).to_numpy(), rows)
    summary = describe_recording(path)
    assert summary["robot"] == "t1" and summary["world"] == "league"


def test_a_vector_of_another_robot_is_refused(tmp_path):
    info = L.RecordingInfo(motion="wave", agent="test", robot="t1")
    with RecordingWriter(tmp_path / "bad.mcap", info) as w:
        with pytest.raises(RecordingError, match="22 positions for 23 joints of the t1") as err:
            w.write_joints(0, get_robot("nao").stand_pose())
    assert "\n" not in str(err.value)


def test_nao_names_in_a_t1_recording_are_explained(tmp_path):
    nao = get_robot("nao")
    path = tmp_path / "mixed.mcap"
    info = L.RecordingInfo(motion="wave", agent="test", robot="t1")
    _write(path, info, [nao.stand_pose()], names=nao.joint_names)
    with pytest.raises(RecordingError, match="wrong joint names") as err:
        read_joint_table(path)
    assert "missing t1 joints" in str(err.value) and "\n" not in str(err.value)
