"""Goals: a spoken-style command matched against the rules' templates, or a PDDL goal
expression typed by the user; both become a list of positive atoms checked against the problem."""
from __future__ import annotations

import re
from typing import Optional

from sg3d.queries.lexicon import known, lemma_phrase
from sg3d.queries.planning.domain import Domain
from sg3d.queries.planning.problem import Atom, PlanObject, Problem, readable, slug
from sg3d.queries.planning.rules import PlanningError, Rules, load_rules
from sg3d.queries.taxonomy import Taxonomy


# -- commands -------------------------------------------------------------------------------
def goal_from_command(command: str, problem: Problem, rules: Optional[Rules] = None) -> list[Atom]:
    rules = rules or load_rules()
    text = " ".join(re.sub(r"[^a-z0-9_ ]+", " ", command.lower()).split())
    for template in rules.commands:
        m = re.match(template["pattern"], text)
        if m is None:
            continue
        if template["kind"] == "clear":
            return _clear_goal(m["source"], problem, rules)
        if template["kind"] == "move":
            return _move_goal(m["items"], m["prep"], m["target"], problem, rules)
    raise PlanningError(f"cannot read the command {command!r}; try 'clean up the table', "
                        f"'put the cups in the sink', 'bring the mug to the table' or --goal '(and (in red_cup sink))'")


def _clear_goal(source: str, problem: Problem, rules: Rules) -> list[Atom]:
    """Clean up a surface: each item on it goes where the placement rule of its kind says
    (tableware to the sink, books to a shelf or another table, electronics stay, ...); the
    chosen destination and the rule are kept in `problem.placement` for the plan's text."""
    surfaces = _one_unless_plural(source, problem, rules, role="surface to clean up")
    goal: list[tuple[str, ...]] = []
    for s in surfaces:
        if s.type != "surface":
            raise PlanningError(f"{s.name} is {_a(s.type)}, not a surface to clean up")
    cleared = {s.name for s in surfaces}
    for s in surfaces:
        for a in problem.init:
            if a[0] != "on" or a[2] != s.name:
                continue
            item = problem.get(a[1])
            assert item is not None                  # the initial state names known objects
            rule = rules.placement_rule(item.label)
            dest = _destination(rule["to"], problem, cleared)
            why = rule["rule"]
            if dest is None and rule["to"][0] != "stay":
                why += f"; the room has no {' or '.join(t for t in rule['to'] if t != 'stay')}, so it stays"
            problem.placement[item.name] = (dest.name if dest else None, why)
            if dest is not None:
                goal.append(("in" if dest.type == "receptacle" else "on", item.name, dest.name))
    if not goal:
        if not problem.placement:
            raise PlanningError(f"nothing to clean up: no movable item is on {', '.join(sorted(cleared))}")
        why = "; ".join(f"{k}: {r}" for k, (_, r) in sorted(problem.placement.items()))
        raise PlanningError(f"nothing to move: every item on {', '.join(sorted(cleared))} stays ({why})")
    return goal


def _destination(choices: list[str], problem: Problem, cleared: set[str]) -> Optional[PlanObject]:
    """The first destination of a placement rule that the room has: a label (a receptacle or
    surface of that label), 'another surface' (any surface but the ones being cleared), or
    'stay' (None)."""
    for choice in choices:
        if choice == "stay":
            return None
        if choice == "another surface":
            found = [o for o in problem.objects if o.type == "surface" and o.name not in cleared]
        else:
            found = [o for o in problem.objects if o.label == choice and o.type in ("receptacle", "surface")
                     and o.name not in cleared]
        if found:
            return min(found, key=lambda o: o.name)
    return None


def _move_goal(items_phrase: str, prep: str, target_phrase: str, problem: Problem, rules: Rules) -> list[Atom]:
    items = _one_unless_plural(items_phrase, problem, rules, role="thing to move")
    [target] = _one_unless_plural(target_phrase, problem, rules, role="destination", force_single=True)
    if prep in ("in", "into", "inside"):
        predicate = "in"
    elif prep in ("on", "onto"):
        predicate = "on"
    else:  # "to": whatever the destination holds things by
        predicate = {"surface": "on", "receptacle": "in"}.get(target.type, "")
    wanted = {"in": "receptacle", "on": "surface"}.get(predicate)
    if wanted is None or target.type != wanted:
        raise PlanningError(f"unsolvable: {target.name} is {_a(target.type)}; nothing can be put "
                            f"{predicate or 'on or in'} it")
    if len(items) > 1 and any(i.type == "item" for i in items):
        items = [i for i in items if i.type == "item"]   # "the tableware", "all objects": the carriable ones
    goal: list[tuple[str, ...]] = []
    for item in items:
        if item.type != "item":
            raise PlanningError(f"unsolvable: {item.name} is {_a(item.type)}, not something the robot can carry")
        goal.append((predicate, item.name, target.name))
    return goal


def _one_unless_plural(phrase: str, problem: Problem, rules: Rules, *, role: str,
                       force_single: bool = False) -> list[PlanObject]:
    found, plural = resolve_phrase(phrase, problem, rules)
    if len(found) > 1 and (force_single or not plural):
        noun = " ".join(w for w in phrase.split() if w not in rules.articles)
        names = [readable(o.name) for o in found]
        raise PlanningError(f"which {noun} as {role}: the {', the '.join(names[:-1])} or the {names[-1]}? "
                            f"(name one, e.g. 'the {names[0]}')")
    return found


def resolve_phrase(phrase: str, problem: Problem, rules: Rules) -> tuple[list[PlanObject], bool]:
    """Objects a noun phrase names, and whether it named them in the plural.
    Order: a PDDL name, a label (or its plural), then the words `ask` knows (`sg3d.queries.lexicon`:
    the one synonym table and taxonomy); a group word ("the dishes", "all objects") names all
    of its kind."""
    words = [w for w in phrase.split() if w not in rules.articles]
    plural = any(w in ("all", "every") for w in phrase.split())
    noun = " ".join(words)
    for name in (noun, slug(noun)):        # a PDDL name, or the readable name it spells
        found = problem.get(name)
        if found is not None:
            return [found], False
    if noun in problem.left_out:
        raise PlanningError(f"the {readable(noun)} is not in the planning problem: {problem.left_out[noun]}")
    candidates = [(noun, False)] + [(s, True) for s in singulars(noun)]
    planned = [o for o in problem.objects if o.node_id]
    for form, is_plural in candidates:
        matches = [o for o in planned if form and o.label == form]
        if matches:
            return matches, plural or is_plural
    tax = Taxonomy.load()
    for form, is_plural in candidates:
        target = known(form) if form else None
        if target is None or target.labels == []:
            continue
        matches = [o for o in planned if target.labels is None or o.label in target.labels]
        if matches:
            group = target.labels is None or all(n in tax.groups for n in target.names)
            return matches, plural or is_plural or group or lemma_phrase(form) != form
    known_labels = sorted({o.label for o in planned})
    unplanned = [n for n in problem.left_out if noun and f" {noun} " in f" {readable(n)} "]
    if unplanned:    # it is in the room, but the planning rules leave it out: say why
        raise PlanningError(f"the {readable(unplanned[0])} is not in the planning problem: "
                            f"{problem.left_out[unplanned[0]]}")
    raise PlanningError(f"no {noun!r} in room {problem.room} to plan with (it has: {', '.join(known_labels)})")


def singulars(noun: str) -> list[str]:
    """Possible singular forms of the last word: cups -> cup, glasses -> glass, knives -> knife."""
    head, _, last = noun.rpartition(" ")
    forms = []
    if last.endswith("ves"):
        forms += [last[:-3] + "fe", last[:-3] + "f"]
    if last.endswith("es"):
        forms.append(last[:-2])
    if last.endswith("s") and not last.endswith("ss"):
        forms.append(last[:-1])
    return [f"{head} {f}".strip() for f in forms]


# -- PDDL goal expressions --------------------------------------------------------------------
def goal_from_pddl(expr: str, problem: Problem, domain: Domain) -> list[Atom]:
    """`(and (in cup_1 sink_1) ...)` or one atom; every name and type checked against the problem."""
    tree = _parse_sexpr(expr)
    atoms = tree[1:] if tree and tree[0] == "and" else [tree]
    goal: list[tuple[str, ...]] = []
    for atom in atoms:
        if not isinstance(atom, list) or not atom or any(isinstance(t, list) for t in atom):
            raise PlanningError(f"goal: expected atoms like (in cup_1 sink_1), got {_show(atom)}")
        if atom[0] in ("not", "or", "imply", "forall", "exists", "when"):
            raise PlanningError(f"goal: '{atom[0]}' is not supported (STRIPS goals: a conjunction of atoms)")
        goal.append(tuple(atom))
    for atom in goal:
        check_atom(atom, problem, domain)
    check_consistent(goal)
    return goal


def check_consistent(goal: list[Atom]) -> None:
    """Refuse at once what no plan can reach, rather than letting search exhaust the state space:
    one thing in two places, two things in the one hand."""
    where: dict[str, Atom] = {}
    for atom in goal:
        if atom[0] in ("on", "in", "holding"):
            thing = atom[2] if atom[0] == "holding" else atom[1]
            if thing in where and where[thing] != atom:
                raise PlanningError(f"unsolvable: {thing} cannot be both {_text(where[thing])} and {_text(atom)}")
            where[thing] = atom
    held = sorted({a[2] for a in goal if a[0] == "holding"})
    if len(held) > 1:
        raise PlanningError(f"unsolvable: the robot has one hand, it cannot hold {' and '.join(held)}")


def _text(atom: Atom) -> str:
    return "(" + " ".join(atom) + ")"


def check_atom(atom: Atom, problem: Problem, domain: Domain) -> None:
    predicate, args = atom[0], atom[1:]
    types = domain.predicates.get(predicate)
    if types is None:
        raise PlanningError(f"goal: unknown predicate {predicate!r} (known: {', '.join(sorted(domain.predicates))})")
    if len(args) != len(types):
        raise PlanningError(f"goal: {predicate} takes {len(types)} argument(s), got {_show(list(atom))}")
    for arg, wanted in zip(args, types):
        obj = problem.get(arg)
        if obj is None:
            why = f" ({problem.left_out[arg]})" if arg in problem.left_out else ""
            raise PlanningError(f"goal: unknown object {arg!r}{why}; the problem has: {', '.join(problem.names())}")
        if not domain.is_subtype(obj.type, wanted):
            raise PlanningError(f"unsolvable: {arg} is {_a(obj.type)}, but {predicate} needs {_a(wanted)} there")


def _parse_sexpr(text: str):
    tokens = re.findall(r"\(|\)|[^\s()]+", text.lower())
    if not tokens:
        raise PlanningError("goal: empty expression")
    stack: list[list] = [[]]
    for tok in tokens:
        if tok == "(":
            stack.append([])
        elif tok == ")":
            if len(stack) == 1:
                raise PlanningError(f"goal: unbalanced ')' in {text!r}")
            done = stack.pop()
            stack[-1].append(done)
        else:
            stack[-1].append(tok)
    if len(stack) != 1 or len(stack[0]) != 1 or not isinstance(stack[0][0], list):
        raise PlanningError(f"goal: expected one parenthesised expression, got {text!r}")
    return stack[0][0]


def _a(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


def _show(x) -> str:
    return "(" + " ".join(_show(t) for t in x) + ")" if isinstance(x, list) else str(x)
