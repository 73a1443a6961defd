"""Generated rooms with exact ground truth: seeded procedural layouts rendered CPU-only into the
plain 7-Scenes layout (frame-NNNNNN.color.jpg, .depth.png uint16 mm, .pose.txt camera-to-world,
camera-intrinsics.txt) that `sg3d build` reads, plus ground_truth.json in the shared format.

    python -m benchmarks.synth --kind desk --seed 3 --out DIR

Kinds (`KINDS`): room (a walk around a furnished room at 1.2-1.7 m looking inwards), desk (a
tabletop scan 0.3-0.7 m above a desk's top; the floor is never seen), robot (a camera 0.3 m
above the floor), shelf (a sweep along a bookcase), corner (a corner seen from one side), apartment (2-6 rooms walked through in one recording at
1.2-1.7 m, `benchmarks.synth.apartment`; its ground truth adds each room's footprint, the
doorways and the room of every object under "apartment").
Needs the optional extra `synth` (open3d-cpu: its RaycastingScene).
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np

from benchmarks.synth import apartment, camera, layouts, render, truth
from benchmarks.synth.scene import Room

LAYOUTS = {**layouts.LAYOUTS, "apartment": apartment.layout_apartment}
PATHS = {**camera.PATHS, "apartment": apartment.walk}
ROOM_KINDS = tuple(layouts.LAYOUTS)      # one room each; `layouts_for` deals these by default
KINDS = tuple(LAYOUTS)
FRAMES = {"apartment": 1}                # frames when not given (else 80); an apartment's walk sets its own
EYE_CLEARANCE_M = 0.15           # no camera inside or this near a thing


def intrinsics(width: int, height: int) -> np.ndarray:
    """A Kinect-like field of view (fx = fy = 525 px at 640 x 480) at any size."""
    f = 525.0 * width / 640
    return np.array([[f, 0, (width - 1) / 2], [0, f, (height - 1) / 2], [0, 0, 1.0]])


def room_to_world(seed: int) -> np.ndarray:
    """The world frame the poses are written in: the room frame turned about a random axis by
    5-25 degrees and moved (real sequences' frames are not gravity-aligned either)."""
    rng = np.random.default_rng(seed + 104729)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = np.radians(rng.uniform(5, 25))
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    T[:3, 3] = rng.uniform(-1.5, 1.5, 3)
    return T


def clear_of_things(room: Room, eye: np.ndarray) -> bool:
    for t in room.things:
        if t.structure:
            continue
        lo, hi = t.box()
        if np.all(eye > lo - EYE_CLEARANCE_M) and np.all(eye < hi + EYE_CLEARANCE_M):
            return False
    return True


def camera_poses(room: Room, scene: render.Scene, n: int, K, w: int, h: int, seed: int) -> list[np.ndarray]:
    """n poses of the kind's path, clear of every thing; a desk scan keeps only the poses that
    see no floor."""
    rng = np.random.default_rng(seed + 7919)
    want, poses = n, []
    floor = next(k for k, t in enumerate(room.things) if t.category == "floor")
    for tries in range(4):
        pairs = PATHS[room.kind](room, want * (tries + 1), rng)
        poses = [camera.look_at(e, t) for e, t in pairs if clear_of_things(room, e)]
        if room.kind == "desk":
            poses = [p for p in poses if not (scene.cast(p, K, w, h)[1] == floor).any()]
        if len(poses) >= n:
            break
    if room.kind == "apartment":           # its walk sets its frames (`apartment.walk`)
        return poses
    idx = np.linspace(0, len(poses) - 1, min(n, len(poses))).round().astype(int)
    return [poses[i] for i in idx]


def generate(kind: str, seed: int, out: Path, frames: Optional[int] = None, width: int = 320,
             height: int = 240, windows: bool = True) -> dict:
    """Render layout `seed` of `kind` into `out` (`frames`: FRAMES of the kind, else 80; an
    apartment without `windows` has whole outside walls); returns its ground truth (also written
    to out/ground_truth.json)."""
    import cv2

    if kind not in LAYOUTS:
        raise ValueError(f"unknown kind {kind!r}: one of {', '.join(KINDS)}")
    frames = frames or FRAMES.get(kind, 80)
    room = apartment.layout_apartment(seed, windows) if kind == "apartment" else LAYOUTS[kind](seed)
    scene = render.Scene(room)
    K = intrinsics(width, height)
    poses = camera_poses(room, scene, frames, K, width, height, seed)
    T = room_to_world(seed)
    rng = np.random.default_rng(seed + 31337)
    gains = render.exposure(len(poses), rng)
    pixels = np.zeros(len(room.things), np.int64)
    frames_seen = np.zeros(len(room.things), np.int64)
    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "camera-intrinsics.txt", K, fmt="%.6f")
    for i, pose in enumerate(poses):
        z, thing, normals, rays = scene.cast(pose, K, width, height)
        counts = np.bincount(thing[thing >= 0], minlength=len(room.things))
        pixels += counts
        frames_seen += counts >= truth.FRAME_PIXELS
        rgb = render.shade(scene, thing, normals, rays, float(gains[i]))
        depth = render.depth_faults(z, thing, scene.albedo, rng)
        stem = out / f"frame-{i:06d}"
        cv2.imwrite(str(stem) + ".color.jpg", render.colour_faults(rgb, i, rng), [cv2.IMWRITE_JPEG_QUALITY, 92])
        cv2.imwrite(str(stem) + ".depth.png", np.round(depth * 1000).astype(np.uint16))
        np.savetxt(str(stem) + ".pose.txt", T @ pose, fmt="%.8f")
    gt = truth.ground_truth(room, T, pixels, frames_seen)
    gt["frames"] = len(poses)
    if isinstance(room, apartment.Apartment):
        gt["apartment"] = apartment.truth(room, poses, scene, K, width, height, T)
        for o in gt["objects"]:
            o["room"] = gt["apartment"]["object_rooms"][o["id"]]
    (out / "ground_truth.json").write_text(json.dumps(gt, indent=1) + "\n", encoding="utf-8")
    return gt


def layouts_for(n: int, first_seed: int = 0, kinds: Optional[tuple[str, ...]] = None) -> list[tuple[str, int]]:
    """n (kind, seed) pairs dealt round the kinds in turn."""
    kinds = kinds or ROOM_KINDS
    return [(kinds[i % len(kinds)], first_seed + i) for i in range(n)]
