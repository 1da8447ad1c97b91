"""Where episodes run: in this process, in a local process pool, or on Ray; one interface.

An executor runs picklable calls ``fn(arg)`` and hands each result back by the handle
``submit`` returned, so callers read results in the order they choose (the episode index),
never in completion order: the same jobs give the same results on every executor.

    with make_executor(workers=2) as ex:            # or make_executor(ray="local")
        handles = [ex.submit(fn, job) for job in jobs]
        results = [ex.result(h) for h in handles]

Ray is an optional extra (``pip install -e ".[ray]"``); it is imported only when asked for.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import socket
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from typing import Any

import mimic.tasks.kick  # noqa: F401
import mimic.tasks.walk  # noqa: F401
from mimic.errors import MimicError

__all__ = [
    "Executor",
    "InlineExecutor",
    "PoolExecutor",
    "RayExecutor",
    "make_executor",
    "available_cores",
    "resolve_workers",
    "RAY_LOCAL",
]

#: ``ray=RAY_LOCAL`` starts (or joins) a Ray instance on this machine.
RAY_LOCAL = "local"
_END = object()


def available_cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


def resolve_workers(requested: int | None) -> tuple[int, str | None]:
    """(worker processes to use, a one-line note when ``requested`` was capped, else None).

    Default: every available core. More processes than cores only add start-up and
    switching (16 workers on 2 cores ran a short trial 9x slower than 2).

    Raises:
        MimicError: ``requested`` < 1.
    """
    cores = available_cores()
    if requested is None:
        return cores, None
    if requested < 1:
        raise MimicError(f"--workers must be >= 1, got {requested}")
    if requested > cores:
        return cores, f"using {cores} workers: {requested} asked, {cores} cores available"
    return requested, None


class Executor(ABC):
    """Runs ``fn(arg)`` calls; ``workers`` is how many run at once."""

    workers: int = 1

    @abstractmethod
    def submit(self, fn: Callable, arg: Any) -> Any:
        """Start (or queue) ``fn(arg)``; returns a handle for ``result``."""

    @abstractmethod
    def result(self, handle: Any, waiting: Callable[[], None] | None = None) -> Any:
        """The result of a submitted call (waits for it; re-raises its exception).
        ``waiting``: called whenever another call ends while this one is waited for."""

    def done(self, handle: Any) -> bool:
        """The call has ended (its result is there without waiting); False if unknown."""
        return False

    def discard(self, handles: Iterable[Any]) -> None:  # noqa: B027 (optional hook)
        """Calls whose results will never be read: cancel what has not started."""

    def close(self) -> None:  # noqa: B027 (optional hook)
        """Release the workers (does not wait for discarded calls)."""

    def map(self, fn: Callable, args: Iterable[Any]) -> list:
        """``[fn(a) for a in args]``, run on the workers, in the order of ``args``; at most
        two calls per worker in flight (so ``workers`` holds on a shared Ray cluster too)."""
        args, results, pending = iter(args), [], deque()
        while True:
            while len(pending) < 2 * self.workers:
                arg = next(args, _END)
                if arg is _END:
                    break
                pending.append(self.submit(fn, arg))
            if not pending:
                return results
            results.append(self.result(pending.popleft()))

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class InlineExecutor(Executor):
    """Runs each call in this process when its result is asked for (nothing speculative)."""

    workers = 1

    def submit(self, fn: Callable, arg: Any) -> Any:
        return (fn, arg)

    def result(self, handle: Any, waiting: Callable[[], None] | None = None) -> Any:
        fn, arg = handle
        return fn(arg)


def _warm_up() -> None:
    """Import the simulator and the episodes in a fresh worker process."""


class _Inline:
    """A call this process runs itself (when its result, or another's, is waited for)."""

    __slots__ = ("fn", "arg", "started", "done", "value", "error")

    def __init__(self, fn: Callable, arg: Any) -> None:
        self.fn, self.arg, self.value, self.error = fn, arg, None, None
        self.started = self.done = False

    def run(self) -> None:
        if not self.started:
            self.started = True
            try:
                self.value = self.fn(self.arg)
            except BaseException as err:  # re-raised by result(), in the caller's order
                if isinstance(err, KeyboardInterrupt):
                    raise
                self.error = err
            self.done = True


#: What a user reads when a worker process dies under a trial.
_WORKER_DIED = (
    "a worker process stopped unexpectedly (killed, or out of memory?), so the trial cannot "
    "go on; run it again, or with --workers 1 (in a Python script, start trials from under "
    "'if __name__ == \"__main__\":')"
)


@contextmanager
def _workers_alive():
    """A worker that died turns into one clear error instead of the pool's traceback."""
    try:
        yield
    except BrokenProcessPool:
        raise MimicError(_WORKER_DIED) from None


class PoolExecutor(Executor):
    """This process plus ``workers - 1`` spawned processes, kept until ``close``.

    Spawning costs each process a fresh interpreter and the simulator's imports (1-3 s), so
    one pool serves every variant of a trial and every generation of a search, and this
    process works too instead of waiting: the first episode starts at once, and a trial whose
    budget one episode fills never waits for a spawned process.
    """

    def __init__(self, workers: int) -> None:
        if workers < 2:
            raise ValueError("a pool needs 2 or more workers; use InlineExecutor for 1")
        self.workers = workers
        self._pool = ProcessPoolExecutor(workers - 1, mp_context=mp.get_context("spawn"))
        self._inline: list[_Inline] = []  # submitted to this process, not yet run
        self._spawned: list = []  # futures of calls given to the spawned processes
        self._started = False  # a call was submitted (the first one runs here, at once)
        self._discarded: list = []
        for _ in range(workers - 1):  # start the processes now, ready when work comes
            self._pool.submit(_warm_up)

    def submit(self, fn: Callable, arg: Any) -> Any:
        """The first call runs in this process (no wait for a spawned one); after that a
        spawned process that has nothing to do gets the call, else this process if it has
        nothing queued, else the pool's queue. Keeping the spawned processes busy first
        matters: callers collect results in order, and this process runs its queued call
        before it waits for a spawned one, so a call queued here while a spawned process
        sits idle would leave that process idle for a whole episode."""
        self._spawned = [f for f in self._spawned if not f.done()]
        if self._started and len(self._spawned) < self.workers - 1:
            return self._spawn(fn, arg)
        self._started = True
        if not self._inline:
            self._inline.append(_Inline(fn, arg))
            return self._inline[-1]
        return self._spawn(fn, arg)

    def _spawn(self, fn: Callable, arg: Any) -> Any:
        with _workers_alive():
            self._spawned.append(self._pool.submit(fn, arg))
        return self._spawned[-1]

    def _run_inline(self) -> None:
        while self._inline:
            self._inline.pop(0).run()

    def done(self, handle: Any) -> bool:
        return handle.done if isinstance(handle, _Inline) else handle.done()

    def result(self, handle: Any, waiting: Callable[[], None] | None = None) -> Any:
        if not isinstance(handle, _Inline):
            if not handle.done():
                self._run_inline()  # work while the spawned process does
            while waiting is not None and not handle.done():
                others = {f for f in self._spawned if not f.done()} | {handle}
                wait(others, return_when=FIRST_COMPLETED)
                waiting()
            with _workers_alive():
                return handle.result()
        if handle in self._inline:
            self._inline.remove(handle)
        handle.run()
        if handle.error is not None:
            raise handle.error
        return handle.value

    def discard(self, handles: Iterable[Any]) -> None:
        for handle in handles:
            if isinstance(handle, _Inline):
                if handle in self._inline:
                    self._inline.remove(handle)
            elif not handle.cancel():
                self._discarded.append(handle)

    def map(self, fn: Callable, args: Iterable[Any]) -> list:
        """As ``Executor.map``; the spawned processes take calls from the front, this
        process from the back, until none is left."""
        args = list(args)
        results: list = [None] * len(args)
        todo, running = deque(range(len(args))), {}
        with _workers_alive():
            while todo or running:
                while todo and len(running) < self.workers - 1:
                    i = todo.popleft()
                    running[self._pool.submit(fn, args[i])] = i
                if todo:
                    i = todo.pop()
                    results[i] = fn(args[i])
                else:
                    wait(running, return_when=FIRST_COMPLETED)
                for future in [f for f in running if f.done()]:
                    results[running.pop(future)] = future.result()
        return results

    def close(self) -> None:
        self._inline.clear()
        running = [f for f in self._discarded if not f.done()]
        self._pool.shutdown(wait=not running, cancel_futures=True)
        if running:  # episodes nobody will read: stop them instead of waiting
            self._terminate()

    def _terminate(self) -> None:
        """Stop the spawned processes now and wait for them (their episodes are lost)."""
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        manager = getattr(self._pool, "_executor_manager_thread", None)  # shutdown forgets it
        for process in processes:
            process.terminate()
        self._pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.join(timeout=5)
            if process.is_alive():
                process.kill()
                process.join(timeout=5)
        # The pool's manager thread closes its wake-up pipe once it sees the workers gone; the
        # interpreter's exit hook writes to that pipe unlocked, so a thread still closing it as
        # the process exits prints a traceback ("Bad file descriptor"). Wait for the thread.
        if manager is not None and manager.is_alive():
            manager.join(timeout=10)

    def __exit__(self, exc_type, *exc) -> None:
        if exc_type is not None and issubclass(exc_type, BaseException):
            # An error, Ctrl-C or SIGTERM: nobody reads the running episodes' results.
            self._inline.clear()
            self._terminate()
            return
        self.close()


def _ray_call(fn: Callable, arg: Any) -> Any:
    return fn(arg)


def _check_reachable(address: str, timeout_s: float = 3.0) -> None:
    """A ``HOST:PORT`` that accepts no TCP connection fails at once, not after Ray's retries."""
    target = address.removeprefix("ray://")
    host, sep, port = target.rpartition(":")
    if not sep or not port.isdigit():
        raise MimicError(
            f"Ray address {address!r} is not HOST:PORT (or 'auto'; or --ray alone for a local Ray)"
        )
    try:
        socket.create_connection((host, int(port)), timeout=timeout_s).close()
    except OSError as err:
        raise MimicError(
            f"cannot reach a Ray cluster at {address} ({err.strerror or err}); "
            "start one with 'ray start --head' or check the address"
        ) from None


class RayExecutor(Executor):
    """Calls as Ray tasks (one CPU each), on a local Ray instance or a cluster.

    ``address``: ``local`` starts Ray on this machine with ``workers`` CPUs (default: every
    core); ``auto`` or ``HOST:PORT`` joins a running cluster, and ``workers`` defaults to its
    CPUs. Ray started here is shut down by ``close``; a Ray already initialised is left alone.
    """

    def __init__(self, address: str = RAY_LOCAL, workers: int | None = None) -> None:
        try:
            import ray
        except ModuleNotFoundError:
            raise MimicError('--ray needs the ray extra: pip install -e ".[ray]"') from None
        self._ray = ray
        self._owner = not ray.is_initialized()
        if self._owner:
            if address not in (RAY_LOCAL, "auto"):
                _check_reachable(address)
            kwargs = dict(include_dashboard=False, log_to_driver=False, logging_level=logging.ERROR)
            try:
                if address == RAY_LOCAL:
                    ray.init(num_cpus=workers or available_cores(), **kwargs)
                else:
                    ray.init(address=address, **kwargs)
            except (ConnectionError, RuntimeError, ValueError) as err:
                reason = (str(err).strip().splitlines() or [type(err).__name__])[0]
                raise MimicError(f"cannot join Ray at {address!r}: {reason}") from None
        cpus = int(ray.cluster_resources().get("CPU", 1))
        self.workers = max(1, min(workers, cpus) if workers else cpus)
        self._remote = ray.remote(num_cpus=1)(_ray_call)

    def submit(self, fn: Callable, arg: Any) -> Any:
        return self._remote.remote(fn, arg)

    def result(self, handle: Any, waiting: Callable[[], None] | None = None) -> Any:
        return self._ray.get(handle)

    def done(self, handle: Any) -> bool:
        ready, _ = self._ray.wait([handle], timeout=0)
        return bool(ready)

    def discard(self, handles: Iterable[Any]) -> None:  # noqa: B027 (optional hook)
        for ref in handles:
            self._ray.cancel(ref, force=True)

    def close(self) -> None:
        if self._owner and self._ray.is_initialized():
            self._ray.shutdown()


def make_executor(workers: int | None = None, ray: str | None = None) -> Executor:
    """The executor for ``--workers K`` or ``--ray [ADDRESS]``.

    ``workers``: processes (capped at the available cores; 1 runs in this process).
    ``ray``: None for the process pool, ``local`` or a cluster address for Ray.

    Raises:
        MimicError: workers < 1, Ray missing or unreachable.
    """
    if ray is not None:
        if workers is not None and workers < 1:
            raise MimicError(f"--workers must be >= 1, got {workers}")
        return RayExecutor(ray, workers)
    n, _ = resolve_workers(workers)
    return InlineExecutor() if n <= 1 else PoolExecutor(n)
