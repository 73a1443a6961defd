"""A second scan of the kitchen with one object taken away: its pixels painted out of the colour
frames and its depth replaced by the support surface behind it (the table it stood on).

The object is given by its box in the first scan's graph (centre, extents along the room's
gravity axes, up), never by ground truth. Frames are written in the 7-Scenes layout: changed
frames as lossless PNG colour (`frame-N.color.png`) and 16-bit depth, every other file linked.
"""
from __future__ import annotations

import functools
import os
from pathlib import Path

import cv2
import numpy as np

from sg3d.core.geometry import horizontal_frame
from sg3d.ingest.readers.registration import DepthRegistrar, Registration

GROW = 1.5            # the painted box: the object's box grown by this factor ...
MARGIN_M = 0.04       # ... and this margin on each side (the handle, the box's own error)
ABOVE_SUPPORT_M = 0.015   # the object's pixels stand this far above the surface it stood on
MIN_OBJECT_PIXELS = 30    # fewer: the frame does not show it


def _read_pose(path: Path) -> np.ndarray:
    return np.loadtxt(path).reshape(4, 4)


def _corners(centre, size, basis) -> np.ndarray:
    half = np.asarray(size, float) * GROW / 2 + MARGIN_M
    return np.array([[sx * half[0], sy * half[1], sz * half[2]] for sx in (-1, 1) for sy in (-1, 1)
                     for sz in (-1, 1)]) @ basis + np.asarray(centre, float)


def paint_out(src: Path, dst: Path, centre, size, up) -> list[int]:
    """Write the sequence `src` to `dst` without the object; returns the frames changed."""
    src, dst = Path(src), Path(dst)
    dst.mkdir(parents=True, exist_ok=True)
    K = np.loadtxt(src / "camera-intrinsics.txt").reshape(3, 3)
    reg = Registration.kinect_v1()
    basis = horizontal_frame(np.asarray(up, float))
    corners = _corners(centre, size, basis)
    support = float(basis[2] @ np.asarray(centre, float)) - float(size[2]) / 2   # the box's bottom
    os.symlink(src / "camera-intrinsics.txt", dst / "camera-intrinsics.txt")
    changed = []
    for colour_path in sorted(src.glob("frame-*.color.jpg")):
        stem = colour_path.name[: -len(".color.jpg")]
        depth_path, pose_path = src / f"{stem}.depth.png", src / f"{stem}.pose.txt"
        os.symlink(pose_path, dst / pose_path.name)
        if _paint_frame(colour_path, depth_path, _read_pose(pose_path), K, reg, corners, centre, basis, support,
                        dst / f"{stem}.color.png", dst / depth_path.name):
            changed.append(int(stem.split("-")[1]))
        else:
            os.symlink(colour_path, dst / colour_path.name)
            os.symlink(depth_path, dst / depth_path.name)
    return changed


def _in_polygon(gu, gv, us, vs) -> np.ndarray:
    """Pixels (gu, gv) inside the convex hull of the projected box corners (us, vs)."""
    hull = cv2.convexHull(np.stack([us, vs], 1).astype(np.float32))
    mask = np.zeros((int(gv.max()) + 2, int(gu.max()) + 2), np.uint8)
    cv2.fillConvexPoly(mask, np.round(hull[:, 0]).astype(np.int32), 1)
    return mask[gv.astype(int), gu.astype(int)] > 0


@functools.lru_cache(maxsize=2)
def _colour_of_depth_pixels(depth_shape, colour_size, cu, cv_, reg):
    """For every raw depth pixel, the colour pixel it is registered to (inverse of the reader's map)."""
    w, h = colour_size
    db, da = np.mgrid[0:depth_shape[0], 0:depth_shape[1]].astype(float)
    u = cu + (da - reg.offset[0] - cu) / reg.scale[0]
    v = cv_ + (db - reg.offset[1] - cv_) / reg.scale[1]
    ui, vi = np.round(u).astype(int), np.round(v).astype(int)
    return u, v, ui, vi, (ui >= 0) & (ui < w) & (vi >= 0) & (vi < h)


def _paint_frame(colour_path, depth_path, pose, K, reg, corners, centre, basis, support, out_colour, out_depth) -> bool:
    """Paint the object out of one frame: the pixels whose 3-D point lies inside its (grown) box and
    above the surface it stood on (what lies flat beside it stays), colour inpainted from around,
    depth replaced by that surface along each pixel's ray. False when the frame does not show it."""
    up_v = basis[2]
    world_to_cam = np.linalg.inv(pose)
    cam = corners @ world_to_cam[:3, :3].T + world_to_cam[:3, 3]
    if (cam[:, 2] <= 0.2).any():
        return False
    us = K[0, 0] * cam[:, 0] / cam[:, 2] + K[0, 2]
    vs = K[1, 1] * cam[:, 1] / cam[:, 2] + K[1, 2]
    img = cv2.imread(str(colour_path), cv2.IMREAD_COLOR)
    h, w = img.shape[:2]
    u0, u1 = int(max(0, np.floor(us.min()))), int(min(w - 1, np.ceil(us.max())))
    v0, v1 = int(max(0, np.floor(vs.min()))), int(min(h - 1, np.ceil(vs.max())))
    if u1 <= u0 or v1 <= v0:
        return False
    raw = cv2.imread(str(depth_path), cv2.IMREAD_UNCHANGED)
    metres = np.where(raw == 65535, 0, raw).astype(np.float32) / 1000.0
    registered = DepthRegistrar(reg, K, (w, h))(metres)
    # the object's pixels: a 3-D point inside the box, above the support
    gv, gu = np.mgrid[v0:v1 + 1, u0:u1 + 1].astype(float)
    z = registered[v0:v1 + 1, u0:u1 + 1].astype(float)
    rays = np.stack([(gu - K[0, 2]) / K[0, 0], (gv - K[1, 2]) / K[1, 1], np.ones_like(gu)], -1)
    points = (rays * z[..., None]) @ pose[:3, :3].T + pose[:3, 3]
    local = (points - np.asarray(centre, float)) @ basis.T
    half = np.abs((corners - np.asarray(centre, float)) @ basis.T).max(axis=0)
    footprint = (z > 0) & np.all(np.abs(local[..., :2]) <= half[:2], axis=-1) & (np.abs(local[..., 2]) <= half[2] + 0.05)
    if footprint.sum() < MIN_OBJECT_PIXELS:
        return False
    # the surface it stood on, as this frame sees it: the low heights in the box's footprint
    support = float(np.percentile(local[..., 2][footprint], 10)) + float(basis[2] @ np.asarray(centre, float))
    inside = footprint & (np.abs(local[..., 2]) <= half[2]) & (points @ up_v > support + ABOVE_SUPPORT_M)
    # too near for the depth sensor (no reading): the box's own projection is the object
    inside |= (z <= 0) & _in_polygon(gu, gv, us, vs)
    if inside.sum() < MIN_OBJECT_PIXELS:
        return False
    mask = np.zeros((h, w), np.uint8)
    mask[v0:v1 + 1, u0:u1 + 1] = inside.astype(np.uint8) * 255
    mask = cv2.dilate(mask, np.ones((7, 7), np.uint8))
    # colour: inpainted inside a crop around the box (cheap, nothing of the object left)
    pad = 12
    a, b = max(0, u0 - pad), min(w, u1 + pad + 1)
    c, d = max(0, v0 - pad), min(h, v1 + pad + 1)
    painted = img.copy()
    painted[c:d, a:b] = cv2.inpaint(img[c:d, a:b], mask[c:d, a:b], 5, cv2.INPAINT_TELEA)
    # depth: raw depth pixels whose colour pixel is masked read the support along that ray
    cu, cv_ = float(K[0, 2]), float(K[1, 2])
    u, v, ui, vi, valid = _colour_of_depth_pixels(raw.shape, (w, h), cu, cv_, reg)
    hit = np.zeros(raw.shape, bool)
    hit[valid] = mask[vi[valid], ui[valid]] > 0
    out = raw.copy()
    if hit.any():
        rays = np.stack([(u[hit] - cu) / K[0, 0], (v[hit] - cv_) / K[1, 1], np.ones(int(hit.sum()))], -1) @ pose[:3, :3].T
        along = rays @ up_v
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (support - float(up_v @ pose[:3, 3])) / along      # camera depth where the ray meets the support
        ok = np.isfinite(t) & (t > 0.2) & (t < 8.0)
        out[hit] = np.where(ok, np.round(t * 1000.0), 0).astype(np.uint16)
    cv2.imwrite(str(out_colour), painted, [cv2.IMWRITE_PNG_COMPRESSION, 0])
    cv2.imwrite(str(out_depth), out, [cv2.IMWRITE_PNG_COMPRESSION, 0])
    return True
