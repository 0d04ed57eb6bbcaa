"""Braking curves (seed 000 §2.4, 002 §3.2): train data validation, the EBD walk against closed forms,
the curve properties proved and each falsified on a mutant whose counterexample replays."""

import dataclasses
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from atcs.model import curves, prepared_curves
from atcs.model.curves import (
    Target,
    adhesion_factor,
    check_braking_capability,
    curve_locations,
    ebd_location_m,
    ebd_speed2_at,
)
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile, gradient_profile
from atcs.model.psl import extend_by_train_length
from atcs.model.train_data import (
    TrainDataError,
    seed000_train,
    seed002_national,
    seed002_train,
    subset026_national,
    validate,
)
from atcs.proofs.cex.trace import replay, reproduce
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import patched
from atcs.properties import PROPERTIES, select
from atcs.properties.curves import PRESETS as CURVE_PRESETS

TRAIN, NATIONAL = seed000_train(), subset026_national()


class TestTrainData:
    def test_presets_are_valid_and_in_si_units(self):
        validate(seed000_train(), subset026_national())
        validate(seed002_train(), seed002_national())
        assert seed000_train().emergency_decelerations_mps2 == (Fraction(10, 9),)  # 4.0 km/h/s
        assert seed002_train().service_decelerations_mps2 == (Fraction(35, 36),)  # 3.5 km/h/s

    @pytest.mark.parametrize(
        ("train_changes", "national_changes", "message"),
        [
            (
                {"emergency_decelerations_mps2": (Fraction(-1),)},
                {},
                "emergency_decelerations_mps2[0] = Fraction(-1, 1) is outside (0, 5] m/s^2",
            ),
            ({"t_be_s": Fraction(121)}, {}, "t_be_s = Fraction(121, 1) is outside [0, 120] s"),
            ({"t_traction_s": Fraction(-1)}, {}, "t_traction_s = Fraction(-1, 1) is outside [0, 120] s"),
            ({"kdry_rst": Fraction(0)}, {}, "kdry_rst = Fraction(0, 1) is outside (0, 1]"),
            ({"service_speeds_mps": (Fraction(1),)}, {}, "service_speeds_mps[0] = Fraction(1, 1) is not 0"),
            (
                {"emergency_speeds_mps": (0, 10), "emergency_decelerations_mps2": (1,)},
                {},
                "emergency_speeds_mps = (0, 10) is not one speed per deceleration",
            ),
            ({}, {"t_driver_s": Fraction(1)}, "t_driver_s = Fraction(1, 1) is below t_warning_s"),
            ({}, {"m_nvavadh": Fraction(2)}, "m_nvavadh = Fraction(2, 1) is outside [0, 1]"),
        ],
    )
    def test_bad_data_named(self, train_changes, national_changes, message):
        with pytest.raises(TrainDataError) as caught:
            validate(dataclasses.replace(TRAIN, **train_changes), dataclasses.replace(NATIONAL, **national_changes))
        assert message in str(caught.value)

    def test_a_train_that_cannot_stop_on_the_gradient_is_refused(self):
        weak = dataclasses.replace(TRAIN, emergency_decelerations_mps2=(Fraction(1, 5),))
        steep = gradient_profile("gradient", [0, 100], [0, -40], 500)
        with pytest.raises(TrainDataError, match=r"gradient_permille\[1\] = -40: the train cannot stop"):
            check_braking_capability(weak, NATIONAL, steep)
        check_braking_capability(TRAIN, NATIONAL, steep)

    def test_a_service_brake_that_cannot_stop_on_the_gradient_is_refused(self):
        weak = dataclasses.replace(TRAIN, service_decelerations_mps2=(Fraction(1, 5),))
        steep = gradient_profile("gradient", [0, 100], [0, -40], 500)
        with pytest.raises(
            TrainDataError,
            match=r"service_decelerations_mps2\[0\] = .* gives A_expected = -0.185 m/s\^2 on gradient_permille\[1\]",
        ):
            check_braking_capability(weak, NATIONAL, steep)


speeds = st.integers(1, 40).map(Fraction)  # m/s


@given(speed=speeds, target_m=st.integers(0, 5000))
def test_ebd_on_level_track_is_the_closed_form(speed, target_m):
    """Level track, one brake step: the EBD reaches v at v^2 / (2 K A) before the target."""
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(5000))
    target = Target(Fraction(target_m), Fraction(0), Fraction(0))
    a = adhesion_factor(EXACT, TRAIN, NATIONAL) * TRAIN.emergency_decelerations_mps2[0]
    assert ebd_location_m(EXACT, TRAIN, NATIONAL, level, target, speed) == target_m - speed * speed / (2 * a)


@given(speed=speeds, cut=st.integers(1, 4999), grads=st.tuples(st.integers(-40, 40), st.integers(-40, 40)))
def test_ebd_speed_and_location_are_inverse(speed, cut, grads):
    gradient = Profile((Fraction(0), Fraction(cut)), tuple(map(Fraction, grads)), Fraction(5000))
    target = Target(Fraction(5000), Fraction(0), Fraction(1))
    location = ebd_location_m(EXACT, TRAIN, NATIONAL, gradient, target, speed)
    if speed > 1:
        assert ebd_speed2_at(EXACT, TRAIN, NATIONAL, gradient, target, location) == speed * speed


def test_behind_the_line_the_ebd_uses_the_gradient_in_force_at_its_start():
    """The compensated profile starts with zero-length segments; the first one's value is what the walk extends
    behind the start: the level of the line's start, not its highest gradient (+20 here, as the merge alone
    gives); so the EBD at 80 km/h, reaching behind the start, is the level line's."""
    line = gradient_profile("gradient", [0, 1000], [0, 20], 3000)
    compensated = extend_by_train_length(EXACT, line, TRAIN.train_length_m)
    assert compensated.starts_m[:2] == (0, 0) and compensated.values[0] == 0
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(3000))
    target, v = Target(Fraction(300), Fraction(0), Fraction(0)), Fraction(80) / Fraction(36, 10)
    expected = ebd_location_m(EXACT, TRAIN, NATIONAL, level, target, v)
    assert expected < 0  # the EBD at 80 km/h starts behind the line
    assert ebd_location_m(EXACT, TRAIN, NATIONAL, compensated, target, v) == expected
    assert ebd_speed2_at(EXACT, TRAIN, NATIONAL, compensated, target, expected) == v * v


GUIDANCE = curves.GuidanceData(
    normal_service_speeds_mps=(Fraction(0), Fraction(20)),
    normal_service_decelerations_mps2=(Fraction(3, 5), Fraction(1, 2)),
    kn_plus_mps2=(Fraction(3), Fraction(2)),
    kn_minus_mps2=(Fraction(5), Fraction(4)),
)


@given(speed=speeds, target_m=st.integers(0, 5000))
def test_gui_on_level_track_is_the_closed_form(speed, target_m):
    """Level track: no Kn correction; 0.6 m/s^2 up to 20 m/s, 0.5 above."""
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(5000))
    low = min(speed, 20)
    braking_m = low * low / (2 * Fraction(3, 5)) + (speed * speed - low * low) / (2 * Fraction(1, 2))
    assert curves.gui_location_m(EXACT, TRAIN, GUIDANCE, level, Fraction(target_m), speed) == target_m - braking_m


@pytest.mark.parametrize(("gradient", "kn"), [(20, Fraction(3)), (-20, Fraction(5)), (Fraction(1, 20), Fraction(3))])
def test_gui_takes_kn_plus_uphill_and_kn_minus_downhill(gradient, kn):
    """Below 20 m/s, A_normal_service = 0.6 + A_gradient - Kn * grad / 1000 (Subset-026 §3.13.6.4.3)."""
    slope = Profile((Fraction(0),), (Fraction(gradient),), Fraction(5000))
    a = Fraction(3, 5) + curves.gradient_acceleration_mps2(EXACT, TRAIN, Fraction(gradient)) - kn * gradient / 1000
    v = Fraction(10)
    assert curves.gui_location_m(EXACT, TRAIN, GUIDANCE, slope, Fraction(3000), v) == 3000 - v * v / (2 * a)


@given(speed=speeds, cut=st.integers(1, 4999), grads=st.tuples(st.integers(-40, 40), st.integers(-40, 40)))
def test_gui_speed_and_location_are_inverse(speed, cut, grads):
    """The forward query (the speed at a location) undoes the inverse one."""
    gradient = Profile((Fraction(0), Fraction(cut)), tuple(map(Fraction, grads)), Fraction(5000))
    location = curves.gui_location_m(EXACT, TRAIN, GUIDANCE, gradient, Fraction(5000), speed)
    brake = curves.normal_service_brake(EXACT, GUIDANCE)
    assert curves.curve_speed2_at(EXACT, TRAIN, brake, gradient, Fraction(5000), 0, location) == speed * speed


def test_the_guidance_curve_moves_the_permitted_speed_only_when_nearer():
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(5000))
    v, eoa = Fraction(25), Fraction(4000)
    sbi1 = curves.sbi1_location_m(EXACT, TRAIN, level, eoa, v) - v * NATIONAL.t_driver_s
    gui = curves.gui_location_m(EXACT, TRAIN, GUIDANCE, level, eoa, v)
    assert gui < sbi1  # the normal service brake is gentler
    assert curves.guided_permitted_location_m(EXACT, TRAIN, NATIONAL, GUIDANCE, level, eoa, v) == gui
    strong = dataclasses.replace(GUIDANCE, normal_service_decelerations_mps2=(Fraction(9), Fraction(9)))
    assert curves.guided_permitted_location_m(EXACT, TRAIN, NATIONAL, strong, level, eoa, v) == sbi1


def test_the_sbd_never_constrains_at_standstill():
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(3000))
    assert curves.sbd_location_m(EXACT, TRAIN, level, Fraction(2000), Fraction(0)) == curves.FAR_M


def test_seed000_curves_at_80_kmh_are_ordered_and_spaced_by_the_times():
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(3000))
    v = Fraction(80) / Fraction(36, 10)
    loc = curve_locations(EXACT, TRAIN, NATIONAL, level, Target(Fraction(2000), Fraction(0), Fraction(0)), v, 0)
    assert loc.indication_m < loc.permitted_m < loc.warning_m < loc.sbi_m < loc.ebi_m < loc.ebd_m < 2000
    assert loc.sbi_m - loc.permitted_m == v * NATIONAL.t_driver_s
    assert loc.ebi_m - loc.sbi_m == v * TRAIN.t_bs_s


# --- proofs, and mutants that must be falsified -------------------------------------------------

CURVE_PROPERTIES = select("curves.*")

MUTANTS = {
    # the indication curve at the permitted curve (atcs mutate's arith_drop in curves_from_ebd_and_ebi)
    "spacing": [(curves.curves_from_ebd_and_ebi, "permitted - speed_mps * n.t_indication_s", "permitted")],
    "order": [(curves.curves_from_ebd_and_ebi, "sbi - speed_mps * n.t_warning_s", "sbi + speed_mps * n.t_warning_s")],
    "ebi_protects_ebd": [
        # EBI without the brake build-up time
        (curves.bec_speed_and_distance, "+ (v_cut + v_d2 / o.const(2)) * t_berem", ""),
        # the speed-measurement error ignored
        (curves.bec_speed_deltas_mps, "o.ite(n.inhibit_speed_inaccuracy, zero, t.v_ura_mps)", "zero"),
    ],
    "ebd_is_braking_curve": [
        # the gradient left out of A_safe (atcs mutate's arith_drop in braking_cells)
        (curves.braking_cells, "a_safe = k * a_brake + a_gradient", "a_safe = k * a_brake"),
        # the rotating masses swapped (cmp_flip at gradient_acceleration_mps2:+3)
        (curves.gradient_acceleration_mps2, "gradient_permille >= o.const(0)", "gradient_permille <= o.const(0)"),
    ],
    "sbd_is_service_braking_curve": [
        # the gradient left out of the walk's deceleration (shared with the EBD)
        (curves.braking_cells, "a_safe = k * a_brake + a_gradient", "a_safe = k * a_brake"),
        # the SBD braking with the emergency brake's steps
        (
            curves.expected_brake,
            "t.service_speeds_mps, t.service_decelerations_mps2",
            "t.emergency_speeds_mps, t.emergency_decelerations_mps2",
        ),
        # SBI1 with the emergency brake's build-up time
        (curves.sbi1_location_m, "speed_mps * t.t_bs_s", "speed_mps * t.t_be_s"),
    ],
    "gui_is_normal_service_curve": [
        # the gradient correction Kn left out of A_normal_service
        (
            curves.braking_cells,
            "a_safe = a_safe - gradient_correction_mps2(o, brake, step, gradient_c.values[j])",
            "a_safe = a_safe",
        ),
        # Kn+ and Kn- swapped (Kn- uphill)
        (
            curves.gradient_correction_mps2,
            "brake.kn_plus_mps2[step], brake.kn_minus_mps2[step]",
            "brake.kn_minus_mps2[step], brake.kn_plus_mps2[step]",
        ),
        # the permitted speed without the guidance curve
        (
            curves.guided_permitted_location_m,
            "gui_location_m(o, t, g, gradient_c, eoa_m, speed_mps)",
            "o.const(FAR_M)",
        ),
    ],
    "prepared_equals_direct": [
        # the table's last step with twice the deceleration: the curve looked up nearer its cell's entry
        (
            prepared_curves.table_location_m,
            "rise2 / (o.const(2) * o.select(table.decel_mps2, cell))",
            "rise2 / o.select(table.decel_mps2, cell)",
        ),
    ],
    "table_ascending": [
        # the walk's end put first among the search keys
        (
            prepared_curves.braking_table,
            "exit_speed2=(*entry_speed2[1:], end_speed2)",
            "exit_speed2=(end_speed2, *entry_speed2[1:])",
        ),
    ],
    "table_order": [
        # the cell's rise added to its entry: the curve recedes as the speed rises within a cell
        (prepared_curves.table_location_m, "inside_m = entry_m - rise2", "inside_m = entry_m + rise2"),
    ],
    "bec_alike_below_train_speed": [
        # the train's term without V_delta1's half: targets between it and the true term taken for alike
        (curves.bec_train_speed_mps, ", speed_mps + v_d0 + v_d1 / o.const(2))", ")"),
        # a metre per second of slack: targets just above the train's speed taken for alike
        (
            curves.bec_train_speed_mps,
            "o.min(speed_mps + v_d0 + v_d1, speed_mps + v_d0 + v_d1 / o.const(2))",
            "speed_mps + o.const(1)",
        ),
    ],
    "ebi_from_brake_build_up": [
        # T_berem = T_be: a longer build-up, safe but not the stated curve (arith_drop at +4), which CRV-02 allows
        (curves.bec_speed_and_distance, "o.max(zero, t.t_be_s - t.t_traction_s)", "o.max(zero, t.t_be_s)"),
        # V_bec from the speed alone, under the target speed too
        (
            curves.bec_speed_and_distance,
            "v_cut = o.max(speed_mps + v_d0 + v_d1, target.speed_mps)",
            "v_cut = speed_mps + v_d0 + v_d1",
        ),
    ],
}

EQUIVALENT_FOR = {
    preset: {
        "o.ite(n.inhibit_speed_inaccuracy, zero, t.v_ura_mps)",  # V_ura 0, and inhibited
        "o.max(zero, t.t_be_s - t.t_traction_s)",  # T_traction 0
        "t.service_speeds_mps, t.service_decelerations_mps2",  # A_brake_service = A_brake_safe
        ", speed_mps + v_d0 + v_d1 / o.const(2))",  # T_traction 0: no V_delta1
    }
    for preset in ("gamma", "lambda")
}
"""Mutants that change nothing for a preset's data, by preset: the ERA frames' trains have no speed
inaccuracy, no traction cut-off time, and a service brake model equal to their safe emergency brake (the Gamma
train's are both 1.0 m/s^2 with correction factors 1, the Lambda train's both the conversion model's at 100 %);
each of their properties keeps another mutant that falsifies it."""


def _kind(prop):
    return next(
        prop.name.removeprefix("curves.").removesuffix(f"_{preset}")
        for preset in CURVE_PRESETS
        if prop.name.endswith(f"_{preset}")
    )


def test_every_curve_property_has_a_mutant():
    assert {_kind(p) for p in CURVE_PROPERTIES} == set(MUTANTS)


@pytest.mark.parametrize("prop", CURVE_PROPERTIES, ids=lambda p: p.name)
def test_proved(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


def _preset(prop) -> str:
    return prop.name.removeprefix(f"curves.{_kind(prop)}_")


def _falsifying(prop) -> list:
    return [m for m in MUTANTS[_kind(prop)] if m[1] not in EQUIVALENT_FOR.get(_preset(prop), ())]


def test_every_curve_property_keeps_a_falsifying_mutant():
    assert all(_falsifying(p) for p in CURVE_PROPERTIES)


@pytest.mark.parametrize(
    ("name", "mutant"),
    [(p.name, m) for p in CURVE_PROPERTIES for m in _falsifying(p)],
    ids=lambda v: v if isinstance(v, str) else v[1][:30],
)
def test_mutant_falsified_and_counterexample_replays(name, mutant):
    prop = PROPERTIES[name]
    function, old, new = mutant
    with patched(function, old, new):
        result = prove(prop, timeout_s=120)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    assert replay(prop, result.trace).first_violation is None


def test_speed_steps_walked_in_order_on_the_stepped_brake():
    """The top of each speed step taken from the wrong step (atcs mutate's arith_drop in braking_cells): the
    one-step presets never leave the last step, the three-step design case does (CRV-08)."""
    prop = PROPERTIES["curves.ebd_is_braking_curve_stepped"]
    old, new = "o.min(speeds[step + 1] * speeds[step + 1]", "o.min(speeds[1] * speeds[step + 1]"
    for name in ("curves.ebd_is_braking_curve_seed000", "curves.ebd_is_braking_curve_seed002"):
        with patched(curves.braking_cells, old, new):
            assert prove(PROPERTIES[name], timeout_s=120).status == "proved"
    with patched(curves.braking_cells, old, new):
        result = prove(prop, timeout_s=120)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    assert replay(prop, result.trace).first_violation is None
