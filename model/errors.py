"""The exceptions atcs raises on purpose, under one root.

Every error about what a user gave (a file, a field of it, a command-line value) is an :class:`AtcsInputError`
whose message names the file or option, the field and the value; the command line catches that class once and
prints it as one line (exit code 2). A failed run-time check of the simulator is an :class:`AtcsViolation`.
"""

from __future__ import annotations


class AtcsError(Exception):
    """The root of every exception atcs raises on purpose."""


class AtcsInputError(AtcsError, ValueError):
    """Bad input: the message names the file or option, the field and the value."""


class AtcsViolation(AtcsError, AssertionError):
    """A property or safety check failed during a simulated run."""


__all__ = ["AtcsError", "AtcsInputError", "AtcsViolation"]
