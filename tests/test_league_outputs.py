"""The league commands' files and lines (#31 sections 2 and 3, #30 item 4): a failed import
leaves its target as it was, `record --server` and `play -o` claim their output and never
replace an input, `play -o` records the torso and ball and says what happened, a model
learned from a league recording is named after the motion, and bad values are one line."""

from __future__ import annotations

import signal
import subprocess
import time

import numpy as np
import pytest
from _cli_helpers import one_line_error
from _league_helpers import mimic_command
from typer.testing import CliRunner

from mimic.agents.base import JointCommand
from mimic.cli.main import app
from mimic.league.server import LeagueServer, ServerConfig, free_port
from mimic.model.model_file import load_model
from mimic.recording import layout as L
from mimic.recording.player_writer import PlayerWriter
from mimic.recording.reader import read_joint_table, read_recording, read_tf
from mimic.team.play import play
from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

runner = CliRunner()
_one_line_error = one_line_error
TEAM, PLAYER = "others", 2


@pytest.fixture(scope="module")
def game(tmp_path_factory):
    """A game log of TEAM #PLAYER standing for 3 s on a hosted server, and its import."""
    d = tmp_path_factory.mktemp("league_outputs")
    log = d / "game.log"
    server = LeagueServer(ServerConfig(logfile=log)).start()
    try:
        world = LeagueWorld(
            "t1",
            agent_address=server.agent_address,
            config=LeagueWorldConfig(team=TEAM, player=PLAYER),
        )
        for _ in range(150):
            world.step(JointCommand.references(world.joint_angles_rad()))
        world.close()
    finally:
        server.stop()
    good = d / "good.mcap"
    result = runner.invoke(
        app, ["import", str(log), "--team", TEAM, "--player", str(PLAYER), "-o", str(good)]
    )
    assert result.exit_code == 0, result.output
    return {"log": log, "good": good, "dir": d}


def _failing_writes(monkeypatch, after: int) -> None:
    """PlayerWriter.write fails (disk full) after ``after`` samples."""
    original = PlayerWriter.write

    def write(self, sample, ball):
        if self.samples >= after:
            raise OSError(28, "No space left on device")
        return original(self, sample, ball)

    monkeypatch.setattr(PlayerWriter, "write", write)


def test_a_failed_import_leaves_the_target_as_it_was(game, tmp_path, monkeypatch):
    target = tmp_path / "seen.mcap"
    target.write_bytes(game["good"].read_bytes())
    before = target.read_bytes()
    _failing_writes(monkeypatch, after=20)
    args = ["import", str(game["log"]), "--team", TEAM, "--player", str(PLAYER)]
    result = runner.invoke(app, [*args, "-o", str(target), "--force"])
    _one_line_error(result, 1, "No space left on device")
    assert target.read_bytes() == before  # not a shorter file marked "import failed"
    new = tmp_path / "new.mcap"
    result = runner.invoke(app, [*args, "-o", str(new)])
    _one_line_error(result, 1, "No space left on device")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["seen.mcap"]  # no new file, no stub


def test_import_never_replaces_its_log_and_names_a_folder(game, tmp_path):
    log = tmp_path / "game.log"
    log.write_bytes(game["log"].read_bytes())
    args = ["import", str(log), "--team", TEAM, "--player", str(PLAYER)]
    _one_line_error(runner.invoke(app, [*args, "-o", str(log), "--force"]), 2, "also an input")
    assert log.read_bytes() == game["log"].read_bytes()
    folder = tmp_path / "logs"
    folder.mkdir()
    result = runner.invoke(app, ["import", str(folder), "--team", TEAM, "--player", "2", "-o", "x"])
    _one_line_error(result, 2, "is a directory")


def test_a_model_from_a_league_recording_is_named_after_the_motion(game, tmp_path):
    out = tmp_path / "seen_stand.mimic"
    result = runner.invoke(
        app, ["train", str(game["good"]), "--target", "reached", "--epochs", "5", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    model = load_model(out)
    assert model.name == "seen_stand"  # not the player, "others_2"
    assert model.metadata["team"] == TEAM and model.metadata["recorded_as"] == f"{TEAM}_{PLAYER}"


def test_two_recorders_of_one_file_the_second_is_refused(tmp_path):
    server = LeagueServer(ServerConfig(sync=False, realtime=True)).start()
    out = tmp_path / "seen.mcap"
    first = subprocess.Popen(
        mimic_command()
        + [
            "record",
            "--server",
            server.monitor_address,
            "--team",
            TEAM,
            "--player",
            "7",
            "--wait",
            "60",
            "-o",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        lock = tmp_path / ".seen.mcap.lock"
        deadline = time.monotonic() + 60
        while not lock.exists() and first.poll() is None:
            assert time.monotonic() < deadline, "the first recorder never claimed its file"
            time.sleep(0.1)
        assert first.poll() is None, first.communicate()
        for force in ([], ["--force"]):
            result = runner.invoke(
                app,
                [
                    "record",
                    "--server",
                    server.monitor_address,
                    "--team",
                    TEAM,
                    "--player",
                    "7",
                    "-o",
                    str(out),
                    *force,
                ],
            )
            _one_line_error(result, 2, "being written by another command", f"pid {first.pid}")
    finally:
        if first.poll() is None:
            first.send_signal(signal.SIGINT)
            first.communicate(timeout=30)
        server.stop()
    assert not out.exists() and not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "extra, message",
    [(["--wait", "nan"], "--wait must be a finite number >= 0"), ([], "start a server")],
)
def test_record_server_bad_values_and_a_closed_port_are_one_line(tmp_path, extra, message):
    port = free_port()
    result = runner.invoke(
        app,
        ["record", "--server", f"127.0.0.1:{port}", "--team", "a", "--player", "1"]
        + ["-o", str(tmp_path / "x.mcap"), *extra],
    )
    line = _one_line_error(result, 2, message)
    assert "let mimic host" not in line  # record cannot host a server
    assert not list(tmp_path.iterdir())


def test_play_refuses_an_existing_output_and_its_own_model(game, tmp_path):
    existing = tmp_path / "played.mcap"
    existing.write_bytes(b"keep me")
    result = runner.invoke(app, ["play", "stand", "-o", str(existing)])
    _one_line_error(result, 2, "exists; pass --force")
    assert existing.read_bytes() == b"keep me"
    t1_model = tmp_path / "stand.mimic"
    result = runner.invoke(
        app,
        ["train", str(game["good"]), "--target", "reached", "--epochs", "5", "-o", str(t1_model)],
    )
    assert result.exit_code == 0, result.output
    before = t1_model.read_bytes()
    for agent in (str(t1_model), f"{t1_model}+balance"):
        result = runner.invoke(app, ["play", agent, "-o", str(t1_model), "--force"])
        _one_line_error(result, 2, "is also an input")
    assert t1_model.read_bytes() == before
    result = runner.invoke(app, ["play", "stand", "--duration", "nan"])
    _one_line_error(result, 2, "--duration must be a finite number > 0")


def test_play_records_the_torso_and_ball_and_says_what_happened(tmp_path):
    out = tmp_path / "walk.mcap"
    # --duration here, --seconds as before: one option with two names
    result = runner.invoke(app, ["play", "other-team-walk", "--seconds", "3", "-o", str(out)])
    assert result.exit_code == 0, result.output
    line = result.output.strip().splitlines()[-1]
    assert "walked" in line and "m/s" in line and "falls" in line, line
    walked = float(line.split("walked ")[1].split(" m")[0])
    rec = read_recording(out)
    tf = read_tf(rec)
    assert {rec.robot.root_link, L.BALL_FRAME} <= set(tf)
    torso = tf[rec.robot.root_link]
    assert len(torso.times_ns) == len(read_joint_table(rec))
    moved = float(np.hypot(*(torso.pos_m[-1, :2] - torso.pos_m[0, :2])))
    assert walked > 0.2 and moved == pytest.approx(walked, abs=0.1)
    result = runner.invoke(app, ["play", "stand", "--duration", "1", "-o", str(out), "--force"])
    assert result.exit_code == 0, result.output
    assert "walked" in result.output and "0 falls" in result.output


def test_a_server_that_stops_under_play_says_how_many_cycles_ran():
    server = LeagueServer(ServerConfig()).start()
    seen = []

    def progress(t_s, total_s):
        seen.append(t_s)
        if len(seen) == 40:
            server.request_stop()  # under the player's feet

    try:
        result = play("stand", agent_address=server.agent_address, seconds=30, progress=progress)
    finally:
        server.stop()
    assert result.end == "server stopped"
    assert result.cycles >= 39  # not "after 0 cycles"


def test_a_failed_recording_from_a_server_leaves_the_target_as_it_was(game, tmp_path, monkeypatch):
    server = LeagueServer(ServerConfig(sync=False, realtime=True)).start()
    player = subprocess.Popen(
        mimic_command()
        + ["play", "stand", "--server", server.agent_address, "--team", TEAM]
        + ["--player", "3", "--seconds", "60"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    target = tmp_path / "seen.mcap"
    target.write_bytes(game["good"].read_bytes())
    try:
        _failing_writes(monkeypatch, after=10)
        result = runner.invoke(
            app,
            ["record", "--server", server.monitor_address, "--team", TEAM, "--player", "3"]
            + ["--wait", "60", "-o", str(target), "--force"],
        )
    finally:
        player.kill()
        player.wait()
        server.stop()
    assert result.exit_code == 1 and "Traceback" not in result.output, result.output
    # (a line may say it waits for the player first)
    assert result.output.splitlines()[-1] == "error: No space left on device", result.output
    assert target.read_bytes() == game["good"].read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["seen.mcap"]


def test_a_failed_play_leaves_its_output_as_it_was(tmp_path, monkeypatch):
    from mimic.recording.recorder import McapObserver

    target = tmp_path / "played.mcap"
    target.write_bytes(b"a good recording")
    original = McapObserver.before_step

    def before_step(self, *args):
        if self.samples >= 10:
            raise OSError(28, "No space left on device")
        original(self, *args)

    monkeypatch.setattr(McapObserver, "before_step", before_step)
    result = runner.invoke(app, ["play", "stand", "--seconds", "2", "-o", str(target), "--force"])
    _one_line_error(result, 1, "No space left on device")
    assert target.read_bytes() == b"a good recording"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["played.mcap"]


def test_play_to_a_closed_port_is_one_line_with_no_blank_line_before_it(tmp_path):
    port = free_port()
    result = runner.invoke(app, ["play", "stand", "--server", f"127.0.0.1:{port}"])
    assert result.output.splitlines()[0].startswith("error: "), repr(result.output)
    _one_line_error(result, 2, f"nothing listens on 127.0.0.1:{port}", "let mimic host one")
