"""Hosting RCSSServerMJ: mimic starts the league's server itself, on free ports.

``LeagueServer`` runs the league's server as a subprocess in a temporary working directory
(``python -m mimic.league.hosted_server``: ``python -m rcsssmj`` with its sends made safe
against a peer that leaves; the server writes ``console.log`` and ``MUJOCO_LOG.TXT`` into its
working directory), headless,
in lock-step with its agents and as fast as they answer by default (``--no-render --sync
--no-realtime``). It returns once both ports listen and the simulation loop runs (the server
logs both) and stops the server on exit (SIGINT, then a kill if it hangs)::

    with LeagueServer(ServerConfig(logfile=Path("game.log"))) as server:
        print(server.agent_address, server.monitor_address)

With no agent connected the server runs its clock freely; with ``sync`` it then waits for
every connected agent's answer each 20 ms cycle.
"""

from __future__ import annotations

import contextlib
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from mimic.league.errors import ServerStartError

__all__ = ["LeagueServer", "ServerConfig", "free_port", "READY_LINE"]

#: What the server logs once its ports listen and its simulation loop runs. (Its "Starting
#: server... DONE!" comes before the world is built; a player joining before the first
#: cycle makes rcsssmj 0.2.1 fail in its audio engine.)
READY_LINE = "simulation update loop."
_OUTPUT = "server.out"
_ATTEMPTS = 3  # a free port can be taken between choosing and binding it: try again


@dataclass(frozen=True)
class ServerConfig:
    """How a hosted server runs."""

    # Wait for every connected agent's answer before each cycle (--sync).
    sync: bool = True
    # Pace the cycles at wall-clock speed (--realtime); False: as fast as the agents answer.
    realtime: bool = False
    # Write the game log (the monitor frames, RSMP) to this file; the server appends to it.
    logfile: Path | None = None
    # Rule book (--rules: ssim, ssim26, fifa) and field (--field); None: the server's default.
    rules: str | None = None
    field: str | None = None
    # Host to listen on.
    host: str = "127.0.0.1"
    # How long to wait for the ports to listen [s].
    startup_timeout_s: float = 30.0
    # How long to wait for a clean stop after SIGINT before killing the server [s].
    stop_timeout_s: float = 5.0
    # The command that starts the server (None: this Python's ``-m mimic.league.hosted_server``,
    # rcsssmj with safe sends); mimic appends the port and mode options.
    command: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        if not self.startup_timeout_s > 0:
            raise ValueError(f"startup_timeout_s must be > 0, got {self.startup_timeout_s}")


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port nobody listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def _die_with_parent() -> None:  # pragma: no cover - runs in the child before exec
    """Linux: the server gets SIGTERM when mimic dies, so no server is left running."""
    with contextlib.suppress(Exception):
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


class LeagueServer:
    """A hosted RCSSServerMJ (a context manager: started on enter, stopped on exit).

    Attributes (after ``start``): ``host``, ``agent_port``, ``monitor_port``, ``workdir``.
    """

    def __init__(self, config: ServerConfig = ServerConfig()) -> None:
        self.config = config
        self.host = config.host
        self.agent_port = 0
        self.monitor_port = 0
        self.workdir: Path | None = None
        self._proc: subprocess.Popen | None = None

    # --- addresses ------------------------------------------------------------------------
    @property
    def agent_address(self) -> str:
        return f"{self.host}:{self.agent_port}"

    @property
    def monitor_address(self) -> str:
        return f"{self.host}:{self.monitor_port}"

    @property
    def running(self) -> bool:
        return self._proc is not None and self._proc.poll() is None

    def _arguments(self) -> list[str]:
        c = self.config
        args = [
            *(c.command or (sys.executable, "-m", "mimic.league.hosted_server")),
            "--host",
            self.host,
            "--aport",
            str(self.agent_port),
            "--mport",
            str(self.monitor_port),
            "--no-render",
        ]
        args += ["--sync"] if c.sync else []
        args += ["--realtime" if c.realtime else "--no-realtime"]
        if c.logfile is not None:
            args += ["--logfile", str(Path(c.logfile).resolve())]
        args += ["--rules", c.rules] if c.rules else []
        args += ["--field", c.field] if c.field else []
        return args

    # --- lifecycle ------------------------------------------------------------------------
    def start(self) -> LeagueServer:
        """Start the server and wait until its ports listen.

        Raises:
            ServerStartError: it exited or did not listen within ``startup_timeout_s``.
        """
        if self.running:
            return self
        self.workdir = Path(tempfile.mkdtemp(prefix="mimic-league-"))
        problem = ""
        for _ in range(_ATTEMPTS):
            self.agent_port = free_port(self.host)
            self.monitor_port = free_port(self.host)
            while self.monitor_port == self.agent_port:
                self.monitor_port = free_port(self.host)
            problem = self._launch()
            if not problem:
                return self
            if "Address already in use" not in problem:
                break
        self.stop()
        raise ServerStartError(f"the league server did not start: {problem}")

    def _launch(self) -> str:
        """Start one server process; '' once it listens, else what went wrong."""
        out_path = self.workdir / _OUTPUT
        with open(out_path, "wb") as out:
            try:
                self._proc = subprocess.Popen(
                    self._arguments(),
                    cwd=self.workdir,
                    stdin=subprocess.DEVNULL,
                    stdout=out,
                    stderr=subprocess.STDOUT,
                    start_new_session=True,
                    preexec_fn=_die_with_parent if sys.platform == "linux" else None,
                )
            except OSError as err:
                return f"cannot run {self._arguments()[0]}: {err.strerror}"
        deadline = time.monotonic() + self.config.startup_timeout_s
        while time.monotonic() < deadline:
            text = out_path.read_text(errors="replace")
            if READY_LINE in text:
                return ""
            if self._proc.poll() is not None:
                lines = [ln for ln in text.strip().splitlines() if ln.strip()]
                return f"exit code {self._proc.returncode}: {lines[-1] if lines else 'no output'}"
            time.sleep(0.05)
        self._kill()
        return (
            f"no '{READY_LINE}' within {self.config.startup_timeout_s:g} s (output in {out_path})"
        )

    def request_stop(self) -> None:
        """Ask the server to stop (SIGINT) without waiting. In sync mode it stops once every
        agent has answered the current cycle or left: close the agents next."""
        if self.running:
            with contextlib.suppress(ProcessLookupError):
                self._proc.send_signal(signal.SIGINT)

    def stop(self) -> None:
        """Stop the server (SIGINT: it closes its log file), kill it if it hangs; remove the
        working directory. A sync server waits up to 5 s for a connected agent that does not
        answer: close agents first (or ``request_stop``, then close them)."""
        self.request_stop()
        proc, self._proc = self._proc, None
        if proc is not None and proc.poll() is None:
            try:
                proc.wait(timeout=self.config.stop_timeout_s)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        if self.workdir is not None:
            shutil.rmtree(self.workdir, ignore_errors=True)
            self.workdir = None

    def _kill(self) -> None:
        if self._proc is not None and self._proc.poll() is None:
            self._proc.kill()
            self._proc.wait()

    def output(self) -> str:
        """What the server printed so far (its log lines)."""
        if self.workdir is None or not (self.workdir / _OUTPUT).is_file():
            return ""
        return (self.workdir / _OUTPUT).read_text(errors="replace")

    def __enter__(self) -> LeagueServer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    def __del__(self) -> None:  # a forgotten server must not keep a core busy
        with contextlib.suppress(Exception):
            self._kill()
