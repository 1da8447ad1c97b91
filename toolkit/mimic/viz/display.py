"""Whether a Rerun viewer can open here: a display to show it on, or a viewer already running.

Without either, Rerun's viewer fails to start ("winit EventLoopError ... DISPLAY is not set")
and the command that spawned it waits for it forever; commands check first and say how to
save a file instead.
"""

from __future__ import annotations

import os
import socket
import sys

from mimic.errors import MimicError

__all__ = ["NoDisplayError", "has_display", "require_viewer", "VIEWER_PORT"]

#: The port a Rerun viewer listens on (``rerun`` and ``spawn`` use it by default).
VIEWER_PORT = 9876


class NoDisplayError(MimicError):
    """No display to open a Rerun viewer on, and no viewer running."""


def has_display(environ: dict[str, str] | None = None, platform: str = sys.platform) -> bool:
    """True unless this is Linux (or another X11/Wayland system) without ``DISPLAY`` and
    ``WAYLAND_DISPLAY``; macOS and Windows always have one."""
    env = os.environ if environ is None else environ
    if platform.startswith(("darwin", "win", "cygwin")):
        return True
    return bool(env.get("DISPLAY") or env.get("WAYLAND_DISPLAY"))


def _viewer_running(port: int = VIEWER_PORT) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
    except OSError:
        return False
    return True


def require_viewer(save_hint: str) -> None:
    """Before the work of a command that opens a viewer: refuse when none can open.

    Args:
        save_hint: how to save instead, e.g. ``--save out/view.rrd``.

    Raises:
        NoDisplayError: no display (no DISPLAY or WAYLAND_DISPLAY) and no viewer running on
            this machine's port ``VIEWER_PORT``.
    """
    if has_display() or _viewer_running():
        return
    raise NoDisplayError(
        "no display to open a Rerun viewer on (DISPLAY and WAYLAND_DISPLAY are not set); "
        f"save the view with {save_hint} and open it with 'rerun FILE.rrd' where there is one"
    )
