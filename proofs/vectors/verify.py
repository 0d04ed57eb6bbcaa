"""``atcs vectors verify``: re-check vector files against the model as it is now.

For each file: the goals and vectors must match the manifest's SHA-256 (an edited file fails), the CSV its
SHA-256 and the vectors, and the model's source its hash (a changed model is reported). Every vector is then
re-computed two ways, each compared exactly with its expected next state and outputs:

- symbolically: the values substituted into the z3 terms of the node's step, simplified to constants;
- on the exact backend.

Each coverage claim is re-checked on the vectors too: a boundary vector is at (or the stated distance from) its
comparison's threshold, the two vectors of an MC/DC pair differ in the condition and in the decision's outcome
(and, for unique cause, in no other condition of the decision), a requirement vector meets the assumptions of
its property.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import z3

from atcs.model.node import as_dict
from atcs.model.ops.symbolic import unwrap
from atcs.proofs.cex.trace import format_value
from atcs.proofs.vectors.files import VectorFile, edits, model_sha256, read
from atcs.proofs.vectors.generate import Vector, expected
from atcs.proofs.vectors.goals import BOUNDARY_DELTA, Decision, StepFrame, boundaries, decisions, gap

_OFFSETS = {"at": Fraction(0), "below": -BOUNDARY_DELTA, "above": BOUNDARY_DELTA}


@dataclass
class Verified:
    path: Path
    function: str
    vectors: int
    problems: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems


def _constant(value, ctx):
    if isinstance(value, bool):
        return z3.BoolVal(value, ctx)
    return z3.Q(value.numerator, value.denominator, ctx)


class _Evaluator:
    """Substitutes a vector's values into terms over a :class:`StepFrame`'s variables."""

    def __init__(self, frame: StepFrame):
        self.frame = frame

    def pairs(self, v: Vector):
        pairs = []
        for role, values in (("params", v.params), ("state", v.state), ("inputs", v.inputs)):
            for name, var in as_dict(getattr(self.frame, role)).items():
                value = values[name]
                for x, y in zip(var, value, strict=True) if isinstance(var, tuple) else ((var, value),):
                    term = unwrap(x)
                    pairs.append((term, _constant(y, term.ctx)))
        return pairs

    def value(self, term: z3.ExprRef, pairs):
        """The constant ``term`` takes, or None when it does not simplify to one (division by zero)."""
        t = z3.simplify(z3.substitute(term, *pairs))
        if z3.is_true(t):
            return True
        if z3.is_false(t):
            return False
        if z3.is_rational_value(t):
            return t.as_fraction()
        return None


def _flat_expected(v: Vector) -> dict[str, object]:
    flat = {}
    for role, record in (("next_state", v.next_state), ("outputs", v.outputs)):
        for name, value in record.items():
            if isinstance(value, tuple):
                flat.update({f"{role}.{name}[{j}]": x for j, x in enumerate(value)})
            else:
                flat[f"{role}.{name}"] = value
    return flat


def _show(value) -> str:
    text = format_value(value)
    return json.dumps(text) if isinstance(text, (bool, list)) else str(text)


def _check_hashes(vf: VectorFile, problems: list[str]) -> None:
    m = vf.manifest
    problems += edits(vf)
    source = model_sha256()
    if source != m["model_sha256"]:
        problems.append(
            f"the model changed since the vectors were generated: its source hashes to {source}, "
            f"the manifest says {m['model_sha256']}"
        )
    for j, raw in enumerate(vf.raw):
        floats, exact = raw["expected_float"], raw["expected"]
        if any(
            _as_float(exact[role].get(n)) != floats[role].get(n)
            for role in ("next_state", "outputs")
            for n in exact[role]
        ):
            problems.append(
                f"vector {raw['id']} (vectors[{j}]): expected_float is not the nearest double of every expected number"
            )


def _as_float(raw):
    if isinstance(raw, list):
        return [_as_float(x) for x in raw]
    return raw if isinstance(raw, bool) else repr(float(Fraction(raw)))


def _check_vector(vf: VectorFile, ev: _Evaluator, v: Vector, problems: list[str]) -> None:
    want = _flat_expected(v)
    pairs = ev.pairs(v)
    for where, term in ev.frame.results():
        got = ev.value(term, pairs)
        if got is None or got != want[where]:
            problems.append(
                f"vector {v.id}: {where} is {_show(want[where])} in the file, the symbolic "
                f"model gives {'no constant' if got is None else _show(got)}"
            )
            return
    computed = Vector(v.id, v.context, v.params, v.state, v.inputs)
    try:
        expected(vf.node, computed)
    except (ArithmeticError, ValueError) as exc:
        problems.append(f"vector {v.id}: the exact model refuses it: {exc}")
        return
    got = _flat_expected(computed)
    for where, value in want.items():
        if got[where] != value:
            problems.append(
                f"vector {v.id}: {where} is {_show(value)} in the file, the exact model gives {_show(got[where])}"
            )
            return


def _check_claims(vf: VectorFile, ev: _Evaluator, problems: list[str]) -> None:
    frame = ev.frame
    found = decisions(frame)
    by_decision = {d.id: d for d in found}
    comparisons = [c for c, _ in boundaries(found)]
    contexts = {c.property.name: c.term for c in frame.contexts}
    pairs_of = {v.id: ev.pairs(v) for v in vf.vectors}
    mcdc: dict[str, dict[str, Vector]] = {}
    masking = {g.get("id") for g in vf.goals if isinstance(g, dict) and str(g.get("text", "")).endswith("(masking)")}
    for v in vf.vectors:
        pairs = pairs_of[v.id]
        if v.context and (v.context not in contexts or ev.value(contexts[v.context], pairs) is not True):
            problems.append(f"vector {v.id}: it is not in the environment of {v.context!r}")
        for claim in v.covers:
            ident = claim.split(" ", 1)[0]
            if ident.startswith("B") and ident[1:].isdigit():
                j, label = int(ident[1:]), claim.split(" ")[1]
                if not 1 <= j <= len(comparisons) or ev.value(gap(comparisons[j - 1]), pairs) != _OFFSETS.get(label):
                    problems.append(f"vector {v.id}: it is not at boundary {claim}")
            elif ident.startswith("D") and "." in ident:
                mcdc.setdefault(ident, {})[claim.rsplit("(", 1)[-1].rstrip(")")] = v
    _check_mcdc_pairs(ev, mcdc, by_decision, pairs_of, masking, problems)


def _check_mcdc_pairs(
    ev: _Evaluator,
    mcdc: dict[str, dict[str, Vector]],
    by_decision: dict[str, Decision],
    pairs_of: dict[str, list],
    masking: set[str],
    problems: list[str],
) -> None:
    """Each MC/DC pair claimed: its two vectors differ in the condition and the decision, and (unless the goal is
    masking MC/DC) in no other condition."""
    for ident, pair in mcdc.items():
        d_id, c_id = ident.split(".")
        d = by_decision.get(d_id)
        j = int(c_id[1:]) if c_id[1:].isdigit() else 0
        if d is None or not 1 <= j <= len(d.conditions) or set(pair) != {"pair a", "pair b"}:
            problems.append(f"MC/DC {ident}: no such condition, or its pair is incomplete")
            continue
        a, b = (pairs_of[pair[side].id] for side in ("pair a", "pair b"))
        c = d.conditions[j - 1]
        if ev.value(c, a) == ev.value(c, b) or ev.value(d.term, a) == ev.value(d.term, b):
            problems.append(
                f"MC/DC {ident}: vectors {pair['pair a'].id} and {pair['pair b'].id} do not differ in "
                "both the condition and the decision"
            )
        elif ident not in masking and any(ev.value(o, a) != ev.value(o, b) for o in d.conditions if o is not c):
            problems.append(
                f"MC/DC {ident}: vectors {pair['pair a'].id} and {pair['pair b'].id} differ in another condition too"
            )


def verify_file(path: str | Path, configured: dict | None = None) -> Verified:
    """Re-check one vector file (see the module docstring), a configuration's with its nodes ``configured``
    (:func:`~atcs.proofs.engine.suite.configured_nodes`: the properties are the configuration's, and their data
    must be those the vectors were made with); raises VectorFileError if it is malformed."""
    from atcs.proofs.engine.suite import configuration_data_sha256
    from atcs.properties import PROPERTIES

    vf = read(path, configured)
    result = Verified(vf.path, vf.node.name, len(vf.vectors))
    _check_hashes(vf, result.problems)
    made_for = vf.manifest.get("configuration")
    if made_for is None:
        props = tuple(p for p in PROPERTIES.values() if p.node is vf.node)
    else:
        props = configured[vf.node.name][1]
        if configuration_data_sha256(props) != made_for["data_sha256"]:
            result.problems.append(
                f"the configuration's data for {vf.node.name} changed since the vectors were made "
                f"(manifest.configuration.data_sha256 {made_for['data_sha256'][:12]}...)"
            )
    ev = _Evaluator(StepFrame(vf.node, props))
    for v in vf.vectors:
        _check_vector(vf, ev, v, result.problems)
    _check_claims(vf, ev, result.problems)
    return result
