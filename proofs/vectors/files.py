"""Test-vector files: JSON with a manifest, and CSV, one of each per function.

``DIR/<function>.json`` holds the manifest, the coverage goals and the vectors; ``DIR/<function>.csv`` is the
same vectors as one table, like the seed's test-case tables (seed 001 Fig. 10 to 12). Numbers are exact
rationals (``"0.1"``, ``"1/3"``); each expected number is also given as the nearest double
(``expected_float``, its shortest decimal), for an implementation in floating point.

The manifest names the function, the requirement ids covered and the coverage achieved, the SHA-256 of the
model's source (every ``.py`` file of :mod:`atcs.model` and :mod:`atcs.properties`, which give the step and
its domain), the tool versions, and the SHA-256 of the goals and vectors (canonical JSON) and of the CSV file.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import platform
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

from atcs.model.data_files import read_json
from atcs.model.errors import AtcsInputError
from atcs.model.node import Node, Sort, flatten
from atcs.proofs.cex import trace
from atcs.proofs.cex.trace import format_value
from atcs.proofs.files import write_atomic
from atcs.proofs.vectors.generate import FunctionVectors, Goal, Vector

FORMAT = "atcs-vectors/1"
_ROLES = (("params", "param"), ("state", "state"), ("inputs", "input"))
_RESULTS = (("next_state", "next"), ("outputs", "out"))


class VectorFileError(AtcsInputError):
    """A vector file is malformed; the message names the file, the field and the value."""


def model_sha256() -> str:
    """SHA-256 over the model's and the properties' source files (relative path and bytes, sorted by path)."""
    import atcs.model
    import atcs.properties

    digest = hashlib.sha256()
    for package in (atcs.model, atcs.properties):
        for root in package.__path__:
            base = Path(root)
            for path in sorted(base.rglob("*.py")):
                digest.update(f"{package.__name__}/{path.relative_to(base).as_posix()}\n".encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()


def tool_versions() -> dict[str, str]:
    import z3

    versions = {"python": platform.python_version(), "z3": z3.get_version_string()}
    try:
        versions["atcs"] = metadata.version("atcs")
    except metadata.PackageNotFoundError:
        versions["atcs"] = "unknown"
    return versions


def _exact(record: dict[str, Any]) -> dict[str, Any]:
    return {n: format_value(v) for n, v in record.items()}


def _float(value):
    if isinstance(value, tuple):
        return [_float(v) for v in value]
    return value if isinstance(value, bool) else repr(float(value))


def vector_json(v: Vector) -> dict[str, Any]:
    return {
        "id": v.id,
        "context": v.context,
        "covers": list(v.covers),
        "params": _exact(v.params),
        "state": _exact(v.state),
        "inputs": _exact(v.inputs),
        "expected": {"next_state": _exact(v.next_state), "outputs": _exact(v.outputs)},
        "expected_float": {
            "next_state": {n: _float(x) for n, x in v.next_state.items()},
            "outputs": {n: _float(x) for n, x in v.outputs.items()},
        },
    }


def goal_json(g: Goal) -> dict[str, str]:
    return {"kind": g.kind, "id": g.id, "text": g.text, "status": g.status, "reason": g.reason}


def content_sha256(goals: list[dict], vectors: list[dict]) -> str:
    """SHA-256 of the goals and vectors as canonical JSON (sorted keys, no spaces)."""
    text = json.dumps({"goals": goals, "vectors": vectors}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def to_csv(vectors: list[dict]) -> str:
    """One row per vector: id, context, covers, then every parameter, state and input field and every expected
    next-state and output field (arrays spread as ``field[j]``), exact; then the expected numbers as doubles."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    if not vectors:
        writer.writerow(["id", "context", "covers"])
        return out.getvalue()
    first = vectors[0]

    def cells(v):
        inputs = [x for role, _ in _ROLES for x in _spread(v[role]).values()]
        results = [x for role, _ in _RESULTS for x in _spread(v["expected"][role]).values()]
        floats = [
            x for role, _ in _RESULTS for x in _spread(v["expected_float"][role]).values() if not isinstance(x, bool)
        ]
        return inputs + results + floats

    header = ["id", "context", "covers"]
    header += [f"{prefix}.{n}" for role, prefix in _ROLES for n in _spread(first[role])]
    header += [f"expected.{prefix}.{n}" for role, prefix in _RESULTS for n in _spread(first["expected"][role])]
    header += [
        f"expected.{prefix}.{n} (double)"
        for role, prefix in _RESULTS
        for n, x in _spread(first["expected_float"][role]).items()
        if not isinstance(x, bool)
    ]
    writer.writerow(header)
    for v in vectors:
        writer.writerow([v["id"], v["context"], "; ".join(v["covers"]), *cells(v)])
    return out.getvalue()


def _spread(record: dict[str, Any]) -> dict[str, Any]:
    return flatten({n: tuple(x) if isinstance(x, list) else x for n, x in record.items()})


def document(fv: FunctionVectors) -> tuple[dict[str, Any], str]:
    """The JSON document and the CSV text of one function's vectors."""
    goals = [goal_json(g) for g in fv.goals]
    vectors = [vector_json(v) for v in fv.vectors]
    csv_text = to_csv(vectors)
    manifest = {
        "function": fv.function,
        "seed": fv.seed,
        "requirements": fv.requirements,
        "requirements_covered": fv.requirements_covered(),
        "coverage": fv.coverage(),
        "vectors": len(vectors),
        "model_sha256": model_sha256(),
        "tools": tool_versions(),
        "content_sha256": content_sha256(goals, vectors),
        "csv_sha256": hashlib.sha256(csv_text.encode()).hexdigest(),
        "generation_s": round(fv.seconds, 3),
    }
    if fv.configuration is not None:
        manifest["configuration"] = fv.configuration
    return {"format": FORMAT, "manifest": manifest, "goals": goals, "vectors": vectors}, csv_text


def write(directory: str | Path, fv: FunctionVectors) -> Path:
    """Write ``<function>.csv`` then ``<function>.json`` (each atomically); returns the JSON path."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    doc, csv_text = document(fv)
    write_atomic(directory / f"{fv.function}.csv", csv_text)
    path = directory / f"{fv.function}.json"
    write_atomic(path, json.dumps(doc, indent=1) + "\n")
    return path


# --- reading -------------------------------------------------------------------------------


@dataclass
class VectorFile:
    path: Path
    node: Node
    manifest: dict[str, Any]
    goals: list[dict[str, Any]]
    raw: list[dict[str, Any]]
    """The vectors as written (for the hashes)."""
    vectors: list[Vector] = field(default_factory=list)


def _need(path, where: str, raw, kind: type, what: str):
    if not isinstance(raw, kind) or (isinstance(raw, bool) and kind is not bool):
        raise VectorFileError(f"{path}: {where} must be {what}, got {raw!r}")
    return raw


def parse_record(path, where: str, raw: Any, sorts: dict[str, Sort]) -> dict[str, Any]:
    return trace.parse_record(str(path), where, raw, sorts, VectorFileError)


def edits(vf: VectorFile) -> list[str]:
    """How the file ``vf`` and its CSV table differ from what was generated, by the manifest's hashes (empty when
    they do not)."""
    m, found = vf.manifest, []
    content = content_sha256(vf.goals, vf.raw)
    if content != m["content_sha256"]:
        found.append(f"edited: the goals and vectors hash to {content}, the manifest says {m['content_sha256']}")
    csv_path = vf.path.with_suffix(".csv")
    if not csv_path.is_file():
        found.append(f"{csv_path.name} is missing" if not csv_path.exists() else f"{csv_path.name} is not a file")
        return found
    try:
        data = csv_path.read_bytes()
    except OSError as exc:
        return [*found, f"{csv_path.name} cannot be read: {exc.strerror}"]
    if hashlib.sha256(data).hexdigest() != m["csv_sha256"]:
        found.append(f"edited: {csv_path.name} does not match the manifest's csv_sha256")
    elif data.decode() != to_csv(vf.raw):  # the generated bytes, UTF-8
        found.append(f"{csv_path.name} is not the table of the JSON file's vectors")
    return found


def read(path: str | Path, configured: dict | None = None) -> VectorFile:
    """Read a vector file; a malformed one raises :class:`VectorFileError` naming the file, field and value. A file
    of a configuration's vectors (its manifest names one) needs the configuration's nodes, ``configured``
    (:func:`~atcs.proofs.engine.suite.configured_nodes`)."""
    from atcs.model import NODES

    path = Path(path)
    doc = read_json(path, VectorFileError, "the vector file")
    _need(path, "the top level", doc, dict, "an object")
    if doc.get("format") != FORMAT:
        raise VectorFileError(f"{path}: field 'format' must be {FORMAT!r}, got {doc.get('format')!r}")
    manifest = _need(path, "field 'manifest'", doc.get("manifest"), dict, "an object")
    for key in ("function", "model_sha256", "content_sha256", "csv_sha256"):
        _need(path, f"manifest.{key}", manifest.get(key), str, "a string")
    function = manifest["function"]
    made_for = manifest.get("configuration")
    if made_for is not None:
        _need(path, "manifest.configuration", made_for, dict, "an object")
        name = _need(path, "manifest.configuration.name", made_for.get("name"), str, "a string")
        _need(path, "manifest.configuration.data_sha256", made_for.get("data_sha256"), str, "a string")
        if configured is None:
            raise VectorFileError(f"{path}: made for the configuration {name!r}: give it with --config FILE")
    nodes = {n: node for n, (node, _) in configured.items()} if made_for is not None else NODES
    if function not in nodes:
        raise VectorFileError(
            f"{path}: manifest.function names no function of the model: {function!r} (functions: {', '.join(nodes)})"
        )
    node = nodes[function]
    goals = _need(path, "field 'goals'", doc.get("goals"), list, "a list")
    raw = _need(path, "field 'vectors'", doc.get("vectors"), list, "a list")
    result = VectorFile(path, node, manifest, goals, raw)
    for j, v in enumerate(raw):
        where = f"vectors[{j}]"
        _need(path, where, v, dict, "an object")
        ident = _need(path, f"{where}.id", v.get("id"), str, "a string")
        context = _need(path, f"{where}.context", v.get("context", ""), str, "a string")
        covers = _need(path, f"{where}.covers", v.get("covers"), list, "a list of goal ids")
        for k, goal in enumerate(covers):
            _need(path, f"{where}.covers[{k}]", goal, str, "a goal id (a string)")
        values = {
            role: parse_record(path, f"{where}.{role}", v.get(role), node.sorts(role))
            for role in ("params", "state", "inputs")
        }
        exp = _need(path, f"{where}.expected", v.get("expected"), dict, "an object")
        floats = _need(path, f"{where}.expected_float", v.get("expected_float"), dict, "an object")
        for role in ("next_state", "outputs"):
            _need(path, f"{where}.expected_float.{role}", floats.get(role), dict, "an object")
        vector = Vector(ident, context, values["params"], values["state"], values["inputs"], covers=list(covers))
        vector.next_state = parse_record(
            path, f"{where}.expected.next_state", exp.get("next_state"), node.sorts("state")
        )
        vector.outputs = parse_record(path, f"{where}.expected.outputs", exp.get("outputs"), node.sorts("outputs"))
        result.vectors.append(vector)
    return result
