"""``atcs platforms``: decode platform data (packet 69 / user packet 44 hex, or a TOML table) and show it,
optionally encoding it as a packet.

Exit code 0, or 2 for bad platform data.
"""

from __future__ import annotations

from rich.table import Table

from atcs.proofs.cli._common import EXIT_OK, UsageError, reraised


def add_parser(subparsers) -> None:
    t = subparsers.add_parser(
        "platforms", help="decode platform data (packet 69 / 44 hex, or a TOML table) and show it"
    )
    t.add_argument("file", nargs="?", metavar="FILE.toml", help="a file with a [platforms] section")
    t.add_argument("--packet", metavar="HEX", help="a packet 69 or user packet 44, as hex")
    t.add_argument(
        "--reference-m", metavar="M", default="0", help="where the packet's balise group was read (m, default 0)"
    )
    t.add_argument(
        "--encode",
        choices=("69", "44"),
        default=None,
        help="also print the platforms as a packet of this kind (hex, Q_SCALE 1 m)",
    )
    t.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.model.bits import PacketError, hex_bytes
    from atcs.model.platform_packets import Q_DIR, decode_platform_packet, encode_platform_packet
    from atcs.model.platforms import PlatformDataError, packet_for_platforms, platforms_from_packet, read_platform_data
    from atcs.model.profile import parse_number

    if (args.file is None) == (args.packet is None):
        raise UsageError("platforms: give either FILE.toml or --packet HEX")
    reference_m = parse_number("--reference-m", "metres", args.reference_m, PlatformDataError)
    if args.file is not None:
        platforms = read_platform_data(args.file)
    else:
        with reraised("platforms: --packet: ", PacketError):
            packet = decode_platform_packet(hex_bytes(args.packet))
            platforms = platforms_from_packet(packet, reference_m)
        if packet.elements and not platforms:
            out.print(
                f"the packet's Q_DIR is {packet.q_dir} ({Q_DIR[packet.q_dir]}): no platforms for a train "
                "running in the nominal direction"
            )
    table = Table(title=f"{len(platforms)} platforms")
    for column in ("start (m)", "end (m)", "length (m)", "side", "height (mm)"):
        table.add_column(column, justify="left" if column == "side" else "right")
    for p in platforms:
        table.add_row(
            str(p.start_m),
            str(p.end_m),
            str(p.end_m - p.start_m),
            p.side,
            "" if p.height_mm is None else str(p.height_mm),
        )
    out.print(table)
    if args.encode:
        with reraised(f"platforms: --encode {args.encode}: ", ValueError, PacketError):
            packet = packet_for_platforms(platforms, reference_m, nid_packet=int(args.encode))
            out.print(f"packet {args.encode}: {encode_platform_packet(packet).hex()}")
    return EXIT_OK
