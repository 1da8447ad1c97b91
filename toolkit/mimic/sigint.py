"""Ctrl-C as a flag: long runs (recording, playing) stop at the end of a cycle or frame, with
their files finished."""

from __future__ import annotations

import signal
import threading

__all__ = ["SigintFlag"]


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
