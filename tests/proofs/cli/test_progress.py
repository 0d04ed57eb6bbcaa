"""Long runs are never silent: in a log a run prints where it is with the time left, and Ctrl-C prints what the
run has so far."""

import io

import pytest
from rich.console import Console

from atcs.proofs.cli import _common, main
from atcs.proofs.cli._common import EXIT_INTERRUPTED, progress_bar
from atcs.sim import simulator


def test_a_log_gets_the_position_and_the_time_left(monkeypatch):
    monkeypatch.setattr(_common, "LOG_EVERY_S", 0.0)
    log = io.StringIO()
    with progress_bar(Console(file=log), "cycles", 10) as bar:
        bar.at(5)
    (line,) = [line for line in log.getvalue().splitlines() if line.strip()]
    assert line.startswith("cycles: 5/10 (50 %), ") and line.endswith(" s left"), line


def test_a_log_is_not_flooded(monkeypatch):
    monkeypatch.setattr(_common, "LOG_EVERY_S", 3600.0)
    log = io.StringIO()
    with progress_bar(Console(file=log), "cycles", 10) as bar:
        for completed in range(10):
            bar.at(completed)
    assert log.getvalue().strip() == ""


def test_an_interrupted_sim_prints_the_run_so_far(monkeypatch, capsys):
    step = simulator.Simulation.step

    def interrupted_after_100_cycles(self):
        if self.step_count == 100:
            raise KeyboardInterrupt
        step(self)

    monkeypatch.setattr(simulator.Simulation, "step", interrupted_after_100_cycles)
    assert main(["sim", "seed000_protection_zone"]) == EXIT_INTERRUPTED
    out = capsys.readouterr().out
    assert "10.0 s simulated" in out and "interrupted at 10.0 s: no violation up to there" in out


def test_an_interrupted_prove_prints_the_verdicts_so_far(monkeypatch, capsys, tmp_path):
    from atcs.proofs.engine import suite

    run = suite.run

    def interrupted_after_two(props, **kw):
        for n, result in enumerate(run(props, **kw)):
            if n == 2:
                raise KeyboardInterrupt
            yield result

    monkeypatch.setattr(suite, "run", interrupted_after_two)
    report = tmp_path / "r.json"
    assert main(["prove", "--only", "supervision.*", "--json", str(report)]) == EXIT_INTERRUPTED
    out = capsys.readouterr().out
    assert "supervision.eb_above_ebi" in out and "supervision.brake_above_sbi" not in out
    assert "interrupted after 2 of 12 properties; no report written" in out and not report.exists()


def test_an_interrupted_certify_prints_the_certificates_so_far(monkeypatch, capsys, tmp_path):
    from atcs.proofs.certify import campaign

    run = campaign.run

    def interrupted_after_one(*args, **kw):
        for n, certificate in enumerate(run(*args, **kw)):
            if n == 1:
                raise KeyboardInterrupt
            yield certificate

    monkeypatch.setattr(campaign, "run", interrupted_after_one)
    directory = tmp_path / "cert"
    argv = ["certify", "--only", "supervision.eb_above_ebi", "--only", "supervision.sb_only_if_fitted"]
    assert main([*argv, "--dir", str(directory)]) == EXIT_INTERRUPTED
    out = capsys.readouterr().out
    assert "certified supervision.eb_above_ebi (own checks, lemmas aside; confirmed by z3, cvc5)" in out
    assert "interrupted after 1 certificates; no certificates.json written" in out
    assert not (directory / "certificates.json").exists()


def test_an_interrupted_mutate_prints_the_outcomes_so_far(monkeypatch, capsys, tmp_path):
    from atcs.proofs.mutation import campaign

    run_mutant, started = campaign.run_mutant, []

    def interrupted_at_the_third(mutant, **kw):
        started.append(mutant.id)
        if len(started) == 3:
            raise KeyboardInterrupt
        return run_mutant(mutant, **kw)

    monkeypatch.setattr(campaign, "run_mutant", interrupted_at_the_third)
    report = tmp_path / "m.json"
    argv = ["mutate", "--only", "supervision.*", "--equivalents", str(tmp_path / "none.toml")]
    (tmp_path / "none.toml").write_text("")
    assert main([*argv, "--json", str(report)]) == EXIT_INTERRUPTED
    out = capsys.readouterr().out
    assert " 2 mutants in " in out and "interrupted after 2 of " in out and not report.exists()


def test_an_interrupted_vectors_generate_prints_the_functions_so_far(monkeypatch, capsys, tmp_path):
    from atcs.proofs.cli import vectors

    generate_one, started = vectors._generate_one, []

    def interrupted_at_the_second(name, *args):
        started.append(name)
        if len(started) == 2:
            raise KeyboardInterrupt
        return generate_one(name, *args)

    monkeypatch.setattr(vectors, "_generate_one", interrupted_at_the_second)
    directory = tmp_path / "v"
    argv = ["vectors", "generate", "--function", "supervision", "--function", "mrsp", "--out", str(directory)]
    assert main(argv) == EXIT_INTERRUPTED
    out = capsys.readouterr().out
    assert "1 functions in " in out and "interrupted after 1 of 2 functions; only their files are written" in out
    assert sorted(p.name for p in directory.iterdir()) == [f"{started[0]}.csv", f"{started[0]}.json"]


def test_leaving_a_worker_pool_by_an_interrupt_terminates_its_workers():
    import signal
    import time

    from atcs.proofs.workers import worker_pool

    with pytest.raises(KeyboardInterrupt), worker_pool(1) as pool:
        pool.submit(time.sleep, 600)
        pool.submit(time.sleep, 600)
        processes = list(pool._processes.values())
        raise KeyboardInterrupt
    assert [p.exitcode for p in processes] == [-signal.SIGTERM]


@pytest.mark.slow
def test_headway_in_a_log_says_where_its_runs_are(monkeypatch, capsys):
    monkeypatch.setattr(_common, "LOG_EVERY_S", 0.0)
    assert main(["headway"]) == 0
    captured = capsys.readouterr()
    lines = [line for line in captured.err.splitlines() if line.startswith("cycles: ")]
    assert lines[0].startswith("cycles: 1/4000 (0 %)") and lines[-1].startswith("cycles: 4000/4000 (100 %)")
    assert "relative_braking" in captured.out and "brick_wall" in captured.out


def test_bench_in_a_log_says_where_it_is(monkeypatch, capsys):
    monkeypatch.setattr(_common, "LOG_EVERY_S", 0.0)
    assert main(["bench", "supervision"]) == 0
    err = capsys.readouterr().err
    assert "bench supervision: 3/3 (100 %)" in err and "bench supervision: done in" in err
