"""Where an envelope's cells run: this process, local worker processes, or a Ray cluster. Each is a context
manager yielding an object with ``submit(fn, *args) -> concurrent.futures.Future``."""

from __future__ import annotations

from collections.abc import Iterator
from concurrent.futures import Future
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


@contextmanager
def local_executor(jobs: int) -> Iterator:
    """This process for ``jobs == 1``, else ``jobs`` spawned worker processes (:func:`worker_pool`)."""
    if jobs == 1:
        yield _Inline()
        return
    with worker_pool(jobs) as pool:
        yield pool


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
