"""Where an envelope's cells run: this process, local worker processes, or a Ray cluster. Each is a context
manager yielding an object with ``submit(fn, *args) -> concurrent.futures.Future``."""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterator
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager

from atcs.proofs.workers import worker_pool

__all__ = ["RAY_INSTALL", "RayUnavailable", "local_executor", "ray_executor"]

RAY_INSTALL = "pip install 'atcs[cluster]'"
"""How to install Ray, which ``--ray`` needs."""


class RayUnavailable(RuntimeError):
    """``--ray`` was asked for, and Ray is not installed or no cluster answers at the address."""


def _check_answers(address: str, timeout_s: float = 5.0) -> None:
    """Refuse at once an address that is not ``HOST:PORT`` or where nothing answers (Ray itself would retry for
    minutes)."""
    import socket

    host, _, port = address.removeprefix("ray://").rpartition(":")
    if not host or not port.isdigit():
        raise RayUnavailable(f"--ray {address!r} is not auto or HOST:PORT")
    try:
        socket.create_connection((host, int(port)), timeout=timeout_s).close()
    except OSError as exc:
        raise RayUnavailable(f"--ray {address}: no Ray cluster answers there ({exc.strerror or exc})") from None


class _Inline:
    """Runs each task at once in this process."""

    def submit(self, fn, *args) -> Future:
        future: Future = Future()
        try:
            future.set_result(fn(*args))
        except BaseException as exc:  # handed to the caller through the future, as a pool would
            future.set_exception(exc)
        return future


class _RetryingWorkers:
    """Local worker processes (:func:`worker_pool`) whose tasks are run again when a worker dies: a dead worker
    breaks its pool, failing every task not finished, so a new pool takes each of them, up to ``max_retries`` times
    a task. A task is a pure function of its arguments, so a retry gives the same verdict, and its future resolves
    once."""

    def __init__(self, jobs: int, max_retries: int):
        self._jobs, self._max_retries = jobs, max_retries
        self._lock = threading.Lock()
        self._context = worker_pool(jobs)
        self._pool = self._context.__enter__()
        self._broken: list = []
        """The contexts of the broken pools, left when the last pool is."""

    def submit(self, fn, *args) -> Future:
        outer: Future = Future()
        self._submit(outer, fn, args, self._max_retries)
        return outer

    def _submit(self, outer: Future, fn, args, retries_left: int) -> None:
        with self._lock:
            pool = self._pool
            try:
                inner = pool.submit(fn, *args)
            except BrokenProcessPool:  # broken before its tasks' callbacks replaced it
                self._replace(pool)
                pool, inner = self._pool, self._pool.submit(fn, *args)
        inner.add_done_callback(lambda done: self._finished(outer, fn, args, retries_left, pool, done))

    def _replace(self, broken) -> None:
        """A new pool for ``broken`` (under the lock), unless another task replaced it already."""
        if self._pool is broken:
            self._broken.append(self._context)
            self._context = worker_pool(self._jobs)
            self._pool = self._context.__enter__()

    def _finished(self, outer: Future, fn, args, retries_left: int, pool, done: Future) -> None:
        error = done.exception()
        if isinstance(error, BrokenProcessPool) and retries_left > 0:
            with self._lock:
                self._replace(pool)
            self._submit(outer, fn, args, retries_left - 1)
        elif error is not None:
            outer.set_exception(error)
        else:
            outer.set_result(done.result())

    def close(self) -> None:
        """Leave the current pool as :func:`worker_pool` does: waiting for it, or terminating its workers when
        called while an exception is raised."""
        error = sys.exc_info()
        self._context.__exit__(*error)
        for context in self._broken:  # their manager threads are done: nothing to wait for
            context.__exit__(None, None, None)


@contextmanager
def local_executor(jobs: int, max_retries: int = 3) -> Iterator:
    """This process for ``jobs == 1``, else ``jobs`` spawned worker processes whose tasks are run again, up to
    ``max_retries`` times, when a worker dies (:class:`_RetryingWorkers`)."""
    if jobs == 1:
        yield _Inline()
        return
    workers = _RetryingWorkers(jobs, max_retries)
    try:
        yield workers
    except BaseException:
        workers.close()
        raise
    workers.close()


class _RayTasks:
    def __init__(self, ray, max_retries: int):
        self._ray = ray
        self._remote = {}
        self._max_retries = max_retries

    def submit(self, fn, *args) -> Future:
        if fn not in self._remote:
            self._remote[fn] = self._ray.remote(max_retries=self._max_retries, retry_exceptions=False)(fn)
        return self._remote[fn].remote(*args).future()


@contextmanager
def ray_executor(address: str, jobs: int, max_retries: int = 3) -> Iterator:
    """Tasks on Ray: ``address`` ``auto`` starts a local cluster of ``jobs`` CPUs (and stops it after), any other
    joins the cluster there. A task whose worker dies is run again, up to ``max_retries`` times: a task is a pure
    function of its arguments, so a retry gives the same verdict, and its future resolves once."""
    try:
        import ray
    except ImportError:
        raise RayUnavailable(f"--ray needs Ray, which is not installed: {RAY_INSTALL}") from None
    started = not ray.is_initialized()
    if started:
        if address == "auto":
            ray.init(num_cpus=jobs, include_dashboard=False, log_to_driver=False, configure_logging=False)
        else:
            _check_answers(address)
            ray.init(address=address, log_to_driver=False, configure_logging=False)
    try:
        yield _RayTasks(ray, max_retries)
    finally:
        if started:
            ray.shutdown()
