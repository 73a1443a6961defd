"""Linking rooms into one building: transforms, SAME_AS and ADJACENT_TO.

Object positions stay in each room's own frame (every query of a room keeps working); a room
carries `to_building`, 16 floats, the row-major 4x4 taking its frame into the building frame.
The first room linked becomes the reference (identity). Linking room B to room A stores
B.to_building = A.to_building @ T(B→A), then objects of both rooms that coincide in the
building frame and match by label and colour get `(a)-[:SAME_AS {distance}]->(b)`, a in A,
and the rooms get `ADJACENT_TO {shared_objects, residual_m}` in both directions.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np
from neo4j import ManagedTransaction

from sg3d.core.embedding import LabelEmbedding
from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore
from sg3d.merge.align import (
    INLIER_M,
    RANSAC_ITERS,
    Alignment,
    AlignmentError,
    WeakAlignment,
    align_objects,
    apply,
    candidate_pairs,
    one_to_one,
    evidence_problem,
    positions,
    up_angle_deg,
)

# Two objects are one when their building-frame centres are this close: alignment residuals
# of a few centimetres plus the per-room scatter of a large object's centre.
LINK_TOL_M = 0.3
# A user's transform must be rigid: scale or shear would change every distance in the room.
RIGID_TOL = 1e-3


def room_objects(store: GraphStore, room_id: str) -> list[Row]:
    """A room's objects as an alignment reads them (`sg3d.merge.align.align_objects`)."""
    return store.read("align_room_objects", room=room_id)


def align_rooms(store: GraphStore, room_a_id: str, room_b_id: str, embedding: Optional[LabelEmbedding] = None, iters: int = RANSAC_ITERS,
                inlier_m: float = INLIER_M, seed: int = 0) -> Alignment:
    """The rigid transform taking room B's frame into room A's, from their shared objects."""
    objs_a, objs_b = room_objects(store, room_a_id), room_objects(store, room_b_id)
    for rid, objs in ((room_a_id, objs_a), (room_b_id, objs_b)):
        if not objs:
            raise AlignmentError(f"room {rid!r} holds no objects")
    return align_objects(objs_a, objs_b, embedding, iters, inlier_m, seed)


class TransformError(Sg3dError, ValueError):
    """A transform file that is not 4 lines of 4 numbers forming a rigid transform."""


@dataclass
class LinkReport:
    room_a: str
    room_b: str
    T: np.ndarray                   # room B frame -> room A frame
    to_building_a: np.ndarray
    to_building_b: np.ndarray
    residual_rms_m: float
    pairs: int                      # correspondences the transform rests on
    same_as: list[Row] = field(default_factory=list)   # {a, b, distance}
    from_file: bool = False
    evidence: int = 0                  # object pairs (not structure) the alignment rests on
    share: float = 0.0                 # ... over the objects that could have matched
    up_angle_deg: Optional[float] = None   # tilt between the rooms' up directions after the transform
    forced: Optional[str] = None       # the evidence rule --force overrode


def load_transform(path: Union[str, Path]) -> np.ndarray:
    """A 4x4 rigid transform from a text file: 4 lines of 4 numbers ('#' lines and blank
    lines ignored); the last row must be 0 0 0 1 and the rotation orthonormal with det +1."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise TransformError(f"cannot read transform file {str(path)!r}: {exc.strerror}") from None
    lines = [ln.split("#", 1)[0].replace(",", " ").split() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln]
    if len(lines) != 4 or any(len(ln) != 4 for ln in lines):
        shape = ", ".join(str(len(ln)) for ln in lines) or "none"
        raise TransformError(f"{path.name}: expected 4 lines of 4 numbers, got {len(lines)} line(s) "
                             f"with {shape} value(s)")
    try:
        T = np.array([[float(v) for v in ln] for ln in lines])
    except ValueError as exc:
        raise TransformError(f"{path.name}: not a number: {exc}") from None
    check_rigid(T, path.name)
    return T


def check_rigid(T: np.ndarray, what: str = "transform") -> None:
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise TransformError(f"{what}: must be a finite 4x4 matrix")
    if not np.allclose(T[3], [0, 0, 0, 1], atol=RIGID_TOL):
        raise TransformError(f"{what}: last row must be 0 0 0 1, got {' '.join(f'{v:g}' for v in T[3])}")
    R = T[:3, :3]
    if not np.allclose(R @ R.T, np.eye(3), atol=RIGID_TOL) or np.linalg.det(R) < 0:
        raise TransformError(f"{what}: the 3x3 part is not a rotation (scale, shear or reflection)")


def to_list(T: np.ndarray) -> list[float]:
    return [float(v) for v in np.asarray(T, dtype=float).reshape(16)]


def from_list(values: Optional[list[float]]) -> Optional[np.ndarray]:
    return None if values is None else np.asarray(values, dtype=float).reshape(4, 4)


def get_room(store: GraphStore, rid: str) -> Row:
    rows = store.read("building_room_get", room=rid)
    if not rows:
        raise AlignmentError(f"no room {rid!r} in the store")
    return rows[0]


def list_rooms(store: GraphStore, building: str) -> list[Row]:
    """The building's rooms: id, name, objects, transform (4x4 or None), adjacent room names."""
    rows = store.read("building_rooms", building=building)
    return [{**r, "to_building": from_list(r["to_building"]), "adjacent": sorted(set(r["adjacent"] or []))}
            for r in rows]


def set_room_transform(store: GraphStore, rid: str, T: np.ndarray) -> None:
    check_rigid(T, rid)
    if not store.write("building_set_transform", room=rid, transform=to_list(T)):
        raise AlignmentError(f"no room {rid!r} in the store")


def link_rooms(store: GraphStore, room_a: str, room_b: str, transform: Optional[np.ndarray] = None,
               link_tol_m: float = LINK_TOL_M, embedding: Optional[LabelEmbedding] = None, seed: int = 0, force: bool = False) -> LinkReport:
    """Align room B to room A (or take `transform`, B frame → A frame), store the transforms
    and replace the two rooms' SAME_AS / ADJACENT_TO links, all in one write transaction.

    An alignment resting on too little independent evidence (`align.evidence_problem`: too few
    objects agreeing in label, colour and size, too small a share of what could match, a large
    residual, floors tilted against each other) is refused with WeakAlignment, which says why,
    unless `force`."""
    if room_a == room_b:
        raise AlignmentError("a room cannot be linked to itself")
    ra, rb = get_room(store, room_a), get_room(store, room_b)
    if ra["building"] != rb["building"]:
        raise AlignmentError(f"{room_a!r} and {room_b!r} are in different buildings")
    objs_a, objs_b = room_objects(store, room_a), room_objects(store, room_b)
    T_a, T_b_stored = from_list(ra["to_building"]), from_list(rb["to_building"])
    set_a = T_a is None

    if transform is None:
        if not objs_a or not objs_b:
            empty = room_a if not objs_a else room_b
            raise AlignmentError(f"room {empty!r} holds no objects to align by (give --transform)")
        al: Alignment = align_objects(objs_a, objs_b, embedding, seed=seed)
        T, residual, n_pairs = al.T, al.residual_rms_m, len(al.pairs)
        ups = {r["id"]: r["up"] for r in store.read("vqa_room_up", rooms=[room_a, room_b])}
        tilt = up_angle_deg(T, ups.get(room_a), ups.get(room_b))
        problem = evidence_problem(al, tilt)
        if problem and not force:
            raise WeakAlignment(f"refusing to link {room_b!r} to {room_a!r}: the alignment is not trustworthy: "
                                f"{problem} (residual {residual:.3f} m; `sg3d rooms link --force` links anyway, "
                                f"--transform FILE takes a known transform)")
        evidence: dict[str, Any] = dict(evidence=len(al.evidence), share=al.share, up_angle_deg=tilt,
                                        forced=problem)
    else:
        evidence = {}
    if transform is not None:
        check_rigid(transform)
        T, residual, n_pairs = np.asarray(transform, dtype=float), float("nan"), 0
    if T_a is None:
        # B already placed: A follows it, so B's earlier links stay in one frame; else A is
        # the first room linked and becomes the building's reference frame
        T_a = T_b_stored @ np.linalg.inv(T) if T_b_stored is not None else np.eye(4)
    T_b = T_a @ T

    same_as = _coinciding(objs_a, objs_b, T_a, T_b, link_tol_m, embedding)
    if transform is not None:
        # the file's fit, measured on the objects it makes coincide
        n_pairs = len(same_as)
        if same_as:
            residual = float(np.sqrt(np.mean([s["distance"] ** 2 for s in same_as])))

    def work(tx: ManagedTransaction) -> None:
        if set_a:
            tx.run(cypher.load("building_set_transform"), room=room_a, transform=to_list(T_a)).consume()
        tx.run(cypher.load("building_set_transform"), room=room_b, transform=to_list(T_b)).consume()
        for name in ("building_links_clear", "building_adjacent_clear"):
            tx.run(cypher.load(name), room_a=room_a, room_b=room_b).consume()
            tx.run(cypher.load(name), room_a=room_b, room_b=room_a).consume()
        if same_as:
            tx.run(cypher.load("building_same_as_merge"), rows=same_as).consume()
            tx.run(cypher.load("building_adjacent_merge"), room_a=room_a, room_b=room_b,
                   shared=len(same_as), residual=None if np.isnan(residual) else residual).consume()
        tx.run(cypher.load("room_bump"), rooms=[room_a, room_b]).consume()

    store.execute_write(work)
    return LinkReport(room_a, room_b, T, T_a, T_b, residual, n_pairs, same_as, transform is not None, **evidence)


def unlink_rooms(store: GraphStore, room_a: str, room_b: str) -> dict[str, int]:
    """Remove the link between two rooms: their ADJACENT_TO edges (both directions) and every
    SAME_AS edge between their objects, in ONE write transaction. The rooms keep their transforms
    (other links may rest on them). AlignmentError when either room is missing or they are not
    linked. Returns {adjacent, same_as}: the edges removed."""
    if room_a == room_b:
        raise AlignmentError("a room is never linked to itself")
    get_room(store, room_a)
    get_room(store, room_b)

    def work(tx: ManagedTransaction) -> dict[str, int]:
        removed = {key: sum(int(r["n"] or 0) for r in tx.run(cypher.load(name), room_a=room_a, room_b=room_b).data())
                   for key, name in (("same_as", "building_unlink_same_as"), ("adjacent", "building_unlink_adjacent"))}
        tx.run(cypher.load("room_bump"), rooms=[room_a, room_b]).consume()
        return removed

    removed = store.execute_write(work)
    if not removed["adjacent"] and not removed["same_as"]:
        raise AlignmentError(f"{room_a!r} and {room_b!r} are not linked (see `sg3d rooms`)")
    return removed


def _coinciding(objs_a: list[Row], objs_b: list[Row], T_a: np.ndarray, T_b: np.ndarray, tol: float,
                embedding: Optional[LabelEmbedding]) -> list[Row]:
    """Label/colour-compatible pairs whose building-frame centres are within `tol`, one
    partner per object (closest first)."""
    pairs = candidate_pairs(objs_a, objs_b, embedding)
    if not pairs:
        return []
    wa, wb = apply(T_a, positions(objs_a)), apply(T_b, positions(objs_b))
    dist = np.array([np.linalg.norm(wa[i] - wb[j]) for i, j in pairs])
    close = [k for k in range(len(pairs)) if dist[k] <= tol]
    sub = [pairs[k] for k in close]
    keep = one_to_one(sub, dist[close])
    return [{"a": objs_a[sub[k][0]]["id"], "b": objs_b[sub[k][1]]["id"], "distance": float(dist[close][k])}
            for k in keep]


def format_matrix(T: np.ndarray) -> str:
    return "\n".join(" ".join(f"{v: .6f}" for v in row) for row in np.asarray(T))
