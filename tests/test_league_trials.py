"""Trials in the league world: its simulation in process (``league``) and on real servers mimic
hosts, one per episode (``league-server``); and the black-box recorder's only channel to
another team's process.

Short budgets: a league episode here is cut at a few simulated seconds. The kick is the T1's
shipped ``kick_right`` once there is one, else ``league_standin_kick.txt`` beside this file.
"""

from __future__ import annotations

import functools
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import polars as pl
import pytest
from _league_helpers import T1, mimic_command
from typer.testing import CliRunner

import mimic.tasks.kick as kick_module
from mimic.agents.registry import agent_spec
from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.league.server import LeagueServer
from mimic.motion.files import list_motions
from mimic.recording.reader import read_joint_table, read_recording, read_tf
from mimic.tasks.kick import KickTrialConfig, run_kick_episode
from mimic.tasks.walk import WalkTrialConfig, run_walk_episode
from mimic.trials.api import check_variants
from mimic.trials.executors import PoolExecutor
from mimic.trials.parallel import derive_seed, run_episodes

runner = CliRunner()
STANDIN_KICK = Path(__file__).with_name("league_standin_kick.txt")
#: Starts the league server like ``python -m rcsssmj``, first writing its process id to a file.
PID_SERVER = """import os, runpy, sys
with open(sys.argv.pop(1), "a") as f:
    f.write(f"{os.getpid()}\\n")
sys.argv[0] = "rcsssmj"
runpy.run_module("rcsssmj", run_name="__main__", alter_sys=True)
"""


def t1_kick() -> str:
    """The T1 kick the tests use: the shipped one, else the stand-in."""
    return "kick_right" if "kick_right" in list_motions("t1") else str(STANDIN_KICK)


def t1_walk() -> str:
    """The other team's T1 walk if it is there, else the T1 standing (a walk of 0 m)."""
    try:
        agent_spec("other-team-walk", robot="t1").check()
        return "other-team-walk"
    except (MimicError, ImportError):
        return "stand"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().split(")")[1].split()[0] == "Z")


def test_league_episodes_on_two_workers_repeat_and_leave_no_server(tmp_path):
    """Two episodes at once (two servers), the same rows as each episode replayed alone in
    this process; every server they started has stopped once the pool is closed."""
    wrapper, pids = tmp_path / "pid_server.py", tmp_path / "servers.txt"
    wrapper.write_text(PID_SERVER)
    config = KickTrialConfig(
        world="league-server",
        episode_limit_s=3.0,
        server_command=(sys.executable, str(wrapper), str(pids)),
    )
    spec = agent_spec(t1_kick(), robot="t1")
    with PoolExecutor(2) as pool:
        batch = run_episodes(run_kick_episode, spec, config, episodes=2, seed=4, executor=pool)
    started = [int(p) for p in pids.read_text().split()]
    assert len(started) == 2
    deadline = time.monotonic() + 5
    while any(_alive(p) for p in started) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(_alive(p) for p in started)
    assert [e["world"] for e in batch.episodes] == ["league-server"] * 2
    assert {e["reach"] for e in batch.episodes} == {"place"}
    assert batch.rows and all(r["ball_start_x_m"] > 10 for r in batch.rows)  # 15 m out
    again, _ = run_kick_episode(spec, derive_seed(4, 1), config)
    pooled = pl.DataFrame([r for r in batch.rows if r["episode"] == 1]).drop("episode")
    assert pooled.equals(pl.DataFrame(again))


def test_a_league_kick_trial_from_the_command_line(tmp_path, monkeypatch):
    """The real command, its episodes cut at 3 s, for 12 s (a budget that ends before the
    first kick does counts none): the table and the parquet file say where the episodes
    played and how the robot reached the ball."""
    monkeypatch.setattr(
        kick_module, "KickTrialConfig", functools.partial(KickTrialConfig, episode_limit_s=3.0)
    )
    out = tmp_path / "league.parquet"
    result = runner.invoke(
        app,
        [
            "trial",
            "kick",
            t1_kick(),
            "--world",
            "league",
            "--minutes",
            "0.2",
            "--workers",
            "1",
            "--success-m",
            "0.01",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "league world" in text and "placed behind the ball after each kick" in text
    # The kick's own success rule, in the legend and in every row.
    assert "ok: kicks farther than 0.01 m" in text
    kicks = pl.read_parquet(out)
    assert kicks.height >= 1
    assert kicks["success"].to_list() == (kicks["distance_m"] > 0.01).to_list()
    import json

    import pyarrow.parquet as pq

    meta = json.loads(pq.read_schema(out).metadata[b"mimic"])
    assert meta["config"]["world"] == "league" and meta["summary"][0]["reach"] == "place"
    assert meta["variants"][0]["robot"] == "t1"


def test_a_motion_only_the_t1_has_passes_the_trials_checks():
    # The checks before a trial once read every motion as the NAO's, so a T1-only motion
    # (kick_right_copyable) was "unknown" in a league kick trial.
    spec = agent_spec("kick_right_copyable", robot="t1")
    check_variants("kick", [spec])
    with pytest.raises(MimicError, match="unknown agent 'kick_right_copyable'"):
        agent_spec("kick_right_copyable", robot="nao")


def test_a_league_walk_runs_10_m_from_a_standing_start():
    config = WalkTrialConfig(world="league", timeout_s=2.0)
    assert config.course_m() == (-5.0, 5.0)
    (row,), _ = run_walk_episode(agent_spec(t1_walk(), robot="t1"), 3, config)
    assert row["world"] == "league" and 0 < row["walk_time_s"] <= 2.0 + 1e-9
    assert row["distance_m"] < 10 and row["end"] in ("timeout", "fell", "agent stopped")
    assert row["fell"] == (row["end"] == "fell") and row["y_error_m"] >= 0


@pytest.mark.parametrize(
    "args,fragment",
    [
        (
            ["kick", "kick_right", "--world", "league", "--robot", "nao"],
            "the league world plays league robots",
        ),
        (["walk", "--world", "moon"], "unknown world 'moon'"),
    ],
)
def test_bad_world_options_are_one_line(args, fragment):
    result = runner.invoke(app, ["trial", *args, "--minutes", "0.1"])
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and fragment in lines[0], result.output


def test_walking_to_the_ball_is_for_the_nao_in_our_world():
    spec = agent_spec(str(STANDIN_KICK), robot="t1")
    with pytest.raises(MimicError, match="walk engine drives the NAO only"):
        kick_module.reach_method(KickTrialConfig(reach="walk"), spec.robot)
    assert kick_module.reach_method(KickTrialConfig(), "nao") == "walk"
    assert kick_module.reach_method(KickTrialConfig(world="league"), "t1") == "place"


# --- black box ------------------------------------------------------------------------------


def _sockets(pid: int) -> tuple[set[int], int]:
    """(remote ports of the process's TCP sockets, how many Unix, UDP or raw sockets it has)
    read from /proc. A socket in no table is a TCP socket not yet connected (created, then
    connecting): it is neither."""
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])

    def table(name: str, inode_column: int) -> list[list[str]]:
        path = Path(f"/proc/{pid}/net/{name}")
        rows = [line.split() for line in path.read_text().splitlines()[1:]] if path.exists() else []
        return [r for r in rows if len(r) > inode_column and r[inode_column] in inodes]

    ports = {int(r[2].split(":")[1], 16) for t in ("tcp", "tcp6") for r in table(t, 9)}
    others = {r[9] for t in ("udp", "udp6", "raw", "raw6") for r in table(t, 9)}
    others |= {r[6] for r in table("unix", 6)}
    return ports, len(others)


@pytest.mark.skipif(not Path("/proc/self/net/tcp").exists(), reason="reads sockets from /proc")
def test_the_recorder_sees_the_other_team_only_through_the_monitor_stream(tmp_path):
    """The other team plays as its own process; the recorder, another process, connects to
    the server's monitor port and nowhere else, and still records the player's joints."""
    out = tmp_path / "seen.mcap"
    with LeagueServer() as server:
        recorder = subprocess.Popen(
            mimic_command()
            + [
                "record",
                "--server",
                server.monitor_address,
                "--team",
                "Others",
                "--player",
                "1",
                "--seconds",
                "4",
                "-o",
                str(out),
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        player = subprocess.Popen(
            mimic_command()
            + [
                "play",
                t1_walk(),
                "--robot",
                "t1",
                "--server",
                server.agent_address,
                "--team",
                "Others",
                "--player",
                "1",
                "--seconds",
                "6",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        seen: list[tuple[set[int], int]] = []
        try:
            while recorder.poll() is None:
                try:
                    seen.append(_sockets(recorder.pid))
                except (FileNotFoundError, ProcessLookupError):
                    break
                time.sleep(0.05)
            _, err = recorder.communicate(timeout=60)
        finally:
            player.kill()
            player.wait()
    assert recorder.returncode == 0, err
    assert player.pid != recorder.pid
    connected = [ports for ports, _ in seen if ports]
    assert connected, "the recorder never showed a connection"
    assert all(ports == {server.monitor_port} for ports in connected)
    assert all(other == 0 for _, other in seen)  # no Unix socket, no socket pair
    rec = read_recording(out)
    assert rec.info.source == "monitor" and rec.info.team == "Others"
    table = read_joint_table(rec)
    assert len(table) >= 20 and set(T1.joint_names) <= set(table.columns)
    # The player stood 1 s where the server put it (it arrives with straight joints), then
    # walked: upright at the end, and on its way (a walk started at once fell within 1.2 s).
    torso = read_tf(rec)[T1.root_link]
    assert torso.pos_m[-1, 2] > 0.5
    if t1_walk() == "other-team-walk":
        assert np.hypot(*(torso.pos_m[-1, :2] - torso.pos_m[0, :2])) > 0.1
