"""The parts of an answer as they appear in `sg3d ask --json`, `POST /ask` and the MCP `ask` tool.

Plain dicts (so the JSON is the dict), typed for readers and mypy. Which keys an object entry
carries depends on the answer's form; every key is optional.
"""
from __future__ import annotations

from typing import Any, Optional, TypedDict


class AnswerObject(TypedDict, total=False):
    """One entry of `Answer.objects`: an object (id, label, colour, volume, room; for a superlative
    its anchor and distance; for "where" its relations), a count per label or per room (label or
    room, n), or a change between scans (name, where it was and is: see sg3d/app/changes.py)."""

    id: str
    label: str
    name: str
    colour: str
    volume: float
    room: str
    n: int
    found_room: str         # the room of a walk (`sg3d build --rooms auto`) a per-room count is of
    anchor_id: str
    anchor_label: str
    distance: float
    relations: list[dict[str, Any]]
    # an unnamed object listed because it could be the asked kind (none of it is named):
    # that kind, its shape class, box sides and what it rests on ("on the desk")
    could_be: str
    shape: Optional[str]
    size: list[float]
    support: str


class Provenance(TypedDict):
    """An object an answer rests on and how sure the store is of it."""

    id: str
    name: Optional[str]
    label: str
    room: Optional[str]
    score: Optional[float]
    observations: Optional[int]
    n_frames: Optional[int]
    first_frame: Optional[int]
    last_frame: Optional[int]
    last_seen: Optional[str]


class TemplateStep(TypedDict, total=False):
    """One Cypher template an answer ran, with its parameters (what --explain prints)."""

    template: str
    rel_type: str
    params: dict[str, Any]
