"""Properties of the braking curves (seed 000 §2.4, 002 §3.2; DESIGN.md reference formulas).

Proved over the node :data:`~atcs.model.curves.CURVES` with the target, the query
speed and acceleration, the front, the true speed and the breakpoints of a
2-segment compensated gradient profile symbolic; train and national data fixed
to the seed presets (``fixed_params``), one property per preset, and the gradient
values fixed to a design case, 40 per mille downhill then 40 uphill
(:data:`DESIGN_GRADIENTS_PERMILLE`). With symbolic gradient values the walk
divides by a symbolic deceleration and z3 answers unknown within 120 s.
"""

from __future__ import annotations

from fractions import Fraction

from atcs.model.curves import CURVES, curve_gradient, curve_target, ebd_location_m
from atcs.model.node import as_dict
from atcs.model.profile import is_well_formed
from atcs.model.train_data import seed000_train, seed002_national, seed002_train, subset026_national
from atcs.properties.property import Assumption, Property

MAX_GRADIENT_PERMILLE = 40
"""Gradients covered by the curve proofs: [-40, 40] per mille (steeper than any metro line)."""

MAX_LINE_M = 1_000_000
"""Longest line covered (m)."""

DESIGN_GRADIENTS_PERMILLE = (-40, 40)
"""The compensated gradient values the curve proofs fix: steepest downhill, then steepest uphill."""

_DESIGN_TRACK = {"gradient_permille": tuple(Fraction(g) for g in DESIGN_GRADIENTS_PERMILLE)}
PRESETS = {
    "seed000": {**as_dict(seed000_train()), **as_dict(subset026_national()), **_DESIGN_TRACK},
    "seed002": {**as_dict(seed002_train()), **as_dict(seed002_national()), **_DESIGN_TRACK},
}
"""The fixed parameters of each preset's curve proofs."""


def _track_and_target(o, p, s, i):
    g = curve_gradient(p)
    bound = o.const(MAX_GRADIENT_PERMILLE)
    return o.and_(
        is_well_formed(o, g),
        *(o.and_(-bound <= v, v <= bound) for v in g.values),
        o.const(0) <= p.target_m, p.target_m <= p.line_end_m, p.line_end_m <= o.const(MAX_LINE_M),
        o.const(0) <= p.target_speed_mps, p.target_speed_mps <= p.target_ebd_foot_mps,
    )


TRACK_AND_TARGET = Assumption(
    "track_and_target",
    f"the compensated gradient profile starts at 0 with increasing breakpoints up to the line end (at most "
    f"{MAX_LINE_M} m), gradients within +-{MAX_GRADIENT_PERMILLE} per mille; the target lies on the line, "
    "its speed >= 0 and at most the EBD's foot speed",
    _track_and_target,
)

QUERY = Assumption(
    "query",
    "speed >= 0, estimated acceleration within [-A_max, A_max]",
    lambda o, p, s, i: o.and_(
        i.speed_mps >= o.const(0), -p.max_acceleration_mps2 <= i.a_est_mps2, i.a_est_mps2 <= p.max_acceleration_mps2,
    ),
)


def _ordered(o, p, s, i, out, nxt):
    return o.and_(
        out.indication_m <= out.permitted_m, out.permitted_m <= out.warning_m, out.warning_m <= out.sbi_m,
        out.sbi_m <= out.ebi_m, out.ebi_m <= out.ebd_m,
    )


def _spaced(o, p, s, i, out, nxt):
    v = i.speed_mps
    return o.and_(
        o.eq(out.ebi_m - out.sbi_m, v * p.t_bs_s), o.eq(out.sbi_m - out.warning_m, v * p.t_warning_s),
        o.eq(out.sbi_m - out.permitted_m, v * p.t_driver_s), o.eq(out.permitted_m - out.indication_m,
                                                                    v * p.t_indication_s),
    )


def _ebi_protects_ebd(o, p, s, i, out, nxt):
    """At or behind the EBI, the worst case until the brake is effective stays behind the EBD."""
    zero = o.const(0)
    accuracy = o.ite(p.inhibit_speed_inaccuracy, zero, p.v_ura_mps)
    t_rem = o.max(zero, p.t_be_s - p.t_traction_s)
    a_traction = o.max(zero, i.a_est_mps2)
    a_build_up = o.min(a_traction, o.const("0.4"))
    v_cut = i.true_speed_mps + a_traction * p.t_traction_s  # speed when traction is cut
    v_brake = v_cut + a_build_up * t_rem  # speed when the brake is effective
    distance = ((i.true_speed_mps + v_cut) / o.const(2) * p.t_traction_s + (v_cut + v_brake) / o.const(2) * t_rem)
    measured = o.and_(i.true_speed_mps >= zero, i.true_speed_mps - i.speed_mps <= accuracy,
                      i.speed_mps - i.true_speed_mps <= accuracy)
    ebd = ebd_location_m(o, p, p, curve_gradient(p), curve_target(p), v_brake)
    return o.implies(o.and_(measured, i.front_m <= out.ebi_m), i.front_m + distance <= ebd)


def _properties(preset: str):
    fixed = PRESETS[preset]
    return (
        Property(
            name=f"curves.order_{preset}",
            requirement="CRV-01",
            seed="000 §2.4, 002 §3.2",
            text=(
                f"With the {preset} train and national data and the design gradients, at every speed the curves "
                "are ordered: indication "
                "<= permitted <= warning <= SBI <= EBI <= EBD (locations where each reaches that speed)."
            ),
            node=CURVES,
            holds=_ordered,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.ebi_protects_ebd_{preset}",
            requirement="CRV-02",
            seed="000 §2.4.2",
            text=(
                f"With the {preset} data and the design gradients: a train at or behind the EBI for its measured "
                "speed, whose true speed "
                "is within V_ura and which accelerates at most A_est while traction is cut (at most min(A_est, "
                "0.4) during the rest of the brake build-up), is still behind the EBD for its speed when the "
                "emergency brake becomes effective."
            ),
            node=CURVES,
            holds=_ebi_protects_ebd,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.spacing_{preset}",
            requirement="CRV-06",
            seed="000 §2.4.2, 002 §3.2 (Subset-026 3.13.9.3)",
            text=(
                f"With the {preset} data: SBI is the speed times T_bs before EBI, the warning T_warning and the "
                "permitted speed T_driver before SBI, the indication T_indication before the permitted speed (so "
                "each curve leaves the driver its stated time, not more and not less)."
            ),
            node=CURVES,
            holds=_spaced,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
    )


PROPERTIES = (*_properties("seed000"), *_properties("seed002"))

__all__ = ["PROPERTIES"]
