"""Properties proved in parts: a property that comes back ``unknown`` and has a split
(:attr:`~atcs.properties.property.Property.split`) is proved as its two halves, each claimed on half of a parameter's
range, and a half that comes back ``unknown`` is split again, down to the split's resolution.

A parameter keeps its value for the whole run, so the property holds on every run if it holds on the runs of each
half: the property is proved when every part is, and otherwise takes the worst part's verdict (falsified with that
part's counterexample, replayed against the part), never better. The parts are properties like any other, named
``<name>_h0`` and ``<name>_h1``; :class:`PropertyRegistry` makes them from those names, so workers, the verdict
cache and the certificates find them by name.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator

from atcs.proofs.engine.prove import Result
from atcs.properties.property import Property

__all__ = ["WORST_FIRST", "PropertyRegistry", "combined", "covering_parts", "leaves", "prove_in_parts"]

WORST_FIRST = ("error", "falsified", "vacuous", "unknown", "proved")
"""Verdicts from worst to best: a property proved in parts takes its worst part's."""

_PART = re.compile(r"^(.+)_h([01])$")


class PropertyRegistry(dict):
    """Properties by name, which also makes the parts of a split property from their names (``<name>_h0`` is the
    first half of the property ``<name>``, itself possibly a part)."""

    def __missing__(self, name: str) -> Property:
        match = _PART.match(name) if isinstance(name, str) else None
        if match is None:
            raise KeyError(name)
        whole = self[match.group(1)]
        if whole.split is None:
            raise KeyError(name)
        part = whole.split()[int(match.group(2))]
        self[name] = part
        return part

    def __contains__(self, name) -> bool:
        try:
            self[name]
        except KeyError:
            return False
        return True

    def get(self, name, default=None):
        try:
            return self[name]
        except KeyError:
            return default


def combined(prop: Property, whole: Result, parts: tuple[Result, Result]) -> Result:
    """The verdict of ``prop`` from its halves' (``whole`` is its own ``unknown`` attempt, whose time counts)."""
    status = min((r.status for r in parts), key=WORST_FIRST.index)
    first = next(r for r in leaves(parts) if r.status == status)
    counts = {s: sum(s == r.status for r in leaves(parts)) for s in WORST_FIRST}
    message = f"{sum(counts.values())} parts: " + ", ".join(f"{n} {s}" for s, n in counts.items() if n)
    if status != "proved":
        message += f"; {first.name}: {first.message}"
    depths = [r.k for r in parts if r.k is not None]
    return Result(
        prop.name,
        prop.requirement,
        status,
        "split",
        max(depths) if status == "proved" and depths else None,
        whole.seconds + sum(r.seconds for r in parts),
        message,
        trace=first.trace if status == "falsified" else None,
        replay=first.replay if status == "falsified" else None,
        parts=parts,
    )


def leaves(results: Iterable[Result]) -> Iterator[Result]:
    """The results proved directly, not in parts, under ``results`` (each in order)."""
    for r in results:
        if r.parts:
            yield from leaves(r.parts)
        else:
            yield r


def covering_parts(name: str, proved: Iterable[str]) -> list[str] | None:
    """The names among ``proved`` that together make the property ``name``: itself, or parts of it whose bands
    cover its own (each half covered, recursively); None when they do not."""
    proved = set(proved)

    def cover(whole: str) -> list[str] | None:
        if whole in proved:
            return [whole]
        if not any(n.startswith(f"{whole}_h") for n in proved):
            return None
        lower, upper = cover(f"{whole}_h0"), cover(f"{whole}_h1")
        return None if lower is None or upper is None else lower + upper

    return cover(name)


def prove_in_parts(props: list[Property], run: Callable[[list[Property]], Iterable[Result]]) -> Iterator[Result]:
    """Yield one result per property of ``props`` as they finish, those that come back ``unknown`` proved in parts
    (module docstring). ``run`` proves a list of properties, yielding their results as they finish; each round of
    halves is one call, so its workers prove them side by side."""
    made = {p.name: p for p in props}
    whole_of: dict[str, str] = {}
    attempts: dict[str, Result] = {}
    finished: dict[str, Result] = {}

    def settle(result: Result) -> Result | None:
        """Record ``result``; the result of the property of ``props`` it completes, if it completes one."""
        while result.name in whole_of:
            finished[result.name] = result
            name = whole_of[result.name]
            halves = (f"{name}_h0", f"{name}_h1")
            if not all(h in finished for h in halves):
                return None
            result = combined(made[name], attempts.pop(name), tuple(finished.pop(h) for h in halves))
        return result

    level = list(props)
    while level:
        following = []
        for result in run(level):
            prop = made[result.name]
            if result.status == "unknown" and prop.split is not None:
                attempts[prop.name] = result
                halves = prop.split()
                if tuple(h.name for h in halves) != (f"{prop.name}_h0", f"{prop.name}_h1"):
                    raise ValueError(f"{prop.name}: its split must give {prop.name}_h0 and {prop.name}_h1")
                for half in halves:
                    made[half.name], whole_of[half.name] = half, prop.name
                    following.append(half)
            elif (done := settle(result)) is not None:
                yield done
        level = following
