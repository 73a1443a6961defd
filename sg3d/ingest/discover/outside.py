"""What depth saw through the room's walls: a window's or a glass door's outside is no object.

Depth goes through glass and gaps: the things outside a sliding glass door come back as segments
beyond the wall the door is in. A plane found as a "wall" (`sg3d.ingest.discover.structure.walls`)
may also be a cabinet front or a partition with things of the room behind it, so distance behind a
plane alone cannot say "outside". The rule here (`seen_through_wall`) asks how the cameras saw
what lies beyond: through the wall's own face (a see-through region of it) or past its ends and
over its top (what lies behind a front or a partition). Coordinates are gravity-frame
(`sg3d.ingest.discover.room_cloud`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.segments import Segment
from sg3d.ingest.discover.structure import WALL_FAR_M, WALL_SLAB_M, Element

# A wall's face: the 2-98 percentile extent, along the wall and in height, of the room's points
# within WALL_SLAB_M of its plane (a stray point does not stretch it).
FACE_PERCENTILES = (2.0, 98.0)
# A wall hides what lies behind it: of the room's points more than WALL_FAR_M beyond its plane, at
# most this share of the room's points may have been seen other than through its face (past its
# ends, over its top): the flying pixels of depth along its edges, well under one in a thousand. A
# cabinet front or a partition lets the cameras see the room go on behind it (what stands on the
# counter behind a base cabinet's front, the desk behind a panel), several in a thousand.
WALL_SEEN_PAST = 0.001
# A segment is seen through a wall when the camera rays to at least this share of its voxels (over
# the views that saw it) cross the wall's plane inside its face: most of what the cameras saw of
# it, they saw through the wall, not past its end or over its top.
SEEN_THROUGH_SHARE = 0.5


@dataclass
class BoundingWall:
    """A wall that bounds the room (`bounding_walls`) and its face's extent."""

    wall: Element
    along: tuple[float, float]      # extent along the wall (metres along its direction)
    height: tuple[float, float]     # extent in height


def _axes(wall: Element) -> tuple[np.ndarray, np.ndarray, float]:
    assert wall.plane is not None
    theta, rho = wall.plane
    normal = np.array([np.cos(theta), np.sin(theta)])
    return normal, np.array([-normal[1], normal[0]]), rho


def _cameras(cloud: RoomCloud) -> np.ndarray:
    """The views' camera centres, gravity frame."""
    cams = np.array([v.pose[:3, 3] @ cloud.basis.T for v in cloud.views], float).reshape(-1, 3)
    cams[:, 2] -= cloud.floor
    return cams


def through_face(points: np.ndarray, cams: np.ndarray, face: BoundingWall) -> np.ndarray:
    """Mask of the points (beyond the wall) whose ray from their camera (`cams`, one row per point)
    crosses the wall's plane inside its face."""
    normal, along, rho = _axes(face.wall)
    off_p = points[:, :2] @ normal - rho
    off_c = cams[:, :2] @ normal - rho
    denom = off_c - off_p
    s = np.divide(off_c, denom, out=np.full(len(points), np.nan), where=np.abs(denom) > 1e-9)
    cross = cams + s[:, None] * (points - cams)
    a, h = cross[:, :2] @ along, cross[:, 2]
    inside = (a >= face.along[0]) & (a <= face.along[1]) & (h >= face.height[0]) & (h <= face.height[1])
    return inside & (s >= 0) & (s <= 1)


def bounding_walls(structure: Sequence[Element], cloud: RoomCloud) -> list[BoundingWall]:
    """Rule "the wall bounds the room": a wall (`structure.walls`) with every camera on its room
    side, and of the room's points more than WALL_FAR_M beyond it at most WALL_SEEN_PAST (a share of
    all the room's points) seen other than through its face (past its ends, over its top). The room's points go on behind a cabinet
    front or a partition and are seen past it; what lies beyond a wall is seen only through a gap or
    glass in it (its see-through region), whatever its share of the room."""
    out: list[BoundingWall] = []
    if not len(cloud.points):
        return out
    cams = _cameras(cloud)
    for e in structure:
        if e.label != "wall" or e.plane is None:
            continue
        normal, along, rho = _axes(e)
        if not bool(np.all(e.side * (cams[:, :2] @ normal - rho) > 0)):
            continue                     # the cameras stand on both sides: it bounds nothing
        off = cloud.points[:, :2] @ normal - rho
        near = np.abs(off) <= WALL_SLAB_M
        if not near.any():
            continue
        a_lo, a_hi = np.percentile(cloud.points[near, :2] @ along, FACE_PERCENTILES)
        h_lo, h_hi = np.percentile(cloud.points[near, 2], FACE_PERCENTILES)
        face = BoundingWall(e, (float(a_lo), float(a_hi)), (float(h_lo), float(h_hi)))
        far = np.flatnonzero(e.side * off < -WALL_FAR_M)
        seen_past = far[~through_face(cloud.points[far], cams[cloud.frame[far]], face)]
        if len(seen_past) <= WALL_SEEN_PAST * len(cloud.points):
            out.append(face)
    return out


def seen_through_wall(seg: Segment, walls: Sequence[BoundingWall], cloud: RoomCloud) -> bool:
    """Rule "seen through the wall": a segment all of whose voxels lie more than WALL_FAR_M beyond a
    wall that bounds the room (`bounding_walls`), and that the cameras saw through that wall's face
    (the rays to SEEN_THROUGH_SHARE of its voxels, over the views that saw it, cross the wall inside
    its face: a glass door, a window), is outside the room, not an object of it. A thing standing
    in a recess or a cabinet behind a plane found as a wall lies less far behind it, or the plane
    does not bound the room (the room's points are seen past it)."""
    if not walls or not len(seg.frames) or not len(seg.voxels):
        return False
    for face in walls:
        normal, _, rho = _axes(face.wall)
        if not bool(np.all(face.wall.side * (seg.voxels[:, :2] @ normal - rho) < -WALL_FAR_M)):
            continue
        cams = _cameras(cloud)      # only for a segment wholly beyond a bounding wall (rare)
        frames = np.asarray(seg.frames, int)
        pts = np.repeat(seg.voxels, len(frames), axis=0)
        rays = np.tile(cams[frames], (len(seg.voxels), 1))
        if float(through_face(pts, rays, face).mean()) >= SEEN_THROUGH_SHARE:
            return True
    return False
