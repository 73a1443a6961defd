"""Where things go: each room's gravity frame (e1, e2, up), the building frame that places rooms
together, object boxes and room outlines in one drawing frame (a, b, h) in metres, h up.

A room's positions are in its own sequence's world frame. When every room of the picture carries
`to_building` (`sg3d rooms link`, `--align-to`), the drawing frame is the building frame turned so
that its up is h; otherwise each room is drawn in its own gravity frame, rooms side by side with
a gap, and the picture says they are not aligned.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from sg3d.core.geometry import gravity_basis
from sg3d.core.stored import RoomFrame, Scene, StoredObject

ROOM_GAP_M = 1.5          # between rooms drawn side by side
OUTLINE_PAD_M = 0.25      # room outline around its objects' footprints
MIN_SIZE_M = 0.03


@dataclass
class Placement:
    """World point p of a room -> drawing frame: M @ p + t."""
    M: np.ndarray
    t: np.ndarray
    basis: np.ndarray          # the room's own gravity frame (its sizes are measured along it)

    def apply(self, pts) -> np.ndarray:
        return np.asarray(pts, dtype=np.float64).reshape(-1, 3) @ self.M.T + self.t


@dataclass
class Frame:
    placements: dict[str, Placement]
    aligned: bool               # rooms share the building frame
    coords: dict[str, np.ndarray] = field(default_factory=dict)     # node id -> (a, b, h) of its position


def _room_of(node: StoredObject) -> str:
    return node.room_name or ""


def _pos(node: StoredObject, key: str = "pos") -> np.ndarray:
    if key == "box" and node.box_centre:
        return np.asarray(node.box_centre, dtype=np.float64)
    return np.array([node.x or 0.0, node.y or 0.0, node.z or 0.0])


def drawing_frame(scene: Scene) -> Frame:
    """Placements of every room of the scene, and each node's position (a, b, h)."""
    names = sorted({_room_of(n) for n in scene.nodes})
    info = {r: scene.rooms.get(r) or RoomFrame(r) for r in names}
    aligned = len(names) > 1 and all(info[r].to_building for r in names)
    placements: dict[str, Placement] = {}
    if aligned:
        ref = names[0]
        T_ref = np.asarray(info[ref].to_building, dtype=np.float64)
        up_ref = info[ref].up or [0.0, 0.0, 1.0]
        B = gravity_basis(T_ref[:3, :3] @ np.asarray(up_ref, dtype=np.float64))
        for r in names:
            T = np.asarray(info[r].to_building, dtype=np.float64)
            placements[r] = Placement(B @ T[:3, :3], B @ T[:3, 3], gravity_basis(info[r].up))
    else:
        offset = 0.0
        for r in names:
            B = gravity_basis(info[r].up)
            pts = np.array([_pos(n) for n in scene.nodes if _room_of(n) == r]) @ B.T
            shift = np.array([offset - pts[:, 0].min(), 0.0, 0.0]) if len(names) > 1 else np.zeros(3)
            placements[r] = Placement(B, shift, B)
            offset = pts[:, 0].max() + shift[0] + ROOM_GAP_M
    frame = Frame(placements, aligned)
    frame.coords = {n.id: placements[_room_of(n)].apply(_pos(n))[0] for n in scene.nodes}
    return frame


def box_corners(node: StoredObject, placement: Placement) -> np.ndarray:
    """The 8 corners (a, b, h) of a node's 3-D box: `size` (w, d, h) along its room's gravity
    axes around its box centre."""
    size = np.maximum(np.asarray(node.size or [0.1, 0.1, 0.1], dtype=np.float64), MIN_SIZE_M)
    c = placement.basis @ _pos(node, "box")
    signs = np.array([[sx, sy, sz] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)], dtype=np.float64)
    local = c + signs * size / 2                    # in the room's gravity frame
    return placement.apply(local @ placement.basis)     # back to world, then to the drawing frame


def room_outlines(scene: Scene, frame: Frame) -> dict[str, np.ndarray]:
    """room -> closed polygon (k x 2, floor plane) around its objects' footprints (convex hull,
    padded): where the room is, as far as its objects tell."""
    from scipy.spatial import ConvexHull, QhullError

    out = {}
    for r, pl in frame.placements.items():
        corners = [box_corners(n, pl)[:, :2] for n in scene.nodes if _room_of(n) == r]
        if not corners:
            continue
        pts = np.vstack(corners)
        ring = np.array([[np.cos(t), np.sin(t)] for t in np.linspace(0, 2 * np.pi, 16, endpoint=False)])
        pts = (pts[:, None, :] + OUTLINE_PAD_M * ring[None]).reshape(-1, 2)
        try:
            hull = pts[ConvexHull(pts).vertices]
        except QhullError:
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            hull = np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])
        out[r] = np.vstack([hull, hull[:1]])
    return out


def project_world(points, room: str, frame: Frame) -> np.ndarray:
    """World points of `room` (N x 3) -> drawing frame (N x 3)."""
    return frame.placements[room].apply(points)
