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
from typing import Generic

from atcs.model.bits import PacketError
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, BitString, N, Ops
from atcs.model.ops.exact import EXACT

__all__ = [
    "REPORT_BYTES",
    "T2T_CODEC",
    "T2T_REPORT",
    "ReceivedReport",
    "T2TReport",
    "decode_report",
    "encode_report",
    "min_speed_mps",
    "report_bits",
    "report_fields",
    "report_from_bits",
    "report_quantities",
    "sent_report",
]

_FIELDS = (("NID_ENGINE", 24), ("N_SEQ", 32), ("T_SENT", 32), ("D_REAR", 32), ("V_MIN", 16))
_WIDTHS = tuple(width for _, width in _FIELDS)
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


def min_speed_mps(o: Ops, speed_est_mps, speed_accuracy_mps):
    """The min speed a train reports: its estimate less the estimate's accuracy, and at least 0."""
    return o.max(o.const(0), speed_est_mps - speed_accuracy_mps)


def report_quantities(o: Ops, rear_m, speed_mps, sent_s):
    """``(rear, speed, time stamp)`` as the report carries them: each rounded down to its field's unit (cm, cm/s,
    ms), the safe side of each (T2T-01 to T2T-03)."""
    cm, ms = o.const(100), o.const(1000)
    return o.floor(rear_m * cm) / cm, o.floor(speed_mps * cm) / cm, o.floor(sent_s * ms) / ms


def report_fields(o: Ops, sender_id, seq, sent_s, rear_m, speed_mps) -> tuple:
    """The report's fields as whole numbers of their units (:data:`_FIELDS`' order): the time stamp in ms, the rear
    in cm (negative behind the line's origin: :meth:`~atcs.model.ops.Ops.pack_bits` takes it modulo 2^32, two's
    complement), the speed in cm/s, each rounded down as :func:`report_quantities` rounds it."""
    ms, cm = o.const(1000), o.const(100)
    return sender_id, seq, o.floor(sent_s * ms), o.floor(rear_m * cm), o.floor(speed_mps * cm)


def report_bits(o: Ops, sender_id, seq, sent_s, rear_m, speed_mps):
    """The report's bits before its safety code (:data:`_FIELDS`, most significant first)."""
    fields = report_fields(o, sender_id, seq, sent_s, rear_m, speed_mps)
    return o.pack_bits(tuple(zip(fields, _WIDTHS, strict=True)))


def report_from_bits(o: Ops, bits) -> tuple:
    """``(sender_id, seq, sent_s, rear_m, speed_mps)`` from a report's bits: D_REAR in two's complement, read as its
    sign bit (worth -2^31) and the 31 bits after it."""
    widths = (*_WIDTHS[:3], 1, _WIDTHS[3] - 1, *_WIDTHS[4:])
    sender_id, seq, sent_ms, rear_sign, rear_rest, speed_cm = o.unpack_bits(bits, widths)
    rear_cm = rear_rest - rear_sign * o.const(1 << 31)
    return sender_id, seq, sent_ms / o.const(1000), rear_cm / o.const(100), speed_cm / o.const(100)


_RANGES = {
    "NID_ENGINE": (0, (1 << 24) - 1, ""),
    "N_SEQ": (0, (1 << 32) - 1, ""),
    "T_SENT": (0, (1 << 32) - 1, " ms"),
    "D_REAR": (-(1 << 31), (1 << 31) - 1, " cm (+-21,474,836.47 m)"),
    "V_MIN": (0, (1 << 16) - 1, " cm/s"),
}
"""Each field's range, in its unit: what the report can carry."""


def encode_report(report: T2TReport) -> bytes:
    """The report's bytes (:func:`report_bits`, then the safety code); a field outside its range raises
    :class:`~atcs.model.bits.PacketError` naming it and the bit it starts at."""
    arguments = (report.sender_id, report.seq, report.sent_s, report.rear_m, report.speed_mps)
    exact = tuple(Fraction(value) for value in arguments)
    offset = 0
    for (name, width), value in zip(_FIELDS, report_fields(EXACT, *exact), strict=True):
        low, high, unit = _RANGES[name]
        if value.denominator != 1:
            raise PacketError("T2T report", name, offset, f"{value} is not a whole number")
        if not low <= value <= high:
            raise PacketError("T2T report", name, offset, f"{value}{unit} is outside {low}..{high}{unit}")
        offset += width
    body = report_bits(EXACT, *exact).value.to_bytes(REPORT_BYTES - _SAFETY_BITS // 8, "big")
    return body + _safety_code(report.sender_id, body).to_bytes(_SAFETY_BITS // 8, "big")


def decode_report(data: bytes, expected_sender_id: int) -> ReceivedReport:
    """The report in ``data`` (:func:`report_from_bits`), intact only if it is a report's length and its safety
    code checks for ``expected_sender_id`` (the train ahead)."""
    body_bytes = REPORT_BYTES - _SAFETY_BITS // 8
    padded = data[:REPORT_BYTES].ljust(REPORT_BYTES, b"\0")
    bits = BitString(int.from_bytes(padded[:body_bytes], "big"), 8 * body_bytes)
    sender_id, seq, sent_s, rear_m, speed_mps = report_from_bits(EXACT, bits)
    code = int.from_bytes(padded[body_bytes:], "big")
    report = T2TReport(int(sender_id), int(seq), sent_s, rear_m, speed_mps)
    intact = len(data) == REPORT_BYTES and code == _safety_code(expected_sender_id, padded[:body_bytes])
    return ReceivedReport(report, intact)


# --- what a report says of its sender, as a node ------------------------------------------------------------------


@dataclass(frozen=True)
class ReportParams(Generic[N, B]):
    train_length_m: N


@dataclass(frozen=True)
class SenderState(Generic[N, B]):
    """The sender's true front and speed, and what its position function estimates when it sends."""

    true_front_m: N
    true_speed_mps: N
    front_min_m: N
    speed_est_mps: N
    speed_accuracy_mps: N
    clock_s: N
    """The sender's clock."""


@dataclass(frozen=True)
class ReportContent(Generic[N, B]):
    """The rear, speed and time stamp the report carries, as the receiver decodes them (an intact report)."""

    report_rear_m: N
    report_speed_mps: N
    report_sent_s: N


def sent_report(o: Ops, train_length_m, front_min_m, speed_est_mps, speed_accuracy_mps, clock_s) -> ReportContent:
    """What a train's report says, from its position function's min front, speed estimate and accuracy and its
    clock: its min safe rear and min speed, rounded down to the units the report carries, and the time stamp."""
    rear, speed, sent = report_quantities(
        o, front_min_m - train_length_m, min_speed_mps(o, speed_est_mps, speed_accuracy_mps), clock_s
    )
    return ReportContent(rear, speed, sent)


def t2t_report_step(o: Ops, p: ReportParams, s: Stateless, i: SenderState):
    return s, sent_report(o, p.train_length_m, i.front_min_m, i.speed_est_mps, i.speed_accuracy_mps, i.clock_s)


@dataclass(frozen=True)
class ReportFields(Generic[N, B]):
    """A report's fields as the sender gives them (:func:`report_bits`)."""

    sender_id: N
    seq: N
    sent_s: N
    rear_m: N
    speed_mps: N


@dataclass(frozen=True)
class ReadFields(Generic[N, B]):
    """The fields the receiver reads from the bits (:func:`report_from_bits`)."""

    read_sender_id: N
    read_seq: N
    read_sent_s: N
    read_rear_m: N
    read_speed_mps: N


def t2t_codec_step(o: Ops, p: Stateless, s: Stateless, i: ReportFields):
    bits = report_bits(o, i.sender_id, i.seq, i.sent_s, i.rear_m, i.speed_mps)
    return s, ReadFields(*report_from_bits(o, bits))


T2T_CODEC = stateless_node(
    name="t2t_codec",
    params=Stateless,
    inputs=ReportFields,
    outputs=ReadFields,
    step=t2t_codec_step,
    seed="001 §3.2 (Fig. 5 iii); EN 50159",
)
"""A report's fields written as bits and read back, every field symbolic."""


T2T_REPORT = stateless_node(
    name="t2t_report",
    params=ReportParams,
    inputs=SenderState,
    outputs=ReportContent,
    step=t2t_report_step,
    seed="001 §3.2 (Fig. 5 iii, Fig. 6); EN 50159",
)
"""What a report says (its min safe rear and min speed, rounded down to the units it carries) from the sender's
position estimate, every value symbolic: what the two-train proofs assume of an intact report (REPORT_REAR,
REPORT_STOP) is true of it when it is sent."""
