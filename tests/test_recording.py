"""Recordings: write, read back, foreign joint names, clear errors, truncated files, Rerun."""

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from mimic.agents.registry import agent_names, make_agent
from mimic.errors import MimicError, MotionFileError, RecordingError
from mimic.motion.files import format_motion, load_motion, parse_motion
from mimic.recording import layout as L
from mimic.recording.reader import describe_recording, read_joint_table, read_recording, read_tf
from mimic.recording.recorder import RecordConfig, record
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot

NAO = get_robot("nao")
JOINT_NAMES = NAO.joint_names
#: The study simulator's names (hj1..rlj6): the NAO's joint aliases.
SIM_NAMES = tuple(j.aliases[0] for j in NAO.joints)


@pytest.fixture(scope="module")
def stand_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("rec") / "stand.mcap"
    result = record("stand", path, duration_s=2.0)
    assert result.samples == 101 and not result.interrupted
    return path


def test_recording_describes_itself(stand_file):
    rec = read_recording(stand_file)
    assert rec.recovery.complete and not rec.interrupted
    assert rec.info.motion == "stand" and rec.info.team == "mimic"
    assert rec.info.source == "reference" and rec.info.joint_order == JOINT_NAMES
    assert rec.info.robot == "nao" and rec.info.world == "nao" and rec.robot is NAO
    assert rec.duration_s == pytest.approx(2.0) and rec.rate_hz == pytest.approx(50.0)
    for topic in (L.JOINT_STATES, L.JOINT_REFERENCES, L.ENDED, L.TF):
        assert rec.topics[topic].count == 101
    assert rec.topics[L.ROBOT_DESCRIPTION].count == 1


def test_joint_table_reaches_the_stand_pose(stand_file):
    table = read_joint_table(stand_file)
    assert table.columns == ["time_s", *JOINT_NAMES, "ended"]
    assert table["time_s"][0] == 0.0 and table["time_s"][-1] == pytest.approx(2.0)
    stand = load_motion("stand").steps[-1].angles_rad
    reached = table.select(JOINT_NAMES).to_numpy()[-1]
    assert np.abs(reached - stand).max() < 0.1  # the robot holds the pose it was told
    refs = read_joint_table(stand_file, topic=L.JOINT_REFERENCES)
    np.testing.assert_allclose(refs.select(JOINT_NAMES).to_numpy()[-1], stand, atol=1e-9)
    assert table["ended"][-1] == 1.0


def test_one_shot_motion_ends_on_its_last_sample(tmp_path):
    path = tmp_path / "stand_once.mcap"
    result = record("stand", path)
    table = read_joint_table(path)
    assert result.duration_s == pytest.approx(load_motion("stand").duration_s)
    assert table["ended"].to_list() == [0.0] * (len(table) - 1) + [1.0]


def test_tf_places_feet_on_the_ground_and_the_ball_aside(stand_file):
    tf = read_tf(stand_file)
    assert {"torso", "left_foot", "right_foot", "head", L.BALL_FRAME} <= set(tf)
    for foot in ("left_foot", "right_foot"):
        # foot frame = ankle-roll anchor, 45 mm above the sole
        assert tf[foot].pos_m[-1, 2] == pytest.approx(0.045, abs=0.01)
    assert tf[L.BALL_FRAME].pos_m[-1, 2] == pytest.approx(0.042, abs=0.005)
    raw = read_tf(stand_file, in_world=False)
    assert raw["left_thigh"].parent == "left_hip2" and raw["torso"].parent == L.WORLD_FRAME


def test_get_up_is_recorded_from_lying_to_standing(tmp_path):
    path = tmp_path / "getup_front.mcap"
    record("getup_front", path, config=RecordConfig(tf_every=5))
    rec = read_recording(path)
    assert rec.info.start_posture == "lying_front"
    torso_z = read_tf(path)["torso"].pos_m[:, 2]
    assert torso_z[0] < 0.15, "the recording starts with the robot lying"
    assert torso_z[-1] > 0.28, "and ends with it standing"


def test_motion_file_start_posture_round_trips():
    movement = load_motion("getup_back")
    assert movement.start_posture == "lying_back"
    assert parse_motion(format_motion(movement)).start_posture == "lying_back"
    with pytest.raises(MotionFileError, match="start must be one of"):
        parse_motion("start sitting\nstep 1\nhead_yaw 0\n", "bad.txt")


def _write_foreign(path: Path, names, rows, times_ns, ended=None):
    info = L.RecordingInfo(motion="foreign", agent="test")
    with RecordingWriter(path, info) as w:
        for t, row in zip(times_ns, rows):
            w.write_joints(t, row, names=names)
        if ended is not None:
            for t, e in zip(times_ns, ended):
                w.write_ended(t, e)


def test_simulator_names_in_any_order_are_accepted(tmp_path):
    rng = np.random.default_rng(0)
    values = rng.normal(size=(5, 22))
    order = rng.permutation(22)
    names = [SIM_NAMES[i] for i in order]
    path = tmp_path / "sim_names.mcap"
    _write_foreign(path, names, values[:, order], [i * 20_000_000 for i in range(5)])
    table = read_joint_table(path)
    np.testing.assert_allclose(table.select(JOINT_NAMES).to_numpy(), values)
    assert table["ended"].to_list() == [0, 0, 0, 0, 1]  # no /ended topic: last row ends


@pytest.mark.parametrize(
    "case, expected",
    [
        ("nan", "NaN"),
        ("backwards", "backwards"),
        ("names", "wrong joint names"),
    ],
)
def test_bad_joint_data_gives_one_clear_error(tmp_path, case, expected):
    values = np.zeros((4, 22))
    times = [0, 20_000_000, 40_000_000, 60_000_000]
    names = list(JOINT_NAMES)
    if case == "nan":
        values[2, 5] = math.nan
    elif case == "backwards":
        times[3] = 10_000_000
    else:
        names[3] = "left_shoulder_yaw"
    path = tmp_path / f"{case}.mcap"
    _write_foreign(path, names, values, times)
    with pytest.raises(RecordingError, match=expected) as err:
        read_joint_table(path)
    assert "\n" not in str(err.value)


def test_not_mcap_and_missing_topic_are_explained(tmp_path):
    text = tmp_path / "notes.mcap"
    text.write_text("hello")
    with pytest.raises(RecordingError, match="not an MCAP file"):
        read_recording(text)
    path = tmp_path / "only_tf.mcap"
    with RecordingWriter(path, L.RecordingInfo(motion="x", agent="test")) as w:
        w.write_ended(0, False)
    with pytest.raises(
        RecordingError, match=r"no joint topic /joint_states; topics present: /ended"
    ):
        read_joint_table(path)


def test_truncated_file_gives_back_its_first_part(stand_file, tmp_path):
    data = stand_file.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    rec = read_recording(cut)
    assert not rec.recovery.complete and rec.interrupted
    assert rec.recovery.bytes_lost > 0 and "recovered" in rec.recovery.summary()
    part, whole = read_joint_table(rec), read_joint_table(stand_file)
    n = len(part)
    assert 20 < n < len(whole)  # chunks close every 0.25 s: only the tail is lost
    assert part.drop("ended").equals(whole.head(n).drop("ended"))
    assert rec.recovery.last_time_s == pytest.approx(part["time_s"][-1])
    summary = describe_recording(cut)
    assert summary["complete"] is False and "lost" in summary["recovery"]


def test_registry_names_and_errors():
    assert "stand" in agent_names() and "walk" in agent_names()
    assert make_agent("stand").name == "stand"
    with pytest.raises(MimicError, match="unknown agent"):
        make_agent("moonwalk")


def test_rerun_imports_joint_plots_and_the_robot(stand_file, tmp_path, rerun_cli):
    rerun = rerun_cli
    rrd = tmp_path / "stand.rrd"
    env = {"RERUN_ANALYTICS": "off", "PATH": "/usr/bin:/bin"}
    # `rerun mcap convert` runs the same importer as `rerun FILE.mcap --save`, without a server
    subprocess.run(
        [rerun, "mcap", "convert", str(stand_file), "-o", str(rrd)],
        check=True,
        capture_output=True,
        env=env,
        timeout=120,
    )
    printed = subprocess.run(
        [rerun, "rrd", "print", str(rrd)],
        check=True,
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    ).stdout
    assert "/joint_states/position - data columns: [Scalars:scalars" in printed
    assert "/joint_references/position" in printed
    assert "Transform3D:child_frame" in printed  # /tf became transforms
    assert "/visual_geometries/left_foot/" in printed  # the URDF from /robot_description


def test_fast_cdr_matches_the_generic_ros2_encoder():
    from mcap_ros2._dynamic import serialize_dynamic

    from mimic.recording import cdr

    rng = np.random.default_rng(1)
    pos, vel = rng.normal(size=22), rng.normal(size=22)
    t = 3_020_000_001
    stamp = {"sec": 3, "nanosec": 20_000_001}
    js = serialize_dynamic("sensor_msgs/msg/JointState", L.SCHEMAS["sensor_msgs/msg/JointState"])
    expected = js["sensor_msgs/msg/JointState"](
        {
            "header": {"stamp": stamp, "frame_id": ""},
            "name": list(JOINT_NAMES),
            "position": pos.tolist(),
            "velocity": vel.tolist(),
            "effort": [],
        }
    )
    assert cdr.encode_joint_state(t, JOINT_NAMES, pos, vel) == expected
    parents, children = ["world", "torso", "neck"], ["torso", "neck", "h"]
    p, q = rng.normal(size=(3, 3)), rng.normal(size=(3, 4))
    tf = serialize_dynamic("tf2_msgs/msg/TFMessage", L.SCHEMAS["tf2_msgs/msg/TFMessage"])
    expected = tf["tf2_msgs/msg/TFMessage"](
        {
            "transforms": [
                {
                    "header": {"stamp": stamp, "frame_id": a},
                    "child_frame_id": b,
                    "transform": {
                        "translation": dict(zip("xyz", pp.tolist())),
                        "rotation": dict(zip("wxyz", qq.tolist())),
                    },
                }
                for a, b, pp, qq in zip(parents, children, p, q)
            ]
        }
    )
    assert cdr.encode_tf(t, parents, children, p, q) == expected
