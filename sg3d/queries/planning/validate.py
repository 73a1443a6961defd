"""Plan validation by simulation: every step's preconditions must hold in the state the previous
steps produced, and the goal must hold at the end. Works on the `pddl` package's parse of the
written domain.pddl and problem.pddl, independently of the planner that made the plan."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pddl.logic.base import And, Not
from pddl.logic.predicates import Predicate

from sg3d.core.errors import Sg3dError
from sg3d.queries.planning.domain import Domain

Atom = tuple[str, ...]


class InvalidPlan(Sg3dError):
    """The plan does not do what it claims; `step` is 1-based (0: the goal check at the end)."""

    def __init__(self, step: int, message: str):
        super().__init__(message)
        self.step = step


@dataclass(frozen=True)
class Simulation:
    initial: frozenset[Atom]
    final: frozenset[Atom]
    steps: int


def _atom(p: Predicate, binding: dict[str, str]) -> Atom:
    return (str(p.name),) + tuple(binding.get(str(t.name), str(t.name)) for t in p.terms)


def _literals(formula, binding) -> tuple[list[Atom], list[Atom]]:
    """A conjunction of literals as (positive atoms, negated atoms)."""
    pos, neg = [], []
    parts = formula.operands if isinstance(formula, And) else ([formula] if formula is not None else [])
    for part in parts:
        if isinstance(part, Not) and isinstance(part.argument, Predicate):
            neg.append(_atom(part.argument, binding))
        elif isinstance(part, Predicate):
            pos.append(_atom(part, binding))
        else:
            raise InvalidPlan(0, f"unsupported formula {part} (STRIPS conjunctions only)")
    return pos, neg


def simulate(domain: Domain, problem_file: Path, plan: list[Atom]) -> Simulation:
    """Run `plan` (steps like ("pick", "robot", "cup_1", "dining_table_1")) from the problem's
    initial state; raise InvalidPlan at the first step or goal that fails."""
    from pddl import parse_problem

    problem = parse_problem(str(problem_file))
    types = {str(o.name): sorted(str(t) for t in o.type_tags) for o in problem.objects}
    state = {_atom(p, {}) for p in problem.init}
    initial = frozenset(state)
    for n, step in enumerate(plan, 1):
        name, args = step[0], step[1:]
        action = domain.action(name)
        if action is None:
            raise InvalidPlan(n, f"step {n}: unknown action {name!r}")
        if len(args) != len(action.parameters):
            raise InvalidPlan(n, f"step {n}: {name} takes {len(action.parameters)} arguments, got {len(args)}")
        binding = {}
        for param, arg in zip(action.parameters, args):
            if arg not in types:
                raise InvalidPlan(n, f"step {n}: unknown object {arg!r}")
            wanted = sorted(str(t) for t in param.type_tags)
            if wanted and not any(domain.is_subtype(t, w) for t in types[arg] for w in wanted):
                raise InvalidPlan(n, f"step {n}: {arg} is not a {wanted[0]}")
            binding[str(param.name)] = arg
        pre_pos, pre_neg = _literals(action.precondition, binding)
        missing = [a for a in pre_pos if a not in state] + [("not",) + a for a in pre_neg if a in state]
        if missing:
            shown = ", ".join("(" + " ".join(a) + ")" for a in missing)
            raise InvalidPlan(n, f"step {n} ({' '.join(step)}): precondition fails: {shown}")
        add, delete = _literals(action.effect, binding)
        state = (state - set(delete)) | set(add)     # PDDL semantics: deletes first, then adds
    goal_pos, goal_neg = _literals(problem.goal, {})
    unmet = [a for a in goal_pos if a not in state] + [("not",) + a for a in goal_neg if a in state]
    if unmet:
        raise InvalidPlan(0, "the plan ends without reaching the goal: "
                             + ", ".join("(" + " ".join(a) + ")" for a in unmet))
    return Simulation(initial=initial, final=frozenset(state), steps=len(plan))
