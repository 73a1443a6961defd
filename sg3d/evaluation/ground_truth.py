"""Ground truth for `sg3d eval`: loading a hand-annotated scene file and normalising its wording.

Annotators write what they see, not what a detector can say: the COCO category may be hedged
("mouse?", "cup? (or wine glass)"), given as the nearest class ("(book)", "remote (nearest
COCO)") or absent ("(none)", null). Relation predicates are plain English ("next to"). This
module turns both into the store's vocabulary and keeps how sure the annotator was.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from sg3d.core.model import RELATION_TYPES
from sg3d.core.stored import Row
from sg3d.ingest.discover import furniture
from sg3d.core.relation_rules import INVERSE, SYMMETRIC  # noqa: F401 - sg3d.evaluation.edges reads them here

# The GT's "sure"/"unsure" wording; anything else is treated as sure (the default annotation).
UNSURE = "unsure"

# English wordings that are not just the type name with spaces.
PREDICATE_WORDING = {"on top of": "ON", "beside": "NEXT_TO", "inside": "IN", "contains": "CONTAINS_OBJ",
                     "below": "BELOW", "beneath": "UNDER", "underneath": "UNDER", "near to": "NEAR",
                     "left of": "LEFT_OF", "right of": "RIGHT_OF", "to the left of": "LEFT_OF",
                     "to the right of": "RIGHT_OF", "bigger than": "BIGGER_THAN",
                     "smaller than": "SMALLER_THAN", "larger than": "BIGGER_THAN"}


@dataclass(frozen=True)
class GTObject:
    id: str
    category: str                   # the annotator's free name
    coco: Optional[str]             # the COCO class a detector could output, or None
    coco_hedged: bool               # the annotator hedged the COCO class ("?", nearest class)
    sure: bool                      # count_confidence == sure
    position: Optional[tuple[float, float, float]]   # None: the annotator gave no position
    colour: Optional[str] = None


@dataclass(frozen=True)
class GTRelation:
    subject: str
    predicate: str                  # as written
    object: str
    type: Optional[str]             # our RELATION_TYPES name, None when no type fits


@dataclass(frozen=True)
class GTQuestion:
    text: str
    answer: object
    kind: str
    sure: bool


@dataclass
class GroundTruth:
    objects: list[GTObject]
    relations: list[GTRelation]
    questions: list[GTQuestion]
    sequence: str = ""
    coordinate_frame: str = ""
    by_id: dict[str, GTObject] = field(init=False)

    def __post_init__(self):
        self.by_id = {o.id: o for o in self.objects}


def coco_class(annotation: Optional[str], coco_names: set[str]) -> tuple[Optional[str], bool]:
    """(COCO class, hedged) from an annotated category such as "cup", "mouse?", "(book)",
    "remote (nearest COCO)", "tv? (free name)" or "(none)".

    The text outside parentheses wins; a bare parenthesised class means "closest class". Anything
    other than an exact class name counts as hedged."""
    if not annotation:
        return None, False
    text = annotation.strip().lower()
    if text in coco_names:
        return text, False
    outside = re.sub(r"\([^)]*\)", " ", text).replace("?", " ")
    outside = " ".join(outside.split())
    if outside in coco_names:
        return outside, True
    for inner in re.findall(r"\(([^)]*)\)", text):
        inner = " ".join(inner.replace("?", " ").split())
        if inner in coco_names:
            return inner, True
    return None, False


def relation_type(predicate: str) -> Optional[str]:
    """Our relation type for an English predicate ("on", "next to", "in front of"), or None."""
    words = " ".join(predicate.strip().lower().replace("_", " ").replace("-", " ").split())
    if words in PREDICATE_WORDING:
        return PREDICATE_WORDING[words]
    name = words.upper().replace(" ", "_")
    return name if name in RELATION_TYPES else None


# Labels sg3d gives from an object's shape where no COCO class fits: a GT object of such a
# category is judged like a COCO-named one (named recall and precision count it).
NAMED_BY_SHAPE = frozenset({furniture.DESK_LABEL, furniture.CABINET_LABEL})


def default_coco_names() -> set[str]:
    from sg3d.ingest.detect.models import load_label_map

    return {name.lower() for name in load_label_map().values()}


def parse_gt(data: dict, coco_names: Optional[set[str]] = None) -> GroundTruth:
    """A ground-truth dict (the JSON file's content) -> GroundTruth. Raises ValueError with the
    offending entry when a required field is missing."""
    names = coco_names if coco_names is not None else default_coco_names()
    objects = []
    for i, o in enumerate(data.get("objects", [])):
        try:
            coco, hedged = coco_class(o.get("coco_category"), names)
            if coco is None and str(o.get("category", "")).strip().lower() in NAMED_BY_SHAPE:
                coco, hedged = str(o["category"]).strip().lower(), False     # a desk: sg3d names it
            raw = o.get("world_position")
            pos = None if raw is None else tuple(float(v) for v in raw)
            if pos is not None and len(pos) != 3:
                raise ValueError("world_position needs 3 numbers")
            objects.append(GTObject(id=str(o["id"]), category=str(o.get("category", "")), coco=coco,
                                    coco_hedged=hedged,
                                    sure=str(o.get("count_confidence", "sure")).lower() != UNSURE,
                                    position=pos, colour=o.get("colour")))
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(f"ground-truth object #{i} ({o.get('id', '?')}): {exc}") from None
    relations = []
    for i, r in enumerate(data.get("relations", [])):
        try:
            relations.append(GTRelation(str(r["subject"]), str(r["predicate"]), str(r["object"]),
                                        relation_type(str(r["predicate"]))))
        except KeyError as exc:
            raise ValueError(f"ground-truth relation #{i}: missing {exc}") from None
    questions = [GTQuestion(str(q["text"]), q.get("answer"), str(q.get("kind", "")), bool(q.get("sure", True)))
                 for q in data.get("questions", []) if "text" in q]
    return GroundTruth(objects, relations, questions, str(data.get("sequence", "")),
                       str(data.get("coordinate_frame", "")))


def load_gt(path, coco_names: Optional[set[str]] = None) -> GroundTruth:
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ValueError(f"cannot read ground truth {path}: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise ValueError(f"ground truth {path} is not valid JSON: {exc}") from None
    if not isinstance(data, dict):
        raise ValueError(f"ground truth {path}: expected a JSON object with objects/relations/questions")
    return parse_gt(data, coco_names)


def outside_extent(gt: GroundTruth, objects: list[Row], margin_m: float = 1.0) -> tuple[int, int]:
    """(GT objects with a position outside the room's extent, GT objects with a position). The
    extent is the axis-aligned box around the stored objects' boxes (`x, y, z, size` rows of
    cypher/eval_objects.cypher), grown by `margin_m`: ground truth of another sequence falls
    mostly outside it."""
    import numpy as np

    placed = [o.position for o in gt.objects if o.position is not None]
    if not placed or not objects:
        return 0, len(placed)
    centres = np.array([[o["x"], o["y"], o["z"]] for o in objects], dtype=float)
    halves = np.array([o.get("size") or (0.0, 0.0, 0.0) for o in objects], dtype=float) / 2
    low = (centres - halves).min(axis=0) - margin_m
    high = (centres + halves).max(axis=0) + margin_m
    points = np.array(placed, dtype=float)
    outside = ~np.all((points >= low) & (points <= high), axis=1)
    return int(outside.sum()), len(placed)
