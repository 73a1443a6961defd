"""The read side's shapes: what the store gives back about a room's graph, one definition each.

`StoredObject`, `StoredRelation` and `StoredGraph` are what `sg3d.graphdb.export.fetch_graph`
returns and what the formats (`sg3d.formats`), the pictures (`sg3d.render`, through a `Scene`) and
the HTTP service's `/graph` read; `as_json` gives the export's JSON form (the paper's JSON of `sg3d export`), key for
key as the store's rows name them. `Row` is one record of a Cypher template (cypher/*.cypher) or
one row sent to one: its keys are the template's `RETURN ... AS` names or its `$rows` fields.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from typing import Any, Optional

# One record a Cypher template returns, or one row of the `$rows` list a template takes.
Row = dict[str, Any]

# The stored properties of an Object node that an export carries, in the export's order.
NODE_FIELDS = ("id", "room", "label", "labels", "scores", "x", "y", "z", "var", "n_points", "size",
               "volume", "colour", "first_frame", "last_frame", "observations", "n_frames",
               "first_seen", "last_seen", "removed_at", "layer", "shape", "colour2", "named_by")
# What a read adds to them, in that order after them, each only where it is known.
_ADDED = ("hist", "thumbnail_jpeg_base64", "name", "box_centre")


@dataclass(frozen=True)
class StoredObject:
    """An Object node as read back: its stored properties (NODE_FIELDS), the name of its room, and
    what a read may add: its colour histogram, its thumbnail (base64 JPEG), its readable name."""

    id: str
    room: Optional[str] = None                  # building/room
    label: Optional[str] = None
    labels: Optional[list[str]] = None
    scores: Optional[list[float]] = None
    x: Optional[float] = None
    y: Optional[float] = None
    z: Optional[float] = None
    var: Optional[list[float]] = None
    n_points: Optional[int] = None
    size: Optional[list[float]] = None
    volume: Optional[float] = None
    colour: Optional[str] = None
    first_frame: Optional[int] = None
    last_frame: Optional[int] = None
    observations: Optional[int] = None
    n_frames: Optional[int] = None
    first_seen: Optional[float] = None
    last_seen: Optional[float] = None
    removed_at: Optional[float] = None
    layer: Optional[str] = None
    shape: Optional[str] = None
    colour2: Optional[str] = None
    named_by: Optional[str] = None
    room_name: Optional[str] = None             # the room's own name (the room id's last part)
    hist: Optional[list[float]] = None          # 512 bins, when the read asked for histograms
    thumbnail_jpeg_base64: Optional[str] = None  # when the read asked for thumbnails
    name: Optional[str] = None                  # the readable name ask, plan and show print
    box_centre: Optional[list[float]] = None    # its 3-D box's centre, where a picture needs it

    def as_json(self) -> Row:
        """The export's JSON form: every stored field (null where unknown), then what the read added."""
        out: Row = {k: getattr(self, k) for k in NODE_FIELDS}
        out["room_name"] = self.room_name
        out.update({k: getattr(self, k) for k in _ADDED if getattr(self, k) is not None})
        return out


@dataclass(frozen=True)
class StoredRelation:
    """A relation edge as read back: subject id, type (the whitelist), object id, score, count."""

    s: str
    type: str
    o: str
    score: Optional[float] = None
    count: Optional[int] = None

    @classmethod
    def from_row(cls, row: Row) -> StoredRelation:
        return cls(s=row["s"], type=row["type"], o=row["o"], score=row.get("score"), count=row.get("count"))

    def as_json(self) -> Row:
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class StoredGraph:
    """A room's (room set) or a whole building's (room None) objects and relation edges; with
    `room_transforms` (room name -> row-major 4x4 room-to-building, or None) where a read asked."""

    building: str
    room: Optional[str]
    nodes: list[StoredObject] = field(default_factory=list)
    edges: list[StoredRelation] = field(default_factory=list)
    room_transforms: Optional[dict[str, Any]] = None

    def named(self, names: dict[str, str]) -> StoredGraph:
        """The graph with each node's readable name (`names`: node id -> name)."""
        return replace(self, nodes=[replace(n, name=names[n.id]) for n in self.nodes])

    def present(self) -> StoredGraph:
        """The graph without the objects a re-scan marked removed (`removed_at`) and their edges."""
        gone = {n.id for n in self.nodes if n.removed_at is not None}
        if not gone:
            return self
        return replace(self, nodes=[n for n in self.nodes if n.id not in gone],
                       edges=[e for e in self.edges if e.s not in gone and e.o not in gone])

    def as_json(self) -> Row:
        """The export's JSON form {building, room, nodes, edges[, room_transforms]}."""
        out: Row = {"building": self.building, "room": self.room, "nodes": [n.as_json() for n in self.nodes],
                    "edges": [e.as_json() for e in self.edges]}
        if self.room_transforms is not None:
            out["room_transforms"] = self.room_transforms
        return out


@dataclass(frozen=True)
class RoomFrame:
    """A room's own frame as stored: its id (building/room), its up direction (3 floats, or None:
    not known) and its room-to-building transform (4x4, or None: not linked)."""

    id: str
    up: Optional[list[float]] = None
    to_building: Optional[list[list[float]]] = None


@dataclass(frozen=True)
class Scene:
    """What the pictures draw (`sg3d show`, `sg3d eval --report`): a named graph whose nodes carry
    their box centres, and the frame of each of its rooms by room name."""

    graph: StoredGraph
    rooms: dict[str, RoomFrame] = field(default_factory=dict)

    @property
    def nodes(self) -> list[StoredObject]:
        return self.graph.nodes

    @property
    def edges(self) -> list[StoredRelation]:
        return self.graph.edges
