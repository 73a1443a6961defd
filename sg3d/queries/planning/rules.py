"""The graph -> PDDL rules (queries/data/planning_rules.json) and a label's taxonomy groups.

Rules are data so that teaching the planner a new kind of object means editing JSON, not code.
Words and groups are not the rules' business: the one synonym table and taxonomy of `ask`
(queries/data/synonyms.json, taxonomy.json, read through `sg3d.queries.lexicon`) serve planning too.
"""
from __future__ import annotations

import functools
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row
from sg3d.queries.taxonomy import Taxonomy

DATA = Path(__file__).resolve().parent.parent / "data"
RULES_FILE = DATA / "planning_rules.json"
DOMAIN_FILE = DATA / "household_domain.pddl"


class PlanningError(Sg3dError):
    """A request the planner cannot serve, with a message a user can act on (one line)."""


@dataclass(frozen=True)
class Rules:
    types: dict[str, str]
    doors: frozenset[str]
    door_state: str
    support_relations: dict[str, str]          # graph relation type -> PDDL predicate
    cleanup_target: str
    robot_name: str
    robot_type: str
    commands: list[Row] = field(default_factory=list)
    phrases: dict[str, str] = field(default_factory=dict)
    articles: tuple[str, ...] = ("the",)
    placement: tuple[dict, ...] = ()
    placement_default: dict = field(default_factory=lambda: {"to": ["stay"], "rule": "it stays unless named"})

    def placement_rule(self, label: str) -> dict:
        """Where clean-up sends an object of `label`: the first placement rule naming the label
        or one of its groups ({to: [...], rule: text}), else the default (stay)."""
        kinds = [label] + self.groups_of(label)
        for rule in self.placement:
            if any(k in rule["kinds"] for k in kinds):
                return rule
        return self.placement_default

    def groups_of(self, label: str) -> list[str]:
        """Taxonomy groups (categories above `label`), nearest first."""
        return Taxonomy.load().ancestors(label)

    def pddl_type(self, label: Optional[str]) -> Optional[str]:
        """The PDDL type of a node label: its own rule first, then its groups'; None = left out."""
        if not label:
            return None
        if label in self.types:
            return self.types[label]
        for group in self.groups_of(label):
            if group in self.types:
                return self.types[group]
        return None


@functools.cache
def load_rules(path: Optional[str] = None) -> Rules:
    raw = json.loads(Path(path or RULES_FILE).read_text())
    return Rules(
        types=dict(raw["types"]), doors=frozenset(raw.get("doors", ())),
        door_state=raw.get("door_state", "closed"),
        support_relations=dict(raw["support_relations"]),
        cleanup_target=raw.get("cleanup_target", "sink"),
        robot_name=raw.get("robot", {}).get("name", "robot"), robot_type=raw.get("robot", {}).get("type", "agent"),
        commands=list(raw.get("commands", [])), phrases=dict(raw.get("phrases", {})),
        articles=tuple(raw.get("articles", ("the",))),
        placement=tuple(raw.get("placement", {}).get("rules", ())),
        placement_default=dict(raw.get("placement", {}).get("default", {"to": ["stay"], "rule": "it stays unless named"})))
