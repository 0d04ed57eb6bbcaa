"""The sub-functions tested on their own (seed 001 §3.4): the ceiling offset dV, the leader's stopping point and
the tachometer's plausibility check: proved, able to fail, and the same functions the larger nodes run."""

from fractions import Fraction

import pytest

from atcs.model import authority, curves, dynamic_profile, position
from atcs.model.curves import CEILING_OFFSET, CeilingOffsetParams, CeilingOffsetQuery, ceiling_offset_mps
from atcs.model.node import Stateless
from atcs.model.ops.exact import EXACT
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import (
    PROPERTIES,
    adhesion,
    ceiling_offset,
    exceedances,
    gradient_acceleration,
    most_restrictive,
    stopping_point,
    tacho_check,
    targets,
)

SUB_FUNCTION_PROPERTIES = [
    p
    for module in (
        ceiling_offset,
        adhesion,
        gradient_acceleration,
        most_restrictive,
        exceedances,
        stopping_point,
        tacho_check,
        targets,
    )
    for p in module.PROPERTIES
]

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    # the interpolation started from the wrong end
    "ceiling_offset.between_its_ends": (
        curves.ceiling_offset_mps,
        "between = dv_min + (dv_max - dv_min)",
        "between = dv_max + (dv_max - dv_min)",
    ),
    # dV_min above V_max too (still between the ends, so CRV-03 holds)
    "ceiling_offset.ends_at_the_stated_speeds": (
        curves.ceiling_offset_mps,
        "o.ite(speed_mps >= v_max, dv_max, between)",
        "o.ite(speed_mps >= v_max, dv_min, between)",
    ),
    # the slope over V_max + V_min (atcs mutate's arith_sign at ceiling_offset_mps:+4)
    "ceiling_offset.linear_between_its_ends": (
        curves.ceiling_offset_mps,
        "o.max(v_max - v_min, o.const(MIN_SPAN))",
        "o.max(v_max + v_min, o.const(MIN_SPAN))",
    ),
    # the wet-rail share added twice (arith_sign at adhesion_factor:+3)
    "adhesion.between_wet_and_dry": (
        curves.adhesion_factor,
        "n.m_nvavadh * (o.const(1) - t.kwet_rst)",
        "n.m_nvavadh * (o.const(1) + t.kwet_rst)",
    ),
    # the rotating mass of the other sign (atcs mutate's cmp_flip at gradient_acceleration_mps2:+3)
    "gradient_acceleration.from_the_seed": (
        curves.gradient_acceleration_mps2,
        "gradient_permille >= o.const(0)",
        "gradient_permille <= o.const(0)",
    ),
    # the farthest target's curve supervised (atcs mutate's minmax at most_restrictive:+4)
    "most_restrictive.nearest_target": (dynamic_profile.most_restrictive, "o.min(", "o.max("),
    # EB already at the EB ceiling (atcs mutate's cmp_strict at exceedances:+8)
    "exceedances.strictly_beyond": (
        dynamic_profile.exceedances,
        "speed_mps > ceiling.ebi_mps",
        "speed_mps >= ceiling.ebi_mps",
    ),
    # the braking distance subtracted: a stopping point behind the rear
    "stopping_point.ahead_of_rear": (
        authority.stopping_point_m,
        "return rear_m + speed_mps * speed_mps",
        "return rear_m - speed_mps * speed_mps",
    ),
    # v^2 / d instead of v^2 / (2 d): a stop the leader cannot make as early
    "stopping_point.reached_at_max_deceleration": (
        authority.stopping_point_m,
        "(o.const(2) * deceleration)",
        "deceleration",
    ),
    # the tachometer error left out of the slack
    "tacho_check.plausible_within_bounds": (
        position.implausible_increment,
        "slack = p.tacho_error * (tacho_m + last_m)",
        "slack = o.const(0)",
    ),
    # a decrease at the max safe front supervised too (and one at the EoA)... the strict bound dropped
    "targets.every_decrease_ahead": (
        dynamic_profile.decrease_targets,
        "o.and_(v < before, max_safe_front_m < start, start < eoa_m)",
        "o.and_(v <= before, max_safe_front_m < start, start < eoa_m)",
    ),
    # the foot at the SBI's offset: the EBD ends below the EBI ceiling past the decrease
    "targets.foot_at_the_ebi_ceiling": (
        dynamic_profile.ebd_foot_mps,
        "n.dv_ebi_min_mps, n.dv_ebi_max_mps, n.v_ebi_min_mps, n.v_ebi_max_mps",
        "n.dv_sbi_min_mps, n.dv_sbi_max_mps, n.v_sbi_min_mps, n.v_sbi_max_mps",
    ),
    # a limit of authority's EBD ending at its speed, not at its EBI ceiling
    "targets.eoa_target": (
        dynamic_profile.eoa_target,
        "ebd_foot_mps(o, n, eoa_speed_mps), eoa_speed_mps)",
        "eoa_speed_mps, eoa_speed_mps)",
    ),
    # a negative distance not checked
    "tacho_check.negative_is_implausible": (position.implausible_increment, "tacho_m < o.const(0),", ""),
}


def test_every_sub_function_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in SUB_FUNCTION_PROPERTIES}


@pytest.mark.parametrize("prop", SUB_FUNCTION_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=1)
    assert run.killed, run


def test_the_node_runs_the_function_the_curves_use():
    """Subset-026's default dV_ebi: 7.5 km/h up to 110 km/h, 15 km/h from 210 km/h, linear in between."""
    kmh = Fraction(10, 36)
    p = CeilingOffsetParams(Fraction(15, 2) * kmh, 15 * kmh, 110 * kmh, 210 * kmh)
    for speed_kmh, dv_kmh in ((0, Fraction(15, 2)), (110, Fraction(15, 2)), (160, Fraction(45, 4)), (300, 15)):
        _, out = CEILING_OFFSET.step(EXACT, p, Stateless(), CeilingOffsetQuery(speed_kmh * kmh))
        assert out.offset_mps == dv_kmh * kmh == ceiling_offset_mps(EXACT, speed_kmh * kmh, *vars(p).values())
