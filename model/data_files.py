"""Reading data files: one place for the errors that name the file when it cannot be read at all."""

from __future__ import annotations

import tomllib
from pathlib import Path


def read_toml(path: str | Path, error: type[ValueError], what: str) -> dict:
    """The document of the TOML file ``path``, or ``error`` naming the file (``what`` is, e.g., "the route") when
    it cannot be read, is not UTF-8 text or is not valid TOML."""
    try:
        return tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise error(f"{path}: cannot read {what}: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise error(f"{path}: {what} is not UTF-8 text") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None
