"""What every command shares: one error line and an exit code, warnings, and the options every
command that writes files has (``--force``, ``--save``)."""

from __future__ import annotations

import functools
import inspect
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import typer
from rich.console import Console
from rich.markup import escape
from typer.core import TyperGroup

from mimic.errors import MimicError

__all__ = [
    "console",
    "err_console",
    "reports_errors",
    "fail",
    "warn",
    "FORCE",
    "SAVE",
    "SAVE_OLD",
    "save_path",
    "OneLineUsageErrors",
]

console = Console()
err_console = Console(stderr=True)
F = TypeVar("F", bound=Callable)

#: ``--force``: the one way to replace an existing output file (see ``mimic.files``).
FORCE = typer.Option("--force", help="Replace output files that exist (default: refuse).")
#: ``--save FILE.rrd``: write a Rerun view to a file (the same name in every command).
SAVE = typer.Option("--save", help="Write the Rerun view to this .rrd file.", show_default=False)
#: The old name of ``--save`` in ``train`` and ``trial``, kept working but not shown.
SAVE_OLD = typer.Option("--save-rrd", hidden=True)
#: ``--world``: where episodes play (``trial``, ``improve``).
WORLD = typer.Option(
    help="Where episodes play: mujoco (ours; also 'nao'), league (the league server's own "
    "simulation, stepped in this process), league-server (a league server mimic hosts per "
    "episode: sync, no real time, free ports) or league-like (ours with the league's solver "
    "and command delay)."
)
#: ``--robot``: whose motion or engine a name means (``trial``, ``improve``).
ROBOT = typer.Option(
    help="The robot (mimic robots); default: nao in our world, t1 in the league.",
    show_default=False,
)

#: ``--disturb``: how much a trial's episodes are disturbed (``episode.disturbance``).
DISTURB = typer.Option(
    "--disturb",
    help="Disturbances per episode: none (only the start pose), game (start delay, pushes "
    "the first variant survives most of the time, friction and masses +-10 %) or hard "
    "(game's pushes, +-20 %, sensor noise); default: "
    "game where mimic steps the physics itself, none on a league server (it cannot push).",
    show_default=False,
)

#: ``--success-m``: the kick rule's distance (``trial kick``, ``improve --objective kick``).
SUCCESS_M = typer.Option(
    "--success-m",
    help="A kick succeeds when the ball travels farther than this \\[m]; default: the "
    "study's 2 m. Give a shorter kick its own (e.g. 0.5 for a 1 m kick).",
    show_default=False,
)


def save_path(save: Path | None, save_old: Path | None) -> Path | None:
    """``--save`` or its old name ``--save-rrd`` (not both)."""
    if save is not None and save_old is not None:
        raise MimicError("give --save only (--save-rrd is its old name)")
    return save if save is not None else save_old


def fail(message: str, code: int = 2) -> None:
    """Print ``error: message`` on stderr and exit with ``code``."""
    # The message is text, not markup: "pip install -e '.[ray]'" must keep its brackets.
    err_console.print(
        f"[bold red]error:[/] {escape(str(message))}", highlight=False, soft_wrap=True
    )
    raise typer.Exit(code)


def warn(message: str) -> None:
    """Print ``warning: message`` on stderr (the command goes on)."""
    err_console.print(
        f"[bold yellow]warning:[/] {escape(str(message))}", highlight=False, soft_wrap=True
    )


def _usage_errors():
    """(click's UsageError, its no-arguments-so-help subclass) of the click Typer uses."""
    try:  # typer >= 0.20 carries its own click
        from typer._click import exceptions
    except ImportError:
        from click import exceptions
    return exceptions.UsageError, getattr(exceptions, "NoArgsIsHelpError", ())


class OneLineUsageErrors(TyperGroup):
    """The application's command groups: a bad option value, a missing option or an unknown
    command is one line, ``error: what (where); see 'mimic CMD --help'``, exit status 2, as
    every other bad input (not Typer's multi-line box)."""

    def get_command(self, ctx, cmd_name):
        # A command's line in the group's list is its help's first paragraph, wrapped to the
        # terminal: the docstring's own line breaks would otherwise cut it mid-sentence.
        command = super().get_command(ctx, cmd_name)
        if command is not None and command.short_help is None and command.help:
            first = inspect.cleandoc(command.help).split("\n\n")[0]
            command.short_help = " ".join(first.split())
        return command

    def make_context(self, *args, **kwargs):
        with _one_line_usage():
            return super().make_context(*args, **kwargs)

    def invoke(self, ctx):
        with _one_line_usage():
            return super().invoke(ctx)


class _one_line_usage:  # noqa: N801 (a context manager used like a function)
    def __enter__(self) -> None:
        return None

    def __exit__(self, exc_type, exc, tb) -> bool:
        usage, help_only = _usage_errors()
        if exc is None or not isinstance(exc, usage) or isinstance(exc, help_only):
            return False
        where = exc.ctx.command_path if exc.ctx is not None else "mimic"
        what = " ".join(exc.format_message().split()).rstrip(".")
        what = what[:1].lower() + what[1:] if what[1:2].islower() else what
        fail(f"{what} ({where}); see '{where} --help'", 2)
        return False


def reports_errors(func: F) -> F:
    """Decorator for commands: a ``MimicError`` becomes one clear line and a non-zero exit, and
    so does an error of the file system (disk full, permission denied); Ctrl-C exits with 130
    after whatever cleanup the library did (files are closed, unfinished outputs removed)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        from mimic.sigint import Terminated, sigterm_raises

        try:
            with sigterm_raises():
                return func(*args, **kwargs)
        except Terminated:  # SIGTERM: cleaned up as after Ctrl-C (workers, servers, files)
            err_console.print("terminated", highlight=False)
            sys.stderr.flush()
            raise typer.Exit(143) from None
        except MimicError as err:
            fail(str(err), err.exit_code)
        except OSError as err:
            where = f"{err.filename}: " if err.filename else ""
            fail(f"{where}{err.strerror or err}", 1)
        except KeyboardInterrupt:
            err_console.print("interrupted", highlight=False)
            sys.stderr.flush()
            raise typer.Exit(130) from None

    return wrapper  # type: ignore[return-value]
