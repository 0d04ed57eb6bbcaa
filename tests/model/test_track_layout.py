"""A line's tags and resources one by one (docs/configuration.md, "Tags, resources and switches"): read into the
configuration's line, and every bad value refused naming the file, the entry, the field and the value."""

import pytest

from atcs.model.configuration import ConfigurationError, load_configuration

from .test_configuration import CONFIG, _write

LAYOUT = """
tags = [{ id = 1, position_m = 0 }, { id = 2, position_m = 5 }, { id = 11, position_m = 200 }]
resources = [
    { id = 1, kind = "track", start_m = 0, end_m = 480 },
    { id = 2, kind = "switch", start_m = 480, end_m = 540, direction = "reverse" },
    { id = 3, kind = "track", start_m = 540, end_m = 3000 },
]
switch_throw_s = 6
"""


def _line_with(tmp_path, layout: str):
    text = CONFIG.replace('name = "short"', 'name = "short"\n' + layout)
    return load_configuration(_write(tmp_path, text)).lines[0]


def test_tags_resources_and_the_throw_time_are_read(tmp_path):
    line = _line_with(tmp_path, LAYOUT)
    assert line.tags.ids == (1, 2, 11) and line.tags.positions_m == (0, 5, 200)
    assert [(r.id, r.kind, r.start_m, r.end_m, r.direction) for r in line.resources] == [
        (1, "track", 0, 480, None),
        (2, "switch", 480, 540, "reverse"),
        (3, "track", 540, 3000, None),
    ]
    assert line.switch_throw_s == 6 and line.tag_spacing_m is None


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("{ id = 2, position_m = 5 }", "{ id = 1, position_m = 5 }", "lines[0].tags[1]: id = 1 duplicates the id of"),
        ("{ id = 2, position_m = 5 }", "{ id = 2, position_m = 0 }", "lines[0].tags[1]: position_m = 0 is not after"),
        ("{ id = 2, position_m = 5 }", "{ id = 2.5, position_m = 5 }", "lines[0].tags[1]: id = 2.5 is not a whole"),
        ("{ id = 2, position_m = 5 }", "{ id = 2 }", "lines[0].tags[1]: position_m is missing"),
        ("{ id = 2, position_m = 5 }", "{ id = 2, position_m = 5, x = 1 }", "lines[0].tags[1]: unknown field 'x'"),
        ("{ id = 11, position_m = 200 }", "{ id = 11, position_m = 3001 }", "tags[2].position_m = 3001 is off the"),
        ("tags = [", "tags = 3 #", "lines[0].tags = 3 must be a list of tables"),
        ('start_m = 480, end_m = 540, direction = "reverse"', "start_m = 480, end_m = 540", "a switch needs direction"),
        ('kind = "switch"', 'kind = "points"', "lines[0].resources[1]: kind = 'points' is not one of track, switch"),
        ("start_m = 540, end_m = 3000", "start_m = 540, end_m = 2000", "resources[2].end_m = 2000 must be the line's"),
        ("start_m = 0, end_m = 480", "start_m = 10, end_m = 480", "lines[0].resources[0].start_m = 10 must be 0"),
        ("start_m = 540, end_m = 3000", "start_m = 550, end_m = 3000", "start_m = 550 does not continue"),
        ("switch_throw_s = 6", "switch_throw_s = 0", "lines[0].switch_throw_s = 0 must be positive"),
        ("switch_throw_s = 6", "switch_throw_s = 61", "lines[0].switch_throw_s = 61 is above 60 s"),
        ("switch_throw_s = 6", "", "lines[0].switch_throw_s is missing: resource 2 is a switch"),
        ("tags = [", "tag_spacing_m = 100\ntags = [", "lines[0].tags = [{'id': 1, "),
    ],
)
def test_a_bad_layout_is_refused_naming_the_entry_and_the_value(tmp_path, old, new, message):
    assert old in LAYOUT
    with pytest.raises(ConfigurationError) as caught:
        _line_with(tmp_path, LAYOUT.replace(old, new, 1))
    assert str(caught.value).startswith(str(tmp_path)) and message in str(caught.value), caught.value


def test_a_throw_time_without_a_switch_is_refused(tmp_path):
    tracks = 'resources = [{ id = 1, kind = "track", start_m = 0, end_m = 3000 }]\nswitch_throw_s = 6\n'
    with pytest.raises(ConfigurationError, match=r"switch_throw_s = 6 is given, but lines\[0\].resources has no"):
        _line_with(tmp_path, tracks)


def test_both_forms_of_the_tags_are_refused_with_both_named(tmp_path):
    with pytest.raises(ConfigurationError, match=r"and lines\[0\].tag_spacing_m both given"):
        _line_with(tmp_path, "tag_spacing_m = 100\n" + LAYOUT)
