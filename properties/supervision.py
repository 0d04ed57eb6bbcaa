"""Properties of speed supervision and the EB latch (seed 000 §2.4.3, seed 002 §3.2).

All are proved for both values of the ``service_brake_fitted`` train parameter
(it is symbolic in the proof) and for every value of the supervision limits that
respects their order.
"""

from __future__ import annotations

from atcs.model.supervision import SUPERVISION
from atcs.properties.property import Assumption, Property

CURVE_ORDER = Assumption(
    name="curve_order",
    text="0 <= permitted <= warning <= SBI <= EBI at the current position",
    holds=lambda o, p, s, i: o.and_(
        o.const(0) <= i.permitted_mps,
        i.permitted_mps <= i.warning_mps,
        i.warning_mps <= i.sbi_mps,
        i.sbi_mps <= i.ebi_mps,
    ),
)

SPEED_NON_NEGATIVE = Assumption(
    name="speed_non_negative",
    text="the measured speed is never negative",
    holds=lambda o, p, s, i: i.speed_mps >= o.const(0),
)


def _braking(o, out):
    return o.or_(out.service_brake, out.emergency_brake)


PROPERTIES = (
    Property(
        name="supervision.eb_above_ebi",
        requirement="SUP-01",
        seed="000 §2.4.2, §2.4.3",
        text="EB is commanded in every cycle in which the measured speed is above EBI.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(i.speed_mps > i.ebi_mps, out.emergency_brake),
    ),
    Property(
        name="supervision.eb_latched_until_standstill",
        requirement="SUP-02",
        seed="000 §2.4.3 (Fig. 11)",
        text="Once commanded, EB is held in every later cycle until standstill and the release input.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(
            o.and_(s.eb_latched, o.not_(o.and_(i.standstill, i.eb_release))),
            out.emergency_brake,
        ),
    ),
    Property(
        name="supervision.brake_above_sbi",
        requirement="SUP-03",
        seed="002 §3.2",
        text="A brake (service, or EB if no service brake is fitted) is commanded whenever the speed is above SBI.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(i.speed_mps > i.sbi_mps, _braking(o, out)),
    ),
    Property(
        name="supervision.sb_held_above_permitted",
        requirement="SUP-04",
        seed="002 §3.2",
        text="A service brake command is not released while the speed is above the permitted speed.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(
            o.and_(s.sb_latched, i.speed_mps > i.permitted_mps),
            out.service_brake,
        ),
    ),
    Property(
        name="supervision.warning_above_warning_limit",
        requirement="SUP-05",
        seed="002 §3.2",
        text="The warning is given in every cycle in which the speed is above the warning limit.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(i.speed_mps > i.warning_mps, out.warning),
    ),
    Property(
        name="supervision.traction_cut_when_braking",
        requirement="SUP-06",
        seed="000 §2.4.3",
        text="Traction is cut off in every cycle in which a brake is commanded.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(_braking(o, out), out.traction_cut),
    ),
    Property(
        name="supervision.no_intervention_below_permitted",
        requirement="SUP-07",
        seed="000 §2.4.2",
        text=(
            "Not over-restrictive: with EB not latched, the position valid and the speed at or under the "
            "permitted speed, "
            "neither brake is commanded and traction is available."
        ),
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(
            o.and_(o.not_(s.eb_latched), i.position_valid, i.speed_mps <= i.permitted_mps),
            o.not_(o.or_(out.service_brake, out.emergency_brake, out.traction_cut)),
        ),
        assumptions=(CURVE_ORDER, SPEED_NON_NEGATIVE),
    ),
    Property(
        name="supervision.sb_only_if_fitted",
        requirement="SUP-08",
        seed="000 §2.4.3",
        text="A train without a service-brake interface is never sent a service brake command.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(o.not_(p.service_brake_fitted), o.not_(nxt.sb_latched)),
    ),
    Property(
        name="supervision.eb_without_position",
        requirement="SUP-09",
        seed="001 §3.2",
        text="EB is commanded in every cycle in which the train does not know its position.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(o.not_(i.position_valid), out.emergency_brake),
    ),
    Property(
        name="supervision.no_spurious_eb",
        requirement="SUP-10",
        seed="000 §2.4.3, 001 §3.2",
        text=(
            "No spurious EB: EB is commanded only above EBI, without a valid position, above SBI on a train without "
            "a service brake, or while latched and not released at standstill."
        ),
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(
            out.emergency_brake,
            o.or_(
                i.speed_mps > i.ebi_mps,
                o.not_(i.position_valid),
                o.and_(i.speed_mps > i.sbi_mps, o.not_(p.service_brake_fitted)),
                o.and_(s.eb_latched, o.not_(o.and_(i.standstill, i.eb_release))),
            ),
        ),
    ),
    Property(
        name="supervision.state_records_commands",
        requirement="SUP-11",
        seed="000 §2.4.3 (Fig. 11)",
        text="The latches record this cycle's commands: next cycle's EB and SB latches are this cycle's EB and SB.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.eq(nxt.eb_latched, out.emergency_brake), o.eq(nxt.sb_latched, out.service_brake)
        ),
    ),
    Property(
        name="supervision.warning_only_above_warning_limit",
        requirement="SUP-12",
        seed="002 §3.2",
        text="No spurious warning: the warning is given only in a cycle in which the speed is above the warning limit.",
        node=SUPERVISION,
        holds=lambda o, p, s, i, out, nxt: o.implies(out.warning, i.speed_mps > i.warning_mps),
    ),
)
