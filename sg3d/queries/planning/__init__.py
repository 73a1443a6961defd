"""Task planning from the scene graph (paper Sec. VI-B): graph -> PDDL problem -> planner -> a
plan validated by simulation. See pipeline.plan_task for the whole path."""
from sg3d.queries.planning.domain import Domain, load_domain
from sg3d.queries.planning.goals import goal_from_command, goal_from_pddl
from sg3d.queries.planning.pipeline import PlanOutcome, plan_task, resolve_room
from sg3d.queries.planning.planner import (
    PLANNERS,
    PlannerResult,
    fast_downward_available,
    solve,
)
from sg3d.queries.planning.problem import PlanObject, Problem, build_problem
from sg3d.queries.planning.rules import PlanningError, Rules, load_rules
from sg3d.queries.planning.validate import InvalidPlan, Simulation, simulate

__all__ = [
    "Domain", "InvalidPlan", "PLANNERS", "PlanObject", "PlanOutcome", "PlannerResult", "PlanningError",
    "Problem", "Rules", "Simulation", "build_problem", "fast_downward_available", "goal_from_command",
    "goal_from_pddl", "load_domain", "load_rules", "plan_task", "resolve_room", "simulate", "solve",
]
