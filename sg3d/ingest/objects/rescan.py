"""Re-scans: which objects already in the store did this scan's frames see gone?

An object the scan did not re-observe is only evidence of a change where the scan looked at its
place: a partial re-scan says nothing about the rest of the room. "Looked at its place and saw it
empty" is a free-space test on the frame's depth (`place_seen_empty`): the rays through the core
of the object's box reach the far side of that core (the table surface under a mug that left, the
wall behind a chair that left) instead of stopping on the object. The store decides removal from
these frames (sg3d.graphdb.merge); this module only measures.
"""
from __future__ import annotations

from typing import Iterable, Optional, Sequence

import numpy as np

from sg3d.core.model import KnownObject
from sg3d.ingest.objects.existence import (
    BORDER_MARGIN,
    MAX_RANGE_M,
    OCCLUSION_TOLERANCE_M,
    View,
)

# The core of a box probed for free space: this fraction of its horizontal extents, and the part
# above CORE_BOTTOM of its height (the bottom is the support the object stood on) up to CORE_TOP.
CORE_HORIZONTAL = 0.6
CORE_BOTTOM = 0.3
CORE_TOP = 0.9
# A ray passed through the core when the depth it measured is no nearer than the core's far side
# by more than this (depth noise of a Kinect-class sensor at room range).
PASS_TOLERANCE_M = 0.02
# The place was seen empty when at least MIN_RAYS rays tell (passed or stopped inside the box)
# and this share of them passed.
EMPTY_FRACTION = 0.8
MIN_RAYS = 6
# A scan saw a place empty when at least this share of its frames that could tell (empty or not)
# saw it empty: a few frames with a misplaced box or depth noise do not outvote the many that
# saw the object standing there. Measured on the kitchen: the painted-out cup, every one of 53;
# objects still there, at most 23 of 43 (53 %: a small thing beside a row of others, seen through
# its box's edge from frames behind its neighbours) - a removal is seen by nearly every frame.
EMPTY_SHARE = 0.8
# Depth noise grows with range: a surface point is still hit within this share of its distance.
SURFACE_NOISE_REL = 0.02
# Objects larger than this are not judged (a table's box is mostly free space under its top).
MAX_JUDGED_EXTENT_M = 1.5


def _slab(origin: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Entry and exit parameters of rays origin + t direction through the box [lo, hi] (per ray)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / direction
        t1 = (lo - origin) * inv
        t2 = (hi - origin) * inv
    t1 = np.where(np.isnan(t1), -np.inf, t1)
    t2 = np.where(np.isnan(t2), np.inf, t2)
    return np.minimum(t1, t2).max(axis=-1), np.maximum(t1, t2).min(axis=-1)


def surface_seen_empty(obj: KnownObject, view: View) -> Optional[bool]:
    """Rule "surface seen through", for objects that carry points seen on their surface (found
    from depth, whose box is no solid: an L-shaped or thin segment): each point in view, in front
    of the camera within MAX_RANGE_M, with depth measured at its pixel, tells: passed when the
    depth lies beyond it by more than PASS_TOLERANCE_M plus the depth noise
    (SURFACE_NOISE_REL of the range), stopped when it lies within that of it; nearer depth is an
    occluder (no evidence). True when at least MIN_RAYS points told and EMPTY_FRACTION of them
    passed, False when fewer passed, None when too few told."""
    pts = np.asarray(obj.surface, float).reshape(-1, 3)
    w2c = np.linalg.inv(view.pose)
    cam = pts @ w2c[:3, :3].T + w2c[:3, 3]
    z = cam[:, 2]
    ok = (z > 0.1) & (z <= MAX_RANGE_M)
    if not ok.any():
        return None
    K, (w, h) = view.K, view.size
    zs = np.where(ok, z, 1.0)
    u = K[0, 0] * cam[:, 0] / zs + K[0, 2]
    v = K[1, 1] * cam[:, 1] / zs + K[1, 2]
    ok &= (u >= 0) & (u < w) & (v >= 0) & (v < h)
    dh, dw = view.depth.shape
    du = np.clip((u[ok] / view.factor).astype(int), 0, dw - 1)
    dv = np.clip((v[ok] / view.factor).astype(int), 0, dh - 1)
    d = view.depth[dv, du].astype(float)
    zi = z[ok]
    tol = PASS_TOLERANCE_M + SURFACE_NOISE_REL * zi
    passed = int(((d > 0) & (d > zi + tol)).sum())
    stopped = int(((d > 0) & (np.abs(d - zi) <= tol)).sum())
    if passed + stopped < MIN_RAYS:
        return None
    return passed >= EMPTY_FRACTION * (passed + stopped)


def place_seen_empty(obj: KnownObject, basis: np.ndarray, view: View) -> Optional[bool]:
    """Rule "place seen empty": the frame looked at the object's place and saw free space there.

    The object's box (centre c, extents s along the gravity axes, rows of `basis`) has a core:
    CORE_HORIZONTAL of s horizontally, from CORE_BOTTOM to CORE_TOP of its height. Every depth
    pixel whose ray crosses the core is one ray; with t_in the ray's entry into the WHOLE box,
    t_out its exit from the core and d the measured depth (all as camera depth z):
        occluded (no evidence)  if d < t_in - OCCLUSION_TOLERANCE_M or d unknown,
        passed                  if d >= t_out - PASS_TOLERANCE_M,
        stopped                 otherwise (something stands in the core).
    True when the centre projects inside the image (BORDER_MARGIN) within MAX_RANGE_M, at least
    MIN_RAYS rays passed or stopped, and at least EMPTY_FRACTION of them passed; False when they
    did not; None when the frame could not tell (out of view, occluded, too few rays, too big).
    An object with surface points is tested on them instead (`surface_seen_empty`)."""
    if obj.surface:
        return surface_seen_empty(obj, view)
    size = np.asarray(obj.size, float)
    if float(size.max()) > MAX_JUDGED_EXTENT_M:
        return None
    world_to_cam = np.linalg.inv(view.pose)
    centre = np.asarray(obj.box_centre, float)
    p = world_to_cam[:3, :3] @ centre + world_to_cam[:3, 3]
    if p[2] <= 0.1 or p[2] > MAX_RANGE_M:
        return None
    K, (w, h) = view.K, view.size
    u0, v0 = K[0, 0] * p[0] / p[2] + K[0, 2], K[1, 1] * p[1] / p[2] + K[1, 2]
    if not (BORDER_MARGIN * w <= u0 < (1 - BORDER_MARGIN) * w and BORDER_MARGIN * h <= v0 < (1 - BORDER_MARGIN) * h):
        return None
    half = size / 2
    core_lo = np.array([-half[0] * CORE_HORIZONTAL, -half[1] * CORE_HORIZONTAL, -half[2] + CORE_BOTTOM * size[2]])
    core_hi = np.array([half[0] * CORE_HORIZONTAL, half[1] * CORE_HORIZONTAL, -half[2] + CORE_TOP * size[2]])
    # the core's corners bound the depth pixels to look at
    corners = np.array([[x, y, z] for x in (core_lo[0], core_hi[0]) for y in (core_lo[1], core_hi[1])
                        for z in (core_lo[2], core_hi[2])]) @ basis + centre
    cam = corners @ world_to_cam[:3, :3].T + world_to_cam[:3, 3]
    if (cam[:, 2] <= 0.05).any():
        return None
    us, vs = K[0, 0] * cam[:, 0] / cam[:, 2] + K[0, 2], K[1, 1] * cam[:, 1] / cam[:, 2] + K[1, 2]
    dh, dw = view.depth.shape
    a0, a1 = max(0, int(us.min() / view.factor)), min(dw - 1, int(us.max() / view.factor))
    b0, b1 = max(0, int(vs.min() / view.factor)), min(dh - 1, int(vs.max() / view.factor))
    if a1 < a0 or b1 < b0:
        return None
    gu, gv = np.meshgrid(np.arange(a0, a1 + 1), np.arange(b0, b1 + 1))
    d = view.depth[gv, gu].ravel().astype(float)
    u = gu.ravel() * view.factor
    v = gv.ravel() * view.factor
    # rays with unit camera depth, so ray parameters are camera depths; in the box's own axes
    rays_cam = np.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], np.ones_like(u, dtype=float)], axis=1)
    dirs = rays_cam @ view.pose[:3, :3].T @ basis.T
    origin = basis @ (view.pose[:3, 3] - centre)
    t_in_core, t_out_core = _slab(origin, dirs, core_lo, core_hi)
    t_in_box, _ = _slab(origin, dirs, -half, half)
    crosses = (t_out_core > t_in_core) & (t_in_core > 0)
    told = crosses & (d > 0) & (d >= t_in_box - OCCLUSION_TOLERANCE_M)
    n = int(told.sum())
    if n < MIN_RAYS:
        return None
    passed = int((told & (d >= t_out_core - PASS_TOLERANCE_M)).sum())
    return passed >= EMPTY_FRACTION * n


def empty_places(known: Sequence[KnownObject], views: Iterable[View], basis: np.ndarray) -> dict[str, list[int]]:
    """Rule "place seen gone": stored object id -> the frames of `views` that saw its place empty
    (`place_seen_empty` True), for the objects where those frames are at least EMPTY_SHARE of the
    frames that could tell (True or False)."""
    views = list(views)
    found: dict[str, list[int]] = {}
    for obj in known:
        verdicts = [(v.index, place_seen_empty(obj, basis, v)) for v in views]
        empty = [i for i, says in verdicts if says is True]
        told = sum(1 for _, says in verdicts if says is not None)
        if empty and len(empty) >= EMPTY_SHARE * told:
            found[obj.id] = empty
    return found
