"""A line with its tags and resources one by one and a switch the route needs reversed (seed 001 §3.2): the
object controller throws it, the movement authority stops at it until it is locked, a train on a switch being
thrown is a violation, and an authority that ignores the lock is caught by its property."""

import pytest

from atcs.model import authority
from atcs.proofs.mutation.mutants import mutate_function
from atcs.sim.monitor import PropertyViolation
from atcs.sim.scenario import ScenarioError, load_scenario
from atcs.sim.simulator import Simulation
from atcs.sim.train_run import SafetyViolation

SWITCH_START_M, THROW_S = 1000, 30
ATP_ATO = """[atp]
safety_margin_m = 20
report_timeout_s = 2
tag_window_m = 2.5
tacho_error = 0.01
[ato]
planning_decel_kmhps = 1.5
margin_m = 30
"""
"""The ATP's and the ATO's settings of a short test line (seed 000's)."""
SCENARIO = f"""name = "switch"
seed = "001 §3.2"
duration_s = 90
cycle_s = 0.1
[line]
length_m = 3000
tags = [
    {{ id = 1, position_m = 0 }}, {{ id = 2, position_m = 400 }}, {{ id = 3, position_m = 405 }},
    {{ id = 4, position_m = 800 }}, {{ id = 5, position_m = 1200 }}, {{ id = 6, position_m = 1600 }},
    {{ id = 7, position_m = 2000 }}, {{ id = 8, position_m = 2400 }}, {{ id = 9, position_m = 2800 }},
]
resources = [
    {{ id = 1, kind = "track", start_m = 0, end_m = {SWITCH_START_M} }},
    {{ id = 2, kind = "switch", start_m = {SWITCH_START_M}, end_m = 1060, direction = "reverse" }},
    {{ id = 3, kind = "track", start_m = 1060, end_m = 3000 }},
]
switch_throw_s = {THROW_S}
max_ma_m = 1500
{ATP_ATO}[[trains]]
name = "T1"
front_m = 400
max_speed_kmh = 60
"""
"""One train at 400 m (on tag 2) of a 3 km line whose switch at 1,000 m the route needs reversed; the switch
takes 30 s to throw, longer than the train needs to reach it."""


def _scenario(tmp_path, text=SCENARIO):
    path = tmp_path / "switch.toml"
    path.write_text(text, encoding="utf-8")
    return load_scenario(path)


def test_the_authority_waits_at_the_switch_until_it_is_locked_reverse(tmp_path):
    rows = []
    sim = Simulation(
        _scenario(tmp_path),
        on_cycle=lambda s: rows.append(
            (s.time_s, s.trains[0].last["eoa_m"], s.trains[0].front_m, dict(s.switch_thrown_at))
        ),
    )
    sim.run()  # a violation raises
    thrown = [t for t, _, _, throwing in rows if throwing]
    assert thrown and thrown[-1] == pytest.approx(THROW_S, abs=1)
    assert all(eoa <= SWITCH_START_M for t, eoa, _, _ in rows if t <= thrown[-1])
    assert max(eoa for *_, eoa, _, _ in rows) > SWITCH_START_M + 1000
    assert sim.switch_reversed == [False, True, False] and sim.trains[0].front_m > 1500
    assert sim.scenario.tags.ids[1] == 2 and [r.id for r in sim.scenario.resources] == [1, 2, 3]


def test_a_train_on_a_switch_being_thrown_is_a_violation(tmp_path):
    sim = Simulation(_scenario(tmp_path))
    while not sim.switch_thrown_at:  # until the train holds the switch and has it thrown
        sim.step()
    sim.trains[0].front_m = SWITCH_START_M + 10.0
    with pytest.raises(SafetyViolation, match="ran onto switch 2, which is not locked reverse"):
        sim._check()


def test_an_authority_that_ignores_the_lock_is_caught(tmp_path, monkeypatch):
    unlocked = mutate_function(authority.confirmed, "o.and_(i.switch_locked[r], in_direction)", "in_direction")
    monkeypatch.setattr(authority, "confirmed", unlocked)
    with pytest.raises(PropertyViolation) as caught:
        Simulation(_scenario(tmp_path)).run()
    assert caught.value.prop.name == "authority.before_unconfirmed_switch"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("front_m = 400", "front_m = 450", "trains[0].front_m = 450 must be on a tag of the line"),
        ("length_m = 3000", "length_m = 3000\ntag_spacing_m = 100", "line.tags = [{'id': 1"),
        ("switch_throw_s = 30", "", "line.switch_throw_s is missing: resource 2 is a switch"),
        ("tags = [", "tagz = [", "line.tagz: unknown field"),
        (
            "position_m = 405",
            "position_m = 402",
            "line: tag 2 at 402 m is 2 m after the tag before it, within a cycle's run at the line's top speed "
            "limit (80 km/h for cycle_s = 0.1 s: 2.22 m)",
        ),
        ("length_m = 3000", "length_m = 3000\ndouble_track = true\nturn_back_m = 200", "line.tags = [{'id'"),
    ],
)
def test_a_bad_layout_is_refused_naming_the_field(tmp_path, old, new, message):
    assert old in SCENARIO
    with pytest.raises(ScenarioError) as caught:
        _scenario(tmp_path, SCENARIO.replace(old, new, 1))
    assert str(caught.value).startswith(str(tmp_path)) and message in str(caught.value), caught.value


def test_a_spacing_that_lays_too_many_tags_is_refused(tmp_path):
    start, end = SCENARIO.index("tags = ["), SCENARIO.index("resources = [")
    text = SCENARIO[:start] + "tag_spacing_m = 0.01\n" + SCENARIO[end:]
    with pytest.raises(ScenarioError, match=r"line.tag_spacing_m = 0.01 lays more than 100,000 of them on the line"):
        _scenario(tmp_path, text)


def test_without_tags_in_either_form_the_spacing_is_asked_for(tmp_path):
    start, end = SCENARIO.index("tags = ["), SCENARIO.index("resources = [")
    with pytest.raises(ScenarioError, match=r"line.tag_spacing_m is missing \(or line.tags, one by one\)"):
        _scenario(tmp_path, SCENARIO[:start] + SCENARIO[end:])


def test_a_switch_reported_unlocked_holds_the_train_before_it(tmp_path):
    """A ``switch_unlocked`` fault from 25 s to 50 s (the switch is thrown and locked at 30 s): while the object
    controller reports it unlocked the end of authority stays before the switch (AUT-02) and the train waits there;
    once it is reported locked again the train runs on."""
    fault = 'faults = [{ kind = "switch_unlocked", from_s = 25, until_s = 50 }]\n'
    rows = []
    sim = Simulation(
        _scenario(tmp_path, SCENARIO + fault),
        on_cycle=lambda s: rows.append((s.time_s, s.trains[0].last["eoa_m"], s.trains[0].front_m)),
    )
    sim.run()  # a violation raises
    assert all(eoa <= SWITCH_START_M and front < SWITCH_START_M for t, eoa, front in rows if t < 50)
    assert max(eoa for t, eoa, _ in rows if t > 51) > SWITCH_START_M + 1000
    assert sim.trains[0].front_m > SWITCH_START_M + 400
