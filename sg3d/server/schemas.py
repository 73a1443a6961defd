"""The shapes of `sg3d serve`'s responses, for /openapi.json.

Routes return JSON encoded once by `json_response`, which FastAPI passes through without
validating against these models (validation would walk every answer a second time); the tests
check that real responses match them. `extra="allow"`: a field added to an answer is documented
here when it matters to callers, and never breaks one.
"""
from __future__ import annotations

from typing import Any, Optional

from pydantic import BaseModel, ConfigDict, Field

from sg3d.core.stored import StoredGraph


class _Open(BaseModel):
    model_config = ConfigDict(extra="allow")


class Health(_Open):
    status: str = Field(description="'ok', or why the store cannot be reached")
    store: bool = Field(description="whether the store answered")
    state: str = Field(description="'up'; 'down' (unreachable, restarting or not answering: 503 with "
                                   "Retry-After); 'stopped' (`sg3d db stop`: 503 until `sg3d db start`); "
                                   "'disk full' (507: less free space than SG3D_MIN_FREE_MB by the store)")
    version: str


class Error(_Open):
    detail: str = Field(description="what went wrong, in one line")


class FieldError(_Open):
    loc: list[Any] = Field(description="where in the request: body/query/path, then the field names")
    msg: str = Field(description="the rule the value broke (the value itself is never echoed)")
    type: str


class ValidationFailure(_Open):
    detail: list[FieldError] | str = Field(description="each field that failed, or why the body is not JSON")


class AnswerObject(_Open):
    id: str
    label: Optional[str] = None
    colour: Optional[str] = None
    room: Optional[str] = Field(None, description="building/room")
    name: Optional[str] = Field(None, description="the readable name ask, plan and show print")


class Provenance(_Open):
    id: str
    name: Optional[str] = None
    label: Optional[str] = None
    room: Optional[str] = None
    score: Optional[float] = None
    observations: Optional[int] = None
    n_frames: Optional[int] = None
    first_frame: Optional[int] = None
    last_frame: Optional[int] = None
    last_seen: Optional[str] = None


class QueryStep(_Open):
    template: str = Field(description="the cypher/*.cypher file run")
    params: dict[str, Any] = Field(default_factory=dict)


class AskAnswer(_Open):
    question: str
    ok: bool = Field(description="false when the question could not be answered; `answer` says why")
    form: Optional[str] = Field(None, description="count, exists, list, where, show, ...")
    answer: str = Field(description="the answer in words")
    value: Any = Field(None, description="the answer as data: a number, a yes/no, an object or a list of them")
    objects: list[dict[str, Any]] = Field(default_factory=list, description="the objects the answer names")
    logical_form: Optional[dict[str, Any]] = None
    absent_evidence: Optional[bool] = None
    query: Optional[dict[str, Any]] = None
    steps: list[QueryStep] = Field(default_factory=list)
    templates: list[str] = Field(default_factory=list)
    provenance: list[Provenance] = Field(default_factory=list, description="what the answer rests on")
    thumbnail_bytes: Optional[int] = None
    thumbnail: Optional[str] = Field(None, description="a picture file on the server (never set over HTTP)")
    thumbnail_jpeg_base64: Optional[str] = Field(None, description="the answer's picture, base64 JPEG")


class Room(_Open):
    building: str
    id: str = Field(description="building/room")
    name: str
    objects: int = Field(description="how many objects it holds")
    to_building: Optional[list[list[float]]] = Field(None, description="4x4 room-to-building transform")
    adjacent: list[Any] = Field(default_factory=list)


class Mapping(_Open):
    state: str = Field(description="live while `sg3d map` follows its source, done once it ended")
    since: Optional[float] = Field(None, description="when mapping began (seconds since the epoch)")
    frames: int = Field(0, description="frames received so far")
    last_publish: Optional[float] = Field(None, description="when the graph was last published")
    source: Optional[str] = None


class RoomState(Room):
    mapping: Optional[Mapping] = Field(None, description="the live map building this room; null: never mapped live")


class RoomObject(_Open):
    id: str
    name: str
    label: str
    colour: Optional[str] = None
    position: list[float] = Field(description="x, y, z in the room's frame (metres)")
    size: Optional[list[float]] = None
    volume: Optional[float] = None
    score: Optional[float] = None
    room: str
    distance: Optional[float] = Field(None, description="metres from `near`, when given")


# GET /graph answers `sg3d.core.stored.StoredGraph.as_json()`: the read side's one definition of
# a node, an edge and a graph
Graph = StoredGraph


class PlanStep(_Open):
    action: str
    args: list[str]
    text: str


class Plan(_Open):
    room: str
    planner: str
    valid: bool
    seconds: float
    goal: list[str] = Field(description="the goal atoms in PDDL")
    plan: list[PlanStep]
    moved: dict[str, dict[str, Any]] = Field(default_factory=dict)
    objects: dict[str, str] = Field(default_factory=dict, description="PDDL object -> node id")
    left_out: dict[str, str] = Field(default_factory=dict, description="objects the plan could not use, and why")
    domain_pddl: str
    problem_pddl: str


class IngestResult(_Open):
    key: Optional[str] = Field(None, description="the observation's merge key")
    room: str
    skipped: bool = Field(description="true when this observation_id was merged already")
    created: int
    updated: int
    absorbed: int
    moved: int
    removed: int
    relations: int
    node_ids: dict[str, str] = Field(description="local id -> stored node id")
    room_objects: int


ROUTE_ERRORS: dict[int | str, dict[str, Any]] = {
    400: {"model": Error, "description": "the request cannot be answered as asked"},
    401: {"model": Error, "description": "missing or wrong token"},
    404: {"model": Error, "description": "no such room or building"},
    413: {"model": Error, "description": "request body larger than --max-body, or a statement too large for "
                                          "one message to the store (refused before it was sent)"},
    422: {"model": ValidationFailure, "description": "a field failed validation, or the body is not strict JSON"},
    503: {"model": Error, "description": "the store is stopped, restarting or did not answer in time "
                                          "(Retry-After unless stopped)"},
    500: {"model": Error, "description": "an internal error, named by its type only"},
    507: {"model": Error, "description": "the store's disk is full"},
}
