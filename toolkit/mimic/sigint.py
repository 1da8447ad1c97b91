"""Ctrl-C as a flag: long runs (recording, playing) stop at the end of a cycle or frame, with
their files finished. ``SIGTERM`` as an exception (``Terminated``): a command that is told to
stop cleans up as after Ctrl-C (its worker processes, servers and unfinished files)."""

from __future__ import annotations

import signal
import threading

__all__ = ["SigintFlag", "Terminated", "sigterm_raises"]


class Terminated(KeyboardInterrupt):
    """Raised in the main thread when the process gets ``SIGTERM`` (``sigterm_raises``); a
    ``KeyboardInterrupt``, so whatever cleans up after Ctrl-C cleans up after it too."""


class sigterm_raises:  # noqa: N801 (a context manager used like a function)
    """Within the block, ``SIGTERM`` raises ``Terminated`` in the main thread (elsewhere, and
    outside the main thread, nothing changes); the previous handler comes back on exit."""

    def __init__(self) -> None:
        self._old = None

    def __enter__(self) -> sigterm_raises:
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGTERM, self._handle)
        return self

    @staticmethod
    def _handle(signum, frame) -> None:
        raise Terminated()

    def __exit__(self, *exc) -> None:
        if self._old is not None:
            signal.signal(signal.SIGTERM, self._old)


class SigintFlag:
    """Turns SIGINT into ``raised``, checked once per cycle (main thread only; a context
    manager that restores the previous handler)."""

    def __init__(self) -> None:
        self.raised = False
        self._old = None

    def __enter__(self) -> SigintFlag:
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame) -> None:
        self.raised = True

    def __call__(self) -> bool:
        return self.raised

    def __exit__(self, *exc) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)
