"""Rule "a box along the room's heading": the boxes a graph keeps are measured along the direction
the room's walls run (`sg3d.ingest.poses.gravity.manhattan_heading`), not along the world's x axis.

The build measures every box in the world's frame first (`sg3d.core.geometry.Ground.basis`): the
sightings, the fused cloud and the voxel grid discovery segments it in, whose rules were set in
that frame. A box there is the axis-aligned hull of a thing turned by the room's heading: a
1.6 x 0.6 m counter turned 13 degrees measures 1.69 x 0.94 m. Once discovery is done, each box is
measured again along the heading from the cloud's points inside it (`along_heading`); the
object's position stays in the recording's world coordinates.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from sg3d.core.model import ObjectObservation, vec3
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.segments import PLANE_CUT_M
from sg3d.ingest.discover.structure import FLOOR_SLAB_M, Element

# A box is measured again from at least ALONG_MIN_POINTS of the cloud's points inside it; the
# extents of those points are taken between the ALONG_PERCENTILE-th percentiles on each side
# (a flying pixel or a neighbour's corner inside the box does not widen it).
ALONG_MIN_POINTS = 20
ALONG_PERCENTILE = 1.0
# Structure measured as it was found: the floor and the walls are planes of the room itself.
KEPT_AS_FOUND = frozenset({"floor", "wall", "window", "front"})


def points_off_planes(cloud: RoomCloud, structure: Sequence[Element]) -> np.ndarray:
    """The cloud's points off the floor's slab and the walls' and fronts' planes: what a box
    inside the room holds of its own."""
    p = cloud.points
    keep = (p[:, 2] > FLOOR_SLAB_M) if cloud.floor_seen else np.ones(len(p), bool)
    for el in structure:
        if el.label in ("wall", "front"):
            keep &= ~el.contains(p, PLANE_CUT_M)
    return p[keep]


def along_heading(obj: ObjectObservation, points: np.ndarray, cloud: RoomCloud, room_basis: np.ndarray) -> None:
    """Rule "a box along the room's heading": `obj`'s box (size along the cloud's axes, centre
    in world coordinates) measured again along `room_basis` (rows e1, e2, up turned to the
    heading), in place: its horizontal extents become those of the points of `points` (the
    cloud's, `points_off_planes`) inside its box along e1 and e2, between their
    ALONG_PERCENTILE-th percentiles; its height stays. Boxes of the floor and walls, and boxes
    holding under ALONG_MIN_POINTS points, stay as they are."""
    if obj.label in KEPT_AS_FOUND and obj.layer == "structure" or not any(obj.size):
        return
    size = np.asarray(obj.size, dtype=np.float64)
    centre_world = np.asarray(obj.box_centre if obj.box_centre is not None else obj.mean, dtype=np.float64)
    c = cloud.basis @ centre_world
    c[2] -= cloud.floor
    lo, hi = c - size / 2, c + size / 2
    inside = points[np.all((points >= lo) & (points <= hi), axis=1)]
    if len(inside) < ALONG_MIN_POINTS:
        return
    turned = cloud.to_world(inside) @ room_basis[:2].T            # (e1, e2) of the heading
    new_lo, new_hi = np.percentile(turned, (ALONG_PERCENTILE, 100.0 - ALONG_PERCENTILE), axis=0)
    new_size = new_hi - new_lo
    mid = (new_lo + new_hi) / 2
    up = room_basis[2]
    obj.size = vec3((new_size[0], new_size[1], size[2]))
    obj.box_centre = vec3(room_basis[:2].T @ mid + up * float(centre_world @ up))
