"""What the Rerun views contain, read back from the saved .rrd with the `rerun` CLI."""

import subprocess
from pathlib import Path

import numpy as np
import pytest

from mimic.recording.reader import read_tf
from mimic.recording.recorder import record
from mimic.robot.registry import get_robot
from mimic.viz.bodies import link_bodies
from mimic.viz.gait import centre_of_mass_path
from mimic.viz.recording import view_recording
from mimic.viz.scene import log_robot_geometry


def rrd_text(rerun: str, path: Path) -> str:
    return subprocess.run(
        [rerun, "rrd", "print", str(path)],
        check=True,
        capture_output=True,
        text=True,
        env={"RERUN_ANALYTICS": "off", "PATH": "/usr/bin:/bin"},
        timeout=120,
    ).stdout


@pytest.fixture(scope="module")
def stand_recording(tmp_path_factory):
    out = tmp_path_factory.mktemp("rec") / "stand.mcap"
    record("stand", out, duration_s=1.0)
    return out


def test_view_has_robot_field_and_grouped_curves(stand_recording, tmp_path, rerun_cli):
    rrd = tmp_path / "view.rrd"
    logged = view_recording(stand_recording, save=rrd)
    assert logged["series"] == ["reached", "reference"] and logged["robot"] == "nao"
    text = rrd_text(rerun_cli, rrd)
    for group, joint in (
        ("head", "head_yaw"),
        ("arms", "left_elbow_roll"),
        ("legs", "right_knee_pitch"),
    ):
        assert f"/joints/{group}/{joint}/reached" in text
        assert f"/joints/{group}/{joint}/reference" in text
    assert "/world/robot/left_foot - data columns: [Transform3D" in text
    assert "/world/robot/torso/shape" in text and "/world/field/lines" in text
    assert "/world/ball" in text


def test_centre_of_mass_of_standing_robot_is_over_the_feet(stand_recording):
    tracks = read_tf(stand_recording)
    com = centre_of_mass_path(tracks, "nao")
    feet_x = (tracks["left_foot"].pos_m[:, 0] + tracks["right_foot"].pos_m[:, 0]) / 2
    assert np.all(np.abs(com[:, 1]) < 0.02)
    assert np.all(np.abs(com[:, 0] - feet_x) < 0.06)
    assert np.all((com[:, 2] > 0.2) & (com[:, 2] < 0.35))


def test_view_with_a_model_shows_compensated_and_replayed_curves(tmp_path, rerun_cli):
    from mimic.learn.presets import FAST
    from mimic.learn.train import TrainConfig, train_model, training_dataset
    from mimic.model.model_file import save_model
    from mimic.recording.recorder import RecordConfig

    source = tmp_path / "kick.mcap"
    record("kick_right", source, config=RecordConfig(tf_every=5))
    model = tmp_path / "kick.mimic"
    save_model(
        train_model(training_dataset(source, "/joint_states"), TrainConfig(FAST, epochs=3000)),
        model,
    )
    rrd = tmp_path / "view.rrd"
    logged = view_recording(source, model=model, save=rrd)
    assert logged["series"] == ["reached", "reference", "learned", "compensated", "replayed"]
    text = rrd_text(rerun_cli, rrd)
    for series in ("learned", "compensated", "replayed"):
        assert f"/joints/legs/right_knee_pitch/{series}" in text


@pytest.mark.parametrize("name", ["nao", "t1"])
def test_every_link_has_its_mass_and_a_shape(name):
    robot = get_robot(name)
    bodies = link_bodies(robot)
    assert [b.name for b in bodies] == [link.name for link in robot.links]
    assert sum(b.mass_kg for b in bodies) == pytest.approx(robot.mass_kg, rel=1e-6)
    assert all(b.shapes for b in bodies)


def test_a_league_robot_is_drawn_from_its_own_model(tmp_path, rerun_cli):
    import rerun as rr

    t1 = get_robot("t1")
    rrd = tmp_path / "t1.rrd"
    rec = rr.RecordingStream("mimic_test")
    rec.save(str(rrd))
    log_robot_geometry(rec, t1)
    rec.flush()
    text = rrd_text(rerun_cli, rrd)
    for link in (t1.root_link, *t1.foot_links):
        assert f"/world/robot/{link}/shape" in text
    assert "Mesh3D" in text
