"""The speed decreases of a line's MRSP as targets of the closed loop (docs/configuration.md "Speed decreases"):
one window per decrease, laid out as the ends of authority's; its theorems proved on a coarse cycle and falsified by
a mutant whose counterexample replays; the windows' side condition (CL-10) proved and falsified the same way."""

import dataclasses
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model import closed_loop, plant
from atcs.model.configuration import load_configuration
from atcs.model.curves import Target, ebd_speed2_at
from atcs.model.dynamic_profile import ebd_foot_mps
from atcs.model.ops.exact import EXACT
from atcs.model.profile import KMH_PER_MPS, value_at
from atcs.model.train_data import preset_data, whole_cycle_train
from atcs.proofs.cex.trace import reproduce
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import falsify
from atcs.properties.closed_loop import decrease_properties
from atcs.properties.configured import (
    _decrease_reach,
    _loa_reach,
    _loop_params,
    compensated_gradients,
    decrease_windows,
    line_windows,
    loop_family,
    speed_decreases,
)
from tests.properties.test_windows import COARSE_CONFIG as WINDOWS_COARSE_CONFIG

EXAMPLE = Path(__file__).parents[2] / "model" / "configurations" / "example_line.toml"

COARSE_CONFIG = WINDOWS_COARSE_CONFIG.replace(
    "speed_limits = [{ start_m = 0, kmh = 80 }]",
    "speed_limits = [{ start_m = 0, kmh = 80 }, { start_m = 4000, kmh = 30 }, { start_m = 4500, kmh = 60 }]",
)
"""The coarse cycle of tests/properties/test_windows.py with a decrease to 30 km/h at 4,000 m."""


@pytest.fixture(scope="module")
def example():
    config = load_configuration(EXAMPLE)
    t, line = config.trains[0], config.lines[0]
    loop_data = preset_data(whole_cycle_train(t.train, config.cycle_s), t.national, config.cycle_s)
    del loop_data["gradient_permille"]
    profile = compensated_gradients(line, t.train.train_length_m)
    return config, t, line, loop_data, profile, decrease_windows(profile, loop_data, line, t.national)


@pytest.fixture(scope="module")
def coarse(tmp_path_factory):
    path = tmp_path_factory.mktemp("coarse") / "coarse.toml"
    path.write_text(COARSE_CONFIG, encoding="utf-8")
    config = load_configuration(path)
    family = loop_family(config, config.trains[0], config.lines[0])
    return {p.name.removesuffix("_seed000_design_d0"): p for p in family if p.name.endswith("_d0")}


@pytest.fixture(scope="module")
def coarse_family(tmp_path_factory):
    path = tmp_path_factory.mktemp("coarse_family") / "coarse.toml"
    path.write_text(COARSE_CONFIG, encoding="utf-8")
    config = load_configuration(path)
    return {p.name: p for p in loop_family(config, config.trains[0], config.lines[0])}


def test_every_decrease_of_the_speed_limits_and_only_those_gets_a_window(example):
    _, _, line, *_, windows = example
    limits = line.speed_limits
    drops = [(s, v) for s, u, v in zip(limits.starts_m[1:], limits.values, limits.values[1:], strict=False) if v < u]
    assert speed_decreases(line) == tuple(drops) and len(drops) == 10
    assert [(w.location_m, w.speed_after_mps) for w in windows] == drops


def test_a_decrease_windows_profile_is_the_lines_up_to_it_and_its_start_is_where_the_ebd_passes_the_cap(example):
    _config, t, line, loop_data, profile, windows = example
    steepest = min(profile.values)
    for w in windows:
        for x in range(0, int(profile.end_m), 50):
            inside = w.start_m <= x < w.location_m
            expected = value_at(EXACT, profile, Fraction(x)) if inside else steepest
            assert value_at(EXACT, w.profile, Fraction(x)) == expected, (w.index, x)
        p = _loop_params(loop_data, line, profile, w.location_m)
        target = Target(w.location_m, w.speed_after_mps, ebd_foot_mps(EXACT, t.national, w.speed_after_mps))
        assert w.start_m > 0
        assert ebd_speed2_at(EXACT, p, p, profile, target, w.start_m) >= w.speed_cap_mps**2
        for s in (s for s in profile.starts_m if w.start_m < s < w.location_m):
            assert ebd_speed2_at(EXACT, p, p, profile, target, s) < w.speed_cap_mps**2


def test_each_decrease_has_its_theorems_its_reach_obligation_and_its_side_condition(example):
    config, t, line, *_, windows = example
    props = {p.name: p for p in loop_family(config, t, line)}
    for w in windows:
        tag = f"gamma_passenger_p_example_d{w.index}"
        kinds = ("decrease_invariant", "under_decrease", "decrease_reach", "braking_order")
        assert [props[f"closed_loop.{kind}_{tag}"].requirement for kind in kinds] == [
            "CL-08",
            "CL-09",
            "CL-07",
            "CL-10",
        ]
        fixed = props[f"closed_loop.under_decrease_{tag}"].fixed_params
        assert (fixed["decrease_m"], fixed["mrsp_after_mps"]) == (w.location_m, w.speed_after_mps)
        assert fixed["mrsp_mps"] == max(line.speed_limits.values)


def test_the_decrease_is_to_the_lower_limit_with_the_top_limit_before_it(coarse):
    fixed = coarse["closed_loop.under_decrease"].fixed_params
    assert fixed["decrease_m"] == 4000
    assert fixed["mrsp_after_mps"] * KMH_PER_MPS == 30 and fixed["mrsp_mps"] * KMH_PER_MPS == 80


@pytest.mark.parametrize("kind", ["decrease_invariant", "under_decrease", "decrease_reach", "braking_order"])
def test_a_decreases_properties_are_proved(coarse, kind):
    lemmas = {p.name: p for p in coarse.values()}
    result = prove(coarse[f"closed_loop.{kind}"], timeout_s=300, lemmas=lemmas)
    assert (result.status, result.engine) == ("proved", "k-induction"), result.message


DECREASE_MUTANTS = [
    # the ceiling kept at the higher MRSP past the decrease
    (closed_loop.decrease_atp_cycle, "o.ite(ahead, p.mrsp_mps, p.mrsp_after_mps)", "p.mrsp_mps"),
    # the decrease's EBD ending at the higher MRSP's EBI ceiling
    (closed_loop.decrease_atp_cycle, "ebd_foot_mps(o, p, p.mrsp_after_mps))", "ebd_foot_mps(o, p, p.mrsp_mps))"),
]


@pytest.fixture(scope="module")
def to_standstill(coarse):
    """The coarse decrease's theorems for a decrease to 0 km/h at 500 m: a mutant's counterexample is a few cycles
    of traction from standstill (to 30 km/h it would take too many for BMC)."""
    window = coarse["closed_loop.under_decrease"]
    fixed = {**window.fixed_params, "decrease_m": Fraction(500), "mrsp_after_mps": 0}
    return {
        p.name.removesuffix("_to_standstill"): dataclasses.replace(p, node=window.node)
        for p in decrease_properties("to_standstill", fixed)
    }


@pytest.mark.parametrize("kind", ["decrease_invariant", "under_decrease"])
@pytest.mark.parametrize("mutant", DECREASE_MUTANTS, ids=["ceiling_kept", "foot_high"])
def test_a_decreases_theorems_are_falsified_by_a_mutant_and_the_counterexample_replays(to_standstill, kind, mutant):
    prop = to_standstill[f"closed_loop.{kind}"]
    assert prove(prop, timeout_s=300, lemmas={p.name: p for p in to_standstill.values()}).status == "proved"
    run = falsify(prop, *mutant, timeout_s=300, max_k=8)
    assert run.killed, run


def test_the_side_condition_is_falsified_when_a_braked_cycle_may_run_farther_than_a_free_one(coarse):
    # a braked cycle allowed twice the distance at the cycle's start speed: more than traction gives
    run = falsify(
        coarse["closed_loop.braking_order"], plant.plant_admits, "distance_m <= v * dt,", "distance_m <= v * dt * 2,"
    )
    assert run.killed, run


# --- a limit of authority (an end of authority with a target speed above 0) anywhere in a window -----------------


def test_each_window_has_the_limit_of_authority_theorems(coarse_family):
    windows = {n.rsplit("_w", 1)[1] for n in coarse_family if n.startswith("closed_loop.no_overrun_")}
    for k in windows:
        tag = f"seed000_design_w{k}"
        assert coarse_family[f"closed_loop.loa_invariant_{tag}"].requirement == "CL-08"
        under = coarse_family[f"closed_loop.under_loa_{tag}"]
        assert under.requirement == "CL-09" and "decrease_m" not in under.fixed_params
        assert "mrsp_after_mps" not in under.fixed_params and under.fixed_params["mrsp_mps"] * KMH_PER_MPS == 80
        reach = f"closed_loop.window_reach_{tag}" in coarse_family
        assert (f"closed_loop.loa_reach_{tag}" in coarse_family) == reach


@pytest.mark.parametrize("kind", ["loa_invariant", "under_loa", "loa_reach"])
def test_the_limit_of_authority_theorems_are_proved(coarse_family, kind):
    (name,) = [n for n in coarse_family if n.startswith(f"closed_loop.{kind}_") and n.endswith("_w5")]
    result = prove(coarse_family[name], timeout_s=300, lemmas=coarse_family)
    assert (result.status, result.engine) == ("proved", "k-induction"), result.message


def test_the_limit_of_authority_theorem_is_falsified_with_the_ceiling_kept_high(coarse_family):
    run = falsify(coarse_family["closed_loop.under_loa_seed000_design_w0"], *DECREASE_MUTANTS[0], max_k=8)
    assert run.killed, run


def test_the_limit_of_authoritys_reach_is_proved_and_fails_one_breakpoint_later(example):
    _, _, line, loop_data, profile, _ = example
    w = next(w for w in line_windows(profile, loop_data, line) if w.start_m > 0 and w.index == 9)
    top = max(line.speed_limits.values)
    assert prove(_loa_reach("closed_loop.loa_reach_test", w, loop_data, profile, top), timeout_s=300).status == "proved"
    later = profile.starts_m[profile.starts_m.index(w.start_m) + 1]
    mutant = _loa_reach("closed_loop.loa_reach_test", dataclasses.replace(w, start_m=later), loop_data, profile, top)
    result = prove(mutant, timeout_s=300)
    assert result.status == "falsified", result.message
    assert reproduce(mutant, result.trace).first_violation == result.k


def test_a_decreases_reach_is_proved_and_fails_one_breakpoint_later(example):
    _, t, line, loop_data, profile, windows = example
    w = windows[0]
    top = max(line.speed_limits.values)
    foot = ebd_foot_mps(EXACT, t.national, w.speed_after_mps)
    prop = _decrease_reach("closed_loop.decrease_reach_test", w, foot, loop_data, profile, top)
    assert prove(prop, timeout_s=300).status == "proved"
    later = profile.starts_m[profile.starts_m.index(w.start_m) + 1]
    moved = dataclasses.replace(w, start_m=later)
    mutant = _decrease_reach("closed_loop.decrease_reach_test", moved, foot, loop_data, profile, top)
    result = prove(mutant, timeout_s=300)
    assert result.status == "falsified", result.message
    assert reproduce(mutant, result.trace).first_violation == result.k
