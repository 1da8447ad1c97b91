"""RCSSServerMJ as mimic hosts it: ``python -m mimic.league.hosted_server ARGS`` runs the league's
server exactly as ``python -m rcsssmj ARGS`` does, with one fix to how it sends.

rcsssmj 0.2.1 sends each frame to a monitor (and each perception to an agent) from its
simulation thread, while a second thread per connection reads from it. When a peer leaves,
that reader thread closes the socket at once; a send already past its "is the connection
active?" check then fails with ``OSError: Bad file descriptor`` (or ``ConnectionResetError``
when the peer left with unread data), and only ``BrokenPipeError`` is caught: the exception
ends the simulation thread and the whole server. Whether a leaving peer meets that window
depends on thread scheduling, not on what the peer does, and it is most likely on a free-running
server (``--sync --no-realtime`` with no player answering) on a busy machine.

``apply`` makes any ``OSError`` of such a send mean what ``BrokenPipeError`` already means to
the server: that peer has left (the monitor or agent is shut down and removed). Nothing else
changes. ``LeagueServer`` runs this module; a server mimic does not host keeps the race (see
``mimic.league.protocol.Connection.close`` for how mimic leaves one).
"""

from __future__ import annotations

import sys

__all__ = ["apply"]


def apply() -> None:
    """Patch rcsssmj's sends (once; safe to call again)."""
    from rcsssmj.server.communication.tcp_lpm_connection import TCPLPMConnection
    from rcsssmj.server.remote_agent import RemoteAgent

    if getattr(TCPLPMConnection, "_mimic_patched", False):
        return
    send_message = TCPLPMConnection.send_message
    send_perceptions = RemoteAgent.send_perceptions

    def send_message_or_broken_pipe(self, msg) -> None:
        try:
            send_message(self, msg)
        except BrokenPipeError:
            raise
        except OSError as err:  # closed under us (EBADF) or reset: the peer has left
            self._active = False
            raise BrokenPipeError(err.errno, err.strerror) from None

    def send_perceptions_or_leave(self) -> None:
        try:
            send_perceptions(self)
        except BrokenPipeError:
            self.shutdown()

    TCPLPMConnection.send_message = send_message_or_broken_pipe
    RemoteAgent.send_perceptions = send_perceptions_or_leave
    TCPLPMConnection._mimic_patched = True


def main() -> None:
    from rcsssmj import __main__ as server_main

    apply()
    sys.argv[0] = "rcssservermj"
    server_main.soccer_sim()


if __name__ == "__main__":
    main()
