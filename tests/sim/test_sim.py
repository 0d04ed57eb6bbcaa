"""The closed-loop simulator: scenarios are validated, the seed 000 runs reproduce the seed's outcomes,
the checks catch a broken model, runs are deterministic, and ``atcs sim`` reports them."""

import dataclasses
import itertools
import json
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.ats_status import ATS_STATUS
from atcs.model.authority import AUTHORITY
from atcs.proofs.cli import main
from atcs.proofs.mutation.mutants import mutant_node
from atcs.sim import simulator
from atcs.sim.monitor import PropertyViolation
from atcs.sim.plots import run_plots
from atcs.sim.scenario import ScenarioError, load_scenario, resolve, shipped
from atcs.sim.simulator import Simulation
from atcs.sim.train_run import SafetyViolation

ZONE_IGNORED = mutant_node(
    AUTHORITY, "zone = o.ite(i.zone_active, i.zone_start_m, o.const(FAR_M))", "zone = o.const(FAR_M)"
)
"""The authority node with the protection zone ignored."""
STALE_STATUS_IGNORED = mutant_node(
    ATS_STATUS, "zone_active = o.or_(o.not_(fresh), kept.kept_zone_active)", "zone_active = kept.kept_zone_active"
)
"""The ATS status node letting the train run on a stale status (the zone it last heard, if any)."""
SEED000 = ("seed000_normal", "seed000_service_brake_disabled", "seed000_slow_leader", "seed000_protection_zone")
SEED002 = ("seed002_speed_restriction", "seed002_protection_zone")
FAULT_LINE = """name = "faults"
seed = "000 §2.5"
duration_s = {duration_s}
cycle_s = 0.1
[line]
length_m = 6000
tag_spacing_m = 100
resource_length_m = 100
max_ma_m = 1500
[atp]
safety_margin_m = 20
report_timeout_s = 2
tag_window_m = 2.5
tacho_error = 0.01
stop_tolerance_m = 5
[ato]
planning_decel_kmhps = 1.5
margin_m = 30
{line}
[[trains]]
name = "T1"
front_m = 1500
max_speed_kmh = 60
eb_release_after_stop_s = 5
{leader}
[[trains]]
name = "T2"
front_m = 1000
max_speed_kmh = 80
"""
"""A short two-train line for fault injection: the leader (60 km/h) carries the faults, its follower runs at up to
80 km/h behind it."""
STATION = """
[[stations]]
name = "S1"
stop_m = 2410
dwell_s = 20
[platforms]
table = [{ start_m = 2195, length_m = 220, side = "left" }]
"""

ATS_LINE = """[[zones]]
start_m = {zone_m}
from_s = 25
[[restrictions]]
start_m = 1850
end_m = 2300
kmh = 20
from_s = 25"""
"""A protection zone and a restriction the ATS sets at 25 s."""
ATS_LOST = 'faults = [{ kind = "ats_status_lost", from_s = 20, until_s = 40 }]'

LOOP = """name = "loop"
seed = "002 §4.2"
duration_s = {duration_s}
cycle_s = 0.1
[line]
length_m = 1600
double_track = true
turn_back_m = 200
turn_back_kmh = 25
wayside_zone_boundaries_m = [800]
tag_spacing_m = 100
resource_length_m = 100
max_ma_m = 1500
[atp]
national = "seed002"
safety_margin_m = 20
report_timeout_s = 2
tag_window_m = 2.5
tacho_error = 0.01
stop_tolerance_m = 5
[ato]
planning_decel_kmhps = 1.5
margin_m = 30
speed_margin_kmh = 5
[[stations]]
name = "S1"
stop_m = 1110
dwell_s = 10
[platforms]
table = [{{ start_m = 895, length_m = 220, side = "left" }}]
{extra}
[[trains]]
name = "A"
preset = "seed002"
track = "down"
front_m = 200
max_speed_kmh = 80
[[trains]]
name = "B"
preset = "seed002"
track = "up"
front_m = 700
max_speed_kmh = 80
depart_s = 40
"""
"""A 1.6 km double track (a loop of 3,600 m): A is near the down track's end, 900 m behind B round the near
turn-back; B waits 40 s at 700 m on the up track, then runs to S1, round the far turn-back and to S1's mirror."""


def _run(scenario):
    records = []
    sim = Simulation(scenario, on_cycle=lambda s: records.append([dict(t.last) for t in s.trains]))
    return sim.run(), records


@pytest.fixture(scope="module")
def runs():
    """Each seed 000 and seed 002 two-train scenario run once to its end, with its per-cycle records."""
    return {name: _run(load_scenario(resolve(name))) for name in (*SEED000, *SEED002)}


def _fault_run(tmp_path, leader="", line="", duration_s=60):
    path = tmp_path / "faults.toml"
    path.write_text(FAULT_LINE.format(leader=leader, line=line, duration_s=duration_s))
    return _run(load_scenario(path))


def _assert_refused(tmp_path, text, change, message):
    """The scenario ``text`` with ``change`` (old, new) made is refused, the error naming the file and ``message``."""
    old, new = change
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path)
    assert str(caught.value).startswith(str(path)) and message in str(caught.value), caught.value


MANUAL = Path(__file__).parents[2] / "docs" / "simulator.md"


def _documented(scenario: str, *figures: str) -> None:
    """The manual's outcome of ``scenario`` (its row in the shipped-scenario tables) states each of ``figures``,
    formatted from the run as the manual writes them: a documented outcome is one the tests reproduce."""
    rows = [line for line in MANUAL.read_text(encoding="utf-8").splitlines() if line.startswith(f"| `{scenario}` |")]
    assert len(rows) == 1, f"docs/simulator.md has {len(rows)} rows for {scenario}"
    missing = [f for f in figures if f not in rows[0]]
    assert not missing, f"docs/simulator.md, {scenario}: the run gives {missing}; the manual says: {rows[0]}"


def _train(sim, name):
    return next(t for t in sim.trains if t.spec.name == name)


class TestScenarios:
    def test_every_shipped_scenario_loads(self):
        names = set(shipped())
        assert set(SEED000) <= names
        for name, path in shipped().items():
            scenario = load_scenario(path)
            assert scenario.name == name and scenario.seed.startswith(name[4:7])

    def test_the_seed000_line(self):
        s = load_scenario(resolve("seed000_normal"))
        assert (s.line_m, len(s.trains), s.trains[0].data.train_length_m) == (15000, 2, 200)
        assert s.tags.positions_m[:3] == (0, 100, 200) and s.tags.ids[:3] == (1, 2, 3) and len(s.tags) == 150
        assert [str(x) for x in (s.trains[0].max_speed_kmh, s.speed_limits_kmh[0].value)] == ["80", "80"]

    @pytest.mark.parametrize(
        ("change", "message"),
        [
            (("duration_s = 320", "duration_s = -1"), "duration_s = -1 must be positive"),
            (("tag_spacing_m = 100", "tag_spacing_m = 'x'"), "line.tag_spacing_m = 'x' is not a number"),
            (("tacho_error = 0.01", "tacho_error = 1.5"), "atp.tacho_error = 1.5 must be below 1"),
            (('mode = "relative_braking"', 'mode = "moving_block"'), "atp.mode = 'moving_block' must be one of"),
            (("front_m = 11000", "front_m = 11050"), "trains[0].front_m = 11050 must be on a tag"),
            (("front_m = 10000", "front_m = 10900"), "trains[1].front_m = 10900 must be behind the rear of T1"),
            (("max_speed_kmh = 80\n\n", "max_speed_kmh = 80\ncolour = 'red'\n\n"), "trains[0].colour: unknown field"),
            (('preset = "seed000"', 'preset = "seed009"'), "trains[0].preset = 'seed009' must be one of"),
            (("[ato]", "[ato"), "not valid TOML"),
            (("[ato]", "[ato_]"), "ato_: unknown field"),
            (("max_ma_m = 1500", "max_ma_m = 0"), "line.max_ma_m = 0 must be positive"),
            (
                ("speed_limits = [{ start_m = 0, kmh = 80 }]", "speed_limits = [{ start_m = 5, kmh = 80 }]"),
                "line.speed_limits[0].start_m = 5 must be 0 for the first segment",
            ),
        ],
    )
    def test_errors_name_the_file_the_field_and_the_value(self, tmp_path, change, message):
        _assert_refused(tmp_path, shipped()["seed000_normal"].read_text(), change, message)

    def test_fault_kinds_and_zones_are_checked(self, tmp_path):
        text = shipped()["seed000_service_brake_disabled"].read_text()
        for old, new, message in [
            ('kind = "ignores_service_brake"', 'kind = "wet_rail"', "faults[0].kind = 'wet_rail' must be one of"),
            ("until_s = 150", "until_s = 0", "faults[0].until_s = 0 must be after from_s"),
            ("start_m = 4000", "start_m = 16000", "zones[0].start_m = 16000 must be on the line"),
        ]:
            path = tmp_path / "bad.toml"
            path.write_text(text.replace(old, new, 1))
            with pytest.raises(ScenarioError, match=message.replace("[", r"\[").replace("]", r"\]")):
                load_scenario(path)

    def test_platforms_are_read_through_the_platform_data_loader(self, tmp_path):
        text = shipped()["seed000_protection_zone"].read_text()
        path = tmp_path / "with_platforms.toml"
        path.write_text(text + '\n[platforms]\npacket = "4540ce803200fa74212c007d38"\nreference_m = 4500\n')
        assert [(p.start_m, p.side) for p in load_scenario(path).platforms] == [(4600, "right"), (5800, "left")]
        path.write_text(text + '\n[platforms]\npacket = "4540ce803200fa74212c007d3f"\nreference_m = 4500\n')
        with pytest.raises(ScenarioError, match=r"Q_PLATFORM\(1\) at bit 101"):
            load_scenario(path)

    def test_unknown_scenario_name(self):
        with pytest.raises(ScenarioError, match="nor a shipped scenario"):
            resolve("seed000_nosuch")


@pytest.mark.slow
class TestSeed000Outcomes:
    """Seed 000 §2.5: the four runs of the integrated simulation."""

    def test_normal_running_without_intervention(self, runs):
        sim, _ = runs["seed000_normal"]
        t1, t2 = sim.trains
        for t in sim.trains:  # the ATO follows the permitted curve: the ATP never intervenes
            assert (t.stats.emergency_brakes, t.stats.service_brakes) == (0, 0), t.spec.name
            assert t.stats.max_speed_kmh > 79 and t.speed_mps == 0
        assert 14950 < t1.front_m < 15000  # stopped before the end of the line
        assert t2.stats.min_gap_m > 0 and t2.front_m < t1.front_m - 200
        _documented(
            "seed000_normal",
            f"up to {int(t1.stats.max_speed_kmh)} km/h",
            f"the leader stops {15000 - t1.front_m:.1f} m short",
            f"the follower {t1.front_m - 200 - t2.front_m:,.0f} m behind its rear",
            f"its MA ends at {t2.last['eoa_m']:,.0f} m",
        )

    def test_service_brake_disabled_reaches_ebi_then_eb_stops_and_restarts(self, runs):
        sim, records = runs["seed000_service_brake_disabled"]
        (train,) = sim.trains
        assert train.stats.emergency_brakes == 1 and train.stats.service_brakes == 1  # SBI passed, then EBI
        first_eb = next(k for k, (r,) in enumerate(records) if r["eb"] and r["t_s"] > 1)
        stop = next(k for k in range(first_eb, len(records)) if records[k][0]["speed_kmh"] == 0)
        assert records[stop][0]["front_m"] < 4000 and records[stop][0]["eb"]  # stopped short of the zone
        released = next(k for k in range(stop, len(records)) if not records[k][0]["eb"])
        assert records[released][0]["t_s"] - records[stop][0]["t_s"] >= 5  # the driver's release at standstill
        assert train.front_m > 4000 and train.speed_mps > 0  # restarted and running once the zone is lifted
        _documented(
            "seed000_service_brake_disabled",
            f"EB stops it at {records[stop][0]['front_m']:,.0f} m",
            f"releases {records[released][0]['t_s'] - records[stop][0]['t_s']:.0f} s later",
        )

    def test_follower_follows_a_slow_leader_without_collision(self, runs):
        sim, records = runs["seed000_slow_leader"]
        leader, follower = sim.trains
        assert leader.stats.max_speed_kmh <= 40 and follower.stats.max_speed_kmh > 60
        assert follower.stats.min_gap_m > 0
        gaps = [r[0]["front_m"] - 200 - r[1]["front_m"] for r in records]
        assert gaps[-1] < gaps[0] / 2  # it caught up, and keeps behind
        late = [r[1]["speed_kmh"] for r in records[-600:]]
        assert 30 < sum(late) / len(late) < 50  # at about the leader's 40 km/h
        assert follower.stats.emergency_brakes == 0
        _documented(
            "seed000_slow_leader",
            f"closes from {gaps[0]:,.0f} m to about {round(min(gaps), -1):,.0f} m",
            f"follows at about {round(sum(late) / len(late), -1):.0f} km/h",
        )

    def test_train_stops_before_the_protection_zone(self, runs):
        sim, _ = runs["seed000_protection_zone"]
        (train,) = sim.trains
        assert 4950 < train.front_m < 5000 and train.speed_mps == 0
        assert (train.stats.emergency_brakes, train.stats.service_brakes) == (0, 0)
        _documented("seed000_protection_zone", f"stops {5000 - train.front_m:.1f} m before it")


@pytest.mark.slow
class TestSeed002Outcomes:
    """Seed 002 §4.2 (Table 1: 56.8 km, tags every 200 m, MA at most 1.5 km, full service 3.5 and EB 4.5 km/h/s)."""

    def test_temporary_restriction_is_run_at_about_25_kmh_and_the_followers_ma_shrinks(self, runs):
        sim, records = runs["seed002_speed_restriction"]
        speeds = []
        for k, train in enumerate(sim.trains):
            inside = [r[k]["speed_kmh"] for r in records if r[k]["front_m"] - 200 >= 4000 and r[k]["front_m"] <= 5000]
            assert inside and min(inside) > 23 and max(inside) < 26, train.spec.name  # the whole train inside
            assert (train.stats.emergency_brakes, train.stats.service_brakes) == (0, 0)
            speeds += inside
        ma = [r[1]["eoa_m"] - r[1]["front_m"] for r in records]
        before = min(ma[300:900])  # at line speed, before the ATS sets the restriction
        assert min(ma[1200:3000]) < before / 3  # the leader slowed down: the follower's MA shrank
        assert sim.trains[1].stats.min_gap_m > 0
        _documented(
            "seed002_speed_restriction",
            f"both trains run it at {min(speeds):.0f}-{max(speeds):.0f} km/h",
            f"shrinks from about {round(before, -1):,.0f} m to about {round(min(ma[1200:3000]), -1):,.0f} m",
        )

    def test_protection_zone_leader_before_4600_follower_behind_it(self, runs):
        sim, _ = runs["seed002_protection_zone"]
        leader, follower = sim.trains
        assert 4550 < leader.front_m < 4600 and leader.speed_mps == 0
        # the seed: about 4,400 m; here the follower's MA ends where the 100 m resource holding the leader's
        # rear begins, 4,300 m
        assert 4250 < follower.front_m < 4300 and follower.speed_mps == 0
        assert all(t.stats.emergency_brakes == 0 for t in sim.trains)
        _documented(
            "seed002_protection_zone",
            f"the leader stops at {leader.front_m:,.0f} m, the follower at {follower.front_m:,.0f} m",
            f"MA ends at {follower.last['eoa_m']:,.0f} m",
            f"the leader's rear (at {leader.front_m - 200:,.0f} m)",
        )


@pytest.mark.slow
class TestDoubleTrack:
    """Seed 002 §4.2: the double track with a turn-back at each end, as one closed track (sim/double_track.py), and
    its two wayside zones."""

    def test_the_shipped_timetable_is_a_steady_service_round_the_loop(self):
        s = load_scenario(resolve("seed002_timetable"))
        layout = s.double_track
        assert (layout.length_m, layout.turn_back_m, layout.zones, s.line_m) == (56800, 400, 2, 114400)
        assert len(s.trains) >= 20 and s.duration_s == 3600 and all(t.depart_s == 0 for t in s.trains)
        assert len(s.stations) == 20 and s.stations[10].name == "S10 (down)"  # both tracks serve the ten stations
        fronts = [t.front_m for t in s.trains]
        assert fronts == sorted(fronts, reverse=True)  # from the front: the last is the front train's leader
        assert {layout.place(x)[0] for x in fronts} == {"up", "down"}

    def test_the_shipped_timetable_first_stops_on_both_tracks(self):
        s = load_scenario(resolve("seed002_timetable"))
        names = ("T2", "T11")  # 2 km from S1 on the up track, 400 m from S10 on the down track
        first = dataclasses.replace(s, trains=tuple(t for t in s.trains if t.name in names), duration_s=Fraction(170))
        sim, records = _run(first)
        stops = [float(station.stop_m) for station in s.stations]
        for k, train in enumerate(sim.trains):
            assert train.stats.station_stops == 1, train.spec.name
            opened = [r[k] for r in records if r[k]["doors_open"]]
            assert opened and all(r["speed_kmh"] == 0 for r in opened)  # doors open only at standstill
            assert all(min(abs(r["front_m"] - x) for x in stops) < float(s.stop_tolerance_m) for r in opened)
            assert 300 <= len(opened) <= 302  # the 30 s dwell from the doors opening
            assert train.stats.emergency_brakes == 0 and train.stats.service_brakes == 0
        assert {r[k]["track"] for r in records for k in range(2) if r[k]["doors_open"]} == {"up", "down"}

    @pytest.mark.slow
    def test_trains_run_round_both_turn_backs_and_the_front_train_follows_the_last(self, tmp_path):
        path = tmp_path / "loop.toml"
        path.write_text(LOOP.format(duration_s=295, extra=""))
        sim, records = _run(load_scenario(path))
        a, b = sim.trains
        loop_m = float(sim.scenario.line_m)
        assert (a.spec.name, b.spec.name) == ("A", "B")  # A is the front train, B its leader a lap on
        # A is held behind B across the near turn-back: its MA ends short of B's rear, a lap on
        waiting = [r for r in records if r[0]["t_s"] < 40]
        assert all(r[0]["eoa_m"] <= 500 + loop_m for r in waiting)
        assert max(r[0]["eoa_m"] for r in waiting) > loop_m  # it reaches round the turn-back
        assert a.front_m > loop_m and a.stats.min_gap_m > 0  # A went round onto the up track behind B
        # B stopped at S1, went round the far turn-back and opened its doors at S1's mirror on the down track
        assert b.stats.station_stops >= 1 and b.next_station == b.stats.station_stops
        assert {r[1]["track"] for r in records if r[1]["doors_open"]} == {"up", "down"}
        assert {r[1]["track"] for r in records} >= {"up", "turn-back", "down"}
        assert all(t.stats.emergency_brakes == 0 and t.stats.service_brakes == 0 for t in sim.trains)
        paths = run_plots(sim, records, tmp_path / "plots", sample_every_s=10)  # time-distance: a train graph
        assert sorted(p.name for p in paths) == ["A_speed_distance.png", "B_speed_distance.png", "time_distance.png"]
        assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in paths)

    def test_a_zone_outage_stops_only_that_zones_grants(self, tmp_path):
        path = tmp_path / "loop.toml"
        path.write_text(LOOP.format(duration_s=40, extra="[[manager_outages]]\nzone = 2\nfrom_s = 0\nuntil_s = 20"))
        sim = Simulation(load_scenario(path))
        zone = sim.resource_zone
        while sim.time_s < 20:
            sim.step()
        held = sim.held[1]  # B, at 700 m on the up track: its MA reaches into zone 2 (from 800 m)
        assert any(h and zone[r] == 1 for r, h in enumerate(held))
        assert not any(h and zone[r] == 2 for r, h in enumerate(held))
        while sim.time_s < 40:
            sim.step()
        assert any(h and zone[r] == 2 for r, h in enumerate(sim.held[1]))

    @pytest.mark.parametrize(
        ("change", "message"),
        [
            (
                ('track = "down"\nfront_m = 200', 'track = "up"\nfront_m = 100'),
                "trains[0].front_m = 100 must put the whole train on the loop",
            ),
            (("front_m = 700", "front_m = 750"), "trains[1].front_m = 750 must be on a tag"),
            (
                ('track = "down"\nfront_m = 200', 'track = "up"\nfront_m = 900'),
                "trains: B (front at 700 m round the loop) overlaps A (rear at 700 m)",
            ),
            (('track = "down"', 'track = "side"'), "trains[0].track = 'side' must be one of up, down"),
            (
                ("turn_back_m = 200", "turn_back_m = 250"),
                "line.turn_back_m = 250 must be a multiple of line.tag_spacing_m",
            ),
            (
                ("wayside_zone_boundaries_m = [800]", "wayside_zone_boundaries_m = [2500]"),
                "line.wayside_zone_boundaries_m[0] = 2500 must lie inside the line",
            ),
            (("turn_back_kmh = 25\n", ""), "line.turn_back_kmh is missing"),
            (("double_track = true", "double_track = 1"), "line.double_track = 1 must be true or false"),
            (("double_track = true", "double_track = false"), "line.turn_back_m = 200 needs line.double_track = true"),
            (("stop_m = 1110", "stop_m = 1300"), "stations[0].stop_m = 1300: no platform of [platforms] contains it"),
        ],
    )
    def test_errors_name_the_file_the_field_and_the_value(self, tmp_path, change, message):
        _assert_refused(tmp_path, LOOP.format(duration_s=10, extra=""), change, message)

    def test_outage_zones_and_tracks_are_checked(self, tmp_path):
        path = tmp_path / "bad.toml"
        path.write_text(LOOP.format(duration_s=10, extra="[[manager_outages]]\nzone = 3"))
        with pytest.raises(ScenarioError, match=r"manager_outages\[0\].zone = 3 must be a wayside zone"):
            load_scenario(path)
        path.write_text(FAULT_LINE.format(leader='track = "up"', line="", duration_s=10))
        with pytest.raises(ScenarioError, match=r"trains\[0\].track: unknown field"):
            load_scenario(path)


class TestReferenceProfile:
    """The ATO tracking the minimum-time profile (cvxpy, Clarabel) from stop to stop: the ATP never intervenes, and
    each stretch takes about the profile's optimal running time."""

    @pytest.mark.slow
    def test_the_atp_never_intervenes_and_the_stretches_take_the_optimal_time(self):
        scenario = load_scenario(resolve("seed002_optimal_profile"))
        assert scenario.ato_reference_profile
        sim, records = _run(scenario)
        (train,) = sim.trains
        assert train.stats.station_stops == 3 and (train.stats.emergency_brakes, train.stats.service_brakes) == (0, 0)
        assert not any(r[0]["eb"] or r[0]["sb"] for r in records[5:])  # past the power-up EB: no intervention
        assert [p.positions_m[-1] for p in train.references] == [8810, 14010, 19210]
        departures = [0.0] + [
            r[0]["t_s"] for a, r in itertools.pairwise(records) if a[0]["doors_open"] and not r[0]["doors_open"]
        ]
        arrivals = [
            r[0]["t_s"] for a, r in itertools.pairwise(records) if r[0]["doors_open"] and not a[0]["doors_open"]
        ]
        for profile, left, arrived in zip(train.references, departures, arrivals, strict=False):
            assert profile.solver_status == "optimal"
            # tracking overshoots by a few cm/s, and the doors open a cycle or two after the stop
            assert abs(arrived - left - profile.running_time_s) <= profile.running_time_s * 0.01 + 1.0

    def test_needs_stations(self, tmp_path):
        path = tmp_path / "bad.toml"
        path.write_text(
            FAULT_LINE.format(leader="", line="", duration_s=10).replace(
                "margin_m = 30", "margin_m = 30\nreference_profile = true"
            )
        )
        with pytest.raises(ScenarioError, match=r"ato\.reference_profile = true needs"):
            load_scenario(path)


class TestFaults:
    """Each fault the scenarios can inject, and the ATP's safe reaction; no property is violated (a violation
    would raise)."""

    @pytest.mark.parametrize(
        "fault",
        [
            '{ kind = "missed_tag", from_s = 20, until_s = 40 }',
            '{ kind = "spurious_tag", from_s = 30, until_s = 30.1 }',
            '{ kind = "tacho_drift", factor = 1.1, from_s = 0 }',
        ],
    )
    def test_a_position_fault_gives_an_emergency_brake(self, tmp_path, fault):
        sim, records = _fault_run(tmp_path, leader=f"faults = [{fault}]")
        leader = sim.trains[0]
        assert leader.stats.emergency_brakes >= 1
        assert any(not r[0]["position_valid"] and r[0]["eb"] for r in records)  # the position is lost: EB
        assert sim.trains[1].stats.min_gap_m > 0

    def test_a_wrong_known_tag_is_caught_at_the_next_tag(self, tmp_path):
        """Two cycles reading the id of the tag at 4,000 m, 2.2 km ahead of the leader: the first is unexpected (the
        position is lost, EB); the second sets the position again there, unconfirmed (one tag read cannot be
        checked). Until the next tag the leader sends no report and releases nothing, so its follower is not
        misled; the next tag, 72 m on, is not the one the wrong position expects: lost again, EB, no collision."""
        sim, records = _fault_run(
            tmp_path, leader='faults = [{ kind = "spurious_tag", tag_id = 41, from_s = 30, until_s = 30.2 }]'
        )
        wrong = [k for k, r in enumerate(records) if r[0]["position_valid"] and r[0]["front_min_m"] > 3000]
        assert wrong and all(not records[k][0]["position_confirmed"] for k in wrong)
        assert records[wrong[-1] + 1][0]["front_m"] - records[wrong[0]][0]["front_m"] < 100  # caught at the next tag
        assert not records[wrong[-1] + 1][0]["position_valid"] and records[wrong[-1] + 1][0]["eb"]
        assert all(r[1]["leader_report"] == "none" for r in records[wrong[0] + 1 : wrong[-1] + 1])
        assert sim.trains[1].stats.min_gap_m > 100

    def test_stuck_traction_is_stopped_by_eb(self, tmp_path):
        """Traction stuck on overrides the service brake and the traction cut: the train passes the ceiling's
        EBI, EB stops it (EB cuts traction by its own loop), and it never reaches the protection zone."""
        sim, records = _fault_run(
            tmp_path,
            line="[[zones]]\nstart_m = 2200\nfrom_s = 0",
            leader='faults = [{ kind = "traction_stuck", from_s = 0 }]',
        )
        leader = sim.trains[0]
        assert leader.stats.emergency_brakes >= 1 and all(r[0]["traction"] for r in records if not r[0]["eb"])
        assert max(r[0]["speed_kmh"] for r in records) > 60  # over its 60 km/h ceiling before EB acts
        assert leader.front_m < 2200 and sim.trains[1].stats.min_gap_m > 0

    def test_an_atp_reset_brakes_and_recovers_through_two_tags(self, tmp_path):
        """The leader's ATP restarts at 30 s running at 59 km/h: position unknown, EB in that cycle; the next tag
        sets the position again, unconfirmed (no report, no release), EB held to a standstill; the driver releases
        it, the tag after confirms the position and the reports resume. The follower, without reports, brakes on the
        last one it had."""
        sim, records = _fault_run(
            tmp_path, leader='faults = [{ kind = "atp_reset", from_s = 30, until_s = 30.1 }]', duration_s=90
        )
        reset = round(30 / 0.1)
        assert not records[reset][0]["position_valid"] and records[reset][0]["eb"]
        confirmed = next(k for k in range(reset, len(records)) if records[k][0]["position_confirmed"])
        assert any(records[k][0]["position_valid"] for k in range(reset, confirmed))  # set again, unconfirmed
        assert min(r[0]["speed_kmh"] for r in records[reset:confirmed]) == 0  # EB held to a standstill
        assert all(r[1]["leader_report"] == "none" for r in records[reset + 1 : confirmed + 1])
        assert records[confirmed + 1][1]["leader_report"] == "accepted"
        assert sim.trains[1].stats.min_gap_m > 100

    def test_wagons_left_behind_stop_the_follower(self, tmp_path):
        """The leader parts at 30 s: its rear half brakes to a stop at about 1,749 m while its front half runs on.
        With the integrity loss reported, it sends no report and releases no resource, so its follower, its
        reports gone stale and the resources behind the leader still held, stops short of the wagons."""
        sim, records = _fault_run(
            tmp_path, leader='faults = [{ kind = "integrity_lost", from_s = 30 }]', duration_s=120
        )
        leader, follower = sim.trains
        wagons_rear_m, wagons_speed = leader.detached
        assert wagons_speed == 0 and leader.front_m - wagons_rear_m > 1000  # the front half ran on
        assert all(r[1]["leader_report"] == "none" for r in records[round(30 / 0.1) + 1 :])
        assert follower.speed_mps == 0 and 0 < wagons_rear_m - follower.front_m < 200
        assert follower.stats.min_gap_m > 100

    def test_a_lost_ats_status_stops_the_train_until_heard_again(self, tmp_path):
        """The leader stops hearing the ATS at 20 s, running at 59 km/h; at 25 s the ATS sets a protection zone from
        1,900 m and a 20 km/h restriction from 1,850 m, neither of which reaches it. Its status goes stale one
        timeout (2 s) after the last one heard: the MA ends at its front, EB, a standstill short of the zone. Heard
        again at 40 s, the zone and the restriction reach it together and it runs on to the zone's start."""
        path = tmp_path / "ats.toml"
        line = ATS_LINE.format(zone_m=1900)
        path.write_text(FAULT_LINE.format(leader=ATS_LOST, line=line, duration_s=70))
        records, restricted = [], []

        def on_cycle(sim):
            records.append([dict(t.last) for t in sim.trains])
            restricted.append("restriction 0" in sim.trains[0].restrictions.active)

        sim = Simulation(load_scenario(path), on_cycle=on_cycle)
        sim.run()
        leader = [r[0] for r in records]
        stale = [k for k, r in enumerate(leader) if r["ats_status"] == "stale"]
        assert (stale[0], stale[-1]) == (220, 399)  # the last heard at 19.9 s, 2.1 s old at 22.0 s; heard at 40 s
        assert leader[stale[0]]["eb"] and leader[stale[0]]["eoa_m"] <= leader[stale[0]]["front_max_m"]
        assert leader[399]["speed_kmh"] == 0 and leader[399]["front_m"] < 1850
        assert restricted.index(True) == 400  # the restriction (set at 25 s) reached it with the status
        assert max(r["front_m"] for r in leader) < 1900 and sim.trains[0].stats.emergency_brakes == 1

    def test_brake_fade_within_the_guaranteed_braking_still_stops_short(self, tmp_path):
        """Stuck traction and brakes at 80 % of the train data: EB, braking at what the curves guarantee (the
        confidence factors), still stops the train short of the zone. At 70 % the brake is weaker than the proofs'
        plant admits: the run stops there, naming the broken assumption, rather than passing on an unproved run."""
        zone = "[[zones]]\nstart_m = 2200\nfrom_s = 0"
        stuck = '{ kind = "traction_stuck", from_s = 0 }'
        sim, _ = _fault_run(
            tmp_path, line=zone, leader=f'faults = [{{ kind = "brake_fade", factor = 0.8, from_s = 0 }}, {stuck}]'
        )
        assert sim.trains[0].stats.emergency_brakes >= 1 and sim.trains[0].front_m < 2200
        with pytest.raises(SafetyViolation, match="leaves the proofs' plant bounds"):
            _fault_run(
                tmp_path, line=zone, leader=f'faults = [{{ kind = "brake_fade", factor = 0.7, from_s = 0 }}, {stuck}]'
            )

    def test_a_slide_while_braking_is_caught(self, tmp_path):
        sim, records = _fault_run(
            tmp_path,
            line="[[zones]]\nstart_m = 2200\nfrom_s = 0",
            leader='faults = [{ kind = "tacho_slide", factor = 0.5, from_s = 0 }]',
        )
        first_brake = next(
            k for k, r in enumerate(records) if r[0]["speed_kmh"] > 0 and not r[0]["traction"] and k > 100
        )
        assert not all(r[0]["position_valid"] for r in records[first_brake:])  # implausible tachometer
        assert sim.trains[0].stats.emergency_brakes >= 1 and sim.trains[0].front_m < 2200

    def test_drift_within_the_tachometer_error_keeps_the_true_front_in_the_interval(self, tmp_path):
        sim, records = _fault_run(tmp_path, leader='faults = [{ kind = "tacho_drift", factor = 1.009, from_s = 0 }]')
        assert sim.trains[0].stats.emergency_brakes == 0
        # each cycle's interval is about the front at the cycle's start: the previous cycle's end
        assert all(
            r[0]["front_min_m"] <= before[0]["front_m"] <= r[0]["front_max_m"]
            for before, r in itertools.pairwise(records)
        )

    def test_an_undetected_drift_misses_by_no_more_than_the_excess(self, tmp_path):
        """A tachometer reading 0.95 times the distance (5 % against the stated 1 %) passes the tag checks (4 m
        over 100 m is within the two tag windows) and the interval misses the true front; the run's every-cycle
        check (POS-22) holds it within the tachometer's excess error since the last tag, or the run would stop."""
        sim, records = _fault_run(tmp_path, leader='faults = [{ kind = "tacho_drift", factor = 0.95, from_s = 0 }]')
        misses = [
            max(r[0]["front_min_m"] - before[0]["front_m"], before[0]["front_m"] - r[0]["front_max_m"])
            for before, r in itertools.pairwise(records)
        ]
        assert max(misses) > 1 and all(r[0]["position_valid"] for r in records[20:])
        assert sim.trains[0].stats.emergency_brakes == 0

    @pytest.mark.parametrize("fault", ['faults = [{ kind = "t2t_loss", from_s = 30, until_s = 60 }]', ""])
    def test_lost_reports_shorten_the_followers_ma(self, tmp_path, fault):
        sim, records = _fault_run(tmp_path, leader=fault)
        ma_m = [r[1]["eoa_m"] - r[1]["front_m"] for r in records[300:600]]
        if fault:  # no report: the MA ends behind the leader's last reported rear, and the follower slows down
            assert min(ma_m) < 100 and sim.trains[1].stats.min_gap_m > 0
            assert records[550][1]["speed_kmh"] < records[300][1]["speed_kmh"] / 2
        else:
            assert min(ma_m) > 200  # the same run with the reports: the MA stays long

    def test_delayed_reports_are_still_safe(self, tmp_path):
        sim, records = _fault_run(tmp_path, leader='faults = [{ kind = "t2t_delay", delay_s = 1, from_s = 0 }]')
        assert sim.trains[1].stats.min_gap_m > 0 and sim.trains[1].stats.emergency_brakes == 0
        assert min(r[1]["eoa_m"] - r[1]["front_m"] for r in records[300:600]) > 200  # 1.1 s old: still fresh

    @pytest.mark.parametrize(
        "fault",
        ['{ kind = "t2t_corrupt", from_s = 30, until_s = 60 }', '{ kind = "t2t_replay", from_s = 30, until_s = 60 }'],
        ids=["corrupted", "replayed"],
    )
    def test_corrupted_or_replayed_reports_shorten_the_followers_ma(self, tmp_path, fault):
        """A corrupted report (its rear 167 km on, were it read without its safety code) is dropped, a replayed one
        renews nothing: the MA ends behind the leader's last good report, as when the reports are lost."""
        sim, records = _fault_run(tmp_path, leader=f"faults = [{fault}]", duration_s=65)
        window = records[301:600]
        assert {r[1]["leader_report"] for r in window} == {"corrupt" if "corrupt" in fault else "out_of_sequence"}
        assert min(r[1]["eoa_m"] - r[1]["front_m"] for r in window) < 100 and sim.trains[1].stats.min_gap_m > 0
        assert records[550][1]["speed_kmh"] < records[300][1]["speed_kmh"] / 2
        assert records[-1][1]["leader_report"] == "accepted"  # once the fault has cleared

    @pytest.mark.parametrize("fault", ['faults = [{ kind = "t2t_delay", delay_s = 5, from_s = 30 }]', ""])
    def test_stale_reports_give_no_credit(self, tmp_path, fault):
        """Reports 5.1 s old are accepted, but older than the 2 s timeout: the MA ends the margin behind the
        leader's rear as it was 5.1 s before (brick wall), where the fresh reports' MA reaches past it."""
        sim, records = _fault_run(tmp_path, leader=fault)
        length_m = float(sim.trains[0].spec.data.train_length_m)
        rear_m = [r[0]["front_m"] - length_m for r in records]
        late = [k for k in range(360, 600) if records[k][1]["eoa_m"] > rear_m[k - 51] - 20]
        assert (late == []) == bool(fault)
        assert {r[1]["leader_report"] for r in records[360:600]} == {"accepted"}
        assert sim.trains[1].stats.min_gap_m > 0 and sim.trains[1].stats.emergency_brakes == 0

    @pytest.mark.parametrize("fast", ["leader", "follower"])
    def test_a_drifting_clock_makes_the_reports_no_sign_of_life(self, tmp_path, fast):
        """The leader's clock running 5 % fast, or the follower's 5 % slow, from 30 s: once the leader's time
        stamps are ahead of the follower's clock (no skew allowed), its reports renew nothing, the time-out
        passes and the MA ends the margin behind the rear they report (brick wall; their bounds stay true). A slow
        follower's clock puts the ATS's time stamps ahead of it too: its ATS status goes stale and it stops."""
        drift = 'faults = [{ kind = "clock_drift", factor = FACTOR, from_s = 30 }]'
        if fast == "leader":
            sim, records = _fault_run(tmp_path, leader=drift.replace("FACTOR", "1.05"))
        else:
            path = tmp_path / "faults.toml"
            text = FAULT_LINE.format(leader="", line="", duration_s=60)
            path.write_text(text + drift.replace("FACTOR", "0.95") + "\n")
            sim, records = _run(load_scenario(path))
        assert {r[1]["leader_report"] for r in records[340:600]} == {"out_of_sequence"}
        length_m = float(sim.trains[0].spec.data.train_length_m)
        assert all(r[1]["eoa_m"] <= r[0]["front_m"] - length_m - 20 for r in records[340:600])
        stale = [k for k, r in enumerate(records) if r[1]["ats_status"] == "stale"]
        if fast == "leader":
            assert sim.trains[1].stats.emergency_brakes == 0 and stale == []
        else:  # stale once 2 s have passed by its clock since the last status it accepted (sent at 30.0 s)
            assert stale[0] == 322 and records[322][1]["eb"] and sim.trains[1].speed_mps == 0
        assert sim.trains[1].stats.min_gap_m > 0

    def test_reordered_reports_keep_the_ma_long(self, tmp_path):
        sim, records = _fault_run(tmp_path, leader='faults = [{ kind = "t2t_reorder", from_s = 30, until_s = 60 }]')
        seen = [r[1]["leader_report"] for r in records[310:600]]
        assert seen.count("out_of_sequence") == seen.count("accepted") == len(seen) // 2  # every overtaken report
        assert min(r[1]["eoa_m"] - r[1]["front_m"] for r in records[300:600]) > 200
        assert sim.trains[1].stats.min_gap_m > 0 and sim.trains[1].stats.emergency_brakes == 0

    def test_a_manager_outage_grants_nothing_and_the_mas_stop_growing(self, tmp_path):
        path = tmp_path / "outage.toml"
        path.write_text(
            FAULT_LINE.format(leader="", line="[[manager_outages]]\nfrom_s = 30\nuntil_s = 60", duration_s=70)
        )
        sim = Simulation(load_scenario(path))
        while sim.time_s < 30:
            sim.step()
        ends = sim.resource_floats[1]
        held = [{r for r, h in enumerate(row) if h} for row in sim.held]
        while sim.time_s < 60:
            sim.step()
            for k, train in enumerate(sim.trains):
                now = {r for r, h in enumerate(sim.held[k]) if h}
                assert now <= held[k]  # no grant in the outage
                assert train.last["eoa_m"] <= ends[max(held[k])]
        while sim.time_s < 70:
            sim.step()
        assert any({r for r, h in enumerate(row) if h} - before for row, before in zip(sim.held, held, strict=True))

    @pytest.mark.slow
    @pytest.mark.parametrize("lying", ["", ', { kind = "lying_door_sensor", from_s = 0 }'])
    def test_a_stuck_door_holds_the_train(self, tmp_path, lying):
        """An obstacle holds the doors open past the dwell: traction stays cut until it is gone, also with one of
        the two door detection loops lying (stuck at closed): the other one still reports the door open."""
        door = f'faults = [{{ kind = "stuck_door", from_s = 90, until_s = 120 }}{lying}]'
        _, records = _fault_run(tmp_path, line=STATION, leader=door, duration_s=125)
        opened = [r[0] for r in records if r[0]["doors_open"]]
        assert opened[0]["front_m"] == pytest.approx(2410, abs=0.5) and opened[0]["t_s"] < 90
        assert opened[0]["t_s"] + 20 < 110  # the dwell (20 s) ended before 110 s, the obstacle holds the doors
        assert opened[-1]["t_s"] == pytest.approx(119.9, abs=0.15)  # closed once the obstacle is gone
        assert all(r["speed_kmh"] == 0 and not r["traction"] for r in opened)
        assert records[-1][0]["speed_kmh"] > 0  # and the train departed

    @pytest.mark.parametrize(
        ("line", "message"),
        [
            (
                STATION.replace("stop_m = 2410", "stop_m = 3000"),
                "stations[0].stop_m = 3000: no platform of [platforms]",
            ),
            (STATION.replace("dwell_s = 20", "dwell_s = -1"), "stations[0].dwell_s = -1 must be at least 0"),
            ("[[restrictions]]\nstart_m = 500\nend_m = 400\nkmh = 30", "restrictions[0].end_m = 400 must lie after"),
            ("[[restrictions]]\nstart_m = 500\nend_m = 900\nkmh = 0", "restrictions[0].kmh = 0 must be positive"),
            ("[[manager_outages]]\nfrom_s = 30\nuntil_s = 10", "manager_outages[0].until_s = 10 must be after"),
        ],
    )
    def test_stations_restrictions_and_outages_are_checked(self, tmp_path, line, message):
        path = tmp_path / "bad.toml"
        path.write_text(FAULT_LINE.format(leader="", line=line, duration_s=10))
        with pytest.raises(ScenarioError) as caught:
            load_scenario(path)
        assert str(caught.value).startswith(str(path)) and message in str(caught.value), caught.value

    def test_a_stop_tolerance_within_the_tag_window_is_refused(self, tmp_path):
        path = tmp_path / "bad.toml"
        path.write_text(
            FAULT_LINE.format(leader="", line=STATION, duration_s=10).replace(
                "stop_tolerance_m = 5", "stop_tolerance_m = 2"
            )
        )
        with pytest.raises(ScenarioError, match=r"atp\.stop_tolerance_m = 2 must exceed atp\.tag_window_m = 5/2"):
            load_scenario(path)

    def test_fault_fields_are_checked(self, tmp_path):
        for fault, message in [
            ('{ kind = "tacho_drift", from_s = 0 }', "faults[0].factor is missing"),
            ('{ kind = "tacho_drift", factor = 0, from_s = 0 }', "faults[0].factor = 0 must be positive"),
            ('{ kind = "brake_fade", factor = 1.2, from_s = 0 }', "faults[0].factor = 1.2 must be at most 1"),
            ('{ kind = "missed_tag", factor = 2 }', "faults[0].factor: unknown field"),
        ]:
            path = tmp_path / "bad.toml"
            path.write_text(FAULT_LINE.format(leader=f"faults = [{fault}]", line="", duration_s=10))
            with pytest.raises(ScenarioError, match=message.replace("[", r"\[").replace("]", r"\]")):
                load_scenario(path)


class TestChecks:
    def test_an_authority_that_ignores_the_zone_is_caught(self, monkeypatch):
        monkeypatch.setattr(simulator, "AUTHORITY", ZONE_IGNORED)
        with pytest.raises(PropertyViolation) as caught:
            Simulation(load_scenario(resolve("seed000_protection_zone"))).run()
        assert caught.value.prop.name == "authority.before_protection_zone"

    def test_a_train_running_on_a_stale_status_is_caught(self, tmp_path, monkeypatch):
        """The ATS status node letting the train run on a stale status: the monitor stops the run on ATS-04; with
        that check off, the leader runs into the zone the lost status would have set."""
        path = tmp_path / "ats.toml"
        path.write_text(FAULT_LINE.format(leader=ATS_LOST, line=ATS_LINE.format(zone_m=1900), duration_s=40))
        monkeypatch.setattr(simulator, "ATS_STATUS", STALE_STATUS_IGNORED)
        with pytest.raises(PropertyViolation) as caught:
            Simulation(load_scenario(path)).run()
        assert caught.value.prop.name == "ats_status.stale_status_stops"
        unchecked = tuple(p for p in simulator.ATS_STATUS_PROPERTIES if p.name != caught.value.prop.name)
        monkeypatch.setattr(simulator, "ATS_STATUS_PROPERTIES", unchecked)
        with pytest.raises(SafetyViolation, match="entered the protection zone at 1900 m"):
            Simulation(load_scenario(path)).run()

    def test_the_zone_check_itself(self):
        scenario = load_scenario(resolve("seed000_protection_zone"))
        sim = Simulation(scenario)
        sim.trains[0].front_m, sim.trains[0].last_distance_m = 5000.5, 1.0
        with pytest.raises(SafetyViolation, match="entered the protection zone at 5000 m"):
            sim._check()
        sim = Simulation(scenario)
        for _ in range(3):
            sim.step()
        sim.trains[0].front_m += 10.0  # moved with no tachometer reading, no tag
        with pytest.raises(SafetyViolation, match=r"true front \d+\.\d+ m is outside the position interval"):
            sim.step()

    def test_runs_are_deterministic(self, runs):
        _, records = runs["seed000_slow_leader"]
        again = []
        sim = Simulation(
            load_scenario(resolve("seed000_slow_leader")),
            on_cycle=lambda s: again.append([dict(t.last) for t in s.trains]),
        )
        for _ in range(600):
            sim.step()
        assert again == records[:600]


HIGH_SPEED = """name = "high_speed"
seed = "001 §3.2"
description = "Two trains at up to {kmh} km/h: a cycle runs several tag windows."
duration_s = {duration_s}
cycle_s = 0.1

[line]
length_m = 30000
tag_spacing_m = 100
resource_length_m = 500
max_ma_m = 8000
speed_limits = [{{ start_m = 0, kmh = {kmh} }}]

[atp]
mode = "relative_braking"
safety_margin_m = 20
report_timeout_s = 2
tag_window_m = 1
tacho_error = 0.01

[ato]
planning_decel_kmhps = 1.5
margin_m = 30

[[trains]]
name = "T1"
preset = "seed000"
front_m = 3000
max_speed_kmh = {kmh}

[[trains]]
name = "T2"
preset = "seed000"
front_m = 1000
max_speed_kmh = {kmh}
depart_s = 10
"""


class TestHighSpeed:
    """Tags are read with the tachometer's distance since their passage, so the position holds at any speed at
    which a cycle passes at most one tag: the every-cycle position check (the true front in the interval) stays
    on."""

    @pytest.mark.slow
    @pytest.mark.parametrize(("kmh", "duration_s", "reached_kmh"), [(160, 120, 155), (300, 300, 290)])
    def test_two_trains_run_at_speed_with_the_position_checked(self, tmp_path, kmh, duration_s, reached_kmh):
        path = tmp_path / "fast.toml"
        path.write_text(HIGH_SPEED.format(kmh=kmh, duration_s=duration_s))
        sim, records = _run(load_scenario(path))
        leader = _train(sim, "T1")
        assert leader.stats.max_speed_kmh >= reached_kmh and leader.stats.emergency_brakes == 0
        assert all(r[k]["position_valid"] for r in records[1:] for k in range(2))
        per_cycle_m = max(r[0]["speed_kmh"] for r in records) / 36
        assert per_cycle_m > 8 * float(sim.scenario.tag_window_m) if kmh == 300 else per_cycle_m > 4

    def test_a_train_passing_two_tags_in_a_cycle_is_stopped(self):
        sim = Simulation(load_scenario(resolve("seed000_normal")))
        sim.trains[0].speed_mps = 2500.0  # 250 m in a cycle on a line with a tag every 100 m
        with pytest.raises(SafetyViolation, match=r"past 2 tags \(from 11100 m\): the position node reads at most one"):
            sim.step()


class TestCommandLine:
    def test_summary_and_csv_trace(self, tmp_path, capsys):
        trace = tmp_path / "t.csv"
        assert main(["sim", "seed000_protection_zone", "--trace", str(trace)]) == 0
        text = capsys.readouterr().out
        assert "no violation" in text and "4982.2" in text
        lines = trace.read_text().splitlines()
        assert lines[0].startswith("train,t_s,front_m,speed_kmh") and len(lines) == 1 + 2500

    def test_jsonl_trace_and_violation_exit_code(self, tmp_path, capsys, monkeypatch):
        trace = tmp_path / "t.jsonl"
        monkeypatch.setattr(simulator, "AUTHORITY", ZONE_IGNORED)
        assert main(["sim", "seed000_protection_zone", "--trace", str(trace)]) == 1
        assert "violation:" in capsys.readouterr().out
        rows = [json.loads(line) for line in trace.read_text().splitlines()]
        assert rows and rows[0]["train"] == "T1"

    def test_a_violation_without_trace_writes_the_last_cycles(self, tmp_path, capsys, monkeypatch):
        monkeypatch.chdir(tmp_path)
        monkeypatch.setattr(simulator, "AUTHORITY", ZONE_IGNORED)
        assert main(["sim", "seed000_protection_zone"]) == 1
        text = capsys.readouterr().out
        assert "authority.before_protection_zone" in text and "seed000_protection_zone_violation.csv" in text
        lines = (tmp_path / "seed000_protection_zone_violation.csv").read_text().splitlines()
        assert lines[0].startswith("train,t_s,front_m") and len(lines) == 1 + 600

    def test_plots(self, tmp_path, capsys):
        out = tmp_path / "plots"
        assert main(["sim", "seed000_protection_zone", "--plot", str(out)]) == 0
        files = sorted(p.name for p in out.iterdir())
        assert files == ["T1_speed_distance.png", "time_distance.png"]
        assert all((out / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for f in files)
        assert f"plot: {out / 'time_distance.png'}" in capsys.readouterr().out

    @pytest.mark.parametrize(
        ("argv", "message"),
        [
            (["sim", "seed000_nosuch"], "nor a shipped scenario"),
            (["sim", "seed000_normal", "--trace", "t.txt"], "must end in .csv or .jsonl"),
            (["sim", "seed000_normal", "--trace", "/nonexistent/t.csv"], "does not exist"),
            (["sim", "seed000_normal", "--plot", "/dev/null"], "exists and is not a directory"),
        ],
    )
    def test_bad_input_is_one_line_and_exit_2(self, argv, message, capsys):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1


class TestTrainDataFiles:
    """A scenario's train may be a train data file (docs/train-data.md) instead of a seed's preset."""

    NORMAL = resolve("seed000_normal").read_text(encoding="utf-8")
    GAMMA = Path(__file__).parents[2] / "model" / "trains" / "gamma_passenger_P.toml"

    def _scenario(self, tmp_path, train_text: str) -> Path:
        (tmp_path / "train.toml").write_text(train_text, encoding="utf-8")
        path = tmp_path / "s.toml"
        path.write_text(self.NORMAL.replace('preset = "seed000"', 'file = "train.toml"'), encoding="utf-8")
        return path

    def test_a_gamma_train_from_its_file_runs_the_line(self, tmp_path):
        text = self.GAMMA.read_text().replace(
            "t_traction_cut_off_s = 0", "t_traction_cut_off_s = 0.5\nmax_acceleration_mps2 = 0.8"
        )
        scenario = load_scenario(self._scenario(tmp_path, text))
        (t1, _) = scenario.trains
        assert t1.data.train_length_m == 600 and t1.data.t_traction_s == Fraction(1, 2)
        sim, _ = _run(scenario)  # every property and safety check held at every cycle (a violation raises)
        for t in sim.trains:
            assert t.stats.distance_m > 3000 and (t.stats.emergency_brakes, t.stats.service_brakes) == (0, 0)
            assert t.stats.max_speed_kmh > 79

    def test_the_build_up_times_are_rounded_up_to_whole_cycles(self, tmp_path):
        text = self.GAMMA.read_text().replace("t_brake_emergency_s = 2.5", "t_brake_emergency_s = 2.53")
        (t1, _) = load_scenario(self._scenario(tmp_path, text)).trains
        assert t1.data.t_be_s == Fraction(26, 10) and t1.data.t_traction_s == Fraction(1, 10)

    @pytest.mark.parametrize(
        ("change", "message"),
        [
            (
                ('file = "train.toml"', 'file = "train.toml"\npreset = "seed000"'),
                "trains[0].file = 'train.toml' and preset both given",
            ),
            (('file = "train.toml"', 'file = "none.toml"'), "trains[0].file: "),
        ],
    )
    def test_bad_train_files_are_named(self, tmp_path, change, message):
        path = self._scenario(tmp_path, self.GAMMA.read_text())
        _assert_refused(tmp_path, path.read_text(), change, message)

    def test_a_stepped_emergency_brake_is_refused(self, tmp_path):
        lam = (Path(__file__).parents[2] / "model" / "trains" / "lambda_passenger_P_100.toml").read_text()
        with pytest.raises(ScenarioError, match=r"gives an emergency brake of 4 speed steps: the simulated plant"):
            load_scenario(self._scenario(tmp_path, lam))


class TestConfiguredLines:
    """A scenario's line may be a configuration's (docs/configuration.md): its length, speed limits and gradients."""

    SEEDS = Path(__file__).parents[2] / "model" / "configurations" / "seeds.toml"
    NORMAL = resolve("seed000_normal").read_text(encoding="utf-8")

    def _text(self, configuration: str, line: str = 'line = "design"\n') -> str:
        text = self.NORMAL.replace("length_m = 15000\n", f'configuration = "{configuration}"\n{line}')
        text = text.replace("speed_limits = [{ start_m = 0, kmh = 80 }]\n", "")
        return text.replace("front_m = 11000", "front_m = 2000").replace("front_m = 10000", "front_m = 1000")

    def test_a_configured_line_is_run(self, tmp_path):
        path = tmp_path / "s.toml"
        path.write_text(self._text(str(self.SEEDS)).replace("duration_s = 320", "duration_s = 120"))
        scenario = load_scenario(path)
        assert scenario.line_m == 5000
        assert [(g.start_m, g.value) for g in scenario.gradients_permille] == [(0, -40), (2500, 40)]
        assert [(g.start_m, g.value) for g in scenario.speed_limits_kmh] == [(0, 80)]
        sim, _ = _run(scenario)  # a violation raises
        assert all(t.stats.distance_m > 1000 for t in sim.trains)

    @pytest.mark.parametrize(
        ("change", "message"),
        [
            (('line = "design"', 'line = "main"'), "line.line = 'main' names no line of"),
            (('line = "design"', 'line = "design"\nlength_m = 5000'), "line.length_m = 5000 and line.configuration"),
            (("seeds.toml", "missing.toml"), "line.configuration: "),
        ],
    )
    def test_bad_configured_lines_are_named(self, tmp_path, change, message):
        _assert_refused(tmp_path, self._text(str(self.SEEDS)), change, message)

    LINE_DATA = """
tag_spacing_m = 100
resource_length_m = 500
stations = [{ name = "Mid", stop_m = 3500, dwell_s = 20 }]

[[lines.platforms.table]]
start_m = 3250
length_m = 300
side = "right"
"""

    def _configured(self, tmp_path, line_data: str = LINE_DATA) -> Path:
        config = self.SEEDS.read_text(encoding="utf-8").replace(
            "gradients = [{ start_m = 0, permille = -40 }, { start_m = 2500, permille = 40 }]\n",
            "gradients = [{ start_m = 0, permille = -40 }, { start_m = 2500, permille = 40 }]\n" + line_data,
        )
        path = tmp_path / "line.toml"
        path.write_text(config, encoding="utf-8")
        return path

    def test_a_configured_lines_tags_resources_platforms_and_stations_are_the_scenarios(self, tmp_path):
        text = self._text("line.toml").replace("tag_spacing_m = 100\n", "").replace("resource_length_m = 500\n", "")
        text = text.replace("duration_s = 320", "duration_s = 300").replace(
            "tacho_error = 0.01\n", "tacho_error = 0.01\nstop_tolerance_m = 5\n"
        )
        path = tmp_path / "s.toml"
        path.write_text(text, encoding="utf-8")
        self._configured(tmp_path)
        scenario = load_scenario(path)
        assert scenario.tags.positions_m[1] == 100 and scenario.resources[1].start_m == 500
        assert [(p.start_m, p.end_m, p.side) for p in scenario.platforms] == [(3250, 3550, "right")]
        assert [(s.name, s.stop_m, s.dwell_s) for s in scenario.stations] == [("Mid", 3500, 20)]
        sim, _ = _run(scenario)  # a violation raises
        assert [t.stats.station_stops for t in sim.trains] == [1, 1]

    @pytest.mark.parametrize(
        ("scenario_adds", "message"),
        [
            ("", "line.tag_spacing_m = 100 and line.configuration's line both give it"),
            ("[platforms]\npacket = '00'\nreference_m = 0\n", "platforms = "),
        ],
    )
    def test_line_data_given_twice_is_refused(self, tmp_path, scenario_adds, message):
        self._configured(tmp_path)
        text = self._text("line.toml")
        if scenario_adds:
            text = text.replace("tag_spacing_m = 100\n", "").replace("resource_length_m = 500\n", "")
        _assert_refused(tmp_path, text + "\n" + scenario_adds, ("", ""), message)

    def test_a_line_name_needs_a_configuration(self, tmp_path):
        text = self.NORMAL.replace("length_m = 15000\n", 'length_m = 15000\nline = "design"\n')
        _assert_refused(tmp_path, text, ("tag_spacing_m", "tag_spacing_m"), "line.line = 'design' needs line.config")
