"""`sg3d plan`: a command or PDDL goal -> PDDL files -> a validated plan (paper Sec. VI-B)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import json
from pathlib import Path

import click

from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings

PLANNER_CHOICES = ("pyperplan", "fast-downward")


@click.command("plan")
@click.argument("command", required=False)
@click.option("--goal", metavar="EXPR", help="A PDDL goal instead of a command, e.g. '(and (in red_cup sink))'.")
@click.option("--room", help="Room name or id (<building>/<room>); optional when the store has one room.")
@click.option("--building", help="Building of --room.")
@click.option("--start", metavar="NAME", help="Where the robot starts (a surface or receptacle name). Default: the first surface.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              help="Directory for domain.pddl and problem.pddl (without --out they are not kept).")
@click.option("--planner", type=click.Choice(PLANNER_CHOICES), default="pyperplan", show_default=True,
              help="pyperplan: greedy best-first + FF heuristic; fast-downward needs unified-planning + up-fast-downward.")
@click.option("--json", "as_json", is_flag=True, help="The plan as JSON (for scripts).")
@click.pass_obj
def plan(settings: Settings, command, goal, room, building, start, out_dir, planner, as_json) -> None:
    """Plan a task in a scanned room: 'clean up the table', 'put the cups in the sink',
    'bring the red cup to the table', or any conjunctive PDDL goal with --goal. Clean-up sends
    each item where the placement rule of its kind says (tableware to the sink, books to a shelf
    or another table, electronics stay) and prints the rule.

    The plan is checked by simulating it against the domain before it is printed."""
    import shutil
    import tempfile

    from sg3d.app.errors import AppError
    from sg3d.app.plan import PlanRun, PlanScope
    from sg3d.app.plan import plan as plan_task
    from sg3d.app.stores import reader

    scratch = None if out_dir else Path(tempfile.mkdtemp(prefix="sg3d-plan-"))
    try:
        outcome = plan_task(reader(settings), command, goal=goal, scope=PlanScope(room, building, start),
                            run=PlanRun(planner, out_dir or scratch))
    except AppError as exc:
        raise UserError(str(exc)) from exc
    finally:
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)
    if as_json:
        data = outcome.to_json()
        if scratch is not None:
            data["domain"] = data["problem"] = None    # removed: --out keeps them
        click.echo(json.dumps(data))
        return
    where = f"PDDL in {outcome.out_dir} (domain.pddl, problem.pddl)" if scratch is None else \
        "add --out DIR to keep domain.pddl and problem.pddl"
    click.echo(f"room {outcome.room}; {where}")
    click.echo("goal: " + " ".join("(" + " ".join(a) + ")" for a in outcome.goal))
    for line in outcome.placement_lines():
        click.echo(f"  {line}")
    if not outcome.steps:
        click.echo("the goal already holds: nothing to do")
    width = len(str(len(outcome.steps)))
    for n, step in enumerate(outcome.steps, 1):
        click.echo(f"{n:>{width}}. {outcome.describe(step)}")
    p = outcome.planner
    click.echo(f"{len(outcome.steps)} steps, validated by simulation; {p.planner} planned in "
               f"{p.seconds * 1000:.0f} ms (search {p.search_seconds * 1000:.0f} ms)")
    if outcome.problem.left_out:
        click.echo(outcome.problem.left_out_summary(), err=True)


commands = [plan]
