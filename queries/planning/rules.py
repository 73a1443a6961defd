"""The graph -> PDDL rules (queries/data/planning_rules.json) and a label's taxonomy groups.

Rules are data so that teaching the planner a new kind of object means editing JSON, not code.
Groups come from `queries.taxonomy` when it is importable, else from the rules' fallback table.
"""
from __future__ import annotations

import functools
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

DATA = Path(__file__).resolve().parent.parent / "data"
RULES_FILE = DATA / "planning_rules.json"
DOMAIN_FILE = DATA / "household_domain.pddl"


class PlanningError(Exception):
    """A request the planner cannot serve, with a message a user can act on (one line)."""


@dataclass(frozen=True)
class Rules:
    types: dict[str, str]
    doors: frozenset[str]
    door_state: str
    support_relations: dict[str, str]          # graph relation type -> PDDL predicate
    fallback_groups: dict[str, list[str]]
    synonyms: dict[str, str]
    cleanup_target: str
    robot_name: str
    robot_type: str
    commands: list[dict] = field(default_factory=list)
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
        groups = _taxonomy_groups(label)
        if groups is None:
            groups = [g for g, members in self.fallback_groups.items() if label in members]
        return groups

    def synonym(self, word: str) -> str:
        """What a word means: the rules' own synonyms first, then the shared VQA table."""
        return self.synonyms.get(word) or shared_synonyms().get(word, "")

    def all_groups(self) -> set[str]:
        return set(self.fallback_groups) | set(_taxonomy_group_names() or ())

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
        fallback_groups={k: list(v) for k, v in raw.get("fallback_groups", {}).items()},
        synonyms=dict(raw.get("synonyms", {})), cleanup_target=raw.get("cleanup_target", "sink"),
        robot_name=raw.get("robot", {}).get("name", "robot"), robot_type=raw.get("robot", {}).get("type", "agent"),
        commands=list(raw.get("commands", [])), phrases=dict(raw.get("phrases", {})),
        articles=tuple(raw.get("articles", ("the",))),
        placement=tuple(raw.get("placement", {}).get("rules", ())),
        placement_default=dict(raw.get("placement", {}).get("default", {"to": ["stay"], "rule": "it stays unless named"})))


# -- the taxonomy, when another part of `queries` provides one -------------------------------
@functools.cache
def _taxonomy():
    try:
        from queries.taxonomy import Taxonomy  # written alongside; optional by design
        return Taxonomy.load()
    except Exception:  # noqa: BLE001 - absent or broken taxonomy: fall back to the rules' table
        return None


def _taxonomy_groups(label: str) -> Optional[list[str]]:
    tax = _taxonomy()
    if tax is None:
        return None
    # the taxonomy's API is not fixed yet; accept the usual spellings of "what is X a kind of"
    for method in ("ancestors", "groups_of", "groups", "parents"):
        fn = getattr(tax, method, None)
        if callable(fn):
            try:
                found = fn(label)
            except Exception:  # noqa: BLE001 - unknown label or another signature
                continue
            return [g for g in found if g != label]
    return None


def _taxonomy_group_names() -> Optional[list[str]]:
    value = getattr(_taxonomy(), "groups", None)   # a set property on queries.taxonomy.Taxonomy
    if callable(value):
        value = value()
    return list(value) if value else None


@functools.cache
def shared_synonyms() -> dict[str, str]:
    """Single-meaning words of the VQA synonym table (queries/data/synonyms.json), if present:
    one vocabulary for asking and for commanding. Words meaning several classes are skipped."""
    try:
        words = json.loads((DATA / "synonyms.json").read_text()).get("words", {})
    except (OSError, ValueError):
        return {}
    return {w: m[0] for w, m in words.items() if isinstance(m, list) and len(m) == 1}
