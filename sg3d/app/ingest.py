"""Ingest a local 3-D scene graph made by someone else's perception (a robot's): the JSON schema,
its validation, and the merge (`POST /ingest`).

The merge is the one `sg3d build` does for each chunk: same-node detection (Eq. 10-15) and the
update of matched nodes, all in ONE write transaction, logged under a key made of the building,
room and the caller's `observation_id`, so sending the same observation twice merges it once.
"""
from __future__ import annotations

import base64
import binascii
import math
from typing import Literal, Optional

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from sg3d.app import bounds
from sg3d.core.model import COLOUR_NAMES, HIST_SIZE, LAYERS, RELATION_TYPES, SHAPE_WORDS
from sg3d.graphdb.protocol import GraphStore

MAX_OBJECTS = 5000
MAX_RELATIONS = 50_000
MAX_LABELS = 20
# A thumbnail is a small crop (sg3d's own are at most 128 px, a few KB): a complete JPEG of at
# most this many bytes, so no field can carry a payload near the store's message limit.
MAX_THUMBNAIL_BYTES = 256 * 1024
MAX_THUMBNAIL_BASE64 = 4 * ((MAX_THUMBNAIL_BYTES + 2) // 3)

Vec3 = tuple[float, float, float]
# floats refuse NaN and +-Infinity (as numbers and as the JSON literals); ints are bounded below
STRICT = ConfigDict(extra="forbid", allow_inf_nan=False)


def _frames(v: list[int]) -> list[int]:
    if len(v) > bounds.MAX_FRAMES:
        raise ValueError(f"at most {bounds.MAX_FRAMES} frame numbers")
    if not all(0 <= f <= bounds.MAX_FRAME for f in v):
        raise ValueError(f"frame numbers must lie in [0, {bounds.MAX_FRAME}]")
    return v


def _checked(problem):
    if problem:
        raise ValueError(problem)


class ObjectIn(BaseModel):
    """One object of the local graph (the paper's vertex): world-frame metres."""

    model_config = STRICT
    id: str = Field(min_length=1, max_length=bounds.MAX_ID_CHARS,
                    description="local id, unique in this graph; relations use it")
    labels: list[str] = Field(min_length=1, max_length=MAX_LABELS, description="top-k labels, best first")
    scores: list[float] = Field(min_length=1, max_length=MAX_LABELS, description="their scores in [0, 1]")
    mean: Vec3 = Field(description="Gaussian position mean x, y, z (Eq. 8)")
    var: Vec3 = Field(description="per-axis position variance (m^2, >= 0)")
    n_points: int = Field(ge=1, le=bounds.MAX_POINTS, description="3-D points behind mean and var")
    size: Vec3 = Field(description="box extent: width, depth, height (m, >= 0)")
    box_centre: Optional[Vec3] = Field(None, description="centre of the 3-D box; default: mean")
    hist: list[float] = Field(min_length=HIST_SIZE, max_length=HIST_SIZE,
                              description=f"HSV histogram, 8x8x8 = {HIST_SIZE} non-negative values (Eq. 9)")
    colour: Literal[COLOUR_NAMES] = "grey"
    colour2: Optional[Literal[COLOUR_NAMES]] = Field(None, description="a second colour (two-coloured objects)")
    layer: Literal[LAYERS] = Field("object", description="object: a thing in the room; structure: floor, "
                                                         "walls, large horizontal surfaces")
    shape: Optional[Literal[SHAPE_WORDS]] = Field(None, description="a shape word for objects no detector named")
    thumbnail: Optional[str] = Field(None, max_length=MAX_THUMBNAIL_BASE64,
                                     description=f"base64 JPEG crop of the object: a complete JPEG of at "
                                                 f"most {MAX_THUMBNAIL_BYTES // 1024} KiB")
    frames: list[int] = Field(default_factory=list, max_length=bounds.MAX_FRAMES,
                              description="frame numbers that saw the object")

    @field_validator("id")
    @classmethod
    def _id(cls, v):
        _checked(bounds.id_problem(v))
        return v

    @field_validator("labels")
    @classmethod
    def _labels(cls, v):
        for s in v:
            _checked(bounds.label_problem(s))
        return [s.strip().lower() for s in v]

    @field_validator("frames")
    @classmethod
    def _object_frames(cls, v):
        return _frames(v)

    @field_validator("scores")
    @classmethod
    def _scores(cls, v):
        if not all(math.isfinite(s) and 0.0 <= s <= 1.0 for s in v):
            raise ValueError("scores must lie in [0, 1]")
        return v

    @field_validator("mean", "box_centre")
    @classmethod
    def _position(cls, v):
        if v is not None and not bounds.within_world(v):
            raise ValueError(f"positions must lie within +-{bounds.WORLD_EXTENT_M:g} m")
        return v

    @field_validator("var")
    @classmethod
    def _variance(cls, v):
        if not all(0 <= x <= bounds.MAX_VAR_M2 for x in v):
            raise ValueError(f"variances must lie in [0, {bounds.MAX_VAR_M2:g}] m^2")
        return v

    @field_validator("size")
    @classmethod
    def _size(cls, v):
        if not all(0 < x <= bounds.MAX_SIZE_M for x in v):
            raise ValueError(f"sizes must lie in (0, {bounds.MAX_SIZE_M:g}] m")
        return v

    @field_validator("hist")
    @classmethod
    def _hist(cls, v):
        if not all(0 <= x < 1e12 for x in v):
            raise ValueError("histogram values must lie in [0, 1e12)")
        return v

    @field_validator("thumbnail")
    @classmethod
    def _thumbnail(cls, v):
        if v is None:
            return v
        try:
            data = base64.b64decode(v, validate=True)
        except (binascii.Error, ValueError):
            raise ValueError("thumbnail must be base64") from None
        if len(data) > MAX_THUMBNAIL_BYTES:
            raise ValueError(f"thumbnail must be at most {MAX_THUMBNAIL_BYTES} bytes ({len(data)} given)")
        from sg3d.ingest.readers.image_checks import jpeg_problem   # (the readers package loads OpenCV)

        problem = jpeg_problem(data)
        if problem:
            raise ValueError(f"thumbnail must be a complete base64 JPEG (it {problem})")
        return v

    @model_validator(mode="after")
    def _pairs(self):
        if len(self.labels) != len(self.scores):
            raise ValueError(f"labels and scores differ in length ({len(self.labels)} vs {len(self.scores)})")
        return self


class RelationIn(BaseModel):
    """A directed edge subject -[predicate]-> object between objects of this graph."""

    model_config = STRICT
    subject: str = Field(min_length=1, max_length=bounds.MAX_ID_CHARS)
    predicate: Literal[RELATION_TYPES]
    object: str = Field(min_length=1, max_length=bounds.MAX_ID_CHARS)
    score: float = Field(1.0, ge=0.0, le=1.0)


class LocalGraphIn(BaseModel):
    """A local 3-D scene graph: objects, relations among them, the frames it came from."""

    model_config = STRICT
    objects: list[ObjectIn] = Field(min_length=1, max_length=MAX_OBJECTS)
    relations: list[RelationIn] = Field(default_factory=list, max_length=MAX_RELATIONS)
    frames: list[int] = Field(default_factory=list, max_length=bounds.MAX_FRAMES)
    up: Optional[Vec3] = Field(None, description="the room's up direction in the world frame (a unit vector)")

    @field_validator("frames")
    @classmethod
    def _graph_frames(cls, v):
        return _frames(v)

    @field_validator("up")
    @classmethod
    def _up(cls, v):
        return None if v is None else bounds.unit_up(v)

    @model_validator(mode="after")
    def _ids(self):
        ids = [o.id for o in self.objects]
        dup = sorted({i for i in ids if ids.count(i) > 1})
        if dup:
            raise ValueError(f"object ids must be unique ({len(dup)} repeated)")
        known = set(ids)
        for n, r in enumerate(self.relations):
            for end in ("subject", "object"):
                if getattr(r, end) not in known:
                    raise ValueError(f"relations[{n}].{end} is no object id of this graph")
            if r.subject == r.object:
                raise ValueError(f"relations[{n}] relates an object to itself")
        return self


class IngestRequest(BaseModel):
    """`POST /ingest`: one observation of a room, merged once per `observation_id`."""

    model_config = STRICT
    building: str = Field("default", max_length=bounds.MAX_NAME_CHARS)
    room: str = Field(max_length=bounds.MAX_NAME_CHARS)
    observation_id: str = Field(min_length=1, max_length=bounds.MAX_ID_CHARS,
                                description="the caller's id of this observation: the same id is merged once")
    graph: LocalGraphIn

    @field_validator("building", "room")
    @classmethod
    def _name(cls, v, info):
        return bounds.check_name(v, info.field_name)

    @field_validator("observation_id")
    @classmethod
    def _observation(cls, v):
        _checked(bounds.id_problem(v, "observation_id"))
        return v


def merge_key(req: IngestRequest) -> str:
    return f"ingest:{req.building}/{req.room}:{req.observation_id}"


def to_local_graph(req: IngestRequest):
    """The validated body as the `sg3d.core.model.LocalGraph` a build produces."""
    import numpy as np

    from sg3d.core.model import LocalGraph, ObjectObservation, RelationObservation

    objects = []
    for o in req.graph.objects:
        frames = sorted(o.frames)
        objects.append(ObjectObservation(
            local_id=o.id, labels=list(o.labels), scores=list(o.scores), mean=o.mean, var=o.var,
            n_points=o.n_points, size=o.size, hist=np.asarray(o.hist, dtype=float), colour=o.colour,
            thumbnail=base64.b64decode(o.thumbnail) if o.thumbnail else None,
            first_frame=frames[0] if frames else 0, last_frame=frames[-1] if frames else 0,
            n_frames=max(1, len(set(frames))), box_centre=o.box_centre, layer=o.layer, shape=o.shape,
            colour2=o.colour2))
    relations = [RelationObservation(r.subject, r.predicate, r.object, r.score) for r in req.graph.relations]
    return LocalGraph(room=req.room, building=req.building, objects=objects, relations=relations,
                      key=merge_key(req), frames=sorted(set(req.graph.frames)), up=req.graph.up)


def ingest_graph(store: GraphStore, req: IngestRequest, embedding=None) -> dict:
    """Merge the observation as one transaction; what was created, updated and linked. The room is
    written by one writer at a time (`sg3d.app.writers.writing`): an ingest waits briefly for
    another ingest of the room and is refused (RoomBusy, HTTP 409) while a build or a live map
    writes it. A new room is created by the merge transaction itself, so a merge that fails (a full
    disk, a store that went away, a statement refused) leaves no room and no building behind."""
    from sg3d.app.writers import INGEST_WAIT_S, Writer, writing
    from sg3d.graphdb.merge import merge_local_graph
    from sg3d.merge.similarity import SimilarityParams
    from sg3d.graphdb.values import room_id

    rid = room_id(req.building, req.room)
    store.ensure_schema()
    writer = Writer("ingest", f"POST /ingest {req.observation_id}", wait=lambda holder: holder.kind == "ingest",
                    wait_s=INGEST_WAIT_S)
    with writing(store, req.building, req.room, writer) as lease:
        report = merge_local_graph(store, to_local_graph(req), embedding, SimilarityParams(),
                                   fence=lease.fence, room_in_tx=True)
    return {"key": report.key, "room": rid, "skipped": report.skipped, "created": report.created,
            "updated": report.updated, "absorbed": report.absorbed, "moved": report.moved, "removed": report.removed, "relations": report.relations,
            "node_ids": report.node_ids, "room_objects": store.read("object_count", room=rid)[0]["n"]}
