"""Envelopes on Ray (docs/configuration.md "On Ray"): a local cluster gives the same map as local worker processes,
a worker killed mid-sweep loses and duplicates no verdict, and ``--ray`` without Ray says how to install it."""

import os
import signal
import sys
import threading
import time
from pathlib import Path

import pytest

from atcs.model.configuration import load_configuration
from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_USAGE
from atcs.proofs.envelope import sweep
from atcs.proofs.envelope.executors import RAY_INSTALL, ray_executor
from atcs.proofs.envelope.sweep import envelope_properties

CONFIG = str(Path(__file__).parents[3] / "model" / "configurations" / "envelope.toml")


def _names() -> list[str]:
    """Three of the envelope's curve properties (a few seconds each: cells enough for a worker to be killed in one,
    and no more, since each sweep runs twice beside the session's proof run)."""
    names = envelope_properties(load_configuration(CONFIG))
    curves = [n for n in names if n.startswith("curves.") and not n.startswith("curves.order")]
    return curves[:3]


def _verdicts(maps) -> dict:
    return {name: [(c.cell, c.status) for c in m.cells] for name, m in maps.items()}


def _kill_one_running_task(killed: list) -> None:
    """SIGKILL the first Ray worker seen running a cell (its process title ``ray::prove_cell``)."""
    deadline = time.monotonic() + 120
    while not killed and time.monotonic() < deadline:
        for pid in filter(str.isdigit, os.listdir("/proc")):
            try:
                title = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if title.startswith(b"ray::prove_cell"):
                os.kill(int(pid), signal.SIGKILL)
                killed.append(int(pid))
                return
        time.sleep(0.01)


@pytest.mark.slow
def test_ray_gives_the_same_map_as_local_workers_even_with_a_worker_killed(undisturbed_sweep):
    names = _names()
    local = undisturbed_sweep
    killed: list = []
    seen: list = []
    with ray_executor("auto", 2) as tasks:
        hunter = threading.Thread(target=_kill_one_running_task, args=(killed,), daemon=True)
        hunter.start()
        on_ray = sweep(CONFIG, names, timeout_s=300, executor=tasks, on_cell=lambda name, c: seen.append(name))
        hunter.join()
    assert killed, "no worker was running a cell to kill"
    assert _verdicts(on_ray) == _verdicts(local)
    assert sorted(seen) == sorted(names)  # each verdict once: none lost, none duplicated
    assert {m.status for m in local.values()} == {"proved"}


def test_ray_missing_is_a_usage_error_naming_the_install(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray raises ImportError
    argv = ["prove", "--config", CONFIG, "--only", "curves.spacing_*", "--ray", "auto"]
    assert main([*argv, "--cex-dir", str(tmp_path)]) == EXIT_USAGE
    assert f"--ray needs Ray, which is not installed: {RAY_INSTALL}" in capsys.readouterr().err


@pytest.mark.slow
def test_the_sweep_benchmark_checks_the_three_ways_agree():
    from rich.console import Console

    from atcs.proofs.bench.sweep import bench_sweep, sweep_tasks

    tasks = [t for t in sweep_tasks() if t[0].startswith("curves.spacing")][:2]
    console = Console(record=True, width=160)
    results = bench_sweep(console, tasks)
    assert set(results) == {
        f"{way} {what}"
        for way in ("this process", "local worker processes (2)", "Ray, local cluster (2 CPUs)")
        for what in ("cells_per_minute", "startup_s")
    }
    assert console.export_text().count("same verdicts") == 3


@pytest.mark.slow
def test_prove_on_ray_with_a_relative_configuration_path(monkeypatch, tmp_path, capsys):
    monkeypatch.chdir(Path(CONFIG).parents[2])
    argv = ["prove", "--config", "model/configurations/envelope.toml", "--only", "curves.spacing_*", "--ray", "auto"]
    assert main([*argv, "--cache", str(tmp_path / "cache"), "--cex-dir", str(tmp_path)]) == 0
    assert "envelope curves.spacing_gamma_passenger_p_design_0: proved (1 cells: 1 proved)" in capsys.readouterr().out


@pytest.mark.slow
def test_prove_joins_a_running_cluster_by_its_address(tmp_path, capsys):
    import socket
    import subprocess

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    ray_cli = Path(sys.executable).parent / "ray"
    subprocess.run(
        [str(ray_cli), "start", "--head", f"--port={port}", "--num-cpus=2", "--include-dashboard=false"],
        check=True,
        capture_output=True,
    )
    try:
        argv = ["prove", "--config", CONFIG, "--only", "curves.spacing_*", "--ray", f"127.0.0.1:{port}"]
        assert main([*argv, "--cex-dir", str(tmp_path)]) == 0
        assert "envelope curves.spacing_gamma_passenger_p_design_0: proved" in capsys.readouterr().out
    finally:
        subprocess.run([str(ray_cli), "stop"], check=False, capture_output=True)


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("127.0.0.1:1", "--ray 127.0.0.1:1: no Ray cluster answers there"),
        ("nonsense", "--ray 'nonsense' is not auto or HOST:PORT"),
    ],
)
def test_an_address_where_no_cluster_answers_is_refused_at_once(tmp_path, capsys, address, message):
    argv = ["prove", "--config", CONFIG, "--only", "curves.spacing_*", "--ray", address, "--cex-dir", str(tmp_path)]
    assert main(argv) == EXIT_USAGE
    assert message in capsys.readouterr().err
