"""The T2T position report a train sends the train behind it, as bytes on the radio (seed 001 §3.2, Fig. 5 iii:
"position information shared between trains"), with the defences EN 50159 asks of a safety-related message on
an open channel.

A report is 168 bits, most significant bit first (:mod:`atcs.model.bits`):

========== ====== ==========================================================================
field      bits   meaning
========== ====== ==========================================================================
NID_ENGINE 24     the sender's identity (source identifier)
N_SEQ      32     sequence number, one more for every report the sender sends
T_SENT     32     time stamp: when it was sent, in ms by the sender's clock
D_REAR     32     its min safe rear, in cm, two's complement
V_MIN      16     its min speed (estimate less accuracy), in cm/s
SAFETY     32     safety code: CRC-32 (IEEE 802.3) of the expected sender's identity and the fields
========== ====== ==========================================================================

Each quantity is rounded down to its unit, which is the safe side of each: a lower rear, a lower speed (an
earlier stopping point) and an earlier time stamp (an older report). The receiver checks the safety code
computed with the identity of the train it expects ahead, so a report corrupted on the way, or sent by any other
train (the identities differ within 24 bits: a burst the code always detects), is not intact; what to do with a
report that is intact but old, repeated or out of order is the authority's
(:func:`atcs.model.authority.report_accepted`).
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass
from fractions import Fraction
from math import floor

from atcs.model.bits import BitReader, BitWriter, PacketError

__all__ = ["REPORT_BYTES", "ReceivedReport", "T2TReport", "decode_report", "encode_report"]

_FIELDS = (("NID_ENGINE", 24), ("N_SEQ", 32), ("T_SENT", 32), ("D_REAR", 32), ("V_MIN", 16))
_SAFETY_BITS = 32
REPORT_BYTES = (sum(width for _, width in _FIELDS) + _SAFETY_BITS) // 8
"""A report's length on the radio."""


@dataclass(frozen=True)
class T2TReport:
    sender_id: int
    seq: int
    sent_s: Fraction
    rear_m: Fraction
    speed_mps: Fraction


@dataclass(frozen=True)
class ReceivedReport:
    """A report as the receiver reads it; its fields are whatever the bytes say, trusted only if ``intact``."""

    report: T2TReport
    intact: bool
    """The safety code checks for the expected sender."""


def _safety_code(sender_id: int, body: bytes) -> int:
    """CRC-32 of the expected sender's identity and the report's fields: every error of at most three bits, and
    every burst of at most 32 (so a report whose 24-bit sender differs), is detected."""
    return zlib.crc32(sender_id.to_bytes(3, "big") + body)


def encode_report(report: T2TReport) -> bytes:
    """The report's bytes; a field outside its range raises :class:`~atcs.model.bits.PacketError` naming it."""
    rear_cm = floor(Fraction(report.rear_m) * 100)
    if not -(1 << 31) <= rear_cm < 1 << 31:
        raise PacketError("T2T report", "D_REAR", 88, f"{report.rear_m} m is beyond +-21,474,836.47 m")
    values = {
        "NID_ENGINE": report.sender_id,
        "N_SEQ": report.seq,
        "T_SENT": floor(Fraction(report.sent_s) * 1000),
        "D_REAR": rear_cm % (1 << 32),
        "V_MIN": floor(Fraction(report.speed_mps) * 100),
    }
    bits = BitWriter("T2T report")
    for name, width in _FIELDS:
        bits.write(name, width, values[name])
    body = bits.to_bytes()
    return body + _safety_code(report.sender_id, body).to_bytes(_SAFETY_BITS // 8, "big")


def decode_report(data: bytes, expected_sender_id: int) -> ReceivedReport:
    """The report in ``data``, intact only if it is a report's length and its safety code checks for
    ``expected_sender_id`` (the train ahead)."""
    body_bytes = REPORT_BYTES - _SAFETY_BITS // 8
    padded = data[:REPORT_BYTES].ljust(REPORT_BYTES, b"\0")
    bits = BitReader("T2T report", padded)
    value = {name: bits.read(name, width) for name, width in _FIELDS}
    code = int.from_bytes(padded[body_bytes:], "big")
    rear_cm = value["D_REAR"] - (1 << 32) if value["D_REAR"] >= 1 << 31 else value["D_REAR"]
    report = T2TReport(
        sender_id=value["NID_ENGINE"],
        seq=value["N_SEQ"],
        sent_s=Fraction(value["T_SENT"], 1000),
        rear_m=Fraction(rear_cm, 100),
        speed_mps=Fraction(value["V_MIN"], 100),
    )
    intact = len(data) == REPORT_BYTES and code == _safety_code(expected_sender_id, padded[:body_bytes])
    return ReceivedReport(report, intact)
