"""Decoding accuracy, measured against the server's own MuJoCo state.

One game on a real RCSSServerMJ whose process also writes the true state at every monitor
frame (``league_truth_server.py``): a T1 played by our client lies on its back and sweeps its
joints like a get-up, then stands and sweeps them like a kick. Meanwhile ``mimic record
--server`` (a separate process) records it from the monitor stream; the server then stops
under it. Afterwards ``mimic import`` reads the server's game log of the same game. Both
recordings must match the truth: every joint within 0.01 rad on average and 0.03 rad at
worst, the torso within 1 cm.

Time: the server draws a frame stamped t from body poses computed before the cycle's last
physics step integrated the joints, so a frame shows the true state at t - dt (dt = 5 ms,
the league world's step; ``qpos - dt * qvel`` by the integrator, exactly). mimic stamps each
sample with that instant, so the check compares every sample with the true ``qpos`` at its
own time. Against ``qpos`` at the frame's stamp the error adds the 5 ms of motion (printed,
not asserted: up to dt times the joint speed).
"""

from __future__ import annotations

import signal
import subprocess
import time

import numpy as np
import pytest
from _league_helpers import (
    T1,
    errors_against_truth,
    getup_sweep,
    kick_sweep,
    mimic_command,
    read_truth,
    truth_server_config,
)
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.episode import Scene, run
from mimic.league.field import league_air
from mimic.league.server import LeagueServer
from mimic.motion.files import list_motions
from mimic.recording import layout as L
from mimic.recording.reader import read_joint_table, read_recording, read_tf
from mimic.robot.actuators import JointCommand
from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

TEAM, PLAYER = "decoders", 4
MEAN_RAD, MAX_RAD, TORSO_M = 0.01, 0.03, 0.01


def _motions():
    """The T1's shipped get-up and kick when they exist, else our sweeps."""
    from mimic.agents.registry import make_agent

    shipped = list_motions("t1")
    getup = make_agent("getup_back", robot="t1") if "getup_back" in shipped else getup_sweep()
    kick = make_agent("kick_right", robot="t1") if "kick_right" in shipped else kick_sweep()
    return getup, kick


@pytest.fixture(scope="module")
def game(tmp_path_factory):
    """Play the game once; return the truth, both recordings and the recorder's output."""
    d = tmp_path_factory.mktemp("league_game")
    truth_path, log, live = d / "truth.jsonl", d / "game.log", d / "live.mcap"
    server = LeagueServer(truth_server_config(truth_path, log)).start()
    recorder = subprocess.Popen(
        mimic_command()
        + [
            "record",
            "--server",
            server.monitor_address,
            "--team",
            TEAM,
            "--player",
            str(PLAYER),
            "--wait",
            "60",
            "-o",
            str(live),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    world = None
    try:
        world = LeagueWorld(
            "t1",
            agent_address=server.agent_address,
            monitor_address=server.monitor_address,
            config=LeagueWorldConfig(team=TEAM, player=PLAYER),
        )
        getup, kick = _motions()
        rng = np.random.default_rng(0)
        scene = Scene(robot_xy_m=(-2.0, 1.0), posture="lying_back", settle_s=0.2)
        scene.setup(world, rng)
        # The recorder starts while the robot is placed; its file appears with its first
        # sample. Hold the pose until then (a sync server drops a player silent for 5 s).
        deadline = time.monotonic() + 30
        while not live.exists() and recorder.poll() is None and time.monotonic() < deadline:
            world.step(JointCommand.references(world.joint_angles_rad()))
        run(world, getup, max_s=4.0)
        Scene(robot_xy_m=(-1.0, -1.0), robot_yaw_rad=0.5, settle_s=0.3).setup(world, rng)
        run(world, kick, max_s=3.0)
        world.step(JointCommand.references(world.joint_angles_rad()))
        time.sleep(0.3)  # let the recorder read the last frames
        server.request_stop()  # under the recorder's feet: it must finish its file, say so
        world.close()
        _, stderr = recorder.communicate(timeout=60)
    finally:
        if world is not None:
            world.close()
        if recorder.poll() is None:
            recorder.send_signal(signal.SIGINT)
            recorder.wait(timeout=30)
        server.stop()
    imported = d / "imported.mcap"
    result = CliRunner().invoke(
        app, ["import", str(log), "--team", TEAM, "--player", str(PLAYER), "-o", str(imported)]
    )
    return {
        "truth": read_truth(truth_path, f"{TEAM} {PLAYER}"),
        "live": live,
        "imported": imported,
        "log": log,
        "recorder_code": recorder.returncode,
        "recorder_stderr": stderr,
        "import": result,
    }


def _errors(path, truth):
    rec = read_recording(path)
    start = float(rec.info.extra["start_server_time_s"])
    table = read_joint_table(rec)
    times = start + table["time_s"].to_numpy()
    angles = table.select(T1.joint_names).to_numpy()
    torso = read_tf(rec)[T1.root_link]
    assert len(torso.times_ns) == len(times)
    return errors_against_truth(times, angles, torso.pos_m, truth, league_air().timestep_s), rec


def _report(name, err) -> None:
    shown, qpos = err["shown"], err["qpos"]
    print(
        f"\n{name}: {len(shown)} samples; vs true qpos at the sample's time: mean "
        f"{shown.mean():.4f} max {shown.max():.4f} rad (worst joint mean "
        f"{shown.mean(0).max():.4f}); vs qpos at the frame's stamp: mean {qpos.mean():.4f} "
        f"max {qpos.max():.4f} rad; torso max {err['torso'].max() * 1000:.1f} mm"
    )


@pytest.mark.parametrize("which", ["live", "imported"])
def test_decoded_angles_match_the_servers_state(game, which):
    err, rec = _errors(game[which], game["truth"])
    _report(which, err)
    assert len(err["shown"]) > 80  # the whole game, at 25 Hz
    per_joint_mean, per_joint_max = err["shown"].mean(axis=0), err["shown"].max(axis=0)
    worst = T1.joint_names[int(np.argmax(per_joint_max))]
    assert per_joint_mean.max() <= MEAN_RAD, dict(zip(T1.joint_names, per_joint_mean))
    assert per_joint_max.max() <= MAX_RAD, (worst, per_joint_max.max())
    assert err["torso"].max() <= TORSO_M
    # the motions moved the joints far and fast: the check is not about a robot standing still
    angles = read_joint_table(rec).select(T1.joint_names).to_numpy()
    assert np.ptp(angles, axis=0).max() > 2.0
    info = rec.info
    assert (info.world, info.robot, info.team, info.extra["player"]) == (
        "league",
        "t1",
        TEAM,
        str(PLAYER),
    )
    assert info.source == ("monitor" if which == "live" else "game_log")
    assert L.ROBOT_DESCRIPTION in rec.topics and L.TF in rec.topics


def test_a_server_that_stops_under_the_recorder(game):
    """The recorder says so in one line, exits non-zero, and its file is valid."""
    lines = [ln for ln in game["recorder_stderr"].splitlines() if ln.strip()]
    assert game["recorder_code"] == 1, game["recorder_stderr"]
    assert "Traceback" not in game["recorder_stderr"]
    assert any("the server stopped" in ln and "saved" in ln for ln in lines), lines
    rec = read_recording(game["live"])
    assert rec.recovery.complete and rec.interrupted
    assert rec.metadata[L.END_METADATA_NAME]["reason"] == "the server stopped"


def test_import_of_the_game_log(game):
    assert game["import"].exit_code == 0, game["import"].output
    assert f"{TEAM} #{PLAYER} (T1)" in game["import"].output


def test_a_cut_off_log_yields_every_complete_frame(game, tmp_path):
    data = game["log"].read_bytes()
    cut = tmp_path / "cut.log"
    cut.write_bytes(data[: len(data) * 2 // 3])  # ends inside a frame
    out = tmp_path / "cut.mcap"
    result = CliRunner().invoke(
        app, ["import", str(cut), "--team", TEAM, "--player", str(PLAYER), "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    full = read_joint_table(game["imported"])
    part = read_joint_table(out)
    assert 20 < len(part) < len(full)
    columns = ["time_s", *T1.joint_names]
    np.testing.assert_array_equal(
        part.select(columns).to_numpy(), full.head(len(part)).select(columns).to_numpy()
    )


def test_import_every_player_of_a_log(game, tmp_path):
    result = CliRunner().invoke(
        app, ["import", str(game["log"]), "--all", "-o", str(tmp_path / "players")]
    )
    assert result.exit_code == 0, result.output
    files = sorted((tmp_path / "players").iterdir())
    assert [f.name for f in files] == [f"{TEAM}_{PLAYER}.mcap"]
    assert read_joint_table(files[0]).equals(read_joint_table(game["imported"]))
