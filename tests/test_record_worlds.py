"""One recorder in every world (issue 32): ``mimic record --world`` records in our world, the
league's simulation in process, on a hosted league server and in the league-like world, with
the same layout: joint states, references, the ended flag, and on ``/tf`` every link in its
parent and the ball."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.recording.reader import read_joint_table, read_recording, read_tf
from mimic.robot.registry import get_robot

T1 = get_robot("t1")
runner = CliRunner()


def _record(tmp_path, world: str, *extra: str):
    out = tmp_path / f"{world}.mcap"
    result = runner.invoke(
        app, ["record", "kick_right", "--robot", "t1", "--world", world, "-o", str(out), *extra]
    )
    assert result.exit_code == 0, result.output
    return out


@pytest.mark.parametrize(
    ("world", "recorded_as"),
    [("league", "league"), ("league-like", "league-like"), ("mujoco", "nao")],
)
def test_a_kick_recorded_in_each_world_shows_every_link_and_the_ball_kicked(
    tmp_path, world, recorded_as
):
    out = _record(tmp_path, world)
    info = read_recording(out).metadata["mimic"]
    assert info["world"] == recorded_as and info["robot"] == "t1"
    tf = read_tf(out)  # every frame in the field frame
    assert set(tf) == {link.name for link in T1.links} | {"ball"}
    joints = read_joint_table(out)
    assert joints.height == len(tf["torso"].times_ns) > 150  # 50 Hz, the whole kick
    torso_z = tf["torso"].pos_m[:, 2]
    assert 0.6 < torso_z[0] < 0.7 and torso_z.min() > 0.5  # stands through its kick
    ball = tf["ball"].pos_m
    assert np.linalg.norm(ball[-1, :2] - ball[0, :2]) > 1.0  # the kick kicked it
    # The kicking foot swings forward and comes back under the robot.
    foot = tf["right_foot_link"].pos_m[:, 0] - tf["torso"].pos_m[:, 0]
    assert foot.max() - foot[0] > 0.1


def test_a_recording_on_a_hosted_league_server_matches_the_one_in_process(tmp_path):
    """The server is seen through its monitor (5 ms older, 25 Hz, 4 decimals): the same
    kick, within a centimetre where the robot moves slowly; the kicking foot, which moves up
    to 4 cm a cycle, is shown a cycle late every other cycle."""
    served, local = _record(tmp_path, "league-server"), _record(tmp_path, "league")
    a, b = read_tf(served), read_tf(local)
    assert read_recording(served).metadata["mimic"]["world"] == "league"
    for frame, within_m in (("torso", 0.01), ("left_foot_link", 0.01), ("right_foot_link", 0.06)):
        assert np.abs(a[frame].pos_m - b[frame].pos_m).max() < within_m, frame
    ja, jb = read_joint_table(served), read_joint_table(local)
    assert ja.height == jb.height
