"""Output files: writability checked before a long run starts, every artefact written to a temporary file
beside its path and then renamed over it (a reader never sees half a file)."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from atcs.model.errors import AtcsInputError


class OutputPathError(AtcsInputError):
    """An output path cannot be written; the message names the option and the path."""


def _probe(option: str, path: str, directory: Path) -> None:
    """Create and delete a file in ``directory``: the only reliable writability test (root ignores modes)."""
    try:
        with tempfile.NamedTemporaryFile(dir=directory, prefix=".atcs-probe-"):
            pass
    except OSError as exc:
        raise OutputPathError(f"{option} {path}: cannot write in {directory}: {exc.strerror}") from None


def check_writable_file(option: str, path: str) -> None:
    """Fail early (before any proof runs) if ``path`` cannot be written as a file."""
    p = Path(path)
    if p.is_dir():
        raise OutputPathError(f"{option} {path}: is a directory")
    if not p.parent.is_dir():
        raise OutputPathError(f"{option} {path}: directory {p.parent} does not exist")
    _probe(option, path, p.parent)


def check_writable_dir(option: str, path: str) -> None:
    """Fail early if ``path`` is not, and cannot become, a writable directory (it is created later)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputPathError(f"{option} {path}: exists and is not a directory")
    existing = p
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise OutputPathError(f"{option} {path}: {existing} is not a directory")
    _probe(option, path, existing)


def write_atomic(path: str | Path, text: str | bytes) -> None:
    """Write ``text`` (or bytes) to a temporary file beside ``path``, then rename it over ``path``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # an ordinary file, not mkstemp's private 0600
    try:
        if isinstance(text, bytes):
            with os.fdopen(fd, "wb") as fh:
                fh.write(text)
        else:
            with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
