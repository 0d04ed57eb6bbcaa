"""``atcs replay CEX.json``: replay a counterexample exactly, show the violating step, and run it on floats.

Exit code 0 the violation is reproduced at the recorded step and the float run agrees, 1 it is not reproduced
(the model changed), 4 reproduced but the float run diverges (a boolean differs, a float is not finite, or the
float run fails), 2 bad input.
"""

from __future__ import annotations

from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import EXIT_FALSIFIED, EXIT_OK

EXIT_DIVERGED = 4


def add_parser(subparsers) -> None:
    r = subparsers.add_parser("replay", help="replay a counterexample exactly and show the violating step")
    r.add_argument("trace", metavar="CEX.json")
    r.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.cex.float_replay import float_replay
    from atcs.proofs.cex.trace import from_json, replay
    from atcs.properties import PROPERTIES

    prop, trace = from_json(args.trace, PROPERTIES)
    result = replay(prop, trace)
    _print_exact(out, prop, trace, result, Path(args.trace).name)
    floats = float_replay(prop, trace, result)
    _print_floats(out, floats)
    if not result.reproduced:
        return EXIT_FALSIFIED
    return EXIT_DIVERGED if floats.diverged else EXIT_OK


def _print_exact(out, prop, trace, result, file_name: str) -> None:
    from atcs.model.node import flatten
    from atcs.proofs.cex.trace import readable_value

    out.print(f"{prop.name} ({prop.requirement}, seed {prop.seed}): {prop.text}")
    if trace.params:
        out.print("parameters: " + ", ".join(f"{n}={readable_value(v)}" for n, v in trace.params.items()))
    first = result.first_violation
    steps = range(len(trace.inputs))
    table = Table(
        title=f"replay of {file_name} (exact arithmetic; one column per step; a value not shown exactly by its "
        "6-digit decimal has its exact value in parentheses)"
    )
    table.add_column("variable", overflow="fold")
    for k in steps:
        table.add_column(
            f"{k} VIOLATED" if k == first else str(k),
            justify="right",
            style="bold red" if k == first else None,
            overflow="fold",  # a long exact value wraps onto more lines, never cut off
        )
    for prefix, values in (("state", result.states), ("input", trace.inputs), ("output", result.outputs)):
        for n in flatten(values[0]):
            table.add_row(f"{prefix}.{n}", *(readable_value(flatten(values[k])[n]) for k in steps))
    table.add_row("holds", *("no" if not ok else "yes" for ok in result.holds))
    out.print(table)
    for problem in result.problems:
        out.print(f"[yellow]not a run of the current model:[/] {problem}")
    if first is None:
        out.print(
            f"[yellow]the property holds at every step on the current model[/] "
            f"(the trace recorded a violation at step {trace.violation_step})"
        )
    else:
        out.print(
            f"[bold red]violated at step {first}[/]"
            + ("" if first == trace.violation_step else f" (the trace recorded step {trace.violation_step})")
        )


def _print_floats(out, floats) -> None:
    from atcs.proofs.cex.trace import readable_value

    if floats.largest:
        gaps = Table(title="float run (IEEE doubles) against the exact run: the largest difference per field")
        for heading in ("field", "|float - exact|", "step", "exact", "float"):
            gaps.add_column(heading, justify="left" if heading == "field" else "right", overflow="fold")
        for name in sorted(floats.largest, key=floats.gap, reverse=True):
            d = floats.largest[name]
            gaps.add_row(name, f"{float(floats.gap(name)):.3g}", str(d.step), readable_value(d.exact), repr(d.float))
        out.print(gaps)
    for what, d in (("a boolean differs", floats.first_boolean), ("a number is not finite", floats.non_finite)):
        if d is not None:
            out.print(f"[bold red]the float run diverges: {what} first at {d.describe()}[/]")
    if floats.error is not None:
        out.print(f"[bold red]the float run fails at {floats.error}[/]")
    if not floats.diverged:
        out.print(
            f"the float run agrees with the exact run on every boolean over {floats.steps} steps"
            + ("" if floats.largest else ", and on every number")
        )
