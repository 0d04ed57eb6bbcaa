"""``atcs vectors check DIR --impl COMMAND``: test an external implementation against the vectors.

The implementation runs as one subprocess speaking JSON lines. For each vector atcs writes one request line::

    {"id": "supervision-0001", "function": "supervision",
     "params": {...}, "state": {...}, "inputs": {...},
     "exact": {"params": {...}, "state": {...}, "inputs": {...}}}

numbers as JSON numbers (the nearest double) and, under ``exact``, as exact strings (``"1/3"``); booleans as
``true``/``false``; array fields as lists. The implementation answers each request with one line::

    {"id": "supervision-0001", "next_state": {...}, "outputs": {...}}

where a number is a JSON number (compared within the tolerances) or an exact string (compared exactly), and a
boolean is compared exactly. This is how a team tests its own code (C, generated code, a target in the loop)
against the model: seed 001 §3.4 tests the generated code with the models' test cases.
"""

from __future__ import annotations

import json
import select
import shlex
import subprocess
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from atcs.model.errors import AtcsError, AtcsInputError
from atcs.proofs.cex.trace import format_value
from atcs.proofs.vectors.files import VectorFile
from atcs.proofs.vectors.generate import Vector


class ImplementationError(AtcsError):
    """The implementation stopped answering (or never answered): no verdict on the remaining vectors."""


class ImplementationStartError(ImplementationError, AtcsInputError):
    """The implementation's command line is malformed or cannot be started."""


@dataclass
class Outcome:
    function: str
    id: str
    covers: list[str]
    passed: bool
    mismatch: str = ""
    """The first difference, ``outputs.emergency_brake: expected true, got false``."""


def _floats(record: dict[str, Any]) -> dict[str, Any]:
    def f(v):
        if isinstance(v, tuple):
            return [f(x) for x in v]
        return v if isinstance(v, bool) else float(v)

    return {n: f(v) for n, v in record.items()}


def request(function: str, v: Vector) -> dict[str, Any]:
    return {
        "id": v.id,
        "function": function,
        "params": _floats(v.params),
        "state": _floats(v.state),
        "inputs": _floats(v.inputs),
        "exact": {
            role: {n: format_value(x) for n, x in getattr(v, role).items()} for role in ("params", "state", "inputs")
        },
    }


def _same(want, got, rel_tol: float, abs_tol: float) -> bool:
    if isinstance(want, bool):
        return got is want
    if isinstance(got, bool):
        return False
    if isinstance(got, str):
        try:
            return Fraction(got) == want
        except (ValueError, ZeroDivisionError):
            return False
    if not isinstance(got, (int, float)):
        return False
    return abs(float(got) - float(want)) <= abs_tol + rel_tol * abs(float(want))


def first_mismatch(v: Vector, answer: Any, rel_tol: float, abs_tol: float) -> str:
    """The first field whose answer differs from the expected value (empty when none does)."""
    if not isinstance(answer, dict):
        return f"the answer is not a JSON object: {answer!r}"
    if answer.get("id") != v.id:
        return f"the answer's id is {answer.get('id')!r}, the request's {v.id!r}"
    for role, want in (("next_state", v.next_state), ("outputs", v.outputs)):
        got = answer.get(role)
        if not isinstance(got, dict):
            return f"{role}: missing from the answer"
        for name, value in want.items():
            if name not in got:
                return f"{role}.{name}: missing from the answer"
            pairs = (
                list(zip(value, got[name], strict=True))
                if isinstance(value, tuple) and isinstance(got[name], list) and len(got[name]) == len(value)
                else None
            )
            if isinstance(value, tuple) and pairs is None:
                return f"{role}.{name}: expected a list of {len(value)}, got {got[name]!r}"
            for j, (w, g) in enumerate(pairs or [(value, got[name])]):
                if not _same(w, g, rel_tol, abs_tol):
                    where = f"{role}.{name}" + (f"[{j}]" if pairs is not None else "")
                    shown = json.dumps(format_value(w))
                    return f"{where}: expected {shown}, got {json.dumps(g)}"
    return ""


class Implementation:
    """The external implementation as a subprocess: one request line in, one answer line out."""

    def __init__(self, command: str, timeout_s: float):
        self.command = command
        self.timeout_s = timeout_s
        try:
            argv = shlex.split(command)
        except ValueError as exc:
            raise ImplementationStartError(f"--impl {command!r} is not a command line: {exc}") from None
        if not argv:
            raise ImplementationStartError("--impl is empty")
        try:
            self.process = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
        except OSError as exc:
            raise ImplementationStartError(f"--impl {command!r} cannot be started: {exc.strerror}") from None

    def ask(self, message: dict[str, Any]) -> Any:
        try:
            self.process.stdin.write(json.dumps(message) + "\n")
            self.process.stdin.flush()
        except BrokenPipeError:
            raise ImplementationError(self._stopped()) from None
        ready, _, _ = select.select([self.process.stdout], [], [], self.timeout_s)
        if not ready:
            raise ImplementationError(
                f"--impl {self.command!r} did not answer {message['id']} within {self.timeout_s:g} s"
            )
        line = self.process.stdout.readline()
        if not line:
            raise ImplementationError(self._stopped())
        try:
            return json.loads(line)
        except json.JSONDecodeError:
            return line.rstrip("\n")

    def _stopped(self) -> str:
        try:
            code = self.process.wait(timeout=2)
        except subprocess.TimeoutExpired:
            code = None
        return f"--impl {self.command!r} stopped answering" + (f" (exit code {code})" if code is not None else "")

    def close(self) -> None:
        if self.process.stdin:
            self.process.stdin.close()
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def check(
    files: list[VectorFile], command: str, *, rel_tol: float = 1e-9, abs_tol: float = 1e-9, timeout_s: float = 10
) -> list[Outcome]:
    """Ask the implementation for every vector of ``files`` and compare; raises ImplementationError if it
    cannot be run or stops answering."""
    impl = Implementation(command, timeout_s)
    outcomes = []
    try:
        for vf in files:
            for v in vf.vectors:
                answer = impl.ask(request(vf.node.name, v))
                mismatch = first_mismatch(v, answer, rel_tol, abs_tol)
                outcomes.append(Outcome(vf.node.name, v.id, v.covers, not mismatch, mismatch))
    finally:
        impl.close()
    return outcomes
