"""A line's infrastructure from a railML 3.1 or 3.2 file, as a configuration's ``[[lines]]`` table
(docs/configuration.md#railml-3-import has the mapping).

The line is a chain of micro-level net elements, each one's end joined to the next one's start by a
``<netRelation>`` (``positionOnA="1" positionOnB="0"``); its positions are metres from the first one's start.
Speed sections (``functionalInfrastructure/speeds/speedSection``, km/h) and gradient curves
(``geometry/gradientCurves/gradientCurve``, per mille, uphill positive) located on the chain by
``<linearLocation>/<associatedNetElement>`` (``posBegin``/``posEnd`` in metres, ``intrinsicCoordBegin``/``End``
of the element's length, or neither: the whole element) give the speed limits and the gradients. Where speed
sections overlap the lowest limit holds; a vertical arc's gradient is the lower of its two ends (the one a
braking curve must assume). Platform edges (``functionalInfrastructure/platformEdges/platformEdge``, railML 3.2)
located the same way give the platforms: their side is the ``lateralSide`` of the location's linear coordinates,
relative to the net element's direction (as railML.org's own example data uses it), their height ``@height`` in
metres. Balise groups (and balises of no group) at their ``<spotLocation>`` give the tags (:func:`_tags`); the
switches the line runs through, in the direction it takes them, give its switch resources (:func:`_switches`).
Every other element is listed as not used. A file that cannot be read this way is refused naming the
element, the attribute and the value (:class:`RailmlError`).
"""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from atcs.model.errors import AtcsInputError
from atcs.model.numbers import exact_number

__all__ = ["NAMESPACES", "ImportedLine", "RailmlError", "import_line", "line_toml"]

NAMESPACES = ("https://www.railml.org/schemas/3.1", "https://www.railml.org/schemas/3.2")
"""The railML 3 versions read."""

_USED = {
    "netElements",
    "netRelations",
    "speeds",
    "gradientCurves",
    "platformEdges",
    "balises",
    "baliseGroups",
    "switchesIS",
}
"""The containers the import reads; the others' elements are listed as not used."""


class RailmlError(AtcsInputError):
    """A railML file that cannot be imported: the message names the file, the element, the attribute, the value."""


@dataclass(frozen=True)
class ImportedLine:
    """A line from railML: its length (m), speed limits ``(start_m, kmh)`` and gradients ``(start_m, permille)``
    from 0, its platforms ``(start_m, end_m, side, height_mm or None)``, its tags ``(position_m, id, railML id)``,
    its resources ``(start_m, end_m, kind, direction or None, railML id or None)`` where it has switches, and the
    elements of the file it does not use, with their count (``("<signalIS>", 1)``)."""

    name: str
    length_m: Fraction
    speed_limits: tuple[tuple[Fraction, Fraction], ...]
    gradients: tuple[tuple[Fraction, Fraction], ...]
    not_used: tuple[tuple[str, int], ...]
    platforms: tuple[tuple[Fraction, Fraction, str, int | None], ...] = ()
    tags: tuple[tuple[Fraction, int, str], ...] = ()
    resources: tuple[tuple[Fraction, Fraction, str, str | None, str | None], ...] = ()

    @property
    def switches(self) -> int:
        return sum(kind == "switch" for _, _, kind, _, _ in self.resources)


class _File:
    def __init__(self, path: str | Path):
        self.source = str(path)
        try:
            root = ET.parse(path).getroot()
        except OSError as exc:
            raise RailmlError(f"{path}: cannot read the railML file: {exc.strerror}") from None
        except ET.ParseError as exc:
            raise RailmlError(f"{path}: not well-formed XML: {exc}") from None
        namespace, _, tag = root.tag[1:].partition("}") if root.tag.startswith("{") else ("", "", root.tag)
        if tag != "railML" or namespace not in NAMESPACES:
            raise RailmlError(
                f"{path}: the root element is {root.tag!r}, not <railML> of railML 3.1 or 3.2 ({', '.join(NAMESPACES)})"
            )
        self.root, self.ns = root, namespace

    def q(self, path: str) -> str:
        return "/".join(part if part in (".", "..", "*") else f"{{{self.ns}}}{part}" for part in path.split("/"))

    def all(self, path: str) -> list[ET.Element]:
        return self.root.findall(self.q(path))

    def fail(self, element: ET.Element, attribute: str, problem: str):
        tag = element.tag.rpartition("}")[2]
        where = f"<{tag} id={element.get('id')!r}>" if element.get("id") else f"<{tag}>"
        raise RailmlError(f"{self.source}: {where} {attribute} = {element.get(attribute)!r} {problem}")

    def number(self, element: ET.Element, attribute: str, *, required: bool = True) -> Fraction | None:
        raw = element.get(attribute)
        if raw is None:
            if required:
                self.fail(element, attribute, "is missing")
            return None
        try:
            value = exact_number(raw)
        except ValueError as exc:
            self.fail(element, attribute, str(exc))
        if abs(value) > 10**7:
            self.fail(element, attribute, "is out of range")
        return value


def _relations(f: _File, lengths: dict[str, Fraction]) -> dict[str, tuple[str, str]]:
    """The passable ``<netRelation>``s joining one net element's end to another's start: id -> (first, then)."""
    relations = {}
    for r in f.all("infrastructure/topology/netRelations/netRelation"):
        a, b = r.find(f.q("elementA")), r.find(f.q("elementB"))
        if a is None or b is None:
            f.fail(r, "elementA" if a is None else "elementB", "is missing")
        if r.get("navigability") == "None" or a.get("ref") not in lengths or b.get("ref") not in lengths:
            continue
        ends = (r.get("positionOnA"), r.get("positionOnB"))
        if ends in (("1", "0"), ("0", "1")):
            first, then = (a, b) if ends == ("1", "0") else (b, a)
            relations[r.get("id")] = (first.get("ref"), then.get("ref"))
    return relations


def _checked_order(f: _File, lengths: dict[str, Fraction], joins: dict, order: list[str]) -> list[str]:
    for ref in order:
        if ref not in lengths:
            raise RailmlError(f"{f.source}: --net-elements names {ref!r}, which is no net element with a length")
    for a, b in itertools.pairwise(order):
        if b not in joins.get(a, []):
            raise RailmlError(f"{f.source}: no <netRelation> joins the end of {a!r} to the start of {b!r}")
    return order


def _chain(f: _File, lengths: dict[str, Fraction], relations: dict, order: list[str] | None) -> list[str]:
    """The net elements of the line in order: ``order`` checked, or the one chain the relations make."""
    joins: dict[str, list[str]] = {}
    for first, then in relations.values():
        joins.setdefault(first, []).append(then)
    if order:
        return _checked_order(f, lengths, joins, order)
    branching = sorted(a for a, bs in joins.items() if len(bs) > 1)
    if branching:
        raise RailmlError(
            f"{f.source}: the topology branches after net element {branching[0]!r}: name the line's net elements "
            "in order (--net-elements)"
        )
    starts = [ref for ref in lengths if not any(ref in bs for bs in joins.values())]
    if len(starts) != 1:
        raise RailmlError(
            f"{f.source}: the net elements make {len(starts)} chains, not one: name the line's net elements in order "
            "(--net-elements)"
        )
    chain = [starts[0]]
    while chain[-1] in joins and len(chain) <= len(lengths):
        chain.append(joins[chain[-1]][0])
    return chain


def _interval(f: _File, part: ET.Element, length: Fraction) -> tuple[Fraction, Fraction]:
    """The ``[begin, end]`` (m from the net element's start) an ``<associatedNetElement>`` covers."""
    if part.get("posBegin") is not None or part.get("posEnd") is not None:
        begin, end = f.number(part, "posBegin"), f.number(part, "posEnd")
    elif part.get("intrinsicCoordBegin") is not None or part.get("intrinsicCoordEnd") is not None:
        begin, end = f.number(part, "intrinsicCoordBegin") * length, f.number(part, "intrinsicCoordEnd") * length
    elif part.find(f.q("linearCoordinateBegin")) is not None:
        f.fail(part, "posBegin", "is missing: a location by linear coordinates alone is not read")
    else:
        begin, end = Fraction(0), length
    begin, end = min(begin, end), max(begin, end)
    if begin < 0 or end > length:
        f.fail(
            part,
            "posEnd" if end > length else "posBegin",
            f"lies outside {part.get('netElementRef')!r} (0 to {length} m)",
        )
    return begin, end


def _pieces(f: _File, element: ET.Element, offsets: dict[str, Fraction], lengths: dict[str, Fraction]):
    """The ``[begin, end)`` intervals (m on the line) that ``element``'s linear locations cover on the chain (a
    location for trains running the other way only, ``applicationDirection="reverse"``, is left out)."""
    locations = element.findall(f.q("linearLocation"))
    if not locations:
        f.fail(element, "linearLocation", "is missing: the element is not located")
    pieces = []
    for location in (loc for loc in locations if loc.get("applicationDirection") != "reverse"):
        for part in location.findall(f.q("associatedNetElement")):
            ref = part.get("netElementRef")
            if ref is None:
                f.fail(part, "netElementRef", "is missing")
            if ref in offsets:  # else off the line
                begin, end = _interval(f, part, lengths[ref])
                if end > begin:
                    pieces.append((offsets[ref] + begin, offsets[ref] + end))
    return pieces


def _profile(f: _File, what: str, covered: list, length_m: Fraction) -> tuple[tuple[Fraction, Fraction], ...]:
    """``covered`` ``(begin, end, value)`` as segments from 0 to ``length_m``, the lowest value where they overlap;
    a stretch nothing covers is refused."""
    cuts = sorted({Fraction(0), length_m, *(x for b, e, _ in covered for x in (b, e) if 0 < x < length_m)})
    segments = []
    for a, b in itertools.pairwise(cuts):
        values = [v for begin, end, v in covered if begin <= a and b <= end]
        if not values:
            raise RailmlError(f"{f.source}: no {what} covers the line from {float(a):g} m to {float(b):g} m")
        if not segments or segments[-1][1] != min(values):
            segments.append((a, min(values)))
    return tuple(segments)


def _lengths(f: _File) -> dict[str, Fraction]:
    """The micro-level net elements' lengths (an aggregate of others, meso or macro level, is left out)."""
    lengths = {}
    for e in f.all("infrastructure/topology/netElements/netElement"):
        if e.find(f.q("elementCollectionOrdered")) is not None or e.find(f.q("elementCollectionUnordered")) is not None:
            continue
        length = f.number(e, "length")
        if not length > 0:
            f.fail(e, "length", "must be positive")
        lengths[e.get("id")] = length
    if not lengths:
        raise RailmlError(f"{f.source}: no <netElement> with a length (infrastructure/topology/netElements)")
    return lengths


def _speed_sections(f: _File, offsets: dict, lengths: dict) -> list:
    speeds = []
    for s in f.all("infrastructure/functionalInfrastructure/speeds/speedSection"):
        if s.get("maxSpeed") == "end":
            f.fail(s, "maxSpeed", "(the end of a restriction) is not read: give the limit that follows")
        kmh = f.number(s, "maxSpeed")
        if not kmh > 0:
            f.fail(s, "maxSpeed", "must be positive")
        speeds += [(b, e, kmh) for b, e in _pieces(f, s, offsets, lengths)]
    return speeds


def _gradient_curves(f: _File, offsets: dict, lengths: dict) -> list:
    gradients = []
    for g in f.all("infrastructure/geometry/gradientCurves/gradientCurve"):
        if g.get("curveType") not in ("straight", "arc", "mixed"):
            f.fail(g, "curveType", "must be straight, arc or mixed")
        permille = f.number(g, "gradient")
        delta = f.number(g, "deltaGradient", required=False) or Fraction(0)
        gradients += [(b, e, min(permille, permille + delta)) for b, e in _pieces(f, g, offsets, lengths)]
    return gradients


MAX_PLATFORM_HEIGHT_M = 2
"""The highest platform edge read (m): railML gives the height in metres, so a larger value is likely millimetres."""


def _lateral_side(f: _File, edge: ET.Element) -> str:
    """The side of a platform edge: the ``lateralSide`` of its linear coordinates, the same along the edge."""
    sides = set()
    for location in edge.findall(f.q("linearLocation")):
        if location.get("applicationDirection") == "reverse":
            continue  # for trains running the other way: left out, as by _pieces
        for part in location.findall(f.q("associatedNetElement")):
            coordinates = [
                c for tag in ("linearCoordinateBegin", "linearCoordinateEnd") if (c := part.find(f.q(tag))) is not None
            ]
            if not coordinates:
                f.fail(part, "linearCoordinateBegin", "is missing: a platform edge's side is its lateralSide")
            for c in coordinates:
                if c.get("lateralSide") not in ("left", "right", "both"):
                    f.fail(c, "lateralSide", "must be left, right or both")
                sides.add(c.get("lateralSide"))
    if len(sides) > 1:
        f.fail(edge, "lateralSide", f"differs along the edge ({', '.join(sorted(sides))})")
    return sides.pop()


def _platform_edges(f: _File, offsets: dict, lengths: dict) -> tuple:
    """The platforms of the platform edges on the line: each edge's pieces joined where they meet."""
    platforms = []
    for edge in f.all("infrastructure/functionalInfrastructure/platformEdges/platformEdge"):
        height = f.number(edge, "height", required=False)
        if height is not None and not 0 < height <= MAX_PLATFORM_HEIGHT_M:
            f.fail(edge, "height", f"is outside (0, {MAX_PLATFORM_HEIGHT_M}] m (railML gives it in metres)")
        pieces = sorted(_pieces(f, edge, offsets, lengths))
        if not pieces:
            continue  # off the line
        side = _lateral_side(f, edge)
        joined = [list(pieces[0])]
        for begin, end in pieces[1:]:
            if begin <= joined[-1][1]:
                joined[-1][1] = max(joined[-1][1], end)
            else:
                joined.append([begin, end])
        height_mm = None if height is None else round(height * 1000)
        platforms += [(begin, end, side, height_mm) for begin, end in joined]
    return tuple(sorted(platforms))


_FUNCTIONAL = "infrastructure/functionalInfrastructure"
_TRUE = ("true", "1")
"""The xs:boolean spellings of true."""
MAX_GROUP_ID = 16383
"""The largest ETCS balise group id, NID_BG (Subset-026 §7.5.1.86)."""
MAX_COUNTRY_ID = 1023
"""The largest ETCS country or region id, NID_C (Subset-026 §7.5.1.80)."""


def _spot_m(f: _File, element: ET.Element, offsets: dict, lengths: dict) -> Fraction | None:
    """Where ``element``'s ``<spotLocation>`` on the line lies (m from its start); None if none is on the line."""
    for spot in element.findall(f.q("spotLocation")):
        ref = spot.get("netElementRef")
        if ref is None:
            f.fail(spot, "netElementRef", "is missing")
        if ref not in offsets:
            continue
        attribute = "pos" if spot.get("pos") is not None else "intrinsicCoord"
        if spot.get(attribute) is None:
            f.fail(spot, "pos", "is missing (and intrinsicCoord): the spot is not located")
        at = f.number(spot, attribute) * (1 if attribute == "pos" else lengths[ref])
        if not 0 <= at <= lengths[ref]:
            f.fail(spot, attribute, f"lies outside {ref!r} (0 to {lengths[ref]} m)")
        return offsets[ref] + at
    return None


def _tags(f: _File, offsets: dict, lengths: dict) -> tuple[tuple, int]:
    """The line's tags: a balise group each (railML 3.2 ``<baliseGroup>``, 3.1 ``<balise isBaliseGroup="true">``;
    its members fold into it), and each balise of no group; and how many lie off the line. A tag's id is its
    group's NID_BG (``isEurobaliseGroup@groupID``, with ``countryID * 16384`` added where the countries differ)
    when every tag has one, else 1, 2, ... in line order."""
    groups = {g.get("id"): g for g in f.all(f"{_FUNCTIONAL}/baliseGroups/baliseGroup")}
    balises = f.all(f"{_FUNCTIONAL}/balises/balise")
    groups.update({b.get("id"): b for b in balises if b.get("isBaliseGroup") in _TRUE})
    members: dict[str, list[ET.Element]] = {}
    singles = []
    for b in balises:
        if b.get("isBaliseGroup") in _TRUE:
            continue
        attribute = "belongsToBaliseGroup" if b.get("belongsToBaliseGroup") is not None else "belongsToParent"
        parent = b.get(attribute)
        if parent is None:
            singles.append(b)
        elif parent not in groups:
            f.fail(b, attribute, "names no balise group")
        else:
            members.setdefault(parent, []).append(b)
    located, off = [], 0
    for element in [*groups.values(), *singles]:
        spotted = [element] if element.find(f.q("spotLocation")) is not None else members.get(element.get("id"), [])
        if not any(e.find(f.q("spotLocation")) is not None for e in spotted):
            f.fail(element, "spotLocation", "is missing (on the group and its balises): the tag is not located")
        places = [x for e in spotted if (x := _spot_m(f, e, offsets, lengths)) is not None]
        if places:
            located.append((min(places), element))
        else:
            off += 1
    located.sort(key=lambda pair: pair[0])
    for (x, a), (y, b) in itertools.pairwise(located):
        if x == y:
            f.fail(b, "id", f"lies at {x} m on the line, as {a.get('id')!r} does: two tags at one place")
    return tuple((x, tag_id, e.get("id")) for (x, e), tag_id in zip(located, _tag_ids(f, located), strict=True)), off


def _tag_ids(f: _File, located: list) -> list[int]:
    euro = [e.find(f.q("isEurobaliseGroup")) for _, e in located]
    if not euro or any(e is None for e in euro):
        return list(range(1, len(located) + 1))
    for e in euro:
        country = f.number(e, "countryID")
        if country.denominator != 1 or not 0 <= country <= MAX_COUNTRY_ID:
            f.fail(e, "countryID", f"is not NID_C, a whole number from 0 to {MAX_COUNTRY_ID}")
    countries = {f.number(e, "countryID") for e in euro}
    ids, seen = [], {}
    for e in euro:
        group = f.number(e, "groupID")
        if group.denominator != 1 or not 0 <= group <= MAX_GROUP_ID:
            f.fail(e, "groupID", f"is not NID_BG, a whole number from 0 to {MAX_GROUP_ID}")
        tag_id = int(group + (f.number(e, "countryID") * (MAX_GROUP_ID + 1) if len(countries) > 1 else 0))
        if tag_id in seen:
            f.fail(e, "groupID", "is the id of another balise group of the line")
        seen[tag_id] = e
        ids.append(tag_id)
    return ids


_BRANCHES = {"leftBranch": "left", "rightBranch": "right", "straightBranch": "straight", "turningBranch": "turning"}


def _course(f: _File, switch: ET.Element, course: str) -> str:
    """The direction (``normal``, ``reverse``) a switch lies in for its ``course`` branch: a switch crossing's
    straight branch is normal, its turning one reverse; a left or right branch is normal where it is the
    ``continueCourse`` (or the other one is the ``branchCourse``)."""
    if course in ("straight", "turning"):
        return "normal" if course == "straight" else "reverse"
    for attribute in ("continueCourse", "branchCourse"):
        if switch.get(attribute) not in (None, "left", "right"):
            f.fail(switch, attribute, "must be left or right")
    if switch.get("continueCourse") is not None:
        return "normal" if switch.get("continueCourse") == course else "reverse"
    if switch.get("branchCourse") is not None:
        return "reverse" if switch.get("branchCourse") == course else "normal"
    f.fail(switch, "continueCourse", "is missing (and branchCourse): which course is the switch's normal one")


def _switch_extent(f: _File, switch, branch, pair, relations: dict, offsets: dict, lengths: dict, default_m):
    """The ``[start, end)`` a switch the line passes from net element ``pair[0]`` to ``pair[1]`` covers: its
    linear location, else its branch's ``length`` (else ``default_m``, the user's) from the junction towards its
    branches (ahead where the switch parts in the line's direction, its toe on ``pair[0]``; behind where it
    joins)."""
    if switch.find(f.q("linearLocation")) is not None:
        pieces = _pieces(f, switch, offsets, lengths)
        if not pieces:
            f.fail(switch, "linearLocation", "lies off the line that runs through the switch")
        return min(b for b, _ in pieces), max(e for _, e in pieces)
    length = f.number(branch, "length", required=False)
    if length is None and default_m is None:
        f.fail(
            branch, "length", "is missing, and so is the switch's linearLocation: give its extent (--switch-length-m)"
        )
    if length is None:
        length = Fraction(default_m)
    elif not length > 0:
        f.fail(branch, "length", "must be positive")
    ends = [relations[r] for e in switch if (r := e.get("netRelationRef")) in relations and relations[r] != pair]
    common = {x for other in ends for x in set(other) & set(pair)}
    if len(common) != 1:
        f.fail(switch, "id", "has no other branch on a net relation: the toe (which side it parts) is unknown")
    junction_m = offsets[pair[1]]
    return (junction_m, junction_m + length) if common == {pair[0]} else (junction_m - length, junction_m)


def _switches(f: _File, chain: list, relations: dict, offsets: dict, lengths: dict, length_m, default_m) -> tuple:
    """The switches the line runs through, ``(start_m, end_m, direction, railML id)`` in line order, and how many
    switches of the file it does not; ``default_m``: the extent of a switch with neither a linear location nor a
    branch length (None: such a switch is refused)."""
    branches = {}
    switches = f.all(f"{_FUNCTIONAL}/switchesIS/switchIS")
    for switch in switches:
        for tag, course in _BRANCHES.items():
            for branch in switch.findall(f.q(tag)):
                if branch.get("netRelationRef") is None:
                    f.fail(branch, "netRelationRef", "is missing")
                branches[branch.get("netRelationRef")] = (switch, course, branch)
    joining = {pair: r for r, pair in relations.items()}
    found = []
    for pair in itertools.pairwise(chain):
        if joining[pair] not in branches:
            continue
        switch, course, branch = branches[joining[pair]]
        start, end = _switch_extent(f, switch, branch, pair, relations, offsets, lengths, default_m)
        if start < 0 or end > length_m:
            f.fail(branch, "length", f"takes the switch off the line ({float(start):g} m to {float(end):g} m)")
        found.append((start, end, _course(f, switch, course), switch.get("id")))
    for (_, end, _, a), (start, _, _, b) in itertools.pairwise(found):
        if start < end:
            raise RailmlError(f"{f.source}: <switchIS id={b!r}> overlaps <switchIS id={a!r}> on the line")
    return found, len(switches) - len(found)


def _resources(switches: list, length_m: Fraction) -> tuple:
    """The line's resources where it runs through switches: each switch, and a track resource between them."""
    if not switches:
        return ()
    resources, x = [], Fraction(0)
    for start, end, direction, railml_id in switches:
        if start > x:
            resources.append((x, start, "track", None, None))
        resources.append((start, end, "switch", direction, railml_id))
        x = end
    if x < length_m:
        resources.append((x, length_m, "track", None, None))
    return tuple(resources)


def _not_used(f: _File) -> tuple[tuple[str, int], ...]:
    """The elements of the topology, functional infrastructure and geometry views the import does not read."""
    counts = Counter()
    for view in ("topology", "functionalInfrastructure", "geometry"):
        for group in f.all(f"infrastructure/{view}/*"):
            if group.tag.rpartition("}")[2] not in _USED:
                counts.update(f"<{child.tag.rpartition('}')[2]}>" for child in group)
    return tuple(sorted(counts.items()))


def import_line(
    path: str | Path, name: str, net_elements: list[str] | None = None, switch_length_m: Fraction | None = None
) -> ImportedLine:
    """The line of the railML file ``path`` (module docstring), named ``name``; ``net_elements`` orders its net
    elements where the topology alone does not (a branching line); ``switch_length_m`` is the extent of a switch
    the file gives neither a linear location nor a branch length (None: such a switch is refused)."""
    f = _File(path)
    lengths = _lengths(f)
    relations = _relations(f, lengths)
    chain = _chain(f, lengths, relations, net_elements)
    offsets = dict(zip(chain, itertools.accumulate([Fraction(0), *(lengths[r] for r in chain)]), strict=False))
    length_m = sum(lengths[r] for r in chain)
    tags, tags_off = _tags(f, offsets, lengths)
    switches, switches_off = _switches(f, chain, relations, offsets, lengths, length_m, switch_length_m)
    off = [("<balise> (group) off the line", tags_off), ("<switchIS> the line does not run through", switches_off)]
    if len(tags) == 1:
        tags, off = (), [*off, ("<balise> (group): a line's tags need at least 2, the line has 1", 1)]
    return ImportedLine(
        name=name,
        length_m=length_m,
        speed_limits=_profile(f, "<speedSection>", _speed_sections(f, offsets, lengths), length_m),
        gradients=_profile(f, "<gradientCurve>", _gradient_curves(f, offsets, lengths), length_m),
        not_used=tuple(sorted([*_not_used(f), *((what, n) for what, n in off if n)])),
        platforms=_platform_edges(f, offsets, lengths),
        tags=tags,
        resources=_resources(switches, length_m),
    )


def line_toml(line: ImportedLine, switch_throw_s: Fraction | None = None) -> str:
    """The line as a configuration's ``[[lines]]`` table (TOML); a line with switches needs ``switch_throw_s``,
    which railML does not give."""
    if line.switches and switch_throw_s is None:
        raise ValueError(f"the line runs through {line.switches} switches: their throw time is needed")

    def number(x: Fraction) -> str:
        return str(x.numerator) if x.denominator == 1 else repr(float(x)) if float(x) == x else f'"{x}"'

    rows = [
        "[[lines]]",
        f"name = {line.name!r}".replace("'", '"'),
        f"length_m = {number(line.length_m)}",
        "speed_limits = [",
        *(f"  {{ start_m = {number(s)}, kmh = {number(v)} }}," for s, v in line.speed_limits),
        "]",
        "gradients = [",
        *(f"  {{ start_m = {number(s)}, permille = {number(v)} }}," for s, v in line.gradients),
        "]",
    ]
    if line.tags:
        rows += [
            "tags = [",
            *(f"  {{ id = {tag_id}, position_m = {number(x)} }},  # {railml_id}" for x, tag_id, railml_id in line.tags),
            "]",
        ]
    if line.resources:
        rows.append("resources = [")
        for k, (start, end, kind, direction, railml_id) in enumerate(line.resources, start=1):
            switch = f', direction = "{direction}" }},  # {railml_id}' if kind == "switch" else " },"
            rows.append(f'  {{ id = {k}, kind = "{kind}", start_m = {number(start)}, end_m = {number(end)}{switch}')
        rows += ["]", f"switch_throw_s = {number(Fraction(switch_throw_s))}"]
    if line.platforms:
        rows += [
            "[lines.platforms]",
            "table = [",
            *(
                f'  {{ start_m = {number(b)}, length_m = {number(e - b)}, side = "{side}"'
                + ("" if height is None else f", height_mm = {height}")
                + " },"
                for b, e, side, height in line.platforms
            ),
            "]",
        ]
    return "\n".join(rows) + "\n"
