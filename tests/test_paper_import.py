"""The study's text files in our layout: names, signs, flags, and the MCAP round trip."""

from pathlib import Path

import numpy as np
import pytest
from _learn_helpers import PAPER_DATA as PAPER  # noqa: E402

from mimic.errors import RecordingError
from mimic.recording import layout as L
from mimic.recording.paper_import import (
    PAPER_SIGNS,
    PAPER_TO_CANONICAL,
    default_topic,
    import_paper_file,
    read_paper_table,
)
from mimic.recording.reader import read_joint_table, read_recording
from mimic.robot.registry import get_robot

NAO = get_robot("nao")  # the study's files are NAO data
JOINT_NAMES = NAO.joint_names


def _paper(name: str) -> Path:
    path = PAPER / name
    if not path.exists():
        pytest.skip(f"study data not found at {PAPER} (see shared/paper-data/README.md)")
    return path


def test_every_joint_has_exactly_one_paper_name():
    targets = {v for k, v in PAPER_TO_CANONICAL.items() if k != "leftHipYawPitc"}
    assert targets == set(JOINT_NAMES) and len(targets) == 22
    assert PAPER_TO_CANONICAL["leftShoulderYaw"] == "left_shoulder_roll"
    assert PAPER_TO_CANONICAL["leftArmRoll"] == "left_elbow_yaw"
    assert PAPER_TO_CANONICAL["leftFootPitch"] == "left_ankle_pitch"


def test_their_stand_becomes_ours():
    """Their stand (shoulder +90, hip -30, knee +60, ankle -30 deg) is ours negated."""
    theirs = {
        "left_shoulder_pitch": 90,
        "left_hip_pitch": -30,
        "left_knee_pitch": 60,
        "left_ankle_pitch": -30,
    }
    ours = {k: PAPER_SIGNS[k] * v for k, v in theirs.items()}
    assert ours == {
        "left_shoulder_pitch": -90,
        "left_hip_pitch": 30,
        "left_knee_pitch": -60,
        "left_ankle_pitch": 30,
    }


def test_kick_fits_our_joint_stops_and_mirror_table():
    table = read_paper_table(_paper("kick_itandroids.txt"))
    assert table.shape == (77, 24)
    assert table["ended"].to_list() == [0.0] * 76 + [1.0]
    q = table.select(JOINT_NAMES).to_numpy()
    tol = np.radians(3)
    outside = (q < NAO.lower_limits_rad - tol) | (q > NAO.upper_limits_rad + tol)
    # only the kick's knee/hip/ankle targets beyond the stops (the README's 186 deg knee)
    cols = {JOINT_NAMES[i] for i in np.nonzero(outside.any(axis=0))[0]}
    assert cols <= {
        "left_hip_pitch",
        "left_knee_pitch",
        "left_ankle_pitch",
        "left_shoulder_pitch",
        "right_shoulder_pitch",
        "right_hip_pitch",
        "right_ankle_pitch",
        "right_hip_yaw_pitch",
    }
    signs = np.array([PAPER_SIGNS[n] for n in JOINT_NAMES])
    unsigned = q * signs  # their raw values, taken with our signs ignored
    outside_raw = (unsigned < NAO.lower_limits_rad - tol) | (unsigned > NAO.upper_limits_rad + tol)
    assert outside.sum() < 0.5 * outside_raw.sum()
    # the ready pose (second row) is left/right symmetric under our mirror table
    ready = q[1]
    np.testing.assert_allclose(NAO.mirror_angles(ready), ready, atol=0.2)
    assert ready[JOINT_NAMES.index("left_knee_pitch")] < -1.0  # knees bent = negative for us


def test_walk_header_typo_and_missing_flag():
    table = read_paper_table(_paper("ut_walk.txt"))
    assert table.shape == (8, 24)
    assert table["ended"].to_list() == [0.0] * 7 + [1.0]
    assert default_topic("ut_walk.txt") == L.JOINT_STATES
    assert default_topic("kick_itandroids.txt") == L.JOINT_REFERENCES


def test_kick_family_is_split_by_distance():
    table = read_paper_table(_paper("kick_family_by_distance.txt"), distance_m=18.0)
    assert table["ended"][-1] == 1.0 and table["time_s"][0] == 0.0
    with pytest.raises(RecordingError, match="no kick for distance"):
        read_paper_table(_paper("kick_family_by_distance.txt"), distance_m=3.0)


def test_import_round_trips_through_mcap(tmp_path):
    src = _paper("kick_itandroids.txt")
    out = tmp_path / "kick.mcap"
    info = import_paper_file(src, out)
    assert info.source == "reference" and info.robot == "nao"
    rec = read_recording(out)
    assert rec.info.robot == "nao" and rec.info.joint_order == JOINT_NAMES
    assert L.JOINT_REFERENCES in rec.topics and L.JOINT_STATES not in rec.topics
    back = read_joint_table(out, topic=L.JOINT_REFERENCES)
    direct = read_paper_table(src)
    np.testing.assert_allclose(back.to_numpy(), direct.to_numpy(), atol=1e-12)


def test_not_a_study_file(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("a,b,c\n1,2,3\n")
    with pytest.raises(RecordingError, match="not a study joint table"):
        read_paper_table(bad)
