"""How often a stock RCSSServerMJ stops when a monitor leaves it, by how the monitor leaves.

    python benchmarks/server_leave.py [--connections 200]

rcsssmj 0.2.1 ends its simulation when a send to a peer fails with anything but
``BrokenPipeError`` (docs/guide.md). This starts the stock server (``rcssservermj --no-render
--sync --no-realtime``: no player, so its clock runs free and it sends all the time), and
connects a monitor ``--connections`` times per way of leaving. Each connection reads three
messages, takes 3 ms over the last (what ``mimic record --list`` does with a frame) and leaves:

- ``at once``: half-close there and then, read until the server closes (mimic before;
  ``Connection.close(message_wait_s=0)``);
- ``after a message`` (``Connection.close``, the default): drop what is unread, wait for the
  next message, half-close at once, read until the server closes.

A server that stopped is counted and started again. The two ways run one after the other on
servers of their own, so a busy machine weighs on both alike.
"""

from __future__ import annotations

import argparse
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from mimic.league.protocol import connect


def _free_port_pair() -> int:
    while True:
        with socket.socket() as a, socket.socket() as b:
            a.bind(("127.0.0.1", 0))
            port = a.getsockname()[1]
            try:
                b.bind(("127.0.0.1", port + 1))
            except OSError:
                continue
            return port


def _start(port: int, log: Path) -> subprocess.Popen:
    command = [shutil.which("rcssservermj") or "rcssservermj", "--no-render", "--sync"]
    command += ["--no-realtime", "--aport", str(port), "--mport", str(port + 1)]
    with log.open("ab") as err:
        proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        listening = subprocess.run(["ss", "-ltnH"], capture_output=True, text=True).stdout
        if f":{port + 1} " in listening:
            time.sleep(0.3)
            return proc
        time.sleep(0.1)
    proc.kill()
    sys.exit(f"error: rcssservermj did not listen on {port + 1} within 60 s (log: {log})")


def stops(way: str, connections: int, log: Path) -> int:
    """Server stops in ``connections`` monitor connections that leave ``way``."""
    port = _free_port_pair()
    proc, stopped = _start(port, log), 0
    try:
        for _ in range(connections):
            try:
                conn = connect("127.0.0.1", port + 1, "monitor port")
                for _ in range(3):
                    conn.receive(timeout_s=5.0)
                time.sleep(0.003)
                conn.close(message_wait_s=0.0 if way == "at once" else 0.2)
            except Exception:  # noqa: BLE001 - a stopped server is counted below
                pass
            time.sleep(0.05)
            if proc.poll() is not None:
                stopped += 1
                proc = _start(port, log)
    finally:
        proc.kill()
        proc.wait()
    return stopped


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--connections", type=int, default=200)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "server.log"
        print(f"| way of leaving | server stops in {args.connections} connections |")
        print("|---|---|")
        for way in ("at once", "after a message"):
            print(f"| {way} | {stops(way, args.connections, log)} |", flush=True)
        causes = log.read_text(errors="replace").count("Bad file descriptor")
        print(f"({causes} of the stops were 'OSError: [Errno 9] Bad file descriptor')")


if __name__ == "__main__":
    main()
