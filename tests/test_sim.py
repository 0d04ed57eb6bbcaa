"""The closed-loop simulator (issue 8): scenarios are validated, the seed 000 runs reproduce the seed's outcomes,
the checks catch a broken model, runs are deterministic, and ``atcs sim`` reports them."""

import json

import pytest

from atcs.model.authority import AUTHORITY
from atcs.proofs.cli import main
from atcs.proofs.mutants import mutant_node
from atcs.sim import simulator
from atcs.sim.monitor import PropertyViolation
from atcs.sim.scenario import ScenarioError, load_scenario, resolve, shipped
from atcs.sim.simulator import SafetyViolation, Simulation

ZONE_IGNORED = mutant_node(AUTHORITY, "zone = o.ite(i.zone_active, i.zone_start_m, o.const(FAR_M))",
                           "zone = o.const(FAR_M)")
"""The authority node with the protection zone ignored."""
SEED000 = ("seed000_normal", "seed000_service_brake_disabled", "seed000_slow_leader", "seed000_protection_zone")


@pytest.fixture(scope="module")
def runs():
    """Each seed 000 scenario run once to its end, with its per-cycle records."""
    results = {}
    for name in SEED000:
        records = []
        sim = Simulation(load_scenario(resolve(name)),
                         on_cycle=lambda s, r=records: r.append([dict(t.last) for t in s.trains]))
        results[name] = (sim.run(), records)
    return results


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
        assert (s.line_m, s.tag_spacing_m, len(s.trains), s.trains[0].data.train_length_m) == (15000, 100, 2, 200)
        assert [str(x) for x in (s.trains[0].max_speed_kmh, s.speed_limits_kmh[0].value)] == ["80", "80"]

    @pytest.mark.parametrize(("change", "message"), [
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
        (("speed_limits = [{ start_m = 0, kmh = 80 }]", "speed_limits = [{ start_m = 5, kmh = 80 }]"),
         "line.speed_limits[0].start_m = 5 must be 0 for the first segment"),
    ])
    def test_errors_name_the_file_the_field_and_the_value(self, tmp_path, change, message):
        text = shipped()["seed000_normal"].read_text()
        old, new = change
        assert old in text
        path = tmp_path / "bad.toml"
        path.write_text(text.replace(old, new, 1))
        with pytest.raises(ScenarioError) as caught:
            load_scenario(path)
        assert str(caught.value).startswith(str(path)) and message in str(caught.value), caught.value

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

    def test_train_stops_before_the_protection_zone(self, runs):
        sim, _ = runs["seed000_protection_zone"]
        (train,) = sim.trains
        assert 4950 < train.front_m < 5000 and train.speed_mps == 0
        assert (train.stats.emergency_brakes, train.stats.service_brakes) == (0, 0)


class TestChecks:
    def test_an_authority_that_ignores_the_zone_is_caught(self, monkeypatch):
        monkeypatch.setattr(simulator, "AUTHORITY", ZONE_IGNORED)
        with pytest.raises(PropertyViolation) as caught:
            Simulation(load_scenario(resolve("seed000_protection_zone"))).run()
        assert caught.value.prop.name == "authority.before_protection_zone"

    def test_the_zone_check_itself(self):
        scenario = load_scenario(resolve("seed000_protection_zone"))
        sim = Simulation(scenario)
        sim.trains[0].front_m = 5000.5
        with pytest.raises(SafetyViolation, match="entered the protection zone at 5000 m"):
            sim.step()

    def test_runs_are_deterministic(self, runs):
        _, records = runs["seed000_slow_leader"]
        again = []
        sim = Simulation(load_scenario(resolve("seed000_slow_leader")),
                         on_cycle=lambda s: again.append([dict(t.last) for t in s.trains]))
        for _ in range(600):
            sim.step()
        assert again == records[:600]


class TestCommandLine:
    def test_summary_and_csv_trace(self, tmp_path, capsys):
        trace = tmp_path / "t.csv"
        assert main(["sim", "seed000_protection_zone", "--trace", str(trace)]) == 0
        text = capsys.readouterr().out
        assert "no violation" in text and "4984" in text
        lines = trace.read_text().splitlines()
        assert lines[0].startswith("train,t_s,front_m,speed_kmh") and len(lines) == 1 + 2500

    def test_jsonl_trace_and_violation_exit_code(self, tmp_path, capsys, monkeypatch):
        trace = tmp_path / "t.jsonl"
        monkeypatch.setattr(simulator, "AUTHORITY", ZONE_IGNORED)
        assert main(["sim", "seed000_protection_zone", "--trace", str(trace)]) == 1
        assert "violation:" in capsys.readouterr().out
        rows = [json.loads(line) for line in trace.read_text().splitlines()]
        assert rows and rows[0]["train"] == "T1"

    def test_plots(self, tmp_path, capsys):
        out = tmp_path / "plots"
        assert main(["sim", "seed000_protection_zone", "--plot", str(out)]) == 0
        files = sorted(p.name for p in out.iterdir())
        assert files == ["T1_speed_distance.png", "time_distance.png"]
        assert all((out / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for f in files)
        assert f"plot: {out / 'time_distance.png'}" in capsys.readouterr().out

    @pytest.mark.parametrize(("argv", "message"), [
        (["sim", "seed000_nosuch"], "nor a shipped scenario"),
        (["sim", "seed000_normal", "--trace", "t.txt"], "must end in .csv or .jsonl"),
        (["sim", "seed000_normal", "--trace", "/nonexistent/t.csv"], "does not exist"),
        (["sim", "seed000_normal", "--plot", "/dev/null"], "exists and is not a directory"),
    ])
    def test_bad_input_is_one_line_and_exit_2(self, argv, message, capsys):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1
