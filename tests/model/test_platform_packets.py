"""Platform data from the wayside (seed 004 §2.2-2.3, Tables 1-2): the packet 69 / user packet 44 codec is
bit-exact, its bits are the codec nodes' (proved: PKT-01 to PKT-12, each with a mutant falsified), its errors name
the field and the bit offset, it survives fuzzing, the platform table is built from a packet or a TOML table alike,
and ``atcs platforms`` shows it.

The expected bit strings are built here by hand from the layout (``f"{value:0{width}b}"``), not with the codec's
own layout tables.
"""

import itertools
from fractions import Fraction

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from atcs.model import platform_packets
from atcs.model import platforms as platform_table_module
from atcs.model.bits import PacketError, hex_bytes
from atcs.model.ops import BitString
from atcs.model.ops.exact import EXACT
from atcs.model.platform_packets import (
    P44_LAYOUT,
    P69_LAYOUT,
    Packet44Platforms,
    Packet69,
    PlatformElement,
    decode_packet44,
    decode_packet69,
    decode_platform_packet,
    encode_packet44,
    encode_packet69,
    encode_platform_packet,
)
from atcs.model.platforms import (
    Platform,
    PlatformDataError,
    packet_for_platforms,
    platform_data,
    platform_inputs,
    platforms_from_packet,
    read_platform_data,
)
from atcs.proofs.cli import main
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES

# --- the layout, written out independently of the codec ---------------------------------------------------

MAX_D = 32767  # 15 bits
HEADER = 8 + 2 + 13  # NID_PACKET Q_DIR L_PACKET
ELEMENT = 15 + 15 + 4 + 2  # D_TRACKCOND L_TRACKCOND M_PLATFORM Q_PLATFORM
P69_FIRST = HEADER + 2 + 1  # the first element starts after Q_SCALE and Q_TRACKINIT: bit 26
P69_ITER = P69_FIRST + ELEMENT + 5  # element (1) starts after the first element and N_ITER: bit 67
P44_ITER = HEADER + 9 + 8 + 2 + 5  # after NID_XUSER NID_XDATA Q_SCALE N_ITER: bit 47
# offsets inside an element
D_AT, L_AT, M_AT, Q_AT = 0, 15, 30, 34


def expected_bits(packet) -> int:
    """L_PACKET, from the layout: 23 header bits and the packet's own fields."""
    if isinstance(packet, Packet44Platforms):
        return HEADER + 9 + 8 + 2 + 5 + ELEMENT * len(packet.elements)
    if packet.q_trackinit:
        return HEADER + 2 + 1 + 15
    return HEADER + 2 + 1 + ELEMENT + 5 + ELEMENT * (len(packet.elements) - 1)


def field(value: int, width: int) -> str:
    text = f"{value:0{width}b}"
    assert len(text) == width, (value, width)
    return text


def element_bits(e: PlatformElement) -> str:
    return field(e.d_trackcond, 15) + field(e.l_trackcond, 15) + field(e.m_platform, 4) + field(e.q_platform, 2)


def reference_bits(packet) -> str:
    """The packet's bits (no padding), concatenated field by field following the module docstring's layout."""
    if isinstance(packet, Packet44Platforms):
        nid = 44
        body = (
            field(210, 9)
            + field(1, 8)
            + field(packet.q_scale, 2)
            + field(len(packet.elements), 5)
            + "".join(element_bits(e) for e in packet.elements)
        )
    else:
        nid = 69
        body = field(packet.q_scale, 2) + field(packet.q_trackinit, 1)
        if packet.q_trackinit:
            body += field(packet.d_trackinit, 15)
        else:
            first, *rest = packet.elements
            body += element_bits(first) + field(len(rest), 5) + "".join(element_bits(e) for e in rest)
    length = 23 + len(body)
    return field(nid, 8) + field(packet.q_dir, 2) + field(length, 13) + body


def reference_bytes(packet) -> bytes:
    bits = reference_bits(packet)
    bits += "0" * (-len(bits) % 8)
    return bytes(int(bits[j : j + 8], 2) for j in range(0, len(bits), 8))


def set_field(data: bytes, offset: int, width: int, value: int) -> bytes:
    """``data`` with the ``width`` bits at ``offset`` replaced by ``value``."""
    size = 8 * len(data)
    number = int.from_bytes(data, "big")
    shift = size - offset - width
    number = (number & ~(((1 << width) - 1) << shift)) | (value << shift)
    return number.to_bytes(len(data), "big")


def get_field(data: bytes, offset: int, width: int) -> int:
    return (int.from_bytes(data, "big") >> (8 * len(data) - offset - width)) & ((1 << width) - 1)


def rejects(data: bytes, decode=decode_platform_packet) -> PacketError:
    with pytest.raises(PacketError) as info:
        decode(data)
    exc = info.value
    assert f"{exc.field} at bit {exc.bit_offset}:" in str(exc)
    return exc


# --- strategies: every valid code of every field -----------------------------------------------------------

distances = st.integers(0, MAX_D)
elements = st.builds(
    PlatformElement,
    d_trackcond=distances,
    l_trackcond=distances,
    m_platform=st.integers(0, 13),
    q_platform=st.integers(0, 2),
)
q_dirs, q_scales = st.integers(0, 2), st.integers(0, 2)
packets69_elements = st.builds(
    Packet69, q_dir=q_dirs, q_scale=q_scales, elements=st.lists(elements, min_size=1, max_size=32).map(tuple)
)
packets69_init = st.builds(
    Packet69, q_dir=q_dirs, q_scale=q_scales, elements=st.just(()), q_trackinit=st.just(1), d_trackinit=distances
)
packets69 = packets69_elements | packets69_init
packets44 = st.builds(
    Packet44Platforms, q_dir=q_dirs, q_scale=q_scales, elements=st.lists(elements, max_size=31).map(tuple)
)
packets = packets69 | packets44

E1 = PlatformElement(100, 250, 7, 1)
E2 = PlatformElement(1200, 250, 7, 0)
P69 = Packet69(1, 1, (E1, E2))
P69_3 = Packet69(2, 0, (E1, E2, PlatformElement(MAX_D, 1, 13, 2)))
P69_INIT = Packet69(1, 1, (), 1, 300)
P44 = Packet44Platforms(2, 0, (PlatformElement(5, 1000, 13, 2),))
P44_3 = Packet44Platforms(1, 2, (E1, E2, PlatformElement(0, MAX_D, 0, 2)))
P44_EMPTY = Packet44Platforms(0, 1, ())

# Hand-checked vectors (bits grouped by field, then by byte).
# P44: NID_PACKET 44 00101100 | Q_DIR 2 10 | L_PACKET 83 0000001010011 | NID_XUSER 210 011010010 |
#      NID_XDATA 1 00000001 | Q_SCALE 0 00 | N_ITER 1 00001 | D_TRACKCOND(1) 5 000000000000101 |
#      L_TRACKCOND(1) 1000 000001111101000 | M_PLATFORM(1) 13 1101 | Q_PLATFORM(1) 2 10 | padding 00000
#   = 00101100 10000000 10100110 11010010 00000001 00000010 00000000 00010100 00011111 01000110 11000000
P44_HEX = "2c80a6d2010200141f46c0"
# P69_INIT: NID_PACKET 69 01000101 | Q_DIR 1 01 | L_PACKET 41 0000000101001 | Q_SCALE 1 01 | Q_TRACKINIT 1 1 |
#      D_TRACKINIT 300 000000100101100 | padding 0000000
#   = 01000101 01000000 01010010 11000000 10010110 00000000
P69_INIT_HEX = "454052c09600"
# P69 (the platforms module's docstring example): 4600-4850 m right and 5800-6050 m left, 760 mm, read at 4500 m
P69_HEX = "4540ce803200fa74212c007d38"


class TestRoundTrip:
    @settings(max_examples=150)
    @given(packets)
    def test_decode_encode_is_identity(self, packet):
        data = encode_platform_packet(packet)
        decoded = decode_platform_packet(data)
        assert decoded == packet and type(decoded) is type(packet)
        assert (decode_packet69 if isinstance(packet, Packet69) else decode_packet44)(data) == packet

    @settings(max_examples=150)
    @given(packets)
    def test_length_and_padding(self, packet):
        data = encode_platform_packet(packet)
        length = get_field(data, 10, 13)
        assert length == expected_bits(packet)
        assert len(data) == -(-length // 8)
        padding = 8 * len(data) - length
        assert 0 < padding < 8  # the layout never ends on a byte boundary
        assert get_field(data, length, padding) == 0

    @settings(max_examples=50)
    @given(packets69_elements)
    def test_packet69_dispatch_and_wrong_decoder(self, packet):
        data = encode_packet69(packet)
        assert isinstance(decode_platform_packet(data), Packet69)
        exc = rejects(data, decode_packet44)
        assert (exc.packet, exc.field, exc.bit_offset) == ("packet 44", "NID_PACKET", 0)

    @settings(max_examples=50)
    @given(packets44)
    def test_packet44_dispatch_and_wrong_decoder(self, packet):
        data = encode_packet44(packet)
        assert isinstance(decode_platform_packet(data), Packet44Platforms)
        exc = rejects(data, decode_packet69)
        assert (exc.packet, exc.field, exc.bit_offset) == ("packet 69", "NID_PACKET", 0)

    @pytest.mark.parametrize("q_dir", range(3))
    @pytest.mark.parametrize("q_scale", range(3))
    def test_every_header_code(self, q_dir, q_scale):
        for packet in (
            Packet69(q_dir, q_scale, (E1,)),
            Packet69(q_dir, q_scale, (), 1, 0),
            Packet44Platforms(q_dir, q_scale, (E1,)),
        ):
            assert decode_platform_packet(encode_platform_packet(packet)) == packet

    @pytest.mark.parametrize("m", range(14))
    @pytest.mark.parametrize("q", range(3))
    def test_every_element_code(self, m, q):
        element = PlatformElement(0, MAX_D, m, q)
        for packet in (Packet69(1, 1, (element, element)), Packet44Platforms(1, 1, (element,))):
            assert decode_platform_packet(encode_platform_packet(packet)) == packet

    def test_sizes_at_the_limits(self):
        full69 = Packet69(1, 1, (E1,) * 32)
        full44 = Packet44Platforms(1, 1, (E1,) * 31)
        assert get_field(encode_packet69(full69), 10, 13) == 31 + 36 * 32 == 1183
        assert get_field(encode_packet44(full44), 10, 13) == 47 + 36 * 31 == 1163
        assert decode_platform_packet(encode_packet69(full69)) == full69
        assert decode_platform_packet(encode_packet44(full44)) == full44


class TestBitExact:
    def test_hand_checked_packet44(self):
        data = encode_packet44(P44)
        assert data.hex() == P44_HEX and len(data) == 11
        assert reference_bytes(P44) == data
        assert decode_platform_packet(bytes.fromhex(P44_HEX)) == P44

    def test_hand_checked_packet69_trackinit(self):
        assert encode_packet69(P69_INIT).hex() == P69_INIT_HEX
        assert reference_bytes(P69_INIT).hex() == P69_INIT_HEX
        assert decode_platform_packet(bytes.fromhex(P69_INIT_HEX)) == P69_INIT

    def test_docstring_example(self):
        assert encode_packet69(P69).hex() == P69_HEX == reference_bytes(P69).hex()
        assert platforms_from_packet(decode_platform_packet(hex_bytes(P69_HEX)), 4500) == (
            Platform(Fraction(4600), Fraction(4850), "right", 760),
            Platform(Fraction(5800), Fraction(6050), "left", 760),
        )

    @pytest.mark.parametrize(
        "packet", [P69, P69_3, P69_INIT, P44, P44_3, P44_EMPTY, Packet69(0, 2, (PlatformElement(MAX_D, MAX_D, 13, 2),))]
    )
    def test_hand_written_packets(self, packet):
        assert encode_platform_packet(packet) == reference_bytes(packet)

    @settings(max_examples=150)
    @given(packets)
    def test_generated_packets(self, packet):
        assert encode_platform_packet(packet) == reference_bytes(packet)

    def test_field_offsets(self):
        """The offsets the error tests use, read back from a reference encoding."""
        data = reference_bytes(P69_3)
        assert get_field(data, P69_FIRST + D_AT, 15) == 100 and get_field(data, P69_FIRST + ELEMENT, 5) == 2
        k2 = P69_ITER + ELEMENT
        assert (get_field(data, k2 + D_AT, 15), get_field(data, k2 + M_AT, 4), get_field(data, k2 + Q_AT, 2)) == (
            MAX_D,
            13,
            2,
        )
        data = reference_bytes(P44_3)
        assert get_field(data, 23, 9) == 210 and get_field(data, 32, 8) == 1 and get_field(data, 40, 2) == 2
        assert get_field(data, P44_ITER + 2 * ELEMENT + L_AT, 15) == MAX_D


class TestDecodeErrors:
    def test_nid_packet(self):
        exc = rejects(b"\x46" + encode_packet69(P69)[1:])
        assert (exc.field, exc.bit_offset) == ("NID_PACKET", 0)
        assert "70 is neither 69 nor 44" in str(exc)
        exc = rejects(b"\x2d" + encode_packet44(P44)[1:], decode_packet44)
        assert (exc.packet, exc.field, exc.bit_offset) == ("packet 44", "NID_PACKET", 0)
        assert "00101101b (45)" in str(exc)

    @pytest.mark.parametrize("packet", [P69, P69_INIT, P44])
    def test_q_dir_spare(self, packet):
        exc = rejects(set_field(encode_platform_packet(packet), 8, 2, 0b11))
        assert (exc.field, exc.bit_offset) == ("Q_DIR", 8)
        assert "11b (3) is spare" in str(exc)

    @pytest.mark.parametrize(("packet", "offset"), [(P69, 23), (P69_INIT, 23), (P44, 40), (P44_EMPTY, 40)])
    def test_q_scale_spare(self, packet, offset):
        exc = rejects(set_field(encode_platform_packet(packet), offset, 2, 0b11))
        assert (exc.field, exc.bit_offset) == ("Q_SCALE", offset)
        assert "11b (3) is spare" in str(exc)

    @pytest.mark.parametrize(
        ("packet", "start", "suffix"),
        [
            (P69_3, P69_FIRST, ""),
            (P69_3, P69_ITER, "(1)"),
            (P69_3, P69_ITER + ELEMENT, "(2)"),
            (P44_3, P44_ITER, "(1)"),
            (P44_3, P44_ITER + 2 * ELEMENT, "(3)"),
        ],
    )
    def test_element_codes(self, packet, start, suffix):
        data = encode_platform_packet(packet)
        exc = rejects(set_field(data, start + Q_AT, 2, 0b11))
        assert (exc.field, exc.bit_offset) == (f"Q_PLATFORM{suffix}", start + Q_AT)
        assert "is spare" in str(exc)
        for code in (14, 15):
            exc = rejects(set_field(data, start + M_AT, 4, code))
            assert (exc.field, exc.bit_offset) == (f"M_PLATFORM{suffix}", start + M_AT)
            assert f"{code:04b}b ({code}) is reserved" in str(exc)

    def test_user_packet_ids(self):
        data = encode_packet44(P44)
        exc = rejects(set_field(data, 23, 9, 211))
        assert (exc.field, exc.bit_offset) == ("NID_XUSER", 23) and "(211) is another user system" in str(exc)
        exc = rejects(set_field(data, 32, 8, 2))
        assert (exc.field, exc.bit_offset) == ("NID_XDATA", 32) and "(2) is not platform information" in str(exc)

    @pytest.mark.parametrize("packet", [P69, P69_3, P69_INIT, P44, P44_3, P44_EMPTY])
    def test_every_truncation(self, packet):
        data = encode_platform_packet(packet)
        for n in range(len(data)):
            exc = rejects(data[:n])
            assert "truncated" in str(exc)
            assert 0 <= exc.bit_offset <= 8 * n

    def test_empty(self):
        exc = rejects(b"")
        assert (exc.field, exc.bit_offset) == ("NID_PACKET", 0) and "no bytes" in str(exc)
        for decode in (decode_packet69, decode_packet44):
            exc = rejects(b"", decode)
            assert (exc.field, exc.bit_offset) == ("NID_PACKET", 0) and "truncated" in str(exc)

    @pytest.mark.parametrize("packet", [P69, P69_INIT, P44, P44_EMPTY])
    @pytest.mark.parametrize("extra", [b"\x00", b"\x00\x00", b"\x80"])
    def test_over_long(self, packet, extra):
        exc = rejects(encode_platform_packet(packet) + extra)
        assert (exc.field, exc.bit_offset) == ("padding", expected_bits(packet))
        assert "over-long" in str(exc)

    @settings(max_examples=50)
    @given(packets, st.data())
    def test_non_zero_padding(self, packet, data):
        encoded = encode_platform_packet(packet)
        length = expected_bits(packet)
        bit = data.draw(st.integers(length, 8 * len(encoded) - 1))
        exc = rejects(set_field(encoded, bit, 1, 1))
        assert (exc.field, exc.bit_offset) == ("padding", length)
        assert "must be 0" in str(exc)

    @settings(max_examples=50)
    @given(packets, st.integers(0, (1 << 13) - 1))
    def test_l_packet_disagrees(self, packet, declared):
        length = expected_bits(packet)
        if declared == length:
            declared += 1
        exc = rejects(set_field(encode_platform_packet(packet), 10, 13, declared))
        assert (exc.field, exc.bit_offset) == ("L_PACKET", 10)
        assert f"{declared} bits declared, but the fields end at bit {length}" in str(exc)

    def test_n_iter_beyond_the_data(self):
        data = set_field(encode_packet44(P44), HEADER + 19, 5, 2)  # N_ITER 2, one element sent
        exc = rejects(data)
        assert exc.field.endswith("(2)") and "truncated" in str(exc)
        assert exc.bit_offset >= P44_ITER + ELEMENT


class TestHexBytes:
    def test_spaces_and_underscores(self):
        assert hex_bytes(" 45 40_CE\n80 ") == bytes.fromhex("4540ce80")
        assert hex_bytes("") == b""

    def test_non_hex_character(self):
        with pytest.raises(PacketError) as info:
            hex_bytes("45 4g", what="--packet")
        assert (info.value.packet, info.value.field, info.value.bit_offset) == ("--packet", "hex string", 12)
        assert "'g' is not a hex digit" in str(info.value)

    def test_odd_digit_count(self):
        with pytest.raises(PacketError) as info:
            hex_bytes("454")
        assert (info.value.field, info.value.bit_offset) == ("hex string", 12)
        assert "3 hex digits are not whole bytes" in str(info.value)


class TestEncodeErrors:
    @pytest.mark.parametrize(
        ("packet", "name", "offset"),
        [
            (Packet69(3, 1, (E1,)), "Q_DIR", 8),
            (Packet69(1, 3, (E1,)), "Q_SCALE", 23),
            (Packet44Platforms(1, 3, (E1,)), "Q_SCALE", 40),
            (Packet69(1, 1, (E1,), 2), "Q_TRACKINIT", 25),
            (Packet69(1, 1, (PlatformElement(MAX_D + 1, 1, 0, 0),)), "D_TRACKCOND", P69_FIRST + D_AT),
            (Packet69(1, 1, (PlatformElement(-1, 1, 0, 0),)), "D_TRACKCOND", P69_FIRST + D_AT),
            (Packet69(1, 1, (PlatformElement(1, MAX_D + 1, 0, 0),)), "L_TRACKCOND", P69_FIRST + L_AT),
            (Packet69(1, 1, (PlatformElement(True, 1, 0, 0),)), "D_TRACKCOND", P69_FIRST + D_AT),
            (Packet69(1, 1, (PlatformElement(1.0, 1, 0, 0),)), "D_TRACKCOND", P69_FIRST + D_AT),
            (Packet69(1, 1, (PlatformElement(1, 1, 14, 0),)), "M_PLATFORM", P69_FIRST + M_AT),
            (Packet69(1, 1, (PlatformElement(1, 1, 0, 3),)), "Q_PLATFORM", P69_FIRST + Q_AT),
            (Packet69(1, 1, (E1, E2, PlatformElement(1, 1, 15, 0))), "M_PLATFORM(2)", P69_ITER + ELEMENT + M_AT),
            (Packet44Platforms(1, 1, (E1, PlatformElement(1, 1, 0, 3))), "Q_PLATFORM(2)", P44_ITER + ELEMENT + Q_AT),
            (Packet44Platforms(1, 1, (PlatformElement(1, -5, 0, 0),)), "L_TRACKCOND(1)", P44_ITER + L_AT),
            (Packet69(1, 1, (E1,) * 33), "N_ITER", P69_FIRST + ELEMENT),
            (Packet69(1, 1, ()), "N_ITER", P69_FIRST + ELEMENT),
            (Packet44Platforms(1, 1, (E1,) * 32), "N_ITER", HEADER + 19),
            (Packet69(1, 1, (E1,), 1, 5), "D_TRACKINIT", 26),
            (Packet69(1, 1, (), 1, None), "D_TRACKINIT", 26),
            (Packet69(1, 1, (E1,), 0, 5), "D_TRACKINIT", 26),
            (Packet69(1, 1, (), 1, MAX_D + 1), "D_TRACKINIT", 26),
        ],
    )
    def test_invalid_values(self, packet, name, offset):
        with pytest.raises(PacketError) as info:
            encode_platform_packet(packet)
        assert (info.value.field, info.value.bit_offset) == (name, offset)
        assert str(info.value).startswith(
            f"packet {44 if isinstance(packet, Packet44Platforms) else 69}: {name} at bit {offset}: "
        )

    def test_not_a_packet(self):
        with pytest.raises(TypeError, match="not a platform packet"):
            encode_platform_packet(E1)


def decodes_or_rejects(data: bytes):
    """The decoder's contract: a packet whose encoding is ``data`` exactly, or a PacketError (nothing else)."""
    try:
        packet = decode_platform_packet(data)
    except PacketError as exc:
        assert exc.field and f"{exc.field} at bit {exc.bit_offset}:" in str(exc)
        assert 0 <= exc.bit_offset <= 8 * len(data)
        return None
    assert encode_platform_packet(packet) == data
    return packet


class TestFuzz:
    @settings(max_examples=200)
    @given(st.binary(max_size=64))
    @example(b"\x45")
    @example(b"\x2c")
    def test_random_bytes(self, data):
        decodes_or_rejects(data)

    @settings(max_examples=200)
    @given(st.sampled_from([b"\x45", b"\x2c"]), st.binary(max_size=200))
    def test_random_bytes_past_nid_packet(self, nid, rest):
        decodes_or_rejects(nid + rest)

    @settings(max_examples=200)
    @given(st.sampled_from([b"\x45", b"\x2c\x40\x00\xd2\x01", b"\x2c\x80\x00\xd2\x01"]), st.binary(max_size=200))
    def test_random_bytes_past_the_user_ids(self, head, rest):
        decodes_or_rejects(head + rest)

    @settings(max_examples=200)
    @given(packets, st.data())
    def test_bit_flips(self, packet, data):
        encoded = encode_platform_packet(packet)
        flips = data.draw(st.lists(st.integers(0, 8 * len(encoded) - 1), min_size=1, max_size=3, unique=True))
        number = int.from_bytes(encoded, "big")
        for bit in flips:
            number ^= 1 << (8 * len(encoded) - 1 - bit)
        flipped = number.to_bytes(len(encoded), "big")
        decoded = decodes_or_rejects(flipped)
        assert decoded != packet  # a changed bit string is never read as the same packet

    @settings(max_examples=100)
    @given(packets, st.data())
    def test_truncations_and_extensions(self, packet, data):
        encoded = encode_platform_packet(packet)
        n = data.draw(st.integers(0, len(encoded) - 1))
        assert decodes_or_rejects(encoded[:n]) is None
        extended = encoded + data.draw(st.binary(min_size=1, max_size=8))
        assert decodes_or_rejects(extended) is None
        assert decodes_or_rejects(encoded) == packet

    def test_a_flip_in_a_distance_is_another_valid_packet(self):
        data = encode_packet69(P69)
        flipped = set_field(data, P69_FIRST + D_AT + 14, 1, 1)  # D_TRACKCOND 100 -> 101
        decoded = decodes_or_rejects(flipped)
        assert decoded == Packet69(1, 1, (PlatformElement(101, 250, 7, 1), E2))


# --- the platform table ----------------------------------------------------------------------------------


class TestPlatformsFromPacket:
    def test_cumulative_positions(self):
        assert platforms_from_packet(P69, 4500) == (
            Platform(Fraction(4600), Fraction(4850), "right", 760),
            Platform(Fraction(5800), Fraction(6050), "left", 760),
        )
        packet = Packet44Platforms(1, 2, (PlatformElement(10, 25, 0, 2), PlatformElement(0, 3, 13, 0)))
        assert platforms_from_packet(packet, 0) == (
            Platform(Fraction(100), Fraction(350), "both", 200),
            Platform(Fraction(100), Fraction(130), "left", 1100),
        )

    def test_decimetre_scale_is_exact(self):
        packet = Packet69(1, 0, (PlatformElement(5, 3, 1, 1), PlatformElement(1, 7, 2, 0)))
        first, second = platforms_from_packet(packet, Fraction(1, 10))
        assert first == Platform(Fraction(6, 10), Fraction(9, 10), "right", 300)
        assert second == Platform(Fraction(7, 10), Fraction(14, 10), "left", 550)
        assert all(isinstance(x, Fraction) for x in (first.start_m, first.end_m, second.start_m, second.end_m))

    def test_direction(self):
        for q_dir, nominal, reverse in ((0, False, True), (1, True, False), (2, True, True)):
            packet = Packet69(q_dir, 1, (E1,))
            assert bool(platforms_from_packet(packet, 0)) is nominal
            assert bool(platforms_from_packet(packet, 0, direction="reverse")) is reverse
        with pytest.raises(ValueError, match="direction must be 'nominal' or 'reverse', got 'both'"):
            platforms_from_packet(P69, 0, direction="both")

    def test_empty_profiles(self):
        assert platforms_from_packet(P69_INIT, 100) == ()
        assert platforms_from_packet(Packet44Platforms(2, 1, ()), 100) == ()

    @settings(max_examples=100)
    @given(packets, st.integers(-(10**6), 10**6).map(lambda n: Fraction(n, 10)))
    def test_packet_for_platforms_inverts(self, packet, reference):
        if packet.q_dir == 0 or (isinstance(packet, Packet69) and packet.q_trackinit):
            return
        platforms = platforms_from_packet(packet, reference)
        nid = 69 if isinstance(packet, Packet69) else 44
        assert (
            packet_for_platforms(platforms, reference, q_scale=packet.q_scale, nid_packet=nid, q_dir=packet.q_dir)
            == packet
        )

    def test_packet_for_platforms_defaults(self):
        platforms = platforms_from_packet(P69, 4500)
        assert packet_for_platforms(platforms, 4500) == P69
        assert packet_for_platforms(platforms, 4500, nid_packet=44) == Packet44Platforms(1, 1, (E1, E2))
        assert packet_for_platforms((), 0, nid_packet=44) == Packet44Platforms(1, 1, ())

    @pytest.mark.parametrize(
        ("platforms", "kwargs", "message"),
        [
            ([Platform(Fraction(10), Fraction(20), "left", 760)], {"q_scale": 3}, "q_scale must be one of [0, 1, 2]"),
            ([Platform(Fraction(10), Fraction(20), "left", 760)], {"nid_packet": 45}, "nid_packet must be 69 or 44"),
            ([Platform(Fraction(-1), Fraction(20), "left", 760)], {}, "platform 0: start_m gives -1 units"),
            ([Platform(Fraction(21, 2), Fraction(20), "left", 760)], {}, "platform 0: start_m gives 21/2 units of 1 m"),
            ([Platform(Fraction(10), Fraction(41, 2), "left", 760)], {}, "platform 0: length gives 21/2 units"),
            ([Platform(Fraction(10), Fraction(5), "left", 760)], {}, "platform 0: length gives -5 units"),
            ([Platform(Fraction(32768), Fraction(32769), "left", 760)], {}, "start_m gives 32768 units"),
            (
                [Platform(Fraction(0), Fraction(32768, 10), "left", 760)],
                {"q_scale": 0},
                "length gives 32768 units of 1/10 m",
            ),
            (
                [Platform(Fraction(10), Fraction(20), "left", 760), Platform(Fraction(5), Fraction(8), "left", 760)],
                {},
                "platform 1: start_m gives -5 units",
            ),
            ([Platform(Fraction(10), Fraction(20), "left")], {}, "platform 0: height_mm = None has no M_PLATFORM code"),
            ([Platform(Fraction(10), Fraction(20), "left", 761)], {}, "platform 0: height_mm = 761"),
            ([Platform(Fraction(10), Fraction(20), "none", 760)], {}, "platform 0: side = 'none'"),
        ],
    )
    def test_packet_for_platforms_errors(self, platforms, kwargs, message):
        with pytest.raises(ValueError) as info:
            packet_for_platforms(platforms, 0, **kwargs)
        assert message in str(info.value)


TABLE_TOML = """
[[platforms.table]]
start_m = 4600
length_m = 250
side = "right"
height_mm = 760

[[platforms.table]]
start_m = "5800"
length_m = 250.0
side = "left"
height_mm = 760
"""

PACKET_TOML = f"""
[platforms]
packet = "{P69_HEX}"
reference_m = 4500
"""


def write(tmp_path, text: str, name: str = "scenario.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def data_error(path, *expected):
    with pytest.raises(PlatformDataError) as info:
        read_platform_data(path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    for text in expected:
        assert text in message, message
    return message


class TestPlatformData:
    def test_table_and_packet_agree(self, tmp_path):
        table = read_platform_data(write(tmp_path, TABLE_TOML, "table.toml"))
        packet = read_platform_data(write(tmp_path, PACKET_TOML, "packet.toml"))
        assert table == packet == platforms_from_packet(P69, 4500)
        assert packet_for_platforms(table, 4500) == P69

    def test_packet_44_with_spaces_and_decimal_reference(self, tmp_path):
        hex_text = encode_packet44(P44).hex()
        path = write(tmp_path, f'[platforms]\npacket = "{hex_text[:6]} {hex_text[6:]}"\nreference_m = 12.5\n')
        assert read_platform_data(path) == (Platform(Fraction(13), Fraction(113), "both", 1100),)

    @settings(max_examples=50)
    @given(
        packets.filter(lambda p: p.q_dir != 0 and p.elements and all(e.l_trackcond for e in p.elements)),
        st.integers(0, 10**6),
    )
    def test_table_and_packet_agree_generated(self, packet, reference):
        from_packet = platform_data(
            {"packet": encode_platform_packet(packet).hex(), "reference_m": reference}, "s.toml"
        )
        rows = [
            {"start_m": str(p.start_m), "length_m": str(p.end_m - p.start_m), "side": p.side, "height_mm": p.height_mm}
            for p in from_packet
        ]
        assert from_packet == platforms_from_packet(packet, reference)
        overlap = any(
            a.start_m < b.end_m and b.start_m < a.end_m and ((a.left and b.left) or (a.right and b.right))
            for a, b in itertools.combinations(from_packet, 2)
        )
        if overlap:  # a packet may lay two edges on one side and place; a table written by hand may not
            with pytest.raises(PlatformDataError, match="on the same side: one platform edge per side and place"):
                platform_data({"table": rows}, "s.toml")
        else:
            assert platform_data({"table": rows}, "s.toml") == from_packet

    def test_direction(self, tmp_path):
        reverse = encode_packet69(Packet69(0, 1, (E1,))).hex()
        path = write(tmp_path, f'[platforms]\npacket = "{reverse}"\nreference_m = 0\ndirection = "reverse"\n')
        assert read_platform_data(path) == (Platform(Fraction(100), Fraction(350), "right", 760),)
        data_error(
            write(tmp_path, f'[platforms]\npacket = "{reverse}"\nreference_m = 0\n'),
            "Q_DIR (0) does not apply to a train running nominal",
        )
        data_error(
            write(tmp_path, f'[platforms]\npacket = "{reverse}"\nreference_m = 0\ndirection = "up"\n'),
            "direction = 'up' must be 'nominal' or 'reverse'",
        )

    def test_empty_profile(self, tmp_path):
        path = write(tmp_path, f'[platforms]\npacket = "{P69_INIT_HEX}"\nreference_m = 0\n')
        assert read_platform_data(path) == ()
        assert read_platform_data(write(tmp_path, "[platforms]\ntable = []\n")) == ()

    @pytest.mark.parametrize(
        ("text", "expected"),
        [
            (PACKET_TOML + TABLE_TOML, ["[platforms]", "give either 'packet'", "not both"]),
            ("[platforms]\nreference_m = 0\n", ["[platforms]", "not neither"]),
            (PACKET_TOML + "colour = 'red'\n", ["unknown field 'colour'"]),
            (f'[platforms]\npacket = "{P69_HEX}"\n', ["a packet needs reference_m"]),
            (f'[platforms]\npacket = "{P69_HEX}"\nreference_m = "far"\n', ["reference_m = 'far' is not a number"]),
            ("[platforms]\npacket = 69\nreference_m = 0\n", ["packet = 69 must be a hex string"]),
            ('[platforms]\npacket = "45 4x"\nreference_m = 0\n', ["packet:", "hex string at bit 12", "'x'"]),
            ('[platforms]\npacket = "454"\nreference_m = 0\n', ["hex string at bit 12", "3 hex digits"]),
            (
                f'[platforms]\npacket = "{set_field(bytes.fromhex(P69_HEX), 8, 2, 3).hex()}"\nreference_m = 0\n',
                ["packet: packet 69: Q_DIR at bit 8:", "11b (3) is spare"],
            ),
            (
                f'[platforms]\npacket = "{set_field(bytes.fromhex(P69_HEX), P69_ITER + M_AT, 4, 15).hex()}"\n'
                "reference_m = 0\n",
                [f"M_PLATFORM(1) at bit {P69_ITER + M_AT}:", "(15) is reserved"],
            ),
            (f'[platforms]\npacket = "{P69_HEX}00"\nreference_m = 0\n', ["padding at bit 103", "over-long"]),
            ("[platforms]\ntable = 5\n", ["table = 5 must be a list"]),
            (f'[platforms]\npacket = "{P69_HEX}"\nreference_m = -1\n', ["reference_m = -1 is negative"]),
            (
                "[platforms]\nreference_m = 10\n" + TABLE_TOML.removeprefix("[platforms]\n"),
                ["reference_m belongs to a packet"],
            ),
            (
                "[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'left'\nheight_mm = 760.0\n",
                ["table[0]: height_mm = 760.0 is not a height packet 69 can give"],
            ),
            ("[platforms]\ntable = [1]\n", ["table[0] must be a table, got 1"]),
            (
                "[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'top'\n",
                ["table[0]: side = 'top' must be one of left, right, both"],
            ),
            (
                "[[platforms.table]]\nstart_m = -5\nlength_m = 2\nside = 'left'\n",
                ["table[0]: start_m = -5 is negative"],
            ),
            (
                "[[platforms.table]]\nstart_m = 1\nlength_m = 0\nside = 'left'\n",
                ["table[0]: length_m = 0 must be positive"],
            ),
            (
                "[[platforms.table]]\nstart_m = 1\nlength_m = -2.5\nside = 'left'\n",
                ["table[0]: length_m = -2.5 must be positive"],
            ),
            (
                "[[platforms.table]]\nstart_m = 'x'\nlength_m = 2\nside = 'left'\n",
                ["table[0]: start_m = 'x' is not a number"],
            ),
            (
                TABLE_TOML + "\n[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'left'\nheight_mm = 123\n",
                ["table[2]: height_mm = 123 is not a height packet 69 can give", "760"],
            ),
            (
                "[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'left'\nwidth = 3\n",
                ["table[0]: unknown field 'width'"],
            ),
            ("[[platforms.table]]\nlength_m = 2\nside = 'left'\n", ["table[0]: start_m is missing"]),
            ("[[platforms.table]]\nstart_m = 1\nside = 'left'\n", ["table[0]: length_m is missing"]),
            ("[[platforms.table]]\nstart_m = 1\nlength_m = 2\n", ["table[0]: side is missing"]),
            ("platforms = 3\n", ["[platforms] must be a table, got 3"]),
            ("[platforms\n", ["not valid TOML"]),
            ("[track]\nlength_m = 3\n", ["no [platforms] section"]),
        ],
    )
    def test_errors_name_file_field_and_value(self, tmp_path, text, expected):
        data_error(write(tmp_path, text), *expected)

    def test_unreadable_file(self, tmp_path):
        data_error(tmp_path / "missing.toml", "cannot read", "No such file")
        data_error(tmp_path, "cannot read")
        path = tmp_path / "latin1.toml"
        path.write_bytes(b"[platforms]\n# caf\xe9\n")
        data_error(path, "not UTF-8")


class TestPlatformInputs:
    def test_pads_to_capacity(self):
        platforms = (Platform(Fraction(10), Fraction(20), "left"), Platform(Fraction(30), Fraction(45), "both", 760))
        inputs = platform_inputs(platforms, 4)
        assert inputs == {
            "platform_start_m": (10, 30, 0, 0),
            "platform_end_m": (20, 45, 0, 0),
            "platform_left": (True, True, False, False),
            "platform_right": (False, True, False, False),
        }
        assert platform_inputs(platforms)["platform_right"] == (False, True)
        assert platform_inputs((), 2)["platform_left"] == (False, False)

    def test_refuses_too_many(self):
        platforms = platforms_from_packet(P69, 0)
        with pytest.raises(ValueError, match="2 platforms do not fit a table of capacity 1"):
            platform_inputs(platforms, 1)


# --- atcs platforms --------------------------------------------------------------------------------------


def one_line_error(capsys, *expected):
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0, err
    assert err.startswith("atcs: error: platforms:"), err
    for text in expected:
        assert text in err, err


def printed_packet(out: str, nid: str) -> bytes:
    lines = [line for line in out.splitlines() if line.startswith(f"packet {nid}: ")]
    assert len(lines) == 1, out
    return bytes.fromhex(lines[0].removeprefix(f"packet {nid}: ").strip())


class TestCli:
    def test_packet(self, capsys):
        assert main(["platforms", "--packet", P69_HEX, "--reference-m", "4500"]) == 0
        out = capsys.readouterr().out
        assert "2 platforms" in out
        for text in ("4600", "4850", "5800", "6050", "250", "right", "left", "760"):
            assert text in out, out
        assert "packet 69:" not in out

    @pytest.mark.parametrize("nid", ["44", "69"])
    def test_encode(self, capsys, nid):
        assert main(["platforms", "--packet", P69_HEX, "--reference-m", "4500", "--encode", nid]) == 0
        packet = decode_platform_packet(printed_packet(capsys.readouterr().out, nid))
        assert type(packet) is (Packet44Platforms if nid == "44" else Packet69)
        assert platforms_from_packet(packet, 4500) == platforms_from_packet(P69, 4500)

    def test_file(self, capsys, tmp_path):
        path = write(tmp_path, TABLE_TOML)
        assert main(["platforms", str(path), "--encode", "44"]) == 0
        out = capsys.readouterr().out
        assert "2 platforms" in out and "4850" in out and "right" in out
        assert platforms_from_packet(decode_platform_packet(printed_packet(out, "44")), 0) == read_platform_data(path)

    def test_bad_packet(self, capsys):
        bad = set_field(bytes.fromhex(P69_HEX), 8, 2, 3).hex()
        assert main(["platforms", "--packet", bad]) == 2
        one_line_error(capsys, "--packet", "packet 69: Q_DIR at bit 8:", "11b (3) is spare")
        assert main(["platforms", "--packet", P69_HEX[:-2]]) == 2
        one_line_error(capsys, "--packet", "truncated")
        assert main(["platforms", "--packet", "45zz"]) == 2
        one_line_error(capsys, "hex string at bit 8", "'z' is not a hex digit")

    def test_bad_file(self, capsys, tmp_path):
        path = write(tmp_path, "[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'top'\n")
        assert main(["platforms", str(path)]) == 2
        one_line_error(capsys, str(path), "side = 'top'")
        assert main(["platforms", str(tmp_path / "missing.toml")]) == 2
        one_line_error(capsys, "missing.toml", "cannot read")

    def test_bad_reference(self, capsys):
        assert main(["platforms", "--packet", P69_HEX, "--reference-m", "east"]) == 2
        one_line_error(capsys, "--reference-m", "'east' is not a number")

    def test_encode_needs_heights(self, capsys, tmp_path):
        path = write(tmp_path, "[[platforms.table]]\nstart_m = 1\nlength_m = 2\nside = 'left'\n")
        assert main(["platforms", str(path), "--encode", "69"]) == 2
        one_line_error(capsys, "--encode 69", "height_mm = None")

    def test_reverse_packet(self, capsys):
        assert main(["platforms", "--packet", encode_packet69(Packet69(0, 1, (E1,))).hex()]) == 0
        out = capsys.readouterr().out
        assert "Q_DIR is 0 (reverse)" in out and "0 platforms" in out

    @pytest.mark.parametrize("argv", [["platforms"], ["platforms", "x.toml", "--packet", P69_HEX]])
    def test_file_xor_packet(self, capsys, argv):
        assert main(argv) == 2
        one_line_error(capsys, "give either FILE.toml or --packet HEX")


# --- the bits, proved (PKT-01 to PKT-12) ----------------------------------------------------------------------------

_P69, _P44 = platform_packets.packet69_bits, platform_packets.packet44_bits
# property -> (function, text in it, faulty replacement)
CODEC_MUTANTS = {
    # Q_DIR and Q_SCALE written in each other's place
    "packet69_codec.header_read_as_written": (_P69, "f.q_dir, length, f.q_scale", "f.q_scale, length, f.q_dir"),
    # an element slot after the last sent: the packet's tail is not padding
    "packet69_codec.length_as_sent": (_P69, "o.const(k) <= f.n_iter", "o.const(k) <= f.n_iter + o.const(1)"),
    # the last element not sent
    "packet69_codec.distances_read_as_written": (_P69, "o.const(k) <= f.n_iter", "o.const(k) < f.n_iter"),
    # the first element's length, height and side dropped with Q_TRACKINIT 0
    "packet69_codec.lengths_read_as_written": (_P69, "*_slot(o, f, 0, listed)[1:]", "*_slot(o, f, 0, init)[1:]"),
    "packet69_codec.heights_read_as_written": (_P69, "*_slot(o, f, 0, listed)[1:]", "*_slot(o, f, 0, init)[1:]"),
    # the side written from the height's column
    "packet69_codec.sides_read_as_written": (
        platform_packets._slot,
        "f.m_platform, f.q_platform)",
        "f.m_platform, f.m_platform)",
    ),
    # NID_XUSER and NID_XDATA swapped
    "packet44_codec.header_read_as_written": (
        _P44,
        "o.const(NID_XUSER_PLATFORMS),\n        o.const(NID_XDATA_PLATFORMS),",
        "o.const(NID_XDATA_PLATFORMS),\n        o.const(NID_XUSER_PLATFORMS),",
    ),
    # L_PACKET without the header's user ids
    "packet44_codec.length_as_sent": (_P44, "o.const(P44_BITS) + o.const", "o.const(P44_BITS - 17) + o.const"),
    # an element sent only from the second on
    "packet44_codec.distances_read_as_written": (_P44, "o.const(k) < f.n_iter", "o.const(k) < f.n_iter - o.const(1)"),
    # the length written from the distance's column
    "packet44_codec.lengths_read_as_written": (
        platform_packets._slot,
        "(f.d_trackcond, f.l_trackcond,",
        "(f.d_trackcond, f.d_trackcond,",
    ),
    # the height written from the side's column
    "packet44_codec.heights_read_as_written": (
        platform_packets._slot,
        "f.l_trackcond, f.m_platform,",
        "f.l_trackcond, f.q_platform,",
    ),
    "packet44_codec.sides_read_as_written": (
        platform_packets._slot,
        "f.m_platform, f.q_platform)",
        "f.m_platform, f.m_platform)",
    ),
}


def _capacity(layout) -> int:
    return sum(field.width for field in layout)


@settings(max_examples=100)
@given(packets)
def test_the_bytes_are_the_codec_nodes_bits(packet):
    """The bytes are the first L_PACKET bits of packet69_bits / packet44_bits, the rest of which are zeros, and the
    decoder's fields are packet_from_bits of them: the functions PKT-01 to PKT-12 are about."""
    data = encode_platform_packet(packet)
    layout = P44_LAYOUT if isinstance(packet, Packet44Platforms) else P69_LAYOUT
    capacity, length = _capacity(layout), expected_bits(packet)
    bits = BitString(int.from_bytes(data, "big") << (capacity - 8 * len(data)), capacity)
    read = [int(v) for v in platform_packets.packet_from_bits(EXACT, layout, bits)]
    if isinstance(packet, Packet44Platforms):
        fields = platform_packets.Packet44Fields(
            *map(Fraction, (packet.q_dir, packet.q_scale, len(packet.elements))),
            *platform_packets._slots(packet.elements, 31),
        )
        written = _P44(EXACT, fields)
    else:
        init = packet.q_trackinit
        fields = platform_packets.Packet69Fields(
            *map(
                Fraction,
                (packet.q_dir, packet.q_scale, init, packet.d_trackinit or 0, max(len(packet.elements) - 1, 0)),
            ),
            *platform_packets._slots(packet.elements, 32),
        )
        written = _P69(EXACT, fields)
    assert written == bits and written.value >> (capacity - length) << (capacity - length) == written.value
    assert read[2] == length


# --- the platforms a packet describes, proved (PLT-01 to PLT-04) ----------------------------------------------------

_TABLE = platform_table_module.packet_platform_table
PLATFORM_MUTANTS = {
    # every distance counted from the balise group, not from the previous platform's start
    "packet_platforms.in_order_from_reference": (
        _TABLE,
        "start = start + d * scale_m",
        "start = i.reference_m + d * scale_m",
    ),
    # the left side read from the right side's code
    "packet_platforms.sides_as_coded": (
        _TABLE,
        "left.append(o.and_(present, o.or_(o.eq(side, o.const(0))",
        "left.append(o.and_(present, o.or_(o.eq(side, o.const(1))",
    ),
    # Q_SCALE 00b read as 1 m: every position ten times too far
    "packet_platforms.positions_as_coded": (
        _TABLE,
        "o.eq(i.q_scale, o.const(0)),\n        o.const(Q_SCALE_M[0]),",
        "o.eq(i.q_scale, o.const(0)),\n        o.const(Q_SCALE_M[1]),",
    ),
    # the train's direction ignored: a packet for the nominal direction read by a train running reverse
    "packet_platforms.other_direction_empty": (
        _TABLE,
        "o.eq(i.q_dir, o.ite(i.reverse, o.const(0), o.const(1)))",
        "o.eq(i.q_dir, o.const(1))",
    ),
}
MUTANTS = {**CODEC_MUTANTS, **PLATFORM_MUTANTS}
PROVED = [
    p
    for name, p in PROPERTIES.items()
    if name.split(".")[0] in ("packet69_codec", "packet44_codec", "packet_platforms")
]
"""PKT-01 to PKT-12 and PLT-01 to PLT-04."""


def test_every_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in PROVED}


@pytest.mark.parametrize("prop", PROVED, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=1)
    assert run.killed, run


@settings(max_examples=100)
@given(packets, st.integers(0, 100_000), st.sampled_from(["nominal", "reverse"]))
def test_platforms_from_packet_are_the_table_nodes(packet, reference_m, direction):
    """platforms_from_packet keeps exactly the slots the proved table marks on a side, at its starts and ends, and
    independently of it each platform starts where the distances add up to."""
    platforms = platforms_from_packet(packet, reference_m, direction=direction)
    applies = packet.q_dir == 2 or packet.q_dir == (0 if direction == "reverse" else 1)
    scale = {0: Fraction(1, 10), 1: Fraction(1), 2: Fraction(10)}[packet.q_scale]
    expected, start = [], Fraction(reference_m)
    for e in packet.elements:
        start += e.d_trackcond * scale
        expected.append((start, start + e.l_trackcond * scale, ("left", "right", "both")[e.q_platform]))
    assert [(p.start_m, p.end_m, p.side) for p in platforms] == (expected if applies else [])
