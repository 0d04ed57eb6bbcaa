"""Worker processes for the long runs (prove, certify, mutate, vectors generate), stoppable at once on Ctrl-C.

The workers ignore SIGINT: Ctrl-C interrupts the main process only, which cancels the work not started and
terminates the workers, instead of waiting for every queued item as ``ProcessPoolExecutor``'s exit would (a
worker interrupted in one item goes on to the next). Spawned, not forked: z3 contexts must not be shared with a
forked child.
"""

from __future__ import annotations

import multiprocessing
import signal
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager

__all__ = ["worker_pool"]


def _start_worker(setup: Callable[..., None] | None, setup_args: tuple) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if setup is not None:
        setup(*setup_args)


def _await_exit_code(process, timeout_s: float = 5.0) -> None:
    """Wait until ``process``'s exit code is recorded: the pool's own thread may reap the terminated worker at the
    same moment (one ``waitpid`` gets its status, the other finds no child), and records it a moment later."""
    deadline = time.monotonic() + timeout_s
    while process.exitcode is None and time.monotonic() < deadline:
        time.sleep(0.001)


@contextmanager
def worker_pool(
    jobs: int, setup: Callable[..., None] | None = None, setup_args: tuple = ()
) -> Iterator[ProcessPoolExecutor]:
    """A pool of ``jobs`` spawned worker processes, each running ``setup(*setup_args)`` first (a module-level
    function); leaving it by an exception (Ctrl-C included) cancels the work not started and terminates the
    workers rather than waiting for them."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    pool = ProcessPoolExecutor(
        max_workers=jobs,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_start_worker,
        initargs=(setup, setup_args),
    )
    try:
        yield pool
    except BaseException:
        processes = list((pool._processes or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        for process in processes:
            process.join()
            _await_exit_code(process)
        raise
    pool.shutdown(wait=True)
