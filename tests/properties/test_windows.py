"""The closed loop's windows of a line (docs/configuration.md "Windows"): they cover every end of authority on the
line, each window's profile is the line's from its start and the steepest downhill elsewhere, its start is the
last breakpoint the EBD passes the speed cap at, and CL-07 proves it, failing for a start one breakpoint later."""

import dataclasses
import itertools
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.configuration import load_configuration
from atcs.model.curves import Target, ebd_speed2_at
from atcs.model.ops.exact import EXACT
from atcs.model.profile import value_at
from atcs.model.train_data import preset_data, whole_cycle_train
from atcs.proofs.cex.trace import reproduce
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import patched
from atcs.properties.configured import (
    MAX_WINDOW_EOA_M,
    _loop_params,
    _window_reach,
    compensated_gradients,
    line_windows,
    loop_family,
)

EXAMPLE = Path(__file__).parents[2] / "model" / "configurations" / "example_line.toml"


@pytest.fixture(scope="module")
def example():
    config = load_configuration(EXAMPLE)
    t, line = config.trains[0], config.lines[0]
    loop_data = preset_data(whole_cycle_train(t.train, config.cycle_s), t.national, config.cycle_s)
    del loop_data["gradient_permille"]
    profile = compensated_gradients(line, t.train.train_length_m)
    return config, t, line, loop_data, profile, line_windows(profile, loop_data, line)


def test_the_windows_cover_every_end_of_authority_on_the_line(example):
    *_, profile, windows = example
    assert windows[0].eoa_from_m == 0 and windows[-1].eoa_to_m == profile.end_m
    assert all(a.eoa_to_m == b.eoa_from_m for a, b in itertools.pairwise(windows))
    assert all(w.eoa_to_m - w.eoa_from_m <= MAX_WINDOW_EOA_M for w in windows)
    ends = (*profile.starts_m[1:], profile.end_m)
    assert set(profile.starts_m) | set(ends) <= {w.eoa_from_m for w in windows} | {w.eoa_to_m for w in windows}


def test_a_windows_profile_is_the_lines_from_its_start_and_the_steepest_downhill_elsewhere(example):
    *_, profile, windows = example
    steepest = min(profile.values)
    for w in windows:
        for x in range(0, int(profile.end_m), 50):
            inside = w.start_m <= x < w.eoa_to_m
            expected = value_at(EXACT, profile, Fraction(x)) if inside else steepest
            assert value_at(EXACT, w.profile, Fraction(x)) == expected, (w.index, x)


def test_a_windows_start_is_the_last_breakpoint_the_ebd_passes_the_speed_cap_at(example):
    _, _, line, loop_data, profile, windows = example
    for w in windows:
        p = _loop_params(loop_data, line, profile, w.eoa_from_m)
        target = Target(w.eoa_from_m, Fraction(0), Fraction(0))
        later = [s for s in profile.starts_m if w.start_m < s < w.eoa_from_m]
        if w.start_m > 0:
            assert ebd_speed2_at(EXACT, p, p, profile, target, w.start_m) >= w.speed_cap_mps**2
        for s in later:
            assert ebd_speed2_at(EXACT, p, p, profile, target, s) < w.speed_cap_mps**2


def test_each_window_not_from_the_line_start_has_its_reach_obligation(example):
    config, t, line, *_, windows = example
    names = {p.name for p in loop_family(config, t, line)}
    for w in windows:
        assert (f"closed_loop.window_reach_gamma_passenger_p_example_w{w.index}" in names) == (w.start_m > 0)


def test_the_reach_obligation_is_proved_and_fails_one_breakpoint_later(example):
    *_, loop_data, profile, windows = example
    w = next(w for w in windows if w.start_m > 0 and w.index == 9)
    top = max(example[2].speed_limits.values)
    prop = _window_reach("closed_loop.window_reach_test", w, loop_data, profile, top)
    assert prove(prop, timeout_s=300).status == "proved"
    later = profile.starts_m[profile.starts_m.index(w.start_m) + 1]
    moved = dataclasses.replace(w, start_m=later)
    mutant = _window_reach("closed_loop.window_reach_test", moved, loop_data, profile, top)
    result = prove(mutant, timeout_s=300)
    assert result.status == "falsified", result.message
    assert reproduce(mutant, result.trace).first_violation == result.k


def test_every_range_field_has_its_end_for_the_layout():
    from atcs.model.configuration import RANGE_FIELDS
    from atcs.properties.configured import _FARTHEST_REACH

    assert set(_FARTHEST_REACH) == set(RANGE_FIELDS)


COARSE_CONFIG = """
name = "coarse"

[atp]
cycle_s = 0.8

[[trains]]
preset = "seed000"

[[lines]]
name = "design"
length_m = 5000
speed_limits = [{ start_m = 0, kmh = 80 }]
gradients = [{ start_m = 0, permille = -40 }, { start_m = 2500, permille = 40 }]
"""


@pytest.mark.slow
def test_each_windows_closed_loop_property_is_falsified_by_its_registered_mutant(tmp_path):
    """A window's CL-00 to CL-06 are the registered statements on the window's data: the registered closed-loop
    mutants (tests/model/test_closed_loop.py) falsify them, on a coarse cycle as there, and the runs replay."""
    from tests.model.test_closed_loop import MUTANTS

    path = tmp_path / "coarse.toml"
    path.write_text(COARSE_CONFIG, encoding="utf-8")
    config = load_configuration(path)
    family = [
        p
        for p in loop_family(config, config.trains[0], config.lines[0])
        if p.name.endswith("_w6") and "loa" not in p.name
    ]
    assert sorted(p.requirement for p in family) == [*(f"CL-0{j}" for j in range(8)), "CL-10"]
    for prop in family:
        if prop.requirement in ("CL-07", "CL-10"):
            continue
        kind = prop.name.removeprefix("closed_loop.").removesuffix("_seed000_design_w6")
        function, old, new = MUTANTS[kind][0]
        bare = dataclasses.replace(prop, lemmas=())
        with patched(function, old, new):
            result = prove(bare, timeout_s=300, max_k=12)
            assert result.status == "falsified", (prop.name, result.message)
            assert reproduce(bare, result.trace).first_violation == result.k
