"""The league's wire format: length-prefixed messages carrying s-expressions.

Every message between RCSSServerMJ and an agent or a monitor is a 4-byte big-endian length
followed by that many bytes of s-expression text, ``(time (now 12.34))(HJ (n q_hj1)(ax 0.5)...)``.
``parse_sexp`` turns the text into nested lists of ``bytes`` atoms; ``Connection`` sends and
receives whole messages over TCP.
"""

from __future__ import annotations

import re
import select
import socket
import struct
import time

from mimic.league.errors import LeagueConnectionError, LeagueProtocolError
from mimic.league.untrusted import MAX_MESSAGE_BYTES

__all__ = ["Connection", "connect", "parse_sexp", "parse_address", "Sexp", "LENGTH_PREFIX_BYTES"]

#: Bytes of the big-endian message length before every message.
LENGTH_PREFIX_BYTES = 4
_LENGTH = struct.Struct(">I")
_TOKEN = re.compile(rb"\(|\)|[^\s()]+")

#: A parsed s-expression: an atom (bytes) or a list of them.
Sexp = bytes | list


def parse_sexp(text: bytes) -> list:
    """The top-level expressions of ``text`` as nested lists of ``bytes`` atoms.

    ``b"(a 1)(b (c 2))"`` -> ``[[b"a", b"1"], [b"b", [b"c", b"2"]]]``. Unbalanced input raises
    ``ValueError``.
    """
    stack: list[list] = [[]]
    for m in _TOKEN.finditer(text):
        token = m.group()
        if token == b"(":
            child: list = []
            stack[-1].append(child)
            stack.append(child)
        elif token == b")":
            if len(stack) == 1:
                raise ValueError(f"unbalanced ')' at byte {m.start()}")
            stack.pop()
        else:
            stack[-1].append(token)
    if len(stack) != 1:
        raise ValueError(f"{len(stack) - 1} unclosed '(' at the end of the message")
    return stack[0]


def parse_address(text: str, what: str) -> tuple[str, int]:
    """``HOST:PORT`` (or ``PORT`` for localhost) as (host, port); ``what`` names the option."""
    host, _, port = text.rpartition(":")
    try:
        number = int(port)
    except ValueError:
        number = -1
    if not 0 < number < 65536:
        raise LeagueConnectionError(
            f"{what}: expected HOST:PORT (e.g. localhost:60000), got {text!r}"
        )
    return host or "127.0.0.1", number


class Connection:
    """One TCP connection exchanging length-prefixed messages (a context manager)."""

    def __init__(self, sock: socket.socket, address: tuple[str, int]) -> None:
        self._sock = sock
        self.address = address
        self._buffer = bytearray()

    def send(self, payload: bytes) -> None:
        """Send one message."""
        try:
            self._sock.sendall(_LENGTH.pack(len(payload)) + payload)
        except OSError as err:
            raise LeagueConnectionError(
                f"lost the server at {self.where}: {err.strerror or err}"
            ) from None

    def receive(self, timeout_s: float | None = None) -> bytes | None:
        """The next message; None if none is complete within ``timeout_s`` [s] (None: wait).

        The timeout bounds the whole call, however the bytes trickle in.

        Raises:
            LeagueConnectionError: the server closed the connection.
            LeagueProtocolError: a message longer than ``MAX_MESSAGE_BYTES`` (not the
                league's stream).
        """
        deadline = None if timeout_s is None else time.monotonic() + max(0.0, timeout_s)
        while True:
            message = self._take()
            if message is not None:
                return message
            if deadline is None:
                self._fill()
                continue
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._sock], [], [], max(0.0, left))
            if not ready:
                return None
            self._fill()
            if left <= 0:
                return self._take()

    def receive_available(self, max_messages: int = 10_000) -> list[bytes]:
        """Every message that has arrived so far (at most ``max_messages``), without waiting."""
        out = []
        while len(out) < max_messages:
            message = self.receive(timeout_s=0.0)
            if message is None:
                break
            out.append(message)
        return out

    def _take(self) -> bytes | None:
        buf = self._buffer
        if len(buf) < LENGTH_PREFIX_BYTES:
            return None
        (size,) = _LENGTH.unpack_from(buf)
        if size > MAX_MESSAGE_BYTES:
            raise LeagueProtocolError(
                f"{self.where} announced a message of {size} bytes (at most "
                f"{MAX_MESSAGE_BYTES} accepted): not an RCSSServerMJ stream; check the port"
            )
        end = LENGTH_PREFIX_BYTES + size
        if len(buf) < end:
            return None
        message = bytes(buf[LENGTH_PREFIX_BYTES:end])
        del buf[:end]
        return message

    def _fill(self) -> None:
        try:
            chunk = self._sock.recv(1 << 20)
        except OSError as err:
            raise LeagueConnectionError(
                f"lost the server at {self.where}: {err.strerror or err}"
            ) from None
        if not chunk:
            raise LeagueConnectionError(f"the server at {self.where} closed the connection")
        self._buffer += chunk

    @property
    def where(self) -> str:
        return f"{self.address[0]}:{self.address[1]}"

    def close(self, linger_s: float = 1.0, message_wait_s: float = 0.2) -> None:
        """Leave: just after a message arrives, half-close, read until the server closes its
        end (at most ``linger_s`` [s]), then close.

        rcsssmj 0.2.1 ends its whole simulation when a send to a peer fails with anything but
        ``BrokenPipeError``, and two ways of leaving meet that:

        - Closing with unread data resets the connection (``ConnectionResetError`` in the
          server's next send), so the half-close goes first and every byte is read until the
          server has closed its end.
        - When the half-close arrives, the server's reader thread closes the socket; if its
          simulation thread is at that moment between "is the peer active?" and its send, the
          send fails with ``Bad file descriptor``. The reader thread runs when the simulation
          thread lets go of the interpreter lock: in MuJoCo's step (harmless) or in a send
          (fatal). Just after a message has arrived the simulation thread is stepping, so
          mimic waits for the next message (at most ``message_wait_s`` [s]) and leaves at once.
          That makes the fatal case rare, not impossible; servers mimic hosts are patched
          against it (``mimic.league.hosted_server``).
        """
        sock = self._sock
        try:
            if not self._skip_to_next_message(message_wait_s):
                sock.shutdown(socket.SHUT_WR)
                deadline = time.monotonic() + linger_s
                while (left := deadline - time.monotonic()) > 0:
                    ready, _, _ = select.select([sock], [], [], left)
                    if ready and not sock.recv(1 << 20):
                        break
        except OSError:
            pass
        sock.close()

    def _skip_to_next_message(self, wait_s: float) -> bool:
        """Drop what has arrived, then wait up to ``wait_s`` [s] for more; True if the server
        has closed its end."""
        sock = self._sock
        self._buffer.clear()
        while select.select([sock], [], [], 0.0)[0]:
            if not sock.recv(1 << 20):
                return True
        if select.select([sock], [], [], wait_s)[0]:
            return not sock.recv(1 << 20)
        return False

    def __enter__(self) -> Connection:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def connect(host: str, port: int, what: str, timeout_s: float = 5.0) -> Connection:
    """Open a connection to ``host:port``; ``what`` says which port it is (error messages).

    Raises:
        LeagueConnectionError: nothing listens there (one line naming the address).
    """
    try:
        sock = socket.create_connection((host, port), timeout=timeout_s)
    except ConnectionRefusedError:
        # Only a command that plays (``mimic play``) can host a server of its own; a recorder
        # watches someone else's.
        todo = (
            "start a server (rcssservermj) first, or give its monitor port (--mport)"
            if "monitor" in what
            else "start a server (rcssservermj) or leave out --server to let mimic host one"
        )
        raise LeagueConnectionError(
            f"nothing listens on {host}:{port} (the {what}); {todo}"
        ) from None
    except OSError as err:
        raise LeagueConnectionError(
            f"cannot reach {host}:{port} (the {what}): {err.strerror or err}"
        ) from None
    sock.settimeout(None)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)  # one message per cycle: now
    return Connection(sock, (host, port))
