"""Reading data files: one place for the errors that name the file when it cannot be read at all."""

from __future__ import annotations

import json
import math
import tomllib
from collections.abc import Mapping
from fractions import Fraction
from pathlib import Path
from typing import Any

from atcs.model.errors import AtcsInputError
from atcs.model.profile import parse_number


def read_text(path: str | Path, error: type[ValueError], what: str) -> str:
    """The text of the file ``path``, or ``error`` naming the file (``what`` is, e.g., "the route") when it cannot
    be read (missing, a directory, not readable) or is not UTF-8 text."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise error(f"{path}: cannot read {what}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise error(f"{path}: {what} is not UTF-8 text (byte {exc.start} is {exc.object[exc.start]:#04x})") from None


def read_toml(path: str | Path, error: type[ValueError], what: str) -> dict:
    """The document of the TOML file ``path``, or ``error`` naming the file (:func:`read_text`) when it cannot be
    read or is not valid TOML."""
    try:
        return tomllib.loads(read_text(path, error, what))
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None


def read_json(path: str | Path, error: type[ValueError], what: str) -> Any:
    """The document of the JSON file ``path``, or ``error`` naming the file (:func:`read_text`) when it cannot be
    read or is not JSON (an integer too long to read included)."""
    text = read_text(path, error, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: {what} is not JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    except (ValueError, RecursionError) as exc:  # an integer of more than 4300 digits; nesting too deep
        raise error(f"{path}: {what} cannot be read: {' '.join(str(exc).split())[:120]}") from None


class TableReader:
    """Typed access to one TOML table, every error (:attr:`error`, set by a subclass) naming the file and the
    dotted field; a field not in ``allowed`` is refused."""

    error: type[AtcsInputError] = AtcsInputError

    def __init__(self, source: str, table: Mapping, where: str, allowed: tuple[str, ...]):
        self.source, self.table, self.where = source, table, where
        if not isinstance(table, Mapping):
            raise self.error(f"{source}: {where or 'the file'} must be a table, got {table!r}")
        unknown = sorted(set(table) - set(allowed))
        if unknown:
            raise self.error(f"{source}: {self.name(unknown[0])}: unknown field (fields here: {', '.join(allowed)})")

    def name(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def fail(self, key: str, problem: str):
        raise self.error(f"{self.source}: {self.name(key)} = {self.table.get(key)!r} {problem}")

    def number(self, key: str, default=None, *, minimum=None, maximum=None, positive=False) -> Fraction:
        """The field ``key`` as an exact number (``default`` when absent, else it is required), checked against
        the bounds given."""
        if key not in self.table:
            if default is None:
                raise self.error(f"{self.source}: {self.name(key)} is missing")
            return Fraction(default)
        value = parse_number(f"{self.source}", self.name(key), self.table[key], self.error)
        if positive and value <= 0:
            self.fail(key, "must be positive")
        if minimum is not None and value < minimum:
            self.fail(key, f"must be at least {minimum}")
        if maximum is not None and value > maximum:
            self.fail(key, f"must be at most {maximum}")
        return value

    def optional_number(self, key: str, **limits) -> Fraction | None:
        if key not in self.table:
            return None
        if isinstance(self.table[key], float) and math.isinf(self.table[key]):
            return None
        return self.number(key, **limits)

    def text(self, key: str, default: str | None = None, choices: tuple[str, ...] | None = None) -> str:
        value = self.table.get(key, default)
        if value is None:
            raise self.error(f"{self.source}: {self.name(key)} is missing")
        if not isinstance(value, str):
            self.fail(key, "must be a string")
        if choices is not None and value not in choices:
            self.fail(key, f"must be one of {', '.join(choices)}")
        return value

    def rows(self, key: str) -> list:
        value = self.table.get(key, [])
        if not isinstance(value, list):
            self.fail(key, "must be a list of tables")
        return value
