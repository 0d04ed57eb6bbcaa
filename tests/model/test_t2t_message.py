"""The T2T report on the radio (model/t2t_message.py): fields rounded to the safe side (and proved so of what a
report says of its sender: T2T-01 to T2T-04), its bits read as written (proved: T2T-05 to T2T-09), and every
corruption of the kinds CRC-32 guarantees to catch, and every other sender, detected."""

import itertools
import random
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from atcs.model import t2t_message
from atcs.model.bits import PacketError
from atcs.model.ops.exact import EXACT
from atcs.model.t2t_message import REPORT_BYTES, T2TReport, decode_report, encode_report
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES

REPORT = T2TReport(sender_id=3, seq=7, sent_s=Fraction("12.3456"), rear_m=Fraction("-100.005"), speed_mps=Fraction(22))

reports = st.builds(
    T2TReport,
    sender_id=st.integers(1, (1 << 24) - 1),
    seq=st.integers(0, (1 << 32) - 1),
    sent_s=st.fractions(0, 86_400),
    rear_m=st.fractions(-1_000_000, 1_000_000),
    speed_mps=st.fractions(0, 170),
)


def _flipped(data: bytes, bits) -> bytes:
    value = int.from_bytes(data, "big")
    for bit in bits:
        value ^= 1 << bit
    return value.to_bytes(len(data), "big")


@given(reports)
def test_each_field_is_rounded_down_to_its_unit(report):
    received = decode_report(encode_report(report), report.sender_id)
    assert received.intact
    got = received.report
    assert (got.sender_id, got.seq) == (report.sender_id, report.seq)
    for name, unit in (("sent_s", Fraction(1, 1000)), ("rear_m", Fraction(1, 100)), ("speed_mps", Fraction(1, 100))):
        sent, read = getattr(report, name), getattr(got, name)
        assert sent - unit < read <= sent, name  # the safe side: older, further back, slower


def test_a_worked_example():
    data = encode_report(REPORT)
    assert len(data) == REPORT_BYTES == 21
    got = decode_report(data, 3).report
    assert (got.sent_s, got.rear_m, got.speed_mps) == (Fraction("12.345"), Fraction("-100.01"), 22)


def test_every_error_of_one_or_two_bits_is_detected():
    data = encode_report(REPORT)
    size = 8 * len(data)
    for bits in itertools.chain(itertools.combinations(range(size), 1), itertools.combinations(range(size), 2)):
        assert not decode_report(_flipped(data, bits), 3).intact, bits


def test_bursts_of_up_to_32_bits_are_detected():
    """A burst: its first and last bits flipped, any bits between them (sampled: 2^30 patterns per place)."""
    data, noise = encode_report(REPORT), random.Random(32)
    size = 8 * len(data)
    for _ in range(20_000):
        length = noise.randint(3, 32)
        start = noise.randint(0, size - length)
        inner = [start + j for j in range(1, length - 1) if noise.random() < 0.5]
        assert not decode_report(_flipped(data, [start, start + length - 1, *inner]), 3).intact


def test_a_report_from_any_other_train_is_not_intact():
    data, noise = encode_report(REPORT), random.Random(24)
    others = [*range(0, 3), *range(4, 1000), *(noise.randint(1, (1 << 24) - 1) for _ in range(20_000))]
    assert not any(decode_report(data, other).intact for other in others if other != 3)


@pytest.mark.parametrize("cut", [0, 1, 20, 22])
def test_a_report_of_the_wrong_length_is_not_intact(cut):
    data = (encode_report(REPORT) + b"\0")[:cut]
    assert not decode_report(data, 3).intact


@pytest.mark.parametrize(
    ("field", "change"),
    [
        ("NID_ENGINE", {"sender_id": 1 << 24}),
        ("N_SEQ", {"seq": -1}),
        ("T_SENT", {"sent_s": Fraction(-1, 1000)}),
        ("D_REAR", {"rear_m": Fraction(30_000_000)}),
        ("V_MIN", {"speed_mps": Fraction(700)}),
    ],
)
def test_a_field_outside_its_range_is_refused_naming_it(field, change):
    with pytest.raises(PacketError, match=f"T2T report: {field} at bit"):
        encode_report(T2TReport(**{**REPORT.__dict__, **change}))


# --- what a report says of its sender, proved (T2T-01 to T2T-03) ----------------------------------------------------

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    # the rear rounded up: a report a centimetre ahead of the sender's min safe rear
    "t2t_report.rear_at_most_the_true_rear": (
        t2t_message.report_quantities,
        "o.floor(rear_m * cm) / cm",
        "(o.floor(rear_m * cm) + o.const(1)) / cm",
    ),
    # the estimate reported without its accuracy: faster than the sender may be
    "t2t_report.speed_at_most_the_true_speed": (
        t2t_message.min_speed_mps,
        "speed_est_mps - speed_accuracy_mps",
        "speed_est_mps",
    ),
    # the time stamp rounded up: a report from the future by up to a millisecond
    "t2t_report.time_stamp_not_ahead": (
        t2t_message.report_quantities,
        "o.floor(sent_s * ms) / ms",
        "(o.floor(sent_s * ms) + o.const(1)) / ms",
    ),
    # the rear rounded to the inch: D_REAR (cm) cannot carry it, the bytes say less than the node
    "t2t_report.whole_units": (t2t_message.report_quantities, "cm, ms = o.const(100)", 'cm, ms = o.const("39.37")'),
}
# property -> (function, text in it, faulty replacement)
CODEC_MUTANTS = {
    # the identity read from the sequence number's bits: fields read one bit late
    "t2t_codec.identity_and_number_read_as_written": (
        t2t_message.report_from_bits,
        "widths = (*_WIDTHS[:3], 1, _WIDTHS[3] - 1, *_WIDTHS[4:])",
        "widths = (_WIDTHS[0] + 1, _WIDTHS[1] - 1, _WIDTHS[2], 1, _WIDTHS[3] - 1, *_WIDTHS[4:])",
    ),
    # the time stamp read in hundredths of a second: ten times too old
    "t2t_codec.time_stamp_read_as_written": (
        t2t_message.report_from_bits,
        "sent_ms / o.const(1000)",
        "sent_ms / o.const(100)",
    ),
    # the sign bit read as worth +2^31: a rear behind the origin read 21,474 km ahead
    "t2t_codec.rear_read_as_written": (
        t2t_message.report_from_bits,
        "rear_rest - rear_sign * o.const(1 << 31)",
        "rear_rest + rear_sign * o.const(1 << 31)",
    ),
    # the speed read in mm/s: ten times too slow
    "t2t_codec.speed_read_as_written": (
        t2t_message.report_from_bits,
        "speed_cm / o.const(100)",
        "speed_cm / o.const(1000)",
    ),
    # the sign bit worth 2^32: a rear outside what D_REAR carries
    "t2t_codec.fields_within_range": (
        t2t_message.report_from_bits,
        "rear_rest - rear_sign * o.const(1 << 31)",
        "rear_rest - rear_sign * o.const(1 << 32)",
    ),
}
T2T_PROPERTIES = [p for name, p in PROPERTIES.items() if name.startswith("t2t_report.")]
CODEC_PROPERTIES = [p for name, p in PROPERTIES.items() if name.startswith("t2t_codec.")]


def test_every_report_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in T2T_PROPERTIES}


@pytest.mark.parametrize("prop", T2T_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=1)
    assert run.killed, run


# --- the report's bits, proved (T2T-05 to T2T-09) ------------------------------------------------------------------


def test_every_codec_property_has_a_mutant():
    assert set(CODEC_MUTANTS) == {p.name for p in CODEC_PROPERTIES}


@pytest.mark.parametrize("prop", CODEC_PROPERTIES, ids=lambda p: p.name)
def test_codec_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(CODEC_MUTANTS))
def test_codec_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *CODEC_MUTANTS[name], max_k=1)
    assert run.killed, run


@given(reports)
def test_the_bytes_are_the_codec_nodes_bits(report):
    """encode_report's body is report_bits, decode_report reads it with report_from_bits: the functions the codec
    properties are about."""
    fields = tuple(Fraction(v) for v in (report.sender_id, report.seq, report.sent_s, report.rear_m, report.speed_mps))
    bits = t2t_message.report_bits(EXACT, *fields)
    data = encode_report(report)
    assert int.from_bytes(data[: bits.width // 8], "big") == bits.value
    got = decode_report(data, report.sender_id).report
    assert (got.sender_id, got.seq, got.sent_s, got.rear_m, got.speed_mps) == t2t_message.report_from_bits(EXACT, bits)


def test_the_bytes_carry_the_quantities_the_node_proves_about(report=REPORT):
    rear, speed, sent = t2t_message.report_quantities(EXACT, report.rear_m, report.speed_mps, report.sent_s)
    read = decode_report(encode_report(report), expected_sender_id=report.sender_id).report
    assert (
        (read.rear_m, read.speed_mps, read.sent_s)
        == (rear, speed, sent)
        == (
            Fraction("-100.01"),
            Fraction(22),
            Fraction("12.345"),
        )
    )
