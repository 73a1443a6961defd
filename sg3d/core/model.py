"""Plain data that flows from perception into the store.

`ingest` produces `LocalGraph`s; `graphdb` persists and merges them. Nothing here touches the
store or the models, so every layer can import it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Optional, cast

import numpy as np

Vec3 = tuple[float, float, float]


def vec3(values: Iterable[float]) -> Vec3:
    """The floats of a 3-vector (a numpy array, a list) as the plain tuple the model stores."""
    return cast(Vec3, tuple(float(v) for v in values))

HIST_BINS = 8  # per HSV axis; the paper's c (Sec. V-B), 8**3 = 512 values
HIST_SIZE = HIST_BINS ** 3
TOP_K = 5
# Coordinates (m) a room or building can have, for camera poses and object positions alike.
WORLD_EXTENT_M = 10_000.0

# The fixed whitelist of relation types. Cypher cannot take a relation type as a parameter,
# so every type that reaches a statement must be one of these.
RELATION_TYPES = (
    "ON", "UNDER", "ABOVE", "BELOW", "IN", "CONTAINS_OBJ", "NEXT_TO", "NEAR",
    "IN_FRONT_OF", "BEHIND", "LEFT_OF", "RIGHT_OF", "BIGGER_THAN", "SMALLER_THAN",
)

COLOUR_NAMES = (
    "red", "orange", "yellow", "green", "blue", "purple", "pink",
    "brown", "black", "white", "grey",
)

# The label of an object found from geometry that no detector named: it is counted and listed,
# described by its shape, size and colour, never given a class name from one view.
UNNAMED_LABEL = "object"
# Layers of the graph (spark_dsg's objects and structure): "object" for things in the room,
# "structure" for the room's floor, walls and large horizontal surfaces (counters, shelves).
LAYERS = ("object", "structure")
# Plain shape words for unnamed objects, where the geometry says one (`sg3d.core.shape`).
SHAPE_WORDS = ("flat", "box-shaped", "tall", "round", "panel")


@dataclass
class ObjectObservation:
    """One object of a local 3-D scene graph (the paper's vertex, Sec. V-A/V-B).

    Positions are in the sequence's world frame (camera-to-world poses), metres.
    """

    local_id: str
    labels: list[str]                      # top-k labels, best first
    scores: list[float]                    # their scores, same order
    mean: tuple[float, float, float]       # Gaussian position mean (Eq. 8 points)
    var: tuple[float, float, float]        # per-axis variance
    n_points: int                          # points behind mean/var
    size: tuple[float, float, float]       # extent: width, depth, height (height along "up"), m
    hist: np.ndarray                       # HSV histogram, HIST_SIZE counts (Eq. 9)
    colour: str = "grey"                   # dominant colour name from COLOUR_NAMES
    thumbnail: Optional[bytes] = None      # JPEG bytes of the box
    first_frame: int = 0
    last_frame: int = 0
    n_frames: int = 1                      # frames of the keyframe group that saw it
    box_centre: Optional[tuple[float, float, float]] = None  # centre of the 3-D box (size); None: mean
    layer: str = "object"                  # one of LAYERS
    shape: Optional[str] = None            # one of SHAPE_WORDS, for unnamed objects; None: not said
    colour2: Optional[str] = None          # a second colour from COLOUR_NAMES (two-coloured objects)
    # a sample of points seen on the object's surface, world frame, flat (x, y, z, x, y, z, ...):
    # what a re-scan tests for free space where the box alone cannot tell (unnamed segments)
    surface: Optional[tuple[float, ...]] = None
    # what named it: None for the detector (or nothing, for unnamed objects), "shape" when its
    # shape in the room's cloud did (`sg3d.ingest.discover.furniture`)
    named_by: Optional[str] = None

    @property
    def label(self) -> str:
        return self.labels[0]

    @property
    def score(self) -> float:
        return float(self.scores[0])


@dataclass
class RelationObservation:
    """A directed edge subject -[predicate]-> object between objects of one local graph."""

    subject: str        # local_id
    predicate: str      # one of RELATION_TYPES
    object: str         # local_id
    score: float = 1.0

    def __post_init__(self) -> None:
        if self.predicate not in RELATION_TYPES:
            raise ValueError(f"unknown relation type {self.predicate!r}")


@dataclass(frozen=True)
class KnownObject:
    """An object already in the store, as a re-scan's removal test sees it: its box."""

    id: str
    box_centre: tuple[float, float, float]   # world frame
    size: tuple[float, float, float]         # extent along the room's gravity axes e1, e2, up
    surface: Optional[tuple[float, ...]] = None   # points seen on it, flat x, y, z (ObjectObservation)


@dataclass(frozen=True)
class ScanInfo:
    """One scan of a room (a `sg3d build` or a `POST /ingest` batch): its id and time. A scan
    of several chunks closes (decides what was removed) in its last chunk's merge."""

    id: str
    at: float                                # seconds since the epoch, when the scan started
    closes: bool = True                      # this local graph is the scan's last chunk


@dataclass
class LocalGraph:
    """The local 3-D scene graph of one keyframe group (Sec. V-B)."""

    room: str
    objects: list[ObjectObservation]
    relations: list[RelationObservation] = field(default_factory=list)
    building: str = "default"
    # identifies this observation so a re-run or --resume can skip it; None = always merge
    key: Optional[str] = None
    frames: list[int] = field(default_factory=list)
    up: Optional[tuple[float, float, float]] = None  # room's up direction in world frame
    scan: Optional[ScanInfo] = None        # None: a scan of its own, named by the key
    # stored object id -> frames of this graph that saw its place empty (sg3d.ingest.objects.rescan)
    empty_places: dict[str, list[int]] = field(default_factory=dict)
