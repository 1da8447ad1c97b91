"""A game log or a server is untrusted input (issue 31, section 1).

Every case starts from a real game log (a T1 standing on a hosted RCSSServerMJ, made once)
and changes what an adversary could: team names that are paths or Rich markup or terminal
escapes, malformed frames, random bytes, a server that never sends a scene. `mimic import`
reads such logs; `mimic record --server` reads them from a fake monitor port of the test's own
(loopback, a free port). Nothing may escape the output folder, replace a file without
--force, crash with a traceback, reach the terminal raw, or hang.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
from pathlib import Path

import pytest
from _league_fakes import (
    FakeMonitor,
    log_lines,
    random_bytes,
    record_real_log,
    renamed,
    replay,
    silent,
)
from _league_helpers import mimic_command
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.league.rsmp import SceneState

runner = CliRunner()
TEAM, PLAYER = "alpha", 1


@pytest.fixture(scope="module")
def real(tmp_path_factory) -> list[bytes]:
    """The frames of a short real game: alpha #1, a T1, standing."""
    return log_lines(record_real_log(tmp_path_factory.mktemp("real") / "game.log", TEAM, PLAYER))


def _log(path: Path, lines: list[bytes]) -> Path:
    path.write_bytes(b"".join(line + b"\n" for line in lines))
    return path


def _on_field(real: list[bytes]) -> list[bytes]:
    """The frames while the player is on the field, from the first full frame that shows it."""
    state, start = SceneState(), None
    for k, line in enumerate(real):
        state.apply(line)
        if start is None and state.players:
            start = k
        elif start is not None and not state.players:
            return real[start:k]
    return real[start:]


def _files(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}


def _no_traceback(result) -> None:
    assert result.exception is None or isinstance(result.exception, SystemExit), (
        result.output,
        result.exception,
    )
    assert "Traceback" not in result.output


def _one_line_error(result, code: int, *fragments: str) -> None:
    assert result.exit_code == code, result.output
    _no_traceback(result)
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


# --- 1. names from a log never choose a path -------------------------------------------------
def test_team_names_never_choose_a_path_outside_the_output_folder(real, tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    lines = (
        renamed(real, TEAM, b"../escaped")
        + renamed(real, TEAM, str(outside / "abs").encode())
        + renamed(real, TEAM, b"a/b/c")
        + renamed(real, TEAM, b"a_b_c")  # the same file name as a/b/c once made safe
    )
    log = _log(tmp_path / "game.log", lines)
    out = tmp_path / "work" / "players"
    result = runner.invoke(app, ["import", str(log), "--all", "-o", str(out)])
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    made = _files(out)
    assert len(made) == 4 and all("/" not in name for name in made), made
    assert _files(tmp_path) == {"game.log"} | {f"work/players/{n}" for n in made}
    assert not list(outside.iterdir())
    before = {n: (out / n).read_bytes() for n in made}
    again = runner.invoke(app, ["import", str(log), "--all", "-o", str(out)])
    _one_line_error(again, 2, "exists; pass --force")
    assert {n: (out / n).read_bytes() for n in made} == before
    forced = runner.invoke(app, ["import", str(log), "--all", "-o", str(out), "--force"])
    assert forced.exit_code == 0, forced.output
    assert _files(out) == made


# --- 2. malformed frames are skipped and counted -------------------------------------------
def _malformed(real: list[bytes]) -> list[bytes]:
    """One bad frame of each kind the issue names, made from the log's own frames."""
    on = _on_field(real)
    full, diff = on[0], on[-1]
    return [
        b"(gt 1 0)abc",
        diff.replace(b"((gt 1 0)", b"((gt 1 0)abc", 1),
        diff.replace(b"(SLT ", b"(SLT x", 1),
        full.replace(b"(SLT ", b"(SLT 1 2 3)(SLT ", 1),
        full.replace(b"(agent alpha 1)", b"(agent alpha two)"),
        full.replace(b"(agent alpha 1)", b"(agent (alpha) 1)"),
        full.replace(b"(gt 1 0)", b"(gt 1 0)(1 2)", 1),
        full.replace(b"(team_left alpha)", b"(team_left (x))"),
        b"((RSMP 1 0)((gt 1 0)1e999)((sg 1 0)full(nd)))",
        b"((RSMP 1 0)((gt 1 0)nan))",
        b"((RSMP 1 0)((sg 1 0)full" + b"(nd " * 5000 + b")" * 5001 + b")",
        b"\xff\xfe\x00(((",
    ]


def test_malformed_frames_are_skipped_and_counted_by_the_scene(real):
    state = SceneState()
    for frame in _on_field(real)[:30]:
        state.apply(frame)
    players, time_s, skipped = state.players, state.time_s, state.skipped
    assert [(p.team, p.player) for p in players] == [(TEAM, PLAYER)]
    for k, frame in enumerate(_malformed(real), 1):
        assert state.apply(frame) is False, frame[:60]
        assert state.skipped == skipped + k
        assert state.players == players and state.time_s == time_s  # the scene as it was
    # A name that is not UTF-8 is a name (shown escaped), not a reason to drop the frame.
    full = _on_field(real)[0]
    assert state.apply(full.replace(b"(agent alpha 1)", b"(agent \xff\xfe 1)")) is True
    assert [p.team for p in state.players] == ["\\xff\\xfe"]


def test_import_skips_malformed_frames_and_says_how_many(real, tmp_path):
    bad = _malformed(real)
    on = _on_field(real)
    lines = on[:20] + bad + on[20:]  # while the player is on the field
    log = _log(tmp_path / "game.log", lines)
    out = tmp_path / "alpha.mcap"
    result = runner.invoke(
        app, ["import", str(log), "--team", TEAM, "--player", str(PLAYER), "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    lines_out = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines_out) == 1 and "frames skipped" in lines_out[0], lines_out
    skipped = int(re.search(r"\((\d+) frames skipped", lines_out[0]).group(1))
    assert skipped >= len(bad)


def test_record_server_skips_malformed_frames(real, tmp_path):
    on = _on_field(real)
    frames = on[:20] + _malformed(real) + on[20:]
    out = tmp_path / "live.mcap"
    with FakeMonitor(replay(frames, then="close")) as fake:
        result = runner.invoke(
            app,
            ["record", "--server", fake.address, "--team", TEAM, "--player", str(PLAYER)]
            + ["--wait", "5", "-o", str(out)],
        )
    _no_traceback(result)
    assert result.exit_code in (0, 1), result.output  # 1: the stream ended (server gone)
    assert out.exists() and "frames skipped" in result.output, result.output


# --- 3. names reach the terminal as plain text ---------------------------------------------
MARKUP, ESCAPE = b"[/x]", b"\x1b[31mred\x1b[0m"


def test_list_prints_markup_and_escapes_as_plain_text(real):
    frames = renamed(_on_field(real), TEAM, MARKUP)[:40]
    with FakeMonitor(replay(frames)) as fake:
        result = runner.invoke(app, ["record", "--server", fake.address, "--list"])
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    assert "[/x] #1 (T1)" in result.output
    frames = renamed(_on_field(real), TEAM, ESCAPE)[:40]
    with FakeMonitor(replay(frames)) as fake:
        result = runner.invoke(app, ["record", "--server", fake.address, "--list"])
    assert result.exit_code == 0, result.output
    assert "\\x1b[31mred\\x1b[0m #1 (T1)" in result.output
    assert "\x1b" not in result.output


def test_the_waiting_message_and_progress_bar_take_any_name(real, tmp_path):
    frames = renamed(_on_field(real), TEAM, MARKUP + ESCAPE)
    with FakeMonitor(replay(frames, period_s=0.01)) as fake:
        result = runner.invoke(
            app,
            ["record", "--server", fake.address, "--team", "[/y]\x1b[2J", "--player", "3"]
            + ["--wait", "1.5", "-o", str(tmp_path / "x.mcap")],
        )
    _no_traceback(result)
    assert result.exit_code == 2, result.output
    assert "\x1b" not in result.output
    assert "[/y]\\x1b[2J #3 is not on the field" in result.output
    assert "[/x]\\x1b[31mred\\x1b[0m #1 (T1)" in result.output


def test_import_all_takes_any_name(real, tmp_path):
    log = _log(tmp_path / "game.log", renamed(real, TEAM, MARKUP + ESCAPE))
    result = runner.invoke(app, ["import", str(log), "--all", "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    assert "[/x]\\x1b[31mred\\x1b[0m #1 (T1)" in result.output
    assert "\x1b" not in result.output
    assert _files(tmp_path / "out") == {"_x_31mred_0m_1.mcap"}
    info = runner.invoke(app, ["info", str(tmp_path / "out" / "_x_31mred_0m_1.mcap")])
    assert info.exit_code == 0, info.output
    _no_traceback(info)
    assert "\x1b" not in info.output


# --- 4. every wait has a bound and answers Ctrl-C ------------------------------------------
def test_a_stream_of_junk_messages_ends_the_wait_for_a_scene():
    """Small messages that are not frames: the wait for a scene has a deadline, and the error
    says how many malformed frames came."""
    from mimic.league.errors import LeagueConnectionError
    from mimic.recording.blackbox import list_players

    junk = [b"(junk %d)" % k for k in range(20000)]
    with FakeMonitor(replay(junk, period_s=0.0005)) as fake:
        with pytest.raises(LeagueConnectionError, match=r"no scene from .*malformed frames"):
            list_players(fake.address, timeout_s=1.5)


def _run(args: list[str]) -> subprocess.Popen:
    return subprocess.Popen(
        mimic_command() + args,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "COLUMNS": "200"},
    )


def test_random_bytes_end_a_recording_with_one_line(tmp_path):
    """Random bytes: a length no frame has, said in one line (not a wait for 4 GB)."""
    with FakeMonitor(random_bytes()) as fake:
        proc = _run(
            ["record", "--server", fake.address, "--team", TEAM, "--player", "1"]
            + ["-o", str(tmp_path / "x.mcap")]
        )
        try:
            _, stderr = proc.communicate(timeout=60)  # a bound against a hang
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            pytest.fail("mimic record --server kept reading random bytes for 60 s")
    assert proc.returncode == 2, stderr
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and fake.address in lines[0] and "not an RCSSServerMJ" in lines[0]
    assert not (tmp_path / "x.mcap").exists()


def _interrupt_after(
    proc: subprocess.Popen,
    fake: FakeMonitor,
    seconds: float,
    sig: int = signal.SIGINT,
    ready=lambda: True,
) -> tuple[str, float]:
    """Signal ``proc`` ``seconds`` after it connected to ``fake`` and ``ready()`` holds; its
    stderr and how long it took to end."""
    deadline = time.monotonic() + 60  # mimic starting on a busy machine
    while not (fake.connections and ready()) and proc.poll() is None:
        if time.monotonic() > deadline:
            break
        time.sleep(0.05)
    time.sleep(seconds)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(sig)
    sent = time.monotonic()
    _, stderr = proc.communicate(timeout=30)  # a bound against a hang, not a timing claim
    return stderr, time.monotonic() - sent


@pytest.mark.parametrize("serve", ["junk messages", "silence"])
def test_ctrl_c_before_the_first_scene(serve, tmp_path):
    junk = replay([b"(junk %d)" % k for k in range(20000)], period_s=0.001)
    with FakeMonitor(junk if serve == "junk messages" else silent()) as fake:
        proc = _run(
            ["record", "--server", fake.address, "--team", TEAM, "--player", "1"]
            + ["-o", str(tmp_path / "x.mcap")]
        )
        stderr, _ = _interrupt_after(proc, fake, 1.0)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert not (tmp_path / "x.mcap").exists()


def test_ctrl_c_while_waiting_for_the_player(real, tmp_path):
    with FakeMonitor(replay(real, period_s=0.02)) as fake:
        proc = _run(
            ["record", "--server", fake.address, "--team", "nobody", "--player", "9"]
            + ["--wait", "120", "-o", str(tmp_path / "x.mcap")]
        )
        stderr, _ = _interrupt_after(proc, fake, 2.0)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and "interrupted" in stderr
    assert not (tmp_path / "x.mcap").exists()


# --- fuzz: thousands of mutated frames of the real log -------------------------------------
_JUNK = [
    b"two",
    b"nan",
    b"-inf",
    b"1e999",
    b"(x)",
    b"()",
    b"(",
    b")",
    b"\xff\xfe",
    b"[/x]",
    b"\x1b[2J",
    b"../up",
    b"/abs/path",
    b"a/b",
    b"-1",
    b"99999999999999999999",
    b"(SLT 1 2)",
    b"(nd",
    b"(agent ../../evil 7)",
    b"(agent [/x] 8)",
]


def _mutate(frame: bytes, rng) -> bytes:
    """One to three random edits: a byte flipped, a span cut or doubled, junk put in, a
    token replaced, the team name replaced, the frame cut short."""
    b = bytearray(frame)
    for _ in range(int(rng.integers(1, 4))):
        n = len(b)
        op = int(rng.integers(0, 7))
        at = int(rng.integers(0, max(n, 1)))
        if op == 0 and n:
            b[at] = int(rng.integers(0, 256))
        elif op == 1 and n:
            del b[at : at + int(rng.integers(1, 64))]
        elif op == 2 and n:
            b[at:at] = b[at : at + int(rng.integers(1, 256))]
        elif op == 3:
            b[at:at] = _JUNK[int(rng.integers(0, len(_JUNK)))]
        elif op == 5:
            name = _JUNK[int(rng.integers(0, len(_JUNK)))]
            b = bytearray(bytes(b).replace(f"(agent {TEAM} ".encode(), b"(agent " + name + b" "))
        elif op == 4:
            tokens = [m.span() for m in re.finditer(rb"[^\s()]+", bytes(b))]
            if tokens:
                s, e = tokens[int(rng.integers(0, len(tokens)))]
                b[s:e] = _JUNK[int(rng.integers(0, len(_JUNK)))]
        else:
            del b[at:]
    return bytes(b)


def _fuzzed(real: list[bytes], seed: int, count: int) -> list[bytes]:
    """``count`` frames of the game in order, about half of them mutated, its first full
    frame again every 20 frames (a scene to break, and names to change)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    on = _on_field(real)
    frames = [on[0]]
    for k in range(1, count):
        frame = on[0] if k % 20 == 0 else on[k % len(on)]
        frames.append(_mutate(frame, rng) if rng.random() < 0.5 else frame)
    return frames


def test_fuzz_scene_state_never_raises(real):
    """Every mutated frame is either applied or skipped and counted."""
    import numpy as np

    rng = np.random.default_rng(1)
    on = _on_field(real)
    state = SceneState()
    state.apply(on[0])
    for k in range(3000):
        frame = _mutate(on[int(rng.integers(0, len(on)))], rng)
        before = state.frames + state.skipped
        state.apply(frame)
        assert state.frames + state.skipped == before + 1
        if k % 50 == 0:
            state.apply(on[0])  # a whole scene again, so that diffs have something to break


@pytest.mark.parametrize("seed", [11, 12])
def test_fuzz_import(real, tmp_path, seed):
    """`mimic import` of a log of mutated frames: a result or one line, nothing outside -o."""
    log = _log(tmp_path / "game.log", _fuzzed(real, seed, 600))
    out = tmp_path / "out"
    every = runner.invoke(app, ["import", str(log), "--all", "-o", str(out / "all")])
    one = runner.invoke(
        app,
        ["import", str(log), "--team", TEAM, "--player", str(PLAYER), "-o", str(out / "a.mcap")],
    )
    for result in (every, one):
        _no_traceback(result)
        assert result.exit_code in (0, 1, 2), result.output
        if result.exit_code:
            lines = [ln for ln in result.output.splitlines() if ln.strip()]
            assert lines[-1].startswith("error:"), lines
    assert {p.relative_to(tmp_path).parts[0] for p in tmp_path.rglob("*")} <= {"game.log", "out"}
    assert all(p.parent in (out, out / "all") for p in out.rglob("*") if p.is_file())


@pytest.mark.parametrize("seed", [21])
def test_fuzz_record_server(real, tmp_path, seed):
    """`mimic record --server` on a fake monitor port streaming mutated frames: it ends (the
    stream closes), with a result or one line, and writes nothing but its -o file."""
    frames = _fuzzed(real, seed, 1500)
    out = tmp_path / "rec" / "live.mcap"
    with FakeMonitor(replay(frames, then="close")) as fake:
        proc = _run(
            ["record", "--server", fake.address, "--team", TEAM, "--player", str(PLAYER)]
            + ["--wait", "3", "-o", str(out)]
        )
        try:
            stdout, stderr = proc.communicate(timeout=120)  # a bound against a hang
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            pytest.fail("mimic record --server did not end within 120 s")
    assert "Traceback" not in stderr, stderr
    assert proc.returncode in (0, 1, 2), stderr
    if proc.returncode:
        assert stderr.strip().splitlines()[-1].startswith("error:"), stderr
    assert all(p == out for p in tmp_path.rglob("*") if p.is_file())


# --- 5. mimic never stops a server --------------------------------------------------------
def test_fifty_lists_and_recorders_leave_a_sync_server_running(tmp_path):
    """A sync server running free (no player answering): 50 `--list` calls and 5 recorders
    whose player is not on the field come and go; the server still runs and serves."""
    from mimic.league.monitor import MonitorClient
    from mimic.league.server import LeagueServer, ServerConfig

    with LeagueServer(ServerConfig(sync=True, realtime=False)) as server:
        for k in range(55):
            if k % 11 == 10:
                args = ["--team", "nobody", "--player", "9", "--wait", "0.3"]
                args += ["-o", str(tmp_path / f"x{k}.mcap")]
                code = 2
            else:
                args, code = ["--list"], 0
            result = runner.invoke(app, ["record", "--server", server.monitor_address, *args])
            assert result.exit_code == code, (k, result.output, server.output()[-3000:])
        with MonitorClient("127.0.0.1", server.monitor_port) as monitor:
            deadline = time.monotonic() + 30
            while not monitor.state.valid and time.monotonic() < deadline:
                monitor.read(timeout_s=1.0)
            t0 = monitor.state.time_s
            while monitor.state.time_s <= t0 + 0.5 and time.monotonic() < deadline:
                monitor.read(timeout_s=1.0)
            assert monitor.state.time_s > t0 + 0.5, "the server's clock stopped"
        assert server.running, server.output()[-3000:]
        assert "Traceback" not in server.output(), server.output()[-3000:]


def test_mimic_leaves_just_after_a_message_with_a_half_close():
    """How mimic leaves a server it does not host: it drops what it has not read, waits for
    the next message and half-closes at once (the server's simulation thread is then
    stepping, not sending; `Connection.close`), then reads until the server closes."""
    import socket
    import struct
    import threading

    from mimic.league.protocol import connect

    listener = socket.create_server(("127.0.0.1", 0))
    seen: dict = {}

    def serve() -> None:
        peer, _ = listener.accept()
        frame = b"(RSMP 1 0)"
        # Three at once (one segment): the client reads one, two wait unread when it leaves.
        peer.sendall((struct.pack(">I", len(frame)) + frame) * 3)
        seen["eof_before_next"] = bool(select_readable(peer, 0.5) and not peer.recv(1))
        seen["next_sent"] = time.monotonic()
        peer.sendall(struct.pack(">I", len(frame)) + frame)
        select_readable(peer, 10.0)
        seen["eof"] = (time.monotonic(), peer.recv(1))
        peer.sendall(frame)  # still read after the half-close: no reset
        peer.close()

    def select_readable(sock, timeout_s: float) -> bool:
        import select

        return bool(select.select([sock], [], [], timeout_s)[0])

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    conn = connect("127.0.0.1", listener.getsockname()[1], "monitor port")
    assert conn.receive(timeout_s=5.0) is not None
    conn.close(message_wait_s=5.0)
    thread.join(timeout=10.0)
    listener.close()
    assert seen["eof_before_next"] is False
    eof_at, data = seen["eof"]
    assert data == b"" and eof_at >= seen["next_sent"]


def test_sigterm_ends_a_recording_with_its_file_finished(real, tmp_path):
    """`kill` (SIGTERM) of a recorder: its file finished and marked interrupted, and it
    leaves the server like Ctrl-C does (a half-close, not a reset); exit 143."""
    from mimic.recording.reader import read_recording

    out = tmp_path / "live.mcap"
    with FakeMonitor(replay(_on_field(real), period_s=0.02)) as fake:
        proc = _run(
            ["record", "--server", fake.address, "--team", TEAM, "--player", str(PLAYER)]
            + ["-o", str(out)]
        )
        # Once it records (its unfinished file is there): on a busy machine the wait for the
        # player alone can take the first seconds.
        started = lambda: any(tmp_path.glob("live.partial-*"))  # noqa: E731
        stderr, _ = _interrupt_after(proc, fake, 2.0, signal.SIGTERM, ready=started)
    assert proc.returncode == 143, stderr
    assert "terminated" in stderr and "Traceback" not in stderr
    rec = read_recording(out)
    assert rec.interrupted and rec.recovery.complete
