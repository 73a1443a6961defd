"""Plan a task in a scanned room: the one call `sg3d plan`, `POST /plan` and the MCP `plan` tool
make."""
from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from sg3d.app import bounds
from sg3d.app.errors import AppError
from sg3d.graphdb.protocol import GraphStore

if TYPE_CHECKING:
    from sg3d.queries.planning.pipeline import PlanOutcome

PLANNERS = ("pyperplan", "fast-downward")


@dataclass(frozen=True)
class PlanScope:
    """Where a plan runs: the room (None: the one room, or the building's rooms), its building, the
    robot's start (an object or room name; None: no start)."""

    room: Optional[str] = None
    building: Optional[str] = None
    start: Optional[str] = None


@dataclass(frozen=True)
class PlanRun:
    """How a plan is made: the planner, and where its PDDL files go (None: a new temporary directory)."""

    planner: str = "pyperplan"
    out_dir: Optional[Path] = None


def plan(store: GraphStore, command: Optional[str] = None, *, goal: Optional[str] = None,
         scope: PlanScope = PlanScope(), run: PlanRun = PlanRun()) -> PlanOutcome:
    """The validated plan (`sg3d.queries.planning.PlanOutcome`) of `command` or `goal`; AppError with a
    one-line reason when there is none."""
    from sg3d.queries.planning import PlanningError, plan_task

    room, building, start, out_dir, planner = scope.room, scope.building, scope.start, run.out_dir, run.planner

    if command and goal:
        raise AppError("give a command or --goal, not both")
    if goal and bounds.paren_depth(goal) > bounds.MAX_GOAL_DEPTH:
        raise AppError(f"the goal nests parentheses deeper than {bounds.MAX_GOAL_DEPTH} levels")
    if planner not in PLANNERS:
        raise AppError(f"unknown planner {planner!r} (choose from {', '.join(PLANNERS)})")
    try:
        return plan_task(store, command, goal=goal, room=room, building=building,
                         out_dir=out_dir, planner=planner, start=start)
    except PlanningError as exc:
        raise AppError(str(exc)) from exc


def plan_json(store: GraphStore, command: Optional[str] = None, *, goal: Optional[str] = None,
              room: Optional[str] = None, building: Optional[str] = None, start: Optional[str] = None) -> dict:
    """A plan as self-contained JSON for remote callers: `PlanOutcome.to_json()` plus the PDDL
    texts (`domain_pddl`, `problem_pddl`); the server's temporary files are removed."""
    tmp = Path(tempfile.mkdtemp(prefix="sg3d-plan-"))
    try:
        outcome = plan(store, command, goal=goal, scope=PlanScope(room, building, start), run=PlanRun(out_dir=tmp))
        data = outcome.to_json()
        data["domain_pddl"] = (tmp / "domain.pddl").read_text()
        data["problem_pddl"] = (tmp / "problem.pddl").read_text()
        data["domain"] = data["problem"] = None     # no path on the server's disk is useful to a caller
        return data
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
