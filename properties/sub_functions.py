"""Properties of the sub-functions tested on their own (seed 001 §3.4: each sub-function model with its own test
cases): the ceiling offset dV, the adhesion factor K, the gradient's share of the safe deceleration, the choice of
the most restrictive target, the limits exceeded, the leader's stopping point and the tachometer's plausibility
check.

Each node runs the very function the larger nodes call (:data:`~atcs.model.curves.CEILING_OFFSET`,
:data:`~atcs.model.curves.ADHESION`, :data:`~atcs.model.curves.GRADIENT_ACCELERATION`,
:data:`~atcs.model.dynamic_profile.MOST_RESTRICTIVE`, :data:`~atcs.model.dynamic_profile.EXCEEDANCES`,
:data:`~atcs.model.authority.STOPPING_POINT`,
:data:`~atcs.model.position.TACHO_CHECK`), with all its data
symbolic, so ``atcs vectors generate`` gives each its own vectors.
"""

from __future__ import annotations

from dataclasses import fields

from atcs.model.authority import STOPPING_POINT
from atcs.model.curves import ADHESION, CEILING_OFFSET, GRADIENT_ACCELERATION, MIN_SPAN, CurveLocations
from atcs.model.dynamic_profile import EXCEEDANCES, MOST_RESTRICTIVE
from atcs.model.position import TACHO_CHECK
from atcs.properties.curves import seed_gradient_acceleration_mps2
from atcs.properties.property import Assumption, Property

NATIONAL_OFFSET = Assumption(
    "national_offset",
    f"0 <= dV_min <= dV_max and 0 <= V_min, V_max - V_min >= {MIN_SPAN} m/s (Subset-026's ranges for dV_ebi, "
    "dV_sbi, dV_warning; the guard in ceiling_offset_mps is for invalid data only)",
    lambda o, p, s, i: o.and_(o.const(0) <= p.dv_min_mps, p.dv_min_mps <= p.dv_max_mps,
                              o.const(0) <= p.v_min_mps, p.v_max_mps - p.v_min_mps >= o.const(MIN_SPAN)),
)

ADHESION_DATA = Assumption(
    "adhesion_data",
    "0 <= Kwet_rst <= 1, 0 <= Kdry_rst <= 1, 0 <= M_NVAVADH <= 1 (Subset-026's ranges)",
    lambda o, p, s, i: o.and_(*(o.and_(o.const(0) <= v, v <= o.const(1)) for v in (p.kwet_rst, p.kdry_rst,
                                                                                    p.m_nvavadh))),
)


def _between_wet_and_dry(o, p, s, i, out, nxt):
    wet, dry = p.kdry_rst * p.kwet_rst, p.kdry_rst
    return o.and_(wet <= out.k, out.k <= dry,
                  o.implies(o.eq(p.m_nvavadh, o.const(0)), o.eq(out.k, wet)),
                  o.implies(o.eq(p.m_nvavadh, o.const(1)), o.eq(out.k, dry)))


ROTATING_MASSES = Assumption(
    "rotating_masses",
    "both rotating masses within [0, 100] % (train data)",
    lambda o, p, s, i: o.and_(*(o.and_(o.const(0) <= m, m <= o.const(100))
                                for m in (p.rotating_mass_uphill_percent, p.rotating_mass_downhill_percent))),
)


def _gradient_from_the_seed(o, p, s, i, out, nxt):
    """A_gradient = g * gradient / (1000 + 10 * M_rotating), the uphill mass on a rising gradient and the downhill
    one on a falling gradient (0 on level track, with either)."""
    return o.eq(out.a_gradient_mps2, seed_gradient_acceleration_mps2(o, p, i.gradient_permille))


def _nearest_target(o, p, s, i, out, nxt):
    """For each curve: at or behind every target's location, and one of them."""
    def nearest(name):
        locations, chosen = getattr(i, f"target_{name}"), getattr(out, name)
        return o.and_(*(chosen <= x for x in locations), o.or_(*(o.eq(chosen, x) for x in locations)))

    return o.and_(*(nearest(f.name) for f in fields(CurveLocations)))


def _strictly_beyond(o, p, s, i, out, nxt):
    """Over a limit exactly when the max safe front is strictly beyond its curve's location or the measured speed
    strictly above its ceiling (at the limit itself the train is not over it)."""
    def over(name):
        return o.or_(i.max_safe_front_m > getattr(i, f"{name}_location_m"),
                     i.measured_speed_mps > getattr(i, f"{name}_ceiling_mps"))

    return o.and_(*(o.eq(getattr(out, f"over_{name}"), over(name)) for name in ("permitted", "warning", "sbi", "ebi")))


LEADER_REPORT = Assumption(
    "leader_report",
    f"the reported speed is >= 0 and the leader's highest deceleration at least {MIN_SPAN} m/s^2 (below any "
    "brake's: the guard in stopping_point_m is for invalid data only)",
    lambda o, p, s, i: o.and_(i.speed_mps >= o.const(0), p.leader_max_deceleration_mps2 >= o.const(MIN_SPAN)),
)


def _sensors(o, p, s, i):
    dt2, e = p.cycle_s * p.cycle_s, p.tacho_error
    change = i.distance_m - i.last_distance_m

    def within(true_m, tacho_m):
        return o.and_(tacho_m >= o.const(0), true_m - tacho_m <= e * tacho_m, tacho_m - true_m <= e * tacho_m)

    return o.and_(
        o.const(0) <= e, e < o.const(1), p.cycle_s > o.const(0),
        within(i.distance_m, i.tacho_m), within(i.last_distance_m, i.last_tacho_m),
        change <= p.max_acceleration_mps2 * dt2, -change <= p.max_deceleration_mps2 * dt2,
    )


SENSORS = Assumption(
    "sensors",
    "0 <= tachometer error < 1, cycle > 0; both cycles' tachometer distances >= 0 and within the error of the "
    "true distances; the true distance changes by at most max_acceleration * dt^2 (max_deceleration * dt^2 down)",
    _sensors,
)


def _offset_between(o, p, s, i, out, nxt):
    return o.and_(p.dv_min_mps <= out.offset_mps, out.offset_mps <= p.dv_max_mps)


def _offset_ends(o, p, s, i, out, nxt):
    return o.and_(o.implies(i.speed_mps <= p.v_min_mps, o.eq(out.offset_mps, p.dv_min_mps)),
                  o.implies(i.speed_mps >= p.v_max_mps, o.eq(out.offset_mps, p.dv_max_mps)))


def _offset_interpolated(o, p, s, i, out, nxt):
    """(dV - dV_min) * (V_max - V_min) = (dV_max - dV_min) * (V - V_min) between the ends: the line through them."""
    between = o.and_(p.v_min_mps < i.speed_mps, i.speed_mps < p.v_max_mps)
    return o.implies(between, o.eq((out.offset_mps - p.dv_min_mps) * (p.v_max_mps - p.v_min_mps),
                                   (p.dv_max_mps - p.dv_min_mps) * (i.speed_mps - p.v_min_mps)))


def _stop_ahead_of_rear(o, p, s, i, out, nxt):
    return o.and_(out.stop_m >= i.rear_m, o.implies(o.eq(i.speed_mps, o.const(0)), o.eq(out.stop_m, i.rear_m)))


def _stop_reachable(o, p, s, i, out, nxt):
    """v^2 = 2 * d * (stop - rear): braking at d from the reported speed ends exactly at the stopping point."""
    two = o.const(2)
    return o.eq(i.speed_mps * i.speed_mps, two * p.leader_max_deceleration_mps2 * (out.stop_m - i.rear_m))


PROPERTIES = (
    Property(
        name="ceiling_offset.between_its_ends",
        requirement="CRV-03",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="The speed-dependent offset dV is never below dV_min nor above dV_max, at any speed.",
        node=CEILING_OFFSET,
        holds=_offset_between,
        assumptions=(NATIONAL_OFFSET,),
    ),
    Property(
        name="ceiling_offset.ends_at_the_stated_speeds",
        requirement="CRV-04",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="dV is dV_min at or below V_min and dV_max at or above V_max.",
        node=CEILING_OFFSET,
        holds=_offset_ends,
        assumptions=(NATIONAL_OFFSET,),
    ),
    Property(
        name="ceiling_offset.linear_between_its_ends",
        requirement="CRV-05",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="Between V_min and V_max, dV is on the straight line from (V_min, dV_min) to (V_max, dV_max).",
        node=CEILING_OFFSET,
        holds=_offset_interpolated,
        assumptions=(NATIONAL_OFFSET,),
    ),
    Property(
        name="adhesion.between_wet_and_dry",
        requirement="CRV-07",
        seed="000 §2.4.1 (Subset-026 3.13.6.2)",
        text="K is between the wet-rail factor Kdry_rst * Kwet_rst and the dry-rail factor Kdry_rst, and is the "
             "wet one at M_NVAVADH = 0 and the dry one at M_NVAVADH = 1.",
        node=ADHESION,
        holds=_between_wet_and_dry,
        assumptions=(ADHESION_DATA,),
    ),
    Property(
        name="gradient_acceleration.from_the_seed",
        requirement="CRV-09",
        seed="000 §2.3 (equation 2), Subset-026 3.13.4.3",
        text="A_gradient = g * gradient / (1000 + 10 * M_rotating), g = 9.81 m/s^2, with the train's uphill "
             "rotating mass on a rising gradient and its downhill one on a falling gradient (stated from the "
             "seed, not through the model's function); 0 on level track.",
        node=GRADIENT_ACCELERATION,
        holds=_gradient_from_the_seed,
        assumptions=(ROTATING_MASSES,),
    ),
    Property(
        name="most_restrictive.nearest_target",
        requirement="DYN-01",
        seed="000 §2.4, 003 §2.2",
        text="With several targets, each curve is supervised at the nearest of the targets' locations for it: at "
             "or behind every target's, and one of them.",
        node=MOST_RESTRICTIVE,
        holds=_nearest_target,
    ),
    Property(
        name="exceedances.strictly_beyond",
        requirement="DYN-02",
        seed="000 §2.4.3",
        text="Each limit (permitted, warning, SBI, EBI) is exceeded exactly when the max safe front is strictly "
             "beyond its curve's location for the measured speed or the measured speed strictly above its ceiling.",
        node=EXCEEDANCES,
        holds=_strictly_beyond,
    ),
    Property(
        name="stopping_point.ahead_of_rear",
        requirement="AUT-12",
        seed="000 §2.2, 002 §4.2",
        text="The leader's earliest stopping point is never behind its reported rear, and is the rear itself at "
             "standstill.",
        node=STOPPING_POINT,
        holds=_stop_ahead_of_rear,
        assumptions=(LEADER_REPORT,),
    ),
    Property(
        name="stopping_point.reached_at_max_deceleration",
        requirement="AUT-13",
        seed="000 §2.2, 002 §4.2",
        text="Braking at its highest deceleration from the reported speed, the leader's rear stops exactly at the "
             "stopping point (v^2 = 2 * d * (stop - rear)): no earlier stop is possible.",
        node=STOPPING_POINT,
        holds=_stop_reachable,
        assumptions=(LEADER_REPORT,),
    ),
    Property(
        name="tacho_check.plausible_within_bounds",
        requirement="POS-17",
        seed="001 §3.2, 002 §3.1",
        text="No false alarm: tachometer distances within their error of true distances that change within the "
             "acceleration bounds are never found implausible.",
        node=TACHO_CHECK,
        holds=lambda o, p, s, i, out, nxt: o.not_(out.implausible_tacho),
        assumptions=(SENSORS,),
    ),
    Property(
        name="tacho_check.negative_is_implausible",
        requirement="POS-18",
        seed="001 §3.2",
        text="A negative tachometer distance (the train rolling back, or a fault) is always implausible.",
        node=TACHO_CHECK,
        holds=lambda o, p, s, i, out, nxt: o.implies(i.tacho_m < o.const(0), out.implausible_tacho),
    ),
)
