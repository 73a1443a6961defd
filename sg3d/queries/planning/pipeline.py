"""Room -> problem -> goal -> planner -> validated plan: the one call the CLI makes."""
from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from sg3d.queries.planning.domain import Domain, load_domain
from sg3d.queries.planning.goals import goal_from_command, goal_from_pddl
from sg3d.queries.planning.planner import PlannerResult, solve
from sg3d.queries.planning.problem import (
    Atom,
    Problem,
    atom_text,
    build_problem,
    readable,
)
from sg3d.queries.planning.rules import PlanningError, Rules, load_rules
from sg3d.queries.planning.validate import InvalidPlan, Simulation, simulate


@dataclass
class PlanOutcome:
    room: str
    goal: list[Atom]
    steps: list[Atom]
    planner: PlannerResult
    simulation: Simulation
    problem: Problem
    out_dir: Path
    moved: dict[str, tuple[str, str]] = field(default_factory=dict)  # item -> (from, to)

    def describe(self, step: Atom, rules: Optional[Rules] = None) -> str:
        """One step in words, objects by their readable names (red_cup -> red cup)."""
        phrase = (rules or load_rules()).phrases.get(step[0])
        args = [readable(a) for a in step[1:]]
        return phrase.format(*args) if phrase else " ".join([step[0]] + args)

    def placement_lines(self) -> list[str]:
        """Where clean-up sends each item and the rule that decided it."""
        return [f"{readable(item)} -> {readable(dest) if dest else 'stays'}: {rule}"
                for item, (dest, rule) in sorted(self.problem.placement.items())]

    def to_json(self) -> dict:
        return {
            "room": self.room, "planner": self.planner.planner, "valid": True,
            "seconds": round(self.planner.seconds, 4), "search_seconds": round(self.planner.search_seconds, 4),
            "goal": [atom_text(a) for a in self.goal],
            "plan": [{"action": s[0], "args": list(s[1:]), "text": self.describe(s)} for s in self.steps],
            "moved": {k: {"from": a, "to": b} for k, (a, b) in self.moved.items()},
            "objects": self.problem.node_ids(), "left_out": self.problem.left_out,
            "placement": {k: {"to": d, "rule": r} for k, (d, r) in self.problem.placement.items()},
            "domain": str(self.out_dir / "domain.pddl"), "problem": str(self.out_dir / "problem.pddl"),
        }


def resolve_room(store, room: Optional[str] = None, building: Optional[str] = None) -> str:
    """The room id for --room/--building; a single room needs no flag."""
    rows = store.read("plan_rooms")
    if not rows:
        raise PlanningError("the store has no rooms yet: build a scene graph first")
    found = [r for r in rows
             if (room is None or room in (r["name"], r["id"])) and (building is None or r["building"] == building)]
    known = ", ".join(r["id"] for r in rows)
    if not found:
        where = f"room {room!r}" if room else "a room"
        where += f" in building {building!r}" if building else ""
        raise PlanningError(f"no {where} in the store (rooms: {known})")
    if len(found) > 1:
        raise PlanningError(f"several rooms match ({', '.join(r['id'] for r in found)}): choose with --room/--building")
    return found[0]["id"]


def plan_task(store, command: Optional[str] = None, *, goal: Optional[str] = None, room: Optional[str] = None,
              building: Optional[str] = None, out_dir: Optional[Path] = None, planner: str = "pyperplan",
              start: Optional[str] = None) -> PlanOutcome:
    """Plan `command` (or the PDDL `goal`) in a room of the store; the plan is validated by
    simulation before it is returned. Raises PlanningError with a one-line reason otherwise."""
    if not command and not goal:
        raise PlanningError("say what to do: a command like 'clean up the table' or --goal '(and ...)'")
    rules, domain = load_rules(), load_domain()
    room_id = resolve_room(store, room, building)
    problem = build_problem(store, room_id, start=start, rules=rules)
    problem.goal = goal_from_pddl(goal, problem, domain) if goal else goal_from_command(command or "", problem, rules)
    out_dir = Path(out_dir) if out_dir else Path(tempfile.mkdtemp(prefix="sg3d-plan-"))
    domain_file, problem_file = write_files(out_dir, domain, problem)
    result = solve(domain_file, problem_file, planner)
    if result.steps is None:
        raise PlanningError(f"unsolvable: no plan reaches {' '.join(atom_text(a) for a in problem.goal)} "
                            f"from the scene graph of {room_id}")
    steps = [_domain_spelling(s, domain) for s in result.steps]
    try:
        sim = simulate(domain, problem_file, steps)
    except InvalidPlan as exc:  # a planner bug or a domain/parser mismatch: never print such a plan
        raise PlanningError(f"the {result.planner} plan failed validation: {exc}") from exc
    return PlanOutcome(room=room_id, goal=problem.goal, steps=steps, planner=result, simulation=sim,
                       problem=problem, out_dir=out_dir, moved=moved_items(sim))


def write_files(out_dir: Path, domain: Domain, problem: Problem) -> tuple[Path, Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    domain_file, problem_file = out_dir / "domain.pddl", out_dir / "problem.pddl"
    domain_file.write_text(domain.text())
    problem_file.write_text(problem.to_pddl())
    return domain_file, problem_file


def moved_items(sim: Simulation) -> dict[str, tuple[str, str]]:
    """item -> (where it was, where it ends), for items whose support changed."""
    def support(state):
        return {a[1]: a[2] for a in state if a[0] in ("on", "in")}
    before, after = support(sim.initial), support(sim.final)
    held = {a[2]: "hand" for a in sim.final if a[0] == "holding"}
    return {i: (before.get(i, "?"), after.get(i) or held.get(i, "?"))
            for i in sorted(set(before) | set(after)) if before.get(i) != after.get(i)}


def _domain_spelling(step: Atom, domain: Domain) -> Atom:
    """Some backends write take-out as take_out; map back to the domain's action names."""
    if domain.action(step[0]) is None and domain.action(step[0].replace("_", "-")) is not None:
        return (step[0].replace("_", "-"),) + step[1:]
    return step
