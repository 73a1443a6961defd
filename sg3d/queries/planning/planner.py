"""Planner backends: pyperplan (greedy best-first search + the FF heuristic, the paper's FF
planner idea, pure Python) by default; Fast Downward through unified-planning when installed."""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from sg3d.queries.planning.rules import PlanningError

Atom = tuple[str, ...]
PLANNERS = ("pyperplan", "fast-downward")


@dataclass(frozen=True)
class PlannerResult:
    steps: Optional[list[Atom]]     # None: the planner proved or gave up that no plan exists
    planner: str
    seconds: float                  # wall time: parse + ground + search
    search_seconds: float
    operators: Optional[int] = None  # grounded actions (pyperplan)


def solve(domain_file: Path, problem_file: Path, planner: str = "pyperplan") -> PlannerResult:
    if planner == "pyperplan":
        return _pyperplan(domain_file, problem_file)
    if planner == "fast-downward":
        return _fast_downward(domain_file, problem_file)
    raise PlanningError(f"unknown planner {planner!r} (choose from: {', '.join(PLANNERS)})")


def _step(name: str) -> Atom:
    """pyperplan's operator name "(pick robot cup_1 dining_table_1)" as a tuple."""
    return tuple(name.strip("()").split())


def _pyperplan(domain_file: Path, problem_file: Path) -> PlannerResult:
    from pyperplan import grounding
    from pyperplan.heuristics.relaxation import hFFHeuristic
    from pyperplan.pddl.parser import Parser
    from pyperplan.search import greedy_best_first_search

    t0 = time.perf_counter()
    parser = Parser(str(domain_file), str(problem_file))
    task = grounding.ground(parser.parse_problem(parser.parse_domain()))
    t1 = time.perf_counter()
    plan = greedy_best_first_search(task, hFFHeuristic(task))
    t2 = time.perf_counter()
    steps = None if plan is None else [_step(op.name) for op in plan]
    return PlannerResult(steps, "pyperplan", t2 - t0, t2 - t1, operators=len(task.operators))


def fast_downward_available() -> bool:
    try:
        import unified_planning  # noqa: F401
        import up_fast_downward  # noqa: F401
    except ImportError:
        return False
    return True


def _fast_downward(domain_file: Path, problem_file: Path) -> PlannerResult:
    if not fast_downward_available():
        raise PlanningError("the fast-downward planner needs `pip install unified-planning up-fast-downward` "
                            "(about 216 MB); the default --planner pyperplan needs nothing more")
    from unified_planning.engines import PlanGenerationResultStatus
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    get_environment().credits_stream = None   # keep the CLI output ours
    t0 = time.perf_counter()
    up_problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
    t1 = time.perf_counter()
    with OneshotPlanner(name="fast-downward") as engine:
        result = engine.solve(up_problem)
    t2 = time.perf_counter()
    solved = (PlanGenerationResultStatus.SOLVED_SATISFICING, PlanGenerationResultStatus.SOLVED_OPTIMALLY)
    steps = None
    if result.status in solved and result.plan is not None:
        steps = [(a.action.name,) + tuple(str(p) for p in a.actual_parameters) for a in result.plan.actions]
    return PlannerResult(steps, "fast-downward", t2 - t0, t2 - t1)
