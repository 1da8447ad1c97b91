"""Writing a Rerun recording to an .rrd file the way every output is written: under a
temporary name, moved into place only when complete (``mimic.files``)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import rerun as rr

from mimic.files import PendingOutput

__all__ = ["save_rrd"]

T = TypeVar("T")


def save_rrd(
    rec: rr.RecordingStream,
    path: str | Path,
    log: Callable[[], T],
    *,
    blueprint=None,
    overwrite: bool = True,
) -> T:
    """Save everything ``log()`` logs to ``rec`` into ``path``; returns what ``log`` returns.

    A failure leaves no file and an existing ``path`` untouched; ``overwrite`` False refuses
    to replace an existing ``path``.
    """
    pending = PendingOutput(path, overwrite=overwrite)
    try:
        rec.save(str(pending.tmp), default_blueprint=blueprint)
        logged = log()
        rec.flush()
    except BaseException:
        rec.disconnect()
        pending.discard()
        raise
    rec.disconnect()
    pending.commit()
    return logged
