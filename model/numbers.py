"""Numbers read from outside atcs (data files, options, traces, reports) as exact fractions, their size bounded
before any exact arithmetic: a number written ``1e300000000`` is refused, not expanded into a 300-million-digit
integer, and every number accepted converts to a finite float.

Readers name the file, the field and the value around the reason :func:`exact_number` gives.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

__all__ = ["MAX_MAGNITUDE", "MAX_TEXT_CHARS", "exact_number"]

MAX_MAGNITUDE = 10**300
"""The largest magnitude of a number read: every one converts to a finite float (the largest is about 1.8e308)."""
MAX_TEXT_CHARS = 400
"""The longest text of a number read (far more digits than any measurement or exact solver value has)."""
_MAX_EXPONENT = 2 * MAX_TEXT_CHARS
"""The largest exponent of a number in decimal notation (a smaller one, with the text's digits, stays small)."""

_DECIMAL = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE]([+-]?\d+))?")
_RATIO = re.compile(r"[+-]?\d+/\d+")


def exact_number(raw) -> Fraction:
    """``raw`` (an int, a float taken as the decimal it prints as, a Fraction, or text: a decimal with an optional
    exponent, or ``p/q``) as an exact fraction; else a ``ValueError`` whose message is the reason, a phrase such as
    "is not a number" to follow the value."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float, Fraction, str)):
        raise ValueError("is not a number")
    if isinstance(raw, float):
        if not math.isfinite(raw):
            raise ValueError("is not finite")
        # a float is taken as the decimal it prints as (80.1 km/h is 801/10, not its binary neighbour)
        value = Fraction(repr(raw))
    elif isinstance(raw, str):
        text = raw.strip()
        if len(text) > MAX_TEXT_CHARS:
            raise ValueError(f"is longer than {MAX_TEXT_CHARS} characters")
        decimal = _DECIMAL.fullmatch(text)
        if decimal is None and _RATIO.fullmatch(text) is None:
            raise ValueError("is not a number")
        if decimal is not None and decimal.group(1) is not None and abs(int(decimal.group(1))) > _MAX_EXPONENT:
            raise ValueError(f"has an exponent beyond +-{_MAX_EXPONENT}")
        try:
            value = Fraction(text)
        except ZeroDivisionError:
            raise ValueError("divides by zero") from None
    else:
        value = Fraction(raw)
    if abs(value) > MAX_MAGNITUDE:
        raise ValueError("is larger than 1e300 in magnitude")
    return value
