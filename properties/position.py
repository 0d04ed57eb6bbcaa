"""Properties of position determination and loss of position (seed 001 §3.2, Fig. 4 and 7; seed 002 §3.1).

Over :data:`~atcs.model.position_loop.POSITION_LOOP` (the position node between the
true motion and supervision), for a tag table of :data:`~atcs.model.position.PROOF_TAGS`
tags with symbolic ids and positions, and symbolic tag window, tachometer error,
train length, cycle time and acceleration bounds. Each property assumes only what it
needs: the interval claims hold for *any* motion (forward) at any speed, the speed
claim needs the acceleration bounds. The fault claims are stated from the tag table entry by entry,
not through the node's own lookups.
"""

from __future__ import annotations

from atcs.model.position import MIN_CYCLE_S
from atcs.model.position_loop import POSITION_LOOP
from atcs.properties.property import Assumption, Property
from atcs.properties.supervision import CURVE_ORDER


def _table(o, p, s, i):
    ids, positions = p.tag_ids, p.tag_positions_m
    n = len(ids)
    return o.and_(
        *(o.not_(o.eq(ids[j], ids[k])) for j in range(n) for k in range(j + 1, n)),
        *(positions[j] < positions[j + 1] for j in range(n - 1)),
        o.const(0) <= p.tacho_error,
        p.tacho_error < o.const(1),
        o.const(0) <= p.tag_window_m,
        o.const(0) < p.train_length_m,
        o.const(MIN_CYCLE_S) <= p.cycle_s,
        o.const(0) <= p.max_acceleration_mps2,
        o.const(0) <= p.max_deceleration_mps2,
    )


TABLE = Assumption(
    "table",
    f"tag ids are distinct and positions strictly increase; 0 <= tachometer error < 1, tag window >= 0, train "
    f"length > 0, cycle >= {MIN_CYCLE_S} s, acceleration bounds >= 0",
    _table,
)


def _within_tacho_error(o, p, true_m, measured_m):
    return o.and_(true_m - measured_m <= p.tacho_error * measured_m, measured_m - true_m <= p.tacho_error * measured_m)


TACHOMETER = Assumption(
    "tachometer",
    "the train never moves backward, and the true distance of each cycle, and from a reported tag's passage to "
    "the cycle's end, is within tacho_error * d of the tachometer's d",
    lambda o, p, s, i: o.and_(
        o.const(0) <= i.distance_m,
        _within_tacho_error(o, p, i.distance_m, i.tacho_m),
        o.implies(i.tag_read, _within_tacho_error(o, p, i.distance_since_tag_m, i.since_tag_m)),
    ),
)


def _genuine_tag(o, p, s, i):
    passage = s.front_m + i.distance_m - i.distance_since_tag_m
    return o.implies(
        i.tag_read,
        o.or_(
            *(
                o.and_(o.eq(i.tag_id, tag_id), tag_m - p.tag_window_m <= passage, passage <= tag_m + p.tag_window_m)
                for tag_id, tag_m in zip(p.tag_ids, p.tag_positions_m, strict=True)
            )
        ),
    )


TAG_READER = Assumption(
    "tag_reader",
    "a tag reported is a tag of the table, and the true front was within the tag window of it at the passage "
    "the reader reports (the true distance since the passage before the cycle's end)",
    _genuine_tag,
)


def _kinematics(o, p, s, i):
    dt, zero, two = p.cycle_s, o.const(0), o.const(2)
    a, d = p.max_acceleration_mps2, p.max_deceleration_mps2
    v, v_next, x = s.speed_mps, i.next_speed_mps, i.distance_m
    return o.and_(
        v_next >= zero,
        v_next - v <= a * dt,
        v - v_next <= d * dt,
        x >= v_next * dt - a * dt * dt / two,
        x <= v_next * dt + d * dt * dt / two,
        x - s.last_distance_m <= a * dt * dt,
        s.last_distance_m - x <= d * dt * dt,
        o.implies(o.eq(x, zero), o.eq(v_next, zero)),
    )


KINEMATICS = Assumption(
    "kinematics",
    "the train accelerates at most max_acceleration_mps2 and decelerates at most max_deceleration_mps2 "
    "(so the end speed is within those bounds of the cycle's mean speed, and consecutive cycles' distances "
    "differ by at most A * dt^2), and a train that does not move for a whole cycle is at standstill",
    _kinematics,
)


def _reader_complete(o, p, s, i):
    front = s.front_m
    crossed = [o.and_(front < tag_m, tag_m <= front + i.distance_m) for tag_m in p.tag_positions_m]
    reads = [o.and_(i.tag_read, o.eq(i.tag_id, tag_id)) for tag_id in p.tag_ids]
    positions = p.tag_positions_m
    return o.and_(
        *(positions[j + 1] - positions[j] > i.distance_m for j in range(len(positions) - 1)),
        *(o.eq(c, r) for c, r in zip(crossed, reads, strict=True)),
        o.implies(i.tag_read, o.and_(o.or_(*reads), _passage_in_cycle(o, i))),
    )


def _passage_in_cycle(o, i):
    return o.and_(o.const(0) <= i.since_tag_m, i.since_tag_m <= i.tacho_m)


READER_COMPLETE = Assumption(
    "reader_complete",
    "fault-free tag reader: a tag is reported, with its own id, exactly in the cycle the true front passes it, "
    "its passage inside the cycle (0 <= the tachometer's distance since it <= the cycle's); the train runs less "
    "than the distance between consecutive tags in a cycle (at most one passage per cycle), at any speed",
    _reader_complete,
)


def _entries(p):
    return list(zip(p.tag_ids, p.tag_positions_m, strict=True))


def _next_tag(o, p, s):
    """``[(lrt is tag j, next id, next position)]`` for every tag j that has a next tag in the table."""
    tags = _entries(p)
    return [(o.eq(s.lrt_index, o.const(j)), *tags[j + 1]) for j in range(len(tags) - 1)]


def _odometry(o, p, s, i, j):
    """The min and max safe front past tag j by the tachometer (docs/design.md odometry), before any reset."""
    offset = s.offset_m + i.tacho_m
    ref = p.tag_positions_m[j]
    return (
        ref + (o.const(1) - p.tacho_error) * offset - p.tag_window_m,
        ref + (o.const(1) + p.tacho_error) * offset + p.tag_window_m,
    )


def _reads_next(o, p, s, i):
    return o.and_(i.tag_read, o.or_(*(o.and_(at, o.eq(i.tag_id, next_id)) for at, next_id, _ in _next_tag(o, p, s))))


def _invalid(o, out):
    return o.not_(out.position_valid)


def _lrt_in_table(o, p, s, i, out, nxt):
    return o.or_(*(o.eq(s.lrt_index, o.const(j)) for j in range(len(p.tag_ids))))


def _front_between_lrt_and_next(o, p, s, i, out, nxt):
    positions, n = p.tag_positions_m, len(p.tag_positions_m)
    within = [
        o.and_(
            o.eq(s.lrt_index, o.const(j)),
            positions[j] <= s.front_m,
            *((s.front_m < positions[j + 1],) if j + 1 < n else ()),
        )
        for j in range(n)
    ]
    return o.implies(s.localised, o.or_(*within))


def _front_in_interval(o, p, s, i, out, nxt):
    return o.implies(out.position_valid, o.and_(out.front_min_m <= nxt.front_m, nxt.front_m <= out.front_max_m))


def _front_within_sensor_excess(o, p, s, i, out, nxt):
    excess = nxt.sensor_excess_m
    return o.implies(
        out.position_valid,
        o.and_(out.front_min_m - excess <= nxt.front_m, nxt.front_m <= out.front_max_m + excess),
    )


def _nominal_sensors_add_no_excess(o, p, s, i, out, nxt):
    """The ghost of POS-22 stays as it was through a cycle of the tachometer within its error, and is 0 after a tag
    read within its window (the tachometer within its error since the passage)."""
    reset = o.and_(i.tag_read, out.position_valid)
    passage_m = nxt.front_m - i.distance_since_tag_m
    tag_m = o.select(p.tag_positions_m, nxt.lrt_index)
    in_window = o.and_(tag_m - p.tag_window_m <= passage_m, passage_m <= tag_m + p.tag_window_m)
    return o.and_(
        o.implies(
            o.and_(o.not_(reset), _within_tacho_error(o, p, i.distance_m, i.tacho_m)),
            o.eq(nxt.sensor_excess_m, s.sensor_excess_m),
        ),
        o.implies(
            o.and_(reset, in_window, _within_tacho_error(o, p, i.distance_since_tag_m, i.since_tag_m)),
            o.eq(nxt.sensor_excess_m, o.const(0)),
        ),
    )


def _genuine_tag_corrects(o, p, s, i, out, nxt):
    passage_m = nxt.front_m - i.distance_since_tag_m
    w = p.tag_window_m
    genuine = [
        o.and_(
            o.eq(i.tag_id, p.tag_ids[j]),
            p.tag_positions_m[j] - w <= passage_m,
            passage_m <= p.tag_positions_m[j] + w,
        )
        for j in range(len(p.tag_ids))
    ]
    return o.implies(
        o.and_(i.tag_read, o.or_(*genuine), _within_tacho_error(o, p, i.distance_since_tag_m, i.since_tag_m)),
        o.implies(out.position_valid, o.and_(out.front_min_m <= nxt.front_m, nxt.front_m <= out.front_max_m)),
    )


def _misread_tag_bounded(o, p, s, i, out, nxt):
    positions, n = p.tag_positions_m, len(p.tag_positions_m)
    cases = []
    for j in range(n):
        before_low, before_high = (
            positions[j] + (o.const(1) - p.tacho_error) * s.offset_m - p.tag_window_m,
            positions[j] + (o.const(1) + p.tacho_error) * s.offset_m + p.tag_window_m,
        )
        low, high = _odometry(o, p, s, i, j)
        width = high - low
        cases.append(
            o.implies(
                o.and_(o.eq(s.lrt_index, o.const(j)), before_low <= s.front_m, s.front_m <= before_high),
                o.and_(out.front_min_m - width <= nxt.front_m, nxt.front_m <= out.front_max_m + width),
            )
        )
    return o.implies(o.and_(s.localised, out.position_valid), o.and_(*cases))


def _rear_in_interval(o, p, s, i, out, nxt):
    rear = nxt.front_m - p.train_length_m
    return o.and_(
        o.eq(out.rear_min_m, out.front_min_m - p.train_length_m),
        o.eq(out.rear_max_m, out.front_max_m - p.train_length_m),
        o.eq(out.rear_est_m, out.front_est_m - p.train_length_m),
        o.implies(out.position_valid, o.and_(out.rear_min_m <= rear, rear <= out.rear_max_m)),
    )


def _speed_within_accuracy(o, p, s, i, out, nxt):
    error = nxt.speed_mps - out.speed_est_mps
    return o.and_(error <= out.speed_accuracy_mps, -error <= out.speed_accuracy_mps)


def _supervised_on_true_speed(o, p, s, i, out, nxt):
    v = nxt.speed_mps
    return o.and_(
        o.implies(v > i.ebi_mps, out.emergency_brake),
        o.implies(v > i.sbi_mps, o.or_(out.service_brake, out.emergency_brake)),
        o.implies(v > i.warning_mps, out.warning),
    )


def _no_intervention_at_permitted(o, p, s, i, out, nxt):
    bound = out.speed_est_mps + out.speed_accuracy_mps
    return o.implies(
        o.and_(o.not_(s.eb_latched), out.position_valid, bound <= i.permitted_mps),
        o.not_(o.or_(out.service_brake, out.emergency_brake, out.traction_cut, out.warning)),
    )


def _unknown_tag(o, p, s, i, out, nxt):
    unknown = o.and_(i.tag_read, *(o.not_(o.eq(i.tag_id, tag_id)) for tag_id in p.tag_ids))
    return o.implies(unknown, _invalid(o, out))


def _unexpected_tag(o, p, s, i, out, nxt):
    return o.implies(o.and_(s.localised, i.tag_read, o.not_(_reads_next(o, p, s, i))), _invalid(o, out))


def _from_passage(o, p, i, tag_m):
    """The min and max safe front by the tachometer's distance since the passage of a tag at ``tag_m``."""
    since = i.since_tag_m
    return (
        tag_m + (o.const(1) - p.tacho_error) * since - p.tag_window_m,
        tag_m + (o.const(1) + p.tacho_error) * since + p.tag_window_m,
    )


def _tag_outside_window(o, p, s, i, out, nxt):
    outside = []
    for j, (at, next_id, next_m) in enumerate(_next_tag(o, p, s)):
        low, high = _odometry(o, p, s, i, j)
        tag_low, tag_high = _from_passage(o, p, i, next_m)
        outside.append(o.and_(at, o.eq(i.tag_id, next_id), o.or_(high < tag_low, low > tag_high)))
    return o.implies(o.and_(s.localised, i.tag_read, o.or_(*outside)), _invalid(o, out))


def _tag_passage_outside_cycle(o, p, s, i, out, nxt):
    return o.implies(o.and_(i.tag_read, o.not_(_passage_in_cycle(o, i))), _invalid(o, out))


def _missed_tag(o, p, s, i, out, nxt):
    passed = [
        o.and_(at, _odometry(o, p, s, i, j)[0] > next_m + p.tag_window_m)
        for j, (at, _, next_m) in enumerate(_next_tag(o, p, s))
    ]
    return o.implies(o.and_(s.localised, o.not_(_reads_next(o, p, s, i)), o.or_(*passed)), _invalid(o, out))


def _implausible_tacho(o, p, s, i, out, nxt):
    dt2, slack = p.cycle_s * p.cycle_s, p.tacho_error * (i.tacho_m + s.last_tacho_m)
    change = i.tacho_m - s.last_tacho_m
    implausible = o.or_(
        i.tacho_m < o.const(0),
        change > p.max_acceleration_mps2 * dt2 + slack,
        -change > p.max_deceleration_mps2 * dt2 + slack,
    )
    return o.implies(implausible, _invalid(o, out))


def _confirmation(o, p, s, i, out, nxt):
    return o.and_(
        o.implies(out.position_confirmed, out.position_valid),
        o.implies(o.not_(s.localised), o.not_(out.position_confirmed)),
        o.implies(out.position_confirmed, o.or_(s.confirmed, _reads_next(o, p, s, i))),
    )


def _localises_at_known_tag(o, p, s, i, out, nxt):
    known = o.or_(*(o.eq(i.tag_id, tag_id) for tag_id in p.tag_ids))
    return o.implies(o.and_(o.not_(s.localised), i.tag_read, known, _passage_in_cycle(o, i)), out.position_valid)


def _no_fault_within_window(o, p, s, i, out, nxt):
    w = p.tag_window_m
    within = []
    for j, (at, next_id, next_m) in enumerate(_next_tag(o, p, s)):
        low, high = _odometry(o, p, s, i, j)
        tag_low, tag_high = _from_passage(o, p, i, next_m)
        reads_next_in_window = o.and_(
            i.tag_read, o.eq(i.tag_id, next_id), _passage_in_cycle(o, i), tag_low <= high, low <= tag_high
        )
        not_yet_due = o.and_(o.not_(i.tag_read), low <= next_m + w)
        within.append(o.and_(at, o.or_(reads_next_in_window, not_yet_due)))
    return o.implies(o.and_(s.localised, o.or_(*within)), out.position_valid)


def _property(name, requirement, text, holds, assumptions=(), lemmas=(), seed="001 §3.2"):
    return Property(
        name=f"position.{name}",
        requirement=requirement,
        seed=seed,
        text=text,
        node=POSITION_LOOP,
        holds=holds,
        assumptions=assumptions,
        lemmas=tuple(f"position.{lemma}" for lemma in lemmas),
    )


PROPERTIES = (
    _property("lrt_in_table", "POS-00", "The last read tag is always an entry of the tag table.", _lrt_in_table),
    _property(
        "front_in_interval",
        "POS-01",
        "While the position is valid, the true front is within [min safe front, max safe front], across tag "
        "resets, for any forward motion (tachometer and tag reader within their stated errors).",
        _front_in_interval,
        (TABLE, TACHOMETER, TAG_READER),
        seed="001 §3.2 (Fig. 7), 002 §3.1; docs/design.md odometry",
    ),
    _property(
        "front_within_sensor_excess",
        "POS-22",
        "Under any sensor fault, while the position is valid the true front is within the interval widened on "
        "each side by the sensors' error beyond their stated bounds since the position was last set at a tag: the "
        "tachometer's (a drift, a slide or spin, a standstill or backward reading) summed since the tag's passage, "
        "and the tag's (its passage reported beyond the tag window from the tag whose id was read: a misplaced tag, "
        "a wrong id of the table). Missed tags and reads of ids not in the table at any time. A fault the position "
        "checks do not catch moves the interval off the true front by no more than that.",
        _front_within_sensor_excess,
        (TABLE,),
        seed="001 §3.2 (Fig. 7), 002 §3.1; docs/design.md odometry",
    ),
    _property(
        "nominal_sensors_add_no_excess",
        "POS-25",
        "Sensors within their stated errors add nothing to POS-22's widening: a cycle with the tachometer within its "
        "error and no tag read leaves it as it was, and a tag read within the tag window of the tag whose id was "
        "read, with the tachometer within its error since the passage, sets it to 0. So with sensors that keep to "
        "their bounds POS-22 is POS-01's claim.",
        _nominal_sensors_add_no_excess,
        (TABLE,),
        seed="001 §3.2 (Fig. 7), 002 §3.1; docs/design.md odometry",
    ),
    _property(
        "genuine_tag_corrects",
        "POS-24",
        "A wrong position, however it came (a wrong or misplaced tag, a tachometer fault, an unconfirmed position "
        "set far off), is caught or corrected at the next genuine tag read: a read of a table id whose passage is "
        "reported within the tag window of that tag, with the tachometer within its error since the passage, "
        "either invalidates the position or leaves the true front within the new interval, whatever came before.",
        _genuine_tag_corrects,
        (TABLE,),
        ("front_within_sensor_excess",),
        seed="001 §3.2 (Fig. 7), 002 §3.1",
    ),
    _property(
        "misread_tag_bounded",
        "POS-19",
        "A tag fault the checks let through moves the interval by at most its own width: while the position is "
        "valid with the true front in its interval, a cycle with a tag read of any id at any place (a misplaced "
        "tag, a wrong id of the table, a misreported passage) either invalidates the position or leaves the true "
        "front within the new interval widened by the width of the odometry interval at the read (2 * window + 2 * "
        "tacho_error * the distance since the last tag): the new tag's interval must overlap that one.",
        _misread_tag_bounded,
        (TABLE, TACHOMETER),
        ("lrt_in_table",),
    ),
    _property(
        "rear_in_interval",
        "POS-02",
        "The rear interval and estimate are the front's shifted back by the train length, and while the position "
        "is valid the true rear is within the rear interval.",
        _rear_in_interval,
        (TABLE, TACHOMETER, TAG_READER),
        ("front_in_interval",),
    ),
    _property(
        "speed_within_accuracy",
        "POS-03",
        "The true speed at the end of each cycle is within the stated accuracy (tacho_error * estimate + "
        "max(A, D) * cycle / 2) of the estimated speed (distance per cycle).",
        _speed_within_accuracy,
        (TABLE, TACHOMETER, KINEMATICS),
        seed="001 §3.2, 002 §3.1",
    ),
    _property(
        "unexpected_tag_invalidates",
        "POS-04",
        "A tag read that is not the table's next tag after the last read tag invalidates the position in that cycle.",
        _unexpected_tag,
        (TABLE,),
        ("lrt_in_table",),
    ),
    _property(
        "unknown_tag_invalidates",
        "POS-05",
        "A tag id that is not in the tag table invalidates the position in that cycle.",
        _unknown_tag,
    ),
    _property(
        "tag_outside_window_invalidates",
        "POS-06",
        "The next tag read where the odometry interval from the last read tag and the one from the new tag's "
        "passage (its window plus the tachometer's distance since the passage) do not overlap invalidates the "
        "position in that cycle.",
        _tag_outside_window,
        (TABLE,),
        ("lrt_in_table",),
    ),
    _property(
        "tag_passage_outside_cycle_invalidates",
        "POS-23",
        "A tag read whose passage is not inside the cycle (the tachometer's distance since it negative, or over "
        "the cycle's) invalidates the position in that cycle.",
        _tag_passage_outside_cycle,
    ),
    _property(
        "missed_tag_invalidates",
        "POS-07",
        "Once the min safe front is past the next tag's window without a read of it, the position is invalid in "
        "that cycle.",
        _missed_tag,
        (TABLE,),
        ("lrt_in_table",),
    ),
    _property(
        "implausible_tacho_invalidates",
        "POS-08",
        "A tachometer increment that is negative or changes by more than the acceleration bounds and the "
        "tachometer error allow (standstill while running, spin, slide) invalidates the position in that cycle.",
        _implausible_tacho,
    ),
    _property(
        "eb_while_invalid",
        "POS-09",
        "EB is commanded in every cycle the position is invalid (from power-up until the first tag, and after "
        "any fault).",
        lambda o, p, s, i, out, nxt: o.implies(_invalid(o, out), out.emergency_brake),
    ),
    _property(
        "eb_held_while_moving",
        "POS-10",
        "Once commanded, EB is held while the train moves: it is released only in a cycle in which the train "
        "is truly at standstill.",
        lambda o, p, s, i, out, nxt: o.implies(o.and_(s.eb_latched, nxt.speed_mps > o.const(0)), out.emergency_brake),
        (TABLE, TACHOMETER, KINEMATICS),
        seed="001 §3.2, 000 §2.4.3",
    ),
    _property(
        "front_between_lrt_and_next",
        "POS-11",
        "With a fault-free tag reader, while the position is valid the true front is at or past the last read "
        "tag and short of the next one in the table.",
        _front_between_lrt_and_next,
        (TABLE, TACHOMETER, READER_COMPLETE),
        ("lrt_in_table",),
    ),
    _property(
        "no_false_alarm",
        "POS-12",
        "Availability (so the claims above are not vacuous): with sensors within their stated errors, a "
        "fault-free tag reader and motion within the acceleration bounds, a valid position stays valid.",
        lambda o, p, s, i, out, nxt: o.implies(s.localised, out.position_valid),
        (TABLE, TACHOMETER, TAG_READER, KINEMATICS, READER_COMPLETE),
        ("lrt_in_table", "front_in_interval", "front_between_lrt_and_next"),
    ),
    # the supervision of the measured speed's upper bound (survivors of atcs mutate)
    _property(
        "supervised_on_true_speed",
        "POS-13",
        "The loop supervises the true speed: EB whenever the true speed at the end of the cycle is above EBI, a "
        "brake above SBI, the warning above the warning limit.",
        _supervised_on_true_speed,
        (TABLE, TACHOMETER, KINEMATICS),
        ("speed_within_accuracy",),
        seed="001 §3.2, 000 §2.4.3",
    ),
    _property(
        "no_intervention_at_permitted",
        "POS-14",
        "Not over-restrictive: with EB not latched, the position valid and the speed's upper bound (estimate plus "
        "accuracy) at or under the permitted speed, no brake, no traction cut and no warning.",
        _no_intervention_at_permitted,
        (CURVE_ORDER,),
        seed="001 §3.2, 000 §2.4.2",
    ),
    # the tag checks not stricter than stated (survivors of atcs mutate: POS-12 needs a fault-free reader, so
    # it says nothing at the windows' edges, and nothing from power-up)
    _property(
        "localises_at_known_tag",
        "POS-15",
        "From power-up or after a fault, the first read of a tag of the table with its passage inside the cycle "
        "(tachometer plausible: sensors within their stated errors, motion within the acceleration bounds) makes "
        "the position valid.",
        _localises_at_known_tag,
        (TABLE, TACHOMETER, KINEMATICS),
    ),
    _property(
        "confirmed_by_a_second_tag",
        "POS-20",
        "A position is confirmed only while valid, never in the cycle it is set from an invalid position (power-up, "
        "after a fault: one tag read may be a wrong one), and becomes confirmed only by a read of the table's next "
        "tag from a valid position (checked against the odometry, POS-04..06).",
        _confirmation,
        (TABLE,),
        ("lrt_in_table",),
    ),
    _property(
        "confirmed_at_next_tag",
        "POS-21",
        "Availability of the confirmation: with sensors within their stated errors, a fault-free tag reader and "
        "motion within the acceleration bounds, a valid position is confirmed at the next tag read and stays so.",
        lambda o, p, s, i, out, nxt: o.implies(
            o.and_(s.localised, o.or_(s.confirmed, i.tag_read)), out.position_confirmed
        ),
        (TABLE, TACHOMETER, TAG_READER, KINEMATICS, READER_COMPLETE),
        ("lrt_in_table", "front_in_interval", "front_between_lrt_and_next", "no_false_alarm"),
    ),
    _property(
        "no_fault_within_window",
        "POS-16",
        "The tag window's edges are inclusive: a valid position stays valid when the next tag is read, its passage "
        "inside the cycle, with the odometry interval meeting the one from the passage, or when no tag is read "
        "while the min safe front is not past the next tag's window (tachometer plausible as for POS-15).",
        _no_fault_within_window,
        (TABLE, TACHOMETER, KINEMATICS),
        ("lrt_in_table",),
    ),
)

__all__ = ["KINEMATICS", "PROPERTIES", "READER_COMPLETE", "TABLE", "TACHOMETER", "TAG_READER"]
