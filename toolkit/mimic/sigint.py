"""Ctrl-C as a flag: long runs (recording, playing) stop at the end of a cycle or frame, with
their files finished."""

from __future__ import annotations

import signal
import threading

__all__ = ["SigintFlag"]


class SigintFlag:
    """Turns SIGINT (and any other ``signals`` given, e.g. SIGTERM) into ``raised``, checked
    once per cycle (main thread only; a context manager that restores the previous handlers).
    ``signum`` is the signal that came."""

    def __init__(self, signals: tuple[int, ...] = (signal.SIGINT,)) -> None:
        self.raised = False
        self.signum: int | None = None
        self._signals = signals
        self._old: dict[int, object] = {}

    def __enter__(self) -> SigintFlag:
        if threading.current_thread() is threading.main_thread():
            for s in self._signals:
                self._old[s] = signal.signal(s, self._handle)
        return self

    def _handle(self, signum, frame) -> None:
        self.raised = True
        self.signum = signum

    def __call__(self) -> bool:
        return self.raised

    def __exit__(self, *exc) -> None:
        for s, old in self._old.items():
            signal.signal(s, old)
        self._old.clear()
