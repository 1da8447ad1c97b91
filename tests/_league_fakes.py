"""A fake monitor port for the league tests: a loopback server of the test's own that sends
whatever the test gives it (frames of a real game log, mutated frames, random bytes)."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading
import time
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np

from mimic.league.server import LeagueServer, ServerConfig
from mimic.robot.actuators import JointCommand
from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

_LENGTH = struct.Struct(">I")


def framed(message: bytes) -> bytes:
    """``message`` with the league's 4-byte big-endian length in front."""
    return _LENGTH.pack(len(message)) + message


class FakeMonitor:
    """Listens on a free loopback port; each connection gets ``serve(sock)`` in a thread
    (a context manager: closed on exit). ``address`` is ``127.0.0.1:PORT``."""

    def __init__(self, serve: Callable[[socket.socket], None]) -> None:
        self._serve = serve
        self._listener = socket.create_server(("127.0.0.1", 0))
        self._listener.settimeout(0.2)
        self.port = self._listener.getsockname()[1]
        self.address = f"127.0.0.1:{self.port}"
        self.connections = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._accept, daemon=True)
        self._thread.start()

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                sock, _ = self._listener.accept()
            except (TimeoutError, OSError):
                continue
            self.connections += 1
            threading.Thread(target=self._run, args=(sock,), daemon=True).start()

    def _run(self, sock: socket.socket) -> None:
        with contextlib.suppress(OSError), sock:
            self._serve(sock)

    @property
    def stopped(self) -> bool:
        return self._stop.is_set()

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        self._listener.close()

    def __enter__(self) -> FakeMonitor:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def replay(frames: Iterable[bytes], then: str = "hold", period_s: float = 0.0):
    """A ``serve`` that sends ``frames`` (each length-prefixed), then ``hold``s the connection
    open (until the peer leaves) or ``close``s it."""
    frames = list(frames)

    def serve(sock: socket.socket) -> None:
        for frame in frames:
            sock.sendall(framed(frame))
            if period_s:
                time.sleep(period_s)
        if then == "hold":
            sock.settimeout(0.5)
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline:
                try:
                    if not sock.recv(1 << 16):
                        return
                except TimeoutError:
                    continue

    return serve


def random_bytes(seed: int = 0, chunk: int = 4096, period_s: float = 0.001):
    """A ``serve`` that sends random bytes until the peer leaves (at most two minutes)."""

    def serve(sock: socket.socket) -> None:
        rng = np.random.default_rng(seed)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            sock.sendall(rng.integers(0, 256, chunk, dtype=np.uint8).tobytes())
            time.sleep(period_s)

    return serve


def silent():
    """A ``serve`` that accepts and never sends anything (until the peer leaves)."""
    return replay([], then="hold")


def record_real_log(path: Path, team: str = "alpha", player: int = 1, cycles: int = 100) -> Path:
    """A short real game log: a hosted RCSSServerMJ writes ``path`` while a T1 of ``team``
    #``player`` stands on its field for ``cycles`` cycles."""
    with LeagueServer(ServerConfig(logfile=path)) as server:
        world = LeagueWorld(
            "t1",
            agent_address=server.agent_address,
            monitor_address=server.monitor_address,
            config=LeagueWorldConfig(team=team, player=player),
        )
        try:
            world.reset()
            for _ in range(cycles):
                world.step(JointCommand.references(world.joint_angles_rad()))
        finally:
            world.close()
    return path


def log_lines(path: Path) -> list[bytes]:
    """The frames of a game log, one per line, without their line ends."""
    return [line.rstrip(b"\n") for line in path.read_bytes().splitlines() if line.strip()]


def renamed(lines: list[bytes], old: str, new: bytes) -> list[bytes]:
    """The frames with team ``old`` renamed ``new`` (raw bytes: any name a log may hold)."""
    return [
        line.replace(f"(agent {old} ".encode(), b"(agent " + new + b" ").replace(
            f"(team_left {old})".encode(), b"(team_left " + new + b")"
        )
        for line in lines
    ]
