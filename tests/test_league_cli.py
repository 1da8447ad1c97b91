"""`mimic play`, `mimic record --server` and `mimic import` on real league servers.

One server runs a real-time match (no sync) with one of our agents on it as a team process
(`mimic play ... --server`, a separate process); the recorder, the list and every bad input
meet that server. A second test hosts its own server (`mimic play` without --server).
"""

from __future__ import annotations

import re
import signal
import subprocess
import threading
import time

import numpy as np
import pytest
from _league_helpers import T1, mimic_command
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.league.server import LeagueServer, ServerConfig, free_port
from mimic.recording import layout as L
from mimic.recording.blackbox import list_players, record_player
from mimic.recording.reader import read_joint_table, read_recording

runner = CliRunner()
TEAM, PLAYER = "visitors", 2


@pytest.fixture(scope="module")
def match(tmp_path_factory):
    """A real-time server with `mimic play stand` on it as visitors #2 (recording itself)."""
    d = tmp_path_factory.mktemp("league_match")
    server = LeagueServer(ServerConfig(sync=False, realtime=True)).start()
    played = d / "played.mcap"
    player = subprocess.Popen(
        mimic_command()
        + [
            "play",
            "stand",
            "--server",
            server.agent_address,
            "--team",
            TEAM,
            "--player",
            str(PLAYER),
            "--seconds",
            "120",
            "-o",
            str(played),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not list_players(server.monitor_address) and player.poll() is None:
            assert time.monotonic() < deadline, "the player never joined"
            time.sleep(0.2)
        yield {"server": server, "player": player, "played": played}
    finally:
        if player.poll() is None:
            player.kill()
            player.wait()
        server.stop()


def _one_line_error(result, code: int, *fragments: str) -> None:
    assert result.exit_code == code, result.output
    assert "Traceback" not in result.output
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def test_list_names_the_players_and_their_robots(match):
    result = runner.invoke(app, ["record", "--server", match["server"].monitor_address, "--list"])
    assert result.exit_code == 0, result.output
    assert f"{TEAM} #{PLAYER} (T1)" in result.output


def test_record_a_player_from_the_monitor_stream(match, tmp_path):
    out = tmp_path / "seen.mcap"
    result = runner.invoke(
        app,
        [
            "record",
            "--server",
            match["server"].monitor_address,
            "--team",
            TEAM,
            "--player",
            str(PLAYER),
            "--seconds",
            "1",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    rec = read_recording(out)
    table = read_joint_table(rec)
    assert 24 <= len(table) <= 27  # 25 Hz
    assert table["time_s"][-1] == pytest.approx(1.0, abs=0.05)
    assert rec.info.world == "league" and rec.info.robot == "t1" and rec.info.team == TEAM
    assert rec.info.source == "monitor" and rec.info.extra["player"] == str(PLAYER)
    stand = table.select(T1.joint_names).to_numpy()[-1]
    assert np.abs(stand - T1.stand_pose()).max() < 0.1  # the player holds its stand pose


def test_a_player_not_on_the_field_is_named_with_those_who_are(match, tmp_path):
    out = tmp_path / "nobody.mcap"
    result = runner.invoke(
        app,
        [
            "record",
            "--server",
            match["server"].monitor_address,
            "--team",
            TEAM,
            "--player",
            "9",
            "--wait",
            "0.3",
            "-o",
            str(out),
        ],
    )
    _one_line_error(result, 2, f"{TEAM} #9 is not on the field", f"{TEAM} #{PLAYER} (T1)")
    assert not out.exists()


def test_a_robot_option_the_stream_contradicts(match, tmp_path):
    out = tmp_path / "k1.mcap"
    result = runner.invoke(
        app,
        [
            "record",
            "--server",
            match["server"].monitor_address,
            "--team",
            TEAM,
            "--player",
            str(PLAYER),
            "--robot",
            "k1",
            "-o",
            str(out),
        ],
    )
    _one_line_error(result, 2, "is a T1 robot, not a K1")
    assert not out.exists()


@pytest.mark.parametrize(
    "command",
    [
        ["record", "--team", "a", "--player", "1"],
        ["play", "stand"],
    ],
)
def test_nothing_listening_on_the_port(tmp_path, command):
    out = tmp_path / "x.mcap"
    port = free_port()
    result = runner.invoke(app, command + ["--server", f"127.0.0.1:{port}", "-o", str(out)])
    _one_line_error(result, 2, f"nothing listens on 127.0.0.1:{port}")
    assert not out.exists()


def test_a_file_that_is_not_a_game_log(tmp_path):
    text = tmp_path / "match.log"
    text.write_text("this is not RSMP\n")
    result = runner.invoke(
        app, ["import", str(text), "--team", "a", "--player", "1", "-o", str(tmp_path / "x.mcap")]
    )
    _one_line_error(result, 2, "is not an RCSSServerMJ game log")


def test_a_model_of_another_robot_played_on_the_t1(tmp_path):
    from _learn_helpers import joint_frame, smooth_motion

    from mimic.learn.dataset import dataset_from_frame
    from mimic.learn.presets import FAST
    from mimic.learn.train import TrainConfig, train_model
    from mimic.model.model_file import save_model

    t, q = smooth_motion(20)
    model = train_model(
        dataset_from_frame(joint_frame(t, q), metadata={"motion": "wave"}),
        TrainConfig(FAST, seed=0, epochs=50),
    )
    path = save_model(model, tmp_path / "nao_wave.mimic")
    result = runner.invoke(app, ["play", str(path), "--robot", "t1"])
    _one_line_error(result, 2, "made for the NAO", "T1")


@pytest.mark.slow  # hosting is covered by test_league_world, playing by the match below
def test_play_on_a_server_of_its_own(tmp_path):
    out = tmp_path / "hosted.mcap"
    result = runner.invoke(
        app, ["play", "stand", "--seconds", "0.8", "--player", "5", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    assert "ball" not in result.output  # only a kick gets a ball in front of it
    rec = read_recording(out)
    assert rec.recovery.complete and not rec.interrupted
    assert {L.JOINT_STATES, L.JOINT_REFERENCES, L.ENDED, L.ROBOT_DESCRIPTION} <= set(rec.topics)
    assert rec.info.world == "league" and rec.info.robot == "t1"
    assert rec.info.extra == {"player": "5", "server": "hosted"}
    refs = read_joint_table(rec, topic=L.JOINT_REFERENCES)
    seen = read_joint_table(rec, topic=L.JOINT_STATES)
    assert len(refs) == len(seen) == 40
    np.testing.assert_allclose(
        refs.select(T1.joint_names).to_numpy()[-1], T1.stand_pose(), atol=1e-9
    )  # the stand motion takes 0.6 s
    assert np.abs(seen.select(T1.joint_names).to_numpy()[-1] - T1.stand_pose()).max() < 0.1


def test_a_kick_on_a_server_of_its_own_gets_a_ball_and_says_how_far_it_went():
    result = runner.invoke(app, ["play", "kick_right"])
    assert result.exit_code == 0, result.output
    went = re.search(r"the ball went ([0-9.]+) m", result.output)
    assert went is not None, result.output
    # The shipped T1 kick puts the ball 3 m or more away (test_t1_motions, 10 seeds).
    assert float(went.group(1)) >= 3.0


def test_ctrl_c_ends_a_team_process_with_its_file_finished(match, tmp_path):
    """Runs last: stops the match's player (and a recording of it ends as it leaves)."""
    results = []
    recorder = threading.Thread(
        target=lambda: results.append(
            record_player(match["server"].monitor_address, tmp_path / "last.mcap", TEAM, PLAYER)
        )
    )
    recorder.start()
    time.sleep(0.5)
    player = match["player"]
    player.send_signal(signal.SIGINT)
    _, stderr = player.communicate(timeout=30)
    recorder.join(timeout=30)
    assert results and results[0].reason == f"{TEAM} #{PLAYER} left the field"
    assert not results[0].interrupted and results[0].samples > 5
    assert player.returncode == 130, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr
    rec = read_recording(match["played"])
    assert rec.recovery.complete and rec.interrupted
    assert len(read_joint_table(rec, topic=L.JOINT_REFERENCES)) > 25


@pytest.mark.parametrize("settle", ["-1", "inf", "nan"])
def test_a_bad_settle_time_is_one_line(settle):
    result = runner.invoke(app, ["play", "stand", "--settle", settle])
    _one_line_error(result, 2, "--settle must be a finite number of seconds >= 0")
