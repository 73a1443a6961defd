"""Viewpoint relations at query time, and "where is X" as one sentence.

"In front of", "behind", "left of" and "right of" depend on where the observer stands, so the
graph never stores them (`sg3d.core.relation_rules`). They are computed when asked, from the stored
3-D boxes, relative to a viewpoint given in one of three ways:

- in the question: "is the cup in front of the table as seen from the sink" (the grammar reads
  "as seen from / seen from / viewed from / looking from the <object>" at the end; the object's
  box centre is the eye);
- by the caller: `answer(..., viewpoint=...)` / `ask` with a camera pose (4x4 camera-to-world,
  `{"pose": [[...]]}`), a point (`{"position": [x, y, z]}`, world frame of the room), or an object
  name (`{"object": "sink"}`): what a robot passes for "in front of the table, from where I am";
- neither: the question is refused with how to give one.

Geometry (gravity frame of the room, horizontal only): the viewing direction d runs from the eye
to the anchor's box centre; "right" is d x up. A target is IN_FRONT_OF the anchor when its far
face (along d) is at most FRONT_TOLERANCE past the anchor's near face, the two overlap laterally
by >= MIN_LATERAL_OVERLAP of the narrower one, and the depth gap is <= MAX_DEPTH_GAP; BEHIND is
the mirror. LEFT_OF: the target's right edge is at most FRONT_TOLERANCE past the anchor's left
edge, within MAX_SIDE_GAP, and their depth intervals overlap (same distance from the eye, up to
FRONT_TOLERANCE); RIGHT_OF the mirror.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

from sg3d.core.geometry import horizontal_frame
from sg3d.core.relation_rules import SYMMETRIC, VIEWPOINT
from sg3d.core.stored import Row
from sg3d.ingest.relate.relations import MIN_EXTENT
from sg3d.queries.lexicon import resolve

FRONT_TOLERANCE = 0.05
MIN_LATERAL_OVERLAP = 0.3
MAX_DEPTH_GAP = 1.5
MAX_SIDE_GAP = 1.0

def eye_from(viewpoint) -> Optional[np.ndarray]:
    """The eye position of a caller's viewpoint: {"pose": 4x4}, {"position": xyz} or an xyz;
    None for {"object": name} (resolved against the store) or no viewpoint."""
    if viewpoint is None:
        return None
    if isinstance(viewpoint, dict):
        if "pose" in viewpoint:
            pose = np.asarray(viewpoint["pose"], dtype=float)
            if pose.shape != (4, 4) or not np.isfinite(pose).all():
                raise ValueError("a viewpoint pose is a finite 4x4 camera-to-world matrix")
            return pose[:3, 3]
        if "position" in viewpoint:
            viewpoint = viewpoint["position"]
        else:
            return None
    eye = np.asarray(viewpoint, dtype=float).reshape(-1)
    if eye.shape != (3,) or not np.isfinite(eye).all():
        raise ValueError("a viewpoint position is three finite numbers (x, y, z)")
    return eye


def _box(row: dict, R: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    centre = row.get("box_centre") or [row["x"], row["y"], row["z"]]
    return R @ np.asarray(centre, dtype=float), np.maximum(np.asarray(row["size"], dtype=float), MIN_EXTENT)


def _interval(c: np.ndarray, s: np.ndarray, v: np.ndarray) -> tuple[float, float]:
    mid = float(c[:2] @ v)
    half = float(abs(v[0]) * s[0] + abs(v[1]) * s[1]) / 2
    return mid - half, mid + half


def _overlap(a: tuple[float, float], b: tuple[float, float]) -> float:
    return max(0.0, min(a[1], b[1]) - max(a[0], b[0]))


def viewpoint_relations(target: dict, anchor: dict, eye: ArrayLike, up: ArrayLike) -> set[str]:
    """Which of IN_FRONT_OF / BEHIND / LEFT_OF / RIGHT_OF the target holds to the anchor, seen
    from `eye` (module docstring). Rows carry box_centre (or x, y, z) and size (w, d, h)."""
    R = horizontal_frame(up)
    tc, ts = _box(target, R)
    ac, as_ = _box(anchor, R)
    d = (ac - R @ np.asarray(eye, dtype=float))[:2]
    if np.linalg.norm(d) < 1e-6:
        return set()
    d = d / np.linalg.norm(d)
    right = np.array([d[1], -d[0]])
    t_depth, a_depth = _interval(tc, ts, d), _interval(ac, as_, d)
    t_side, a_side = _interval(tc, ts, right), _interval(ac, as_, right)
    out = set()
    lateral = _overlap(t_side, a_side) / max(min(t_side[1] - t_side[0], a_side[1] - a_side[0]), 1e-9)
    if lateral >= MIN_LATERAL_OVERLAP:
        if t_depth[1] <= a_depth[0] + FRONT_TOLERANCE and a_depth[0] - t_depth[1] <= MAX_DEPTH_GAP:
            out.add("IN_FRONT_OF")
        elif t_depth[0] >= a_depth[1] - FRONT_TOLERANCE and t_depth[0] - a_depth[1] <= MAX_DEPTH_GAP:
            out.add("BEHIND")
    if _overlap(t_depth, a_depth) > FRONT_TOLERANCE or lateral == 0.0 and _overlap(t_depth, a_depth) > 0:
        if t_side[1] <= a_side[0] + FRONT_TOLERANCE and a_side[0] - t_side[1] <= MAX_SIDE_GAP:
            out.add("LEFT_OF")
        elif t_side[0] >= a_side[1] - FRONT_TOLERANCE and t_side[0] - a_side[1] <= MAX_SIDE_GAP:
            out.add("RIGHT_OF")
    return out


def related(run, q, rooms, viewpoint, seen_from: Optional[str]) -> list[Row]:
    """Rows of `q.target` objects that hold `q.relation` (a viewpoint type) to a `q.anchor`
    object, seen from the viewpoint; shaped like the vqa_related rows. `run` reads templates
    (sg3d.queries.vqa._Run); ValueError carries the refusal text."""
    if q.relation not in VIEWPOINT:
        raise ValueError(f"{q.relation} is not a viewpoint relation")
    name = seen_from or (viewpoint.get("object") if isinstance(viewpoint, dict) else None)
    eye = eye_from(viewpoint) if name is None else None
    if eye is None and name is None:
        raise ValueError(f"'{q.relation_word}' depends on where you stand: add 'as seen from the <object>' "
                         "or pass a viewpoint (a camera pose, a point, or an object)")
    targets = run.read("vqa_boxes", labels=q.target.labels, rooms=rooms, colour=q.colour)
    anchors = run.read("vqa_boxes", labels=q.anchor.labels, rooms=rooms, colour=None)
    ups = {r["id"]: r["up"] for r in run.read("vqa_room_up", rooms=sorted({a["room"] for a in anchors}))}
    eyes: dict[str, np.ndarray] = {}
    eye_ids: set[str] = set()
    if name is not None:
        named, _ = resolve(name, use_embedding=False)      # synonyms: "fridge" is a refrigerator
        labels = named.labels if named is not None and named.labels else [name.lower()]
        for v in run.read("vqa_boxes", labels=labels, rooms=rooms, colour=None):
            if v["room"] not in eyes:
                eyes[v["room"]] = np.asarray(v.get("box_centre") or [v["x"], v["y"], v["z"]], float)
                eye_ids.add(v["id"])
        if not eyes:
            raise ValueError(f"no {name} in the store to look from")
    rows = []
    for t in targets:
        if t["id"] in eye_ids:          # the observer is not in front of anything it looks at
            continue
        for a in anchors:
            if a["id"] == t["id"] or a["room"] != t["room"]:
                continue
            at = eye if name is None else eyes.get(a["room"])
            if at is None:
                continue
            if q.relation in viewpoint_relations(t, a, at, ups.get(a["room"]) or (0.0, 0.0, 1.0)):
                rows.append({**{k: t.get(k) for k in ("id", "label", "colour", "volume", "size", "room")},
                             "anchor_id": a["id"], "anchor_label": a["label"]})
    seen, unique = set(), []
    for r in rows:
        if r["id"] not in seen:
            seen.add(r["id"])
            unique.append(r)
    return unique


# -- "where is X": one sentence, support first -------------------------------------------------
# the order in which relations describe where something is: what holds it, what it is under or
# over, then its neighbours
PLACE_ORDER = ("IN", "ON", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR")
PLACE_WORDS = {"IN": "in", "ON": "on", "UNDER": "under", "ABOVE": "above", "BELOW": "below",
               "NEXT_TO": "next to", "NEAR": "near"}
MAX_NEIGHBOURS = 2


def _name(other: dict, names: Optional[dict] = None) -> str:
    if names and other.get("other_id") in names:
        return names[other["other_id"]]
    colour = other.get("other_colour")
    return f"the {colour} {other['other_label']}" if colour else f"the {other['other_label']}"


def describe_place(relations: list[Row], names: Optional[dict] = None) -> str:
    """'on the dining table, next to the white cup and the black chair' from where-rows (rel,
    other_id, other_label, other_colour): supports first, at most MAX_NEIGHBOURS side-by-side
    neighbours, NEAR only when nothing is NEXT_TO, each other object named once; `names` (id ->
    name with its article) names the others as everywhere else."""
    ranked = sorted((r for r in relations if r["rel"] in PLACE_WORDS),
                    key=lambda r: (PLACE_ORDER.index(r["rel"]), -(r.get("rel_score") or 0.0)))
    if any(r["rel"] == "NEXT_TO" for r in ranked):
        ranked = [r for r in ranked if r["rel"] != "NEAR"]
    parts: list[tuple[str, list[str]]] = []
    named: set[str] = set()
    neighbours = 0
    for r in ranked:
        if r["other_id"] in named:
            continue
        side_by_side = r["rel"] in SYMMETRIC
        if side_by_side and neighbours >= MAX_NEIGHBOURS:
            continue
        named.add(r["other_id"])
        neighbours += side_by_side
        word = PLACE_WORDS[r["rel"]]
        if parts and parts[-1][0] == word:
            parts[-1][1].append(_name(r, names))
        else:
            parts.append((word, [_name(r, names)]))
    return ", ".join(f"{w} {' and '.join(names)}" for w, names in parts)
