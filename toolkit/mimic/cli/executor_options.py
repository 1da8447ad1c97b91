"""Where a command's episodes run: ``--workers K`` (local process pool, the default) or
``--ray`` / ``--ray-address ADDRESS`` (Ray, local or a cluster); shared by `trial` and
`improve`.

(``--ray`` is a flag and the address a second option: Typer has no option whose value may be
left out.)
"""

from __future__ import annotations

import typer

from mimic.cli.common import err_console
from mimic.errors import MimicError

__all__ = ["WORKERS", "RAY", "RAY_ADDRESS", "open_executor", "check_workers"]

WORKERS = typer.Option(help="Worker processes (default: all cores; capped at the cores).")
RAY = typer.Option(
    "--ray",
    help="Run episodes on Ray started on this machine (needs the ray "
    "extra); same seed, same results as the process pool.",
)
RAY_ADDRESS = typer.Option(
    "--ray-address",
    metavar="ADDRESS",
    help="Run episodes on the Ray cluster at HOST:PORT (or 'auto'); implies --ray.",
)


def check_workers(workers: int | None, ray: bool) -> int | None:
    """``--workers`` checked: capped at the cores for the pool, with one line saying so."""
    from mimic.trials.executors import resolve_workers

    if workers is not None and workers < 1:
        raise MimicError(f"--workers must be >= 1, got {workers}")
    if ray or workers is None:
        return workers
    n, note = resolve_workers(workers)
    if note:
        err_console.print(note, highlight=False)
    return n


def open_executor(workers: int | None, ray: bool, ray_address: str | None):
    """The executor for the options (see ``check_workers``)."""
    from mimic.trials.executors import RAY_LOCAL, make_executor

    workers = check_workers(workers, ray or bool(ray_address))
    return make_executor(workers, ray=(ray_address or RAY_LOCAL) if ray or ray_address else None)
