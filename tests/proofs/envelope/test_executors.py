"""Local worker processes for an envelope's cells (docs/configuration.md "On Ray"): a worker killed mid-sweep breaks
its pool, and a new pool runs every task not finished, so no result is lost or duplicated."""

import os
import signal
import threading
import time
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import pytest

from atcs.proofs.envelope import sweep
from atcs.proofs.envelope.executors import local_executor


def _slow_square(x: int) -> int:
    time.sleep(0.5)
    return x * x


def _workers() -> set[int]:
    """The pids of this process's spawned workers (``spawn_main`` in their command line)."""
    found = set()
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            parent = int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
            command = Path(f"/proc/{pid}/cmdline").read_bytes()
        except (OSError, IndexError, ValueError):
            continue
        if parent == os.getpid() and b"spawn_main" in command:
            found.add(int(pid))
    return found


def _kill_one_worker(spare: frozenset = frozenset(), deadline_s: float = 60) -> int:
    """SIGKILL one of this process's workers not in ``spare``; its pid."""
    deadline = time.monotonic() + deadline_s
    while time.monotonic() < deadline:
        for pid in sorted(_workers() - spare):
            os.kill(pid, signal.SIGKILL)
            return pid
        time.sleep(0.01)
    raise AssertionError("no worker to kill")


def test_a_killed_workers_tasks_are_run_again_and_each_resolves_once():
    with local_executor(2) as tasks:
        futures = [tasks.submit(_slow_square, x) for x in range(8)]
        time.sleep(0.7)  # the workers are busy with the first tasks
        _kill_one_worker()
        assert [f.result(timeout=120) for f in futures] == [x * x for x in range(8)]


def test_a_task_whose_workers_keep_dying_fails_after_the_retries():
    with local_executor(2, max_retries=1) as tasks:
        assert tasks.submit(_slow_square, 2).result(timeout=60) == 4  # the pool's workers are up
        doomed = tasks.submit(_slow_square, 3)
        first_pool = frozenset(_workers())
        _kill_one_worker()  # the first run's pool breaks
        _kill_one_worker(spare=first_pool)  # and the one retry's
        with pytest.raises(BrokenProcessPool, match="terminated abruptly"):
            doomed.result(timeout=60)


@pytest.mark.slow
def test_local_workers_give_the_same_map_with_a_worker_killed(undisturbed_sweep):
    from tests.proofs.envelope.test_ray import CONFIG, _names, _verdicts

    names = _names()
    seen: list = []
    killed: list = []
    with local_executor(2) as tasks:
        hunter = threading.Thread(target=lambda: killed.append(_kill_one_worker()), daemon=True)
        hunter.start()
        on_workers = sweep(CONFIG, names, timeout_s=300, executor=tasks, on_cell=lambda name, c: seen.append(name))
        hunter.join()
    assert killed, "no worker was running to kill"
    assert _verdicts(on_workers) == _verdicts(undisturbed_sweep)
    assert sorted(seen) == sorted(names)  # each verdict once: none lost, none duplicated
