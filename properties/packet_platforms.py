"""The platforms a packet describes (seed 004 §2.2-2.3, Tables 1-2): the door node's platform table from a packet
69's or 44's element codes.

Over :data:`~atcs.model.platforms.PACKET_PLATFORMS`, every code symbolic, 32 elements (packet 69's most), any
reference location, either direction of travel: the function ``platforms_from_packet`` runs. Which element codes
are spare is the byte codec's check before the table is made (a spare Q_PLATFORM gives no platform here).
"""

from __future__ import annotations

from atcs.model.platform_packets import Q_SCALE_M
from atcs.model.platforms import PACKET_PLATFORMS
from atcs.properties.property import Assumption, Property

DISTANCES = Assumption(
    "distances",
    "every element's D_TRACKCOND and L_TRACKCOND >= 0 (as their unsigned bits give)",
    lambda o, p, s, i: o.and_(*(v >= o.const(0) for v in (*i.d_trackcond, *i.l_trackcond))),
)


def _present(o, out, k: int):
    return o.or_(out.platform_left[k], out.platform_right[k])


def _in_order(o, p, s, i, out, nxt):
    starts, ends = out.platform_start_m, out.platform_end_m
    return o.and_(
        *(
            o.implies(
                _present(o, out, k),
                o.and_(
                    i.reference_m <= starts[k],
                    starts[k] <= ends[k],
                    *((starts[k - 1] <= starts[k],) if k else ()),
                ),
            )
            for k in range(len(starts))
        )
    )


def _sides(o, p, s, i, out, nxt):
    def code(k: int, value: int):
        return o.eq(i.q_platform[k], o.const(value))

    for_this = o.or_(o.eq(i.q_dir, o.const(2)), o.eq(i.q_dir, o.ite(i.reverse, o.const(0), o.const(1))))
    return o.and_(
        *(
            o.implies(
                o.and_(o.const(k) < i.elements, for_this),
                o.and_(
                    o.eq(out.platform_left[k], o.or_(code(k, 0), code(k, 2))),
                    o.eq(out.platform_right[k], o.or_(code(k, 1), code(k, 2))),
                ),
            )
            for k in range(len(i.q_platform))
        ),
        *(o.implies(o.not_(o.const(k) < i.elements), o.not_(_present(o, out, k))) for k in range(len(i.q_platform))),
    )


def _positions(o, p, s, i, out, nxt):
    unit_m = {code: o.const(metres) for code, metres in Q_SCALE_M.items()}
    claims = []
    for code, metres in unit_m.items():
        distance_m = o.const(0)
        for k in range(len(i.d_trackcond)):
            distance_m = distance_m + i.d_trackcond[k] * metres
            at = o.and_(o.eq(i.q_scale, o.const(code)), _present(o, out, k))
            claims.append(
                o.implies(
                    at,
                    o.and_(
                        o.eq(out.platform_start_m[k], i.reference_m + distance_m),
                        o.eq(out.platform_end_m[k], i.reference_m + distance_m + i.l_trackcond[k] * metres),
                    ),
                )
            )
    return o.and_(*claims)


def _other_direction(o, p, s, i, out, nxt):
    for_other = o.eq(i.q_dir, o.ite(i.reverse, o.const(1), o.const(0)))
    return o.implies(for_other, o.not_(o.or_(*(_present(o, out, k) for k in range(len(out.platform_left))))))


def _property(name: str, requirement: str, text: str, holds, assumptions=()) -> Property:
    return Property(
        name=f"packet_platforms.{name}",
        requirement=requirement,
        seed="004 §2.2-2.3 (Tables 1-2)",
        text=text,
        node=PACKET_PLATFORMS,
        holds=holds,
        assumptions=assumptions,
    )


PROPERTIES = (
    _property(
        "in_order_from_reference",
        "PLT-01",
        "Every platform a packet describes starts at or beyond the balise group that sent it, ends at or beyond its "
        "start, and starts at or beyond the previous platform's start, whatever the distances, lengths and Q_SCALE.",
        _in_order,
        (DISTANCES,),
    ),
    _property(
        "sides_as_coded",
        "PLT-02",
        "For a train the packet applies to (Q_DIR both directions, or the train's own), each of the packet's "
        "elements is a platform on the left for Q_PLATFORM 00b, on the right for 01b, on both sides for 10b, and "
        "none for the spare 11b; a slot after the packet's elements is no platform.",
        _sides,
    ),
    _property(
        "positions_as_coded",
        "PLT-03",
        "Each platform a packet describes starts its elements' D_TRACKCOND, added up to its own, after the balise "
        "group and ends its L_TRACKCOND after its start, in the unit Q_SCALE gives (00b 10 cm, 01b 1 m, 10b 10 m).",
        _positions,
    ),
    _property(
        "other_direction_empty",
        "PLT-04",
        "A packet whose Q_DIR is the other direction's (reverse for a train running nominal, nominal for one running "
        "reverse) describes no platform at all.",
        _other_direction,
    ),
)

__all__ = ["DISTANCES", "PROPERTIES"]
