"""What every command shares: the parser, argument types, the consoles, the progress display, output-path checks,
the property selection and the exit codes (docs/design.md).

Exit codes: 0 everything asked for holds, 1 a verdict against (falsified, disagreement, a surviving mutant, a
failed vector or check), 2 bad input (:class:`~atcs.model.errors.AtcsInputError`, one line naming the option or
file, the field and the value), 3 incomplete (unknown, error, time-out) with nothing against; ``replay`` adds 4.
Any command: 70 an internal error (a bug of atcs: one line, ``ATCS_TRACEBACK=1`` shows the traceback), 130
interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import fnmatch
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from atcs.model.errors import AtcsInputError

EXIT_OK, EXIT_FALSIFIED, EXIT_USAGE, EXIT_UNKNOWN = 0, 1, 2, 3
EXIT_INTERNAL = 70
"""An unexpected exception escaped a command: a bug of atcs (sysexits' EX_SOFTWARE)."""
EXIT_INTERRUPTED = 130
"""Interrupted (Ctrl-C): 128 + SIGINT, as a shell reports it."""


def exit_code(*, against: bool, incomplete: bool) -> int:
    """1 if any verdict is against, else 3 if any is incomplete, else 0."""
    if against:
        return EXIT_FALSIFIED
    return EXIT_UNKNOWN if incomplete else EXIT_OK


class UsageError(AtcsInputError):
    """Bad command-line input, its message already naming the command: printed as one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not argparse's usage block
        command = self.prog.removeprefix("atcs").strip()
        raise UsageError(f"{command}: {message}" if command else message)


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text!r}")
    return value


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text!r}")
    return value


def tolerance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not 0 <= value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text!r}")
    return value


def add_only(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--only",
        metavar="PATTERN",
        action="append",
        help="glob over property names, e.g. 'supervision.*'; repeatable (the properties any matches)",
    )


def add_jobs(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--jobs", metavar="N", type=positive_int, default=1, help="worker processes (default 1)")


def selected_properties(command: str, patterns: list[str] | None, properties: dict | None = None) -> list:
    """The registered properties (or ``properties``, by name) any ``--only`` glob selects (all without one); a
    glob that matches no property is a usage error."""
    from atcs.properties import PROPERTIES

    properties = PROPERTIES if properties is None else properties
    if not patterns:
        return list(properties.values())
    chosen = set(matching(properties, patterns))
    for pattern in patterns:
        if not matching(properties, [pattern]):
            modules = sorted({p.module for p in properties.values()})
            raise UsageError(f"{command}: --only {pattern!r} matches no property (modules: {', '.join(modules)})")
    return [p for name, p in properties.items() if name in chosen]


def matching(names, patterns: list[str]) -> list[str]:
    """The ``names`` any of the globs ``patterns`` matches, in order."""
    return [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in patterns)]


def check_outputs(*, files: dict[str, str | None] = (), dirs: dict[str, str | None] = ()) -> None:
    """Fail before any work starts if an output file or directory (by option; None: not asked for) cannot be
    written (:class:`~atcs.proofs.files.OutputPathError`)."""
    from atcs.proofs.files import check_writable_dir, check_writable_file

    for option, path in dict(files).items():
        if path is not None:
            check_writable_file(option, path)
    for option, path in dict(dirs).items():
        if path is not None:
            check_writable_dir(option, path)


@contextmanager
def reraised(prefix: str, *errors: type[Exception]) -> Iterator[None]:
    """Errors of these types (the input given by one option) as a :class:`UsageError` starting ``prefix``."""
    try:
        yield
    except errors as exc:
        raise UsageError(f"{prefix}{exc}") from None


LOG_EVERY_S = 10.0
"""In a log (not a terminal), a long run's position is printed at most this often."""


@dataclass
class Bar:
    """A progress bar with the time left on a terminal; in a log (not a terminal), ``done`` prints one line per
    item and ``at`` a line with the time left every :data:`LOG_EVERY_S`."""

    progress: Progress
    task: int
    console: Console
    started_s: float = field(default_factory=time.monotonic)
    logged_s: float = field(default_factory=time.monotonic)

    def done(self, what: str, log_line: str | None = None) -> None:
        """One item finished: the bar shows ``what``; a log gets ``log_line`` (default ``what``)."""
        self.progress.update(self.task, advance=1, description=what)
        if not self.console.is_terminal:
            print(log_line or what, file=self.console.file, flush=True)

    def more(self, items: int) -> None:
        """``items`` more to do than the total said."""
        if items:
            task = self.progress.tasks[self.task]
            self.progress.update(self.task, total=(task.total or 0) + items)

    def at(self, completed: int, total: int | None = None) -> None:
        """Move the bar to ``completed`` items (of ``total``, if given, from now on); in a log, say so with the time
        left every :data:`LOG_EVERY_S`."""
        self.progress.update(self.task, completed=completed, total=total)
        now = time.monotonic()
        if self.console.is_terminal or now - self.logged_s < LOG_EVERY_S:
            return
        self.logged_s = now
        print(self.position(completed, now), file=self.console.file, flush=True)

    def position(self, completed: int, now: float) -> str:
        """``description: completed/total (percent), elapsed, the time left at the rate so far``."""
        task = self.progress.tasks[self.task]
        total, elapsed = task.total or 0, now - self.started_s
        left = elapsed * (total - completed) / completed if completed else float("nan")
        percent = 100 * completed / total if total else 0.0
        return (
            f"{task.description}: {completed}/{total:g} ({percent:.0f} %), {elapsed:.0f} s elapsed, "
            f"about {left:.0f} s left"
        )


@contextmanager
def progress_bar(console: Console, description: str, total: int) -> Iterator[Bar]:
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("left"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=console, transient=True) as progress:
        yield Bar(progress, progress.add_task(description, total=total), console)
