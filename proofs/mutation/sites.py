"""Mutation sites: the systematic faults of ``atcs mutate``, found in the AST of the model's own functions.

The functions mutated are each node's ``step`` and ``init`` and the model helpers they call, directly or not
(module-level functions of ``atcs.model`` modules, the Ops backends and the node framework excepted). Each site
is one textual change of one function's source, applied by :func:`atcs.proofs.mutation.mutants.mutate_function`; the
operators (``OPERATORS``):

- ``cmp_strict``: ``<`` <-> ``<=``, ``>`` <-> ``>=``; ``cmp_flip``: ``<`` <-> ``>``, ``<=`` <-> ``>=``;
- ``arith_sign``: ``+`` <-> ``-``, a unary minus dropped; ``arith_drop``: one term of a ``+`` / ``-`` dropped;
- ``const``: ``o.const(x)`` nudged to ``(o.const(x) * 11 + 1) / 10``; ``literal``: an integer operand ``n`` ->
  ``n + 1``; ``const_bool``: ``o.const_bool(True)`` <-> ``False``;
- ``bool_swap``: ``o.and_`` <-> ``o.or_``; ``not_drop``: ``o.not_(x)`` -> ``x``; ``minmax``: ``o.min`` <-> ``o.max``;
- ``delay_late`` (a value used a cycle late): a use of a local that becomes next-state field ``f`` replaced by
  ``s.f``, the previous cycle's value; ``delay_hold``: a next-state field keeps the previous state's value.

A mutant is identified stably by ``module.function:+line:operator:original -> replacement`` (the line counted
from the function's ``def``; ``#n`` for the n-th identical change on one line).
"""

from __future__ import annotations

import ast
import dataclasses
import difflib
import importlib
import inspect
import textwrap
import types
from collections.abc import Callable, Iterable
from dataclasses import dataclass

OPERATORS = (
    "cmp_strict",
    "cmp_flip",
    "arith_sign",
    "arith_drop",
    "const",
    "literal",
    "const_bool",
    "bool_swap",
    "not_drop",
    "minmax",
    "delay_late",
    "delay_hold",
)
_EXCLUDED_MODULES = ("atcs.model.ops", "atcs.model.node")
_CMP = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">="}
_STRICT = {"<": "<=", "<=": "<", ">": ">=", ">=": ">"}
_FLIP = {"<": ">", ">": "<", "<=": ">=", ">=": "<="}
_SWAP = {"and_": "or_", "or_": "and_", "min": "max", "max": "min"}
_ATOMS = (ast.Name, ast.Attribute, ast.Constant, ast.Call, ast.Subscript)


@dataclass(frozen=True)
class Mutant:
    """One site: ``original`` at line ``offset`` of ``module.function`` becomes ``replacement``."""

    model_module: str
    """The function's module under ``atcs.model``, e.g. ``supervision``."""
    function: str
    operator: str
    line: int
    """Line in the module's file."""
    offset: int
    """Line counted from the function's ``def`` (1 is the ``def`` line): what the id uses."""
    original: str
    replacement: str
    occurrence: int
    old: str
    """A snippet of the function's source that occurs once in it ..."""
    new: str
    """... and its replacement (the arguments of :func:`~atcs.proofs.mutation.mutants.mutate_function`)."""
    diff: str
    """Unified diff of the function's source."""

    @property
    def id(self) -> str:
        suffix = f"#{self.occurrence}" if self.occurrence > 1 else ""
        return (
            f"{self.model_module}.{self.function}:+{self.offset}:{self.operator}:"
            f"{self.original} -> {self.replacement}{suffix}"
        )

    def resolve(self) -> Callable:
        """The real function this mutant changes."""
        return getattr(importlib.import_module(f"atcs.model.{self.model_module}"), self.function)


def _is_model_function(value) -> bool:
    return (
        isinstance(value, types.FunctionType)
        and value.__module__.startswith("atcs.model.")
        and not value.__module__.startswith(_EXCLUDED_MODULES)
        and value.__qualname__ == value.__name__
        and getattr(importlib.import_module(value.__module__), value.__name__, None) is value
    )


def _names(code: types.CodeType) -> set[str]:
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _names(const)
    return names


def callees(fn: Callable) -> list[Callable]:
    """The model functions ``fn`` names (directly, or as ``module.name`` of a model module)."""
    found = []
    names = _names(fn.__code__)
    for name in sorted(names):
        value = fn.__globals__.get(name)
        if isinstance(value, types.ModuleType) and value.__name__.startswith("atcs.model."):
            found += [getattr(value, n) for n in sorted(names) if _is_model_function(getattr(value, n, None))]
        elif _is_model_function(value):
            found.append(value)
    return found


def reachable(roots: Iterable[Callable]) -> list[Callable]:
    """``roots`` (the model functions among them) and every model function they call, transitively; sorted."""
    seen: dict[tuple[str, str], Callable] = {}
    todo = [r for r in roots if _is_model_function(r)]
    while todo:
        fn = todo.pop()
        key = (fn.__module__, fn.__name__)
        if key not in seen:
            seen[key] = fn
            todo += callees(fn)
    return [seen[k] for k in sorted(seen)]


def node_functions(node) -> list[Callable]:
    """The functions a node's proofs run: its step and init and what they call."""
    return reachable((node.step, node.init))


def _state_classes(nodes) -> dict[str, list[str]]:
    return {node.state.__name__: [f.name for f in dataclasses.fields(node.state)] for node in nodes}


class _Source:
    """A function's dedented source with offsets from AST positions (columns are UTF-8 byte offsets)."""

    def __init__(self, fn: Callable):
        self.text = textwrap.dedent(inspect.getsource(fn))
        self.lines = self.text.splitlines(keepends=True)
        self.starts = [0]
        for line in self.lines:
            self.starts.append(self.starts[-1] + len(line))

    def index(self, lineno: int, col: int) -> int:
        return self.starts[lineno - 1] + len(self.lines[lineno - 1].encode()[:col].decode())

    def span(self, node: ast.AST) -> tuple[int, int]:
        return self.index(node.lineno, node.col_offset), self.index(node.end_lineno, node.end_col_offset)

    def segment(self, node: ast.AST) -> str:
        start, end = self.span(node)
        return self.text[start:end]


def _wrapped(source: _Source, node: ast.AST) -> str:
    text = source.segment(node)
    return text if isinstance(node, _ATOMS) else f"({text})"


def _edits(fn: Callable, source: _Source, tree: ast.FunctionDef, states: dict[str, list[str]]):
    """``(operator, start, end, original, replacement)`` for every site in ``fn``'s body."""
    ops_name = tree.args.args[0].arg if tree.args.args else None
    body = (
        tree.body[1:]
        if (tree.body and isinstance(tree.body[0], ast.Expr) and isinstance(tree.body[0].value, ast.Constant))
        else tree.body
    )
    nodes = [n for stmt in body for n in ast.walk(stmt)]
    skip_literals: set[int] = set()

    def is_ops_call(n, *attrs):
        return (
            isinstance(n, ast.Call)
            and isinstance(n.func, ast.Attribute)
            and n.func.attr in attrs
            and isinstance(n.func.value, ast.Name)
            and n.func.value.id == ops_name
        )

    for n in nodes:
        if is_ops_call(n, "const", "const_bool"):
            skip_literals |= {id(a) for arg in n.args for a in ast.walk(arg)}
        elif isinstance(n, ast.Subscript):
            skip_literals |= {id(a) for a in ast.walk(n.slice)}
    for n in nodes:
        if isinstance(n, ast.Compare):
            yield from _compare_edits(source, n)
        elif isinstance(n, (ast.BinOp, ast.UnaryOp)):
            yield from _arith_edits(source, n)
        elif isinstance(n, ast.Constant) and type(n.value) is int and id(n) not in skip_literals:
            yield "literal", *source.span(n), source.segment(n), str(n.value + 1)
        elif is_ops_call(n, "const", "const_bool", "and_", "or_", "min", "max", "not_"):
            yield from _ops_call_edits(source, n)
    yield from _delays(source, tree, nodes, states)


def _compare_edits(source: _Source, n: ast.Compare):
    """A comparison made strict (or not) and flipped."""
    operands = [n.left, *n.comparators]
    for op, left, right in zip(n.ops, operands, operands[1:], strict=False):
        token = _CMP.get(type(op))
        if token is None:
            continue
        start, end = source.span(left)[1], source.span(right)[0]
        at = start + source.text[start:end].index(token)
        for operator, table in (("cmp_strict", _STRICT), ("cmp_flip", _FLIP)):
            yield operator, at, at + len(token), token, table[token]


def _arith_edits(source: _Source, n: ast.BinOp | ast.UnaryOp):
    """A sum or difference with its sign swapped or an operand dropped; a negation dropped."""
    if isinstance(n, ast.BinOp) and isinstance(n.op, (ast.Add, ast.Sub)):
        token, other = ("+", "-") if isinstance(n.op, ast.Add) else ("-", "+")
        start, end = source.span(n.left)[1], source.span(n.right)[0]
        at = start + source.text[start:end].index(token)
        yield "arith_sign", at, at + 1, token, other
        whole = source.span(n)
        yield "arith_drop", *whole, source.segment(n), _wrapped(source, n.left)
        if isinstance(n.op, ast.Add):
            yield "arith_drop", *whole, source.segment(n), _wrapped(source, n.right)
    elif isinstance(n, ast.UnaryOp) and isinstance(n.op, ast.USub):
        yield "arith_sign", *source.span(n), source.segment(n), _wrapped(source, n.operand)


def _ops_call_edits(source: _Source, n: ast.Call):
    """A call of the ops: a constant changed, a boolean constant negated, and/or and min/max swapped, a
    negation dropped."""
    attr = n.func.attr
    if attr == "const" and len(n.args) == 1:
        text = source.segment(n)
        yield "const", *source.span(n), text, f"({text} * 11 + 1) / 10"
    elif attr == "const_bool" and len(n.args) == 1 and isinstance(n.args[0], ast.Constant):
        yield "const_bool", *source.span(n.args[0]), str(n.args[0].value), str(not n.args[0].value)
    elif attr in ("and_", "or_", "min", "max"):
        operator = "bool_swap" if attr in ("and_", "or_") else "minmax"
        end = source.span(n.func)[1]
        yield operator, end - len(attr), end, attr, _SWAP[attr]
    elif attr == "not_" and len(n.args) == 1:
        yield "not_drop", *source.span(n), source.segment(n), _wrapped(source, n.args[0])


def _delays(source: _Source, tree: ast.FunctionDef, nodes: list[ast.AST], states: dict[str, list[str]]):
    """The off-by-one cycle sites: the function builds a node's next state from a parameter of that state type."""
    params = {
        a.arg: a.annotation.id
        if isinstance(a.annotation, ast.Name)
        else (a.annotation.value if isinstance(a.annotation, ast.Constant) else None)
        for a in tree.args.args
        if a.annotation is not None
    }
    for n in nodes:
        if not (isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id in states):
            continue
        previous = next((name for name, cls in params.items() if cls == n.func.id), None)
        if previous is None:
            continue
        fields = states[n.func.id]
        given = [(fields[j], arg) for j, arg in enumerate(n.args) if j < len(fields)]
        given += [(k.arg, k.value) for k in n.keywords if k.arg is not None]
        inside = {id(a) for a in ast.walk(n)}
        for field, value in given:
            held = f"{previous}.{field}"
            if source.segment(value) != held:
                yield "delay_hold", *source.span(value), source.segment(value), held
            if isinstance(value, ast.Name):
                for use in nodes:
                    if (
                        isinstance(use, ast.Name)
                        and use.id == value.id
                        and isinstance(use.ctx, ast.Load)
                        and id(use) not in inside
                    ):
                        yield "delay_late", *source.span(use), use.id, held


def _unique_change(source: _Source, start: int, end: int, replacement: str) -> tuple[str, str]:
    """The smallest run of whole lines around ``[start, end)`` that occurs once in the source, and its change."""
    text = source.text
    first = next(j for j in range(len(source.lines)) if source.starts[j + 1] > start)
    last = next(j for j in range(len(source.lines)) if source.starts[j + 1] >= end)
    while True:
        lo, hi = source.starts[first], source.starts[last + 1]
        old = text[lo:hi]
        if text.count(old) == 1:
            return old, text[lo:start] + replacement + text[end:hi]
        first, last = max(first - 1, 0), min(last + 1, len(source.lines) - 1)


def function_mutants(fn: Callable, nodes) -> list[Mutant]:
    """Every mutant of one model function (``nodes``: the node types whose state classes mark delays)."""
    source = _Source(fn)
    tree = ast.parse(source.text).body[0]
    module = fn.__module__.removeprefix("atcs.model.")
    first_line = fn.__code__.co_firstlineno
    seen: dict[tuple, int] = {}
    mutants = []
    for operator, start, end, original, replacement in _edits(fn, source, tree, _state_classes(nodes)):
        if original == replacement:
            continue
        offset = source.text.count("\n", 0, start) + 1
        key = (offset, operator, original, replacement)
        seen[key] = seen.get(key, 0) + 1
        old, new = _unique_change(source, start, end, replacement)
        mutated = source.text[:start] + replacement + source.text[end:]
        diff = "".join(
            difflib.unified_diff(
                source.lines,
                mutated.splitlines(keepends=True),
                f"a/{module}.py:{fn.__name__}",
                f"b/{module}.py:{fn.__name__}",
                n=2,
            )
        )
        mutants.append(
            Mutant(
                module,
                fn.__name__,
                operator,
                first_line + offset - 1,
                offset,
                " ".join(original.split()),
                " ".join(replacement.split()),
                seen[key],
                old,
                new,
                diff,
            )
        )
    return mutants


def enumerate_mutants(nodes) -> list[Mutant]:
    """Every mutant of every function the ``nodes``' proofs run, in a fixed order (module, function, line)."""
    nodes = list(nodes)
    functions = reachable(fn for node in nodes for fn in (node.step, node.init))
    mutants = [m for fn in functions for m in function_mutants(fn, nodes)]
    return sorted(mutants, key=lambda m: (m.model_module, m.function, m.offset, OPERATORS.index(m.operator), m.id))
