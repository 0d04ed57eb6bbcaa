"""Kept verdicts (``atcs prove --cache``): reused while the property, its data and every source it imports are
unchanged, proved again otherwise; only ``proved`` is kept."""

import dataclasses
from fractions import Fraction

from atcs.proofs.cli import main
from atcs.proofs.engine import cache as verdict_cache
from atcs.proofs.engine.cache import VerdictCache, fingerprint
from atcs.proofs.engine.prove import Result
from atcs.properties import PROPERTIES

CURVE = "curves.spacing_seed000"
DOOR = "doors.enable_left_only_at_platform_stop"


def test_a_second_run_reuses_the_proved_verdicts(tmp_path, capsys):
    argv = ["prove", "--only", CURVE, "--only", DOOR, "--cache", str(tmp_path / "c"), "--cex-dir", str(tmp_path)]
    assert main(argv) == 0
    assert "reused" not in capsys.readouterr().out
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"reused 2 proved verdicts from {tmp_path / 'c'}: {CURVE}, {DOOR}" in out


def test_a_change_outside_what_a_property_imports_keeps_its_fingerprint(monkeypatch):
    curve, door = PROPERTIES[CURVE], PROPERTIES[DOOR]
    before = fingerprint(curve, PROPERTIES), fingerprint(door, PROPERTIES)
    real = verdict_cache._source

    def edited(module):
        source = real(module)
        return source + b"\n# edited\n" if module == "atcs.model.doors" and source is not None else source

    monkeypatch.setattr(verdict_cache, "_source", edited)
    assert fingerprint(curve, PROPERTIES) == before[0]  # curves do not import the doors
    assert fingerprint(door, PROPERTIES) != before[1]


def test_other_data_is_another_fingerprint():
    prop = PROPERTIES[CURVE]
    other = dataclasses.replace(prop, fixed_params={**prop.fixed_params, "t_driver_s": Fraction(5)})
    assert fingerprint(other, PROPERTIES) != fingerprint(prop, PROPERTIES)


def test_a_lemma_is_part_of_the_fingerprint(monkeypatch):
    prop = next(p for p in PROPERTIES.values() if p.lemmas)
    before = fingerprint(prop, PROPERTIES)
    lemma = PROPERTIES[prop.lemmas[0]]
    monkeypatch.setitem(PROPERTIES, lemma.name, dataclasses.replace(lemma, text=lemma.text + " (changed)"))
    assert fingerprint(prop, PROPERTIES) != before


def test_only_proved_is_kept_and_a_bad_file_is_proved_again(tmp_path):
    cache, prop = VerdictCache(tmp_path, PROPERTIES), PROPERTIES[CURVE]
    cache.put(prop, Result(prop.name, prop.requirement, "unknown", "", None, 1.0))
    assert cache.get(prop) is None and not list(tmp_path.iterdir())
    cache.put(prop, Result(prop.name, prop.requirement, "proved", "k-induction", 0, 1.0))
    assert cache.get(prop).status == "proved"
    (path,) = tmp_path.iterdir()
    path.write_bytes(b"not a pickle")
    assert cache.get(prop) is None
