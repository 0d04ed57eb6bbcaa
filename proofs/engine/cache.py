"""Proved verdicts kept between runs (``atcs prove --cache DIR``), so that a re-run after a change re-proves only
the properties the change can reach.

A verdict is found again by the property's fingerprint: SHA-256 over its statement (name, requirement, text,
assumptions, lemmas' fingerprints), its node (name, array sizes), its fixed data, the z3 version, and the source
of every module the property's and the node's modules import, transitively (every ``import`` statement in
``atcs``, in function bodies too, so a lazy import counts), with the engine's and the backends' own. Python code
can only depend on what it imports, so a change in a module outside that closure cannot change the verdict.
Only ``proved`` verdicts are kept: a counterexample is cheap to find again and its files are written afresh.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import pickle
from pathlib import Path

from atcs.proofs.engine.prove import Result

__all__ = ["VerdictCache", "fingerprint"]

_ALWAYS = ("atcs.model.ops.symbolic", "atcs.model.ops.exact", "atcs.model.node", "atcs.proofs.engine.prove")
"""Modules every verdict depends on: the backends, the node frame, the engine (their imports follow)."""


def _source(module: str) -> bytes | None:
    """The source of ``module``, None if it is no module of source (a name imported from a module, a package)."""
    try:
        spec = importlib.util.find_spec(module)
    except (ModuleNotFoundError, ValueError):
        return None
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        return None
    return Path(spec.origin).read_bytes()


def _imports(module: str, source: bytes) -> set[str]:
    """The ``atcs`` modules ``module``'s source imports anywhere in it (relative imports resolved)."""
    package = module if module.endswith("__init__") else module.rpartition(".")[0]
    found = set()
    for n in ast.walk(ast.parse(source)):
        if isinstance(n, ast.Import):
            found |= {a.name for a in n.names}
        elif isinstance(n, ast.ImportFrom):
            base = n.module or ""
            if n.level:
                base = ".".join([*package.split(".")[: len(package.split(".")) - n.level + 1], base]).strip(".")
            for a in n.names:  # ``from package import module`` needs the module, ``from module import name`` it
                found.add(f"{base}.{a.name}" if _source(f"{base}.{a.name}") is not None else base)
    return {m for m in found if m.startswith("atcs.") and _source(m) is not None}


def _closure(roots) -> dict[str, bytes]:
    sources, todo = {}, list(roots)
    while todo:
        module = todo.pop()
        if module in sources:
            continue
        source = _source(module)
        if source is None:
            continue
        sources[module] = source
        todo += sorted(_imports(module, source))
    return sources


def fingerprint(prop, registry: dict, _seen: tuple[str, ...] = ()) -> str:
    """The property's fingerprint (module docstring); ``registry`` gives its lemmas by name."""
    import z3

    node = prop.node
    roots = {prop.holds.__module__, node.step.__module__, node.init.__module__, *_ALWAYS}
    roots |= {a.holds.__module__ for a in prop.assumptions}
    digest = hashlib.sha256()
    for part in (
        prop.name,
        prop.requirement,
        prop.text,
        repr([(a.name, a.text) for a in prop.assumptions]),
        node.name,
        repr(sorted(node.sizes.items())),
        repr(sorted((k, repr(v)) for k, v in prop.fixed_params.items())),
        str(prop.max_k),
        z3.get_version_string(),
    ):
        digest.update(part.encode() + b"\0")
    for module, source in sorted(_closure(roots).items()):
        digest.update(module.encode() + b"\0" + source)
    for lemma in prop.lemmas:
        if lemma not in _seen:
            digest.update(fingerprint(registry[lemma], registry, (*_seen, prop.name)).encode())
    return digest.hexdigest()


class VerdictCache:
    """Proved verdicts by fingerprint, one file each in ``directory``."""

    def __init__(self, directory: str | Path, registry: dict):
        self.directory, self.registry = Path(directory), registry

    def _path(self, prop) -> Path:
        return self.directory / f"{fingerprint(prop, self.registry)}.verdict"

    def get(self, prop) -> Result | None:
        """The kept verdict of ``prop``, or None (none kept, or a file that cannot be read: proved again)."""
        try:
            result = pickle.loads(self._path(prop).read_bytes())
        except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ImportError, TypeError, ValueError):
            return None
        return result if isinstance(result, Result) and result.name == prop.name else None

    def put(self, prop, result: Result) -> None:
        """Keep ``result`` if it is ``proved`` (written to a temporary file, then renamed)."""
        if result.status != "proved":
            return
        from atcs.proofs.files import write_atomic

        self.directory.mkdir(parents=True, exist_ok=True)
        write_atomic(self._path(prop), pickle.dumps(result))
