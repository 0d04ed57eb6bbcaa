"""What proof coverage counts: the lines and decisions of the model's functions, found in their source.

A *line* is the first line of a statement in a function's body, the docstring excepted (a ``lambda`` outside any
function, such as a node's ``init``: its body's first line); a *decision* is a call of ``ite``, ``and_`` or
``or_`` on an Ops (``o.ite(...)``), named by its line and kind (several calls of one kind on one line are one
decision). The modules are every module of ``atcs.model`` but the Ops backends (``atcs.model.ops``: their
agreement is tested backend against backend, no property runs the float or exact one), each read from its file.
"""

from __future__ import annotations

import ast
import functools
import pkgutil
from dataclasses import dataclass
from pathlib import Path

import atcs.model

DECISION_KINDS = ("ite", "and_", "or_")
EXCLUDED_PACKAGES = ("atcs.model.ops",)


@dataclass(frozen=True)
class Site:
    """A line or a decision of a model function."""

    module: str
    """``atcs.model.authority``."""
    function: str
    """The function's qualified name in its module (``Monitor.step``, ``outer.<locals>.<lambda>``)."""
    line: int
    kind: str = "line"
    """``line``, or the decision's Ops call: ``ite``, ``and_`` or ``or_``."""

    @property
    def where(self) -> str:
        """``module.function:line`` (and the decision's kind)."""
        suffix = "" if self.kind == "line" else f" {self.kind}"
        return f"{self.module}.{self.function}:{self.line}{suffix}"


@functools.cache
def model_modules() -> dict[str, Path]:
    """Every module of ``atcs.model`` in coverage's scope, by name, with its file."""
    root = Path(atcs.model.__file__).parent
    modules = {"atcs.model": root / "__init__.py"}
    for info in pkgutil.walk_packages([str(root)], prefix="atcs.model."):
        if any(info.name == p or info.name.startswith(p + ".") for p in EXCLUDED_PACKAGES):
            continue
        path = root.joinpath(*info.name.split(".")[2:])
        modules[info.name] = path / "__init__.py" if info.ispkg else path.with_suffix(".py")
    return modules


def module_sites(module: str, path: Path) -> list[Site]:
    """The lines and decisions of every function in one module's source."""
    return _collected(module, path).sites


@functools.cache
def statement_lines(module: str) -> dict[int, int]:
    """Each source line inside a function's statement, to the first line of the innermost statement holding it
    (Python reports a statement spread over lines at whichever line its first instruction is on)."""
    return _collected(module, model_modules()[module]).owner


@functools.cache
def _collected(module: str, path: Path) -> _Collector:
    collector = _Collector(module)
    collector.visit(ast.parse(path.read_text(), filename=str(path)))
    return collector


class _Collector(ast.NodeVisitor):
    """Statements and Ops decisions inside functions, each named by its function's qualified name."""

    def __init__(self, module: str):
        self.module, self.sites = module, []
        self.owner: dict[int, int] = {}
        self.scope: list[str] = []
        self.function: str | None = None

    def visit(self, node):
        if isinstance(node, ast.stmt) and self.function is not None:
            self.sites.append(Site(self.module, self.function, node.lineno))
            for line in range(node.lineno, (node.end_lineno or node.lineno) + 1):
                self.owner[line] = node.lineno  # a nested statement, visited later, takes its own lines
        return super().visit(node)

    def visit_FunctionDef(self, node):
        for outer in (*node.decorator_list, *node.args.defaults, *(d for d in node.args.kw_defaults if d)):
            self.visit(outer)
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body = body[1:]  # the docstring
        self._inside(node.name, body)

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_Lambda(self, node):
        if self.function is not None:  # a part of its statement, counted with it
            self.generic_visit(node)
            return
        for outer in (*node.args.defaults, *(d for d in node.args.kw_defaults if d)):
            self.visit(outer)
        body = node.body
        for line in range(body.lineno, (body.end_lineno or body.lineno) + 1):
            self.owner[line] = body.lineno
        self._inside("<lambda>", [body], line=body.lineno)

    def visit_ClassDef(self, node):
        self.scope.append(node.name)
        self.generic_visit(node)
        self.scope.pop()

    def visit_Call(self, node):
        func = node.func
        if (
            self.function is not None
            and isinstance(func, ast.Attribute)
            and func.attr in DECISION_KINDS
            and isinstance(func.value, ast.Name)
        ):
            self.sites.append(Site(self.module, self.function, node.lineno, func.attr))
        self.generic_visit(node)

    def _inside(self, name: str, body: list, line: int | None = None) -> None:
        outer_scope, outer_function = self.scope, self.function
        self.scope = [*self.scope, *(("<locals>",) if self.function is not None else ()), name]
        self.function = ".".join(self.scope)
        if line is not None:
            self.sites.append(Site(self.module, self.function, line))
        for child in body:
            self.visit(child)
        self.scope, self.function = outer_scope, outer_function


@functools.cache
def all_sites() -> tuple[Site, ...]:
    """Every line and decision in scope, without repeats, module by module in line order."""
    found: dict[tuple, Site] = {}
    for module, path in model_modules().items():
        for site in module_sites(module, path):
            found.setdefault((site.module, site.line, site.kind), site)
    return tuple(sorted(found.values(), key=lambda s: (s.module, s.line, s.kind)))


__all__ = [
    "DECISION_KINDS",
    "EXCLUDED_PACKAGES",
    "Site",
    "all_sites",
    "model_modules",
    "module_sites",
    "statement_lines",
]
