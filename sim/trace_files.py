"""A simulated run's trace as a file: every cycle of every train, as CSV or JSON lines."""

from __future__ import annotations

import csv
import io
import json


def trace_text(rows: list[dict], suffix: str) -> str:
    """A trace as CSV (one row per train and cycle) or JSON lines."""
    if suffix == ".jsonl":
        return "".join(json.dumps(row) + "\n" for row in rows)
    buffer = io.StringIO()
    if rows:
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()
