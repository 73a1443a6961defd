"""Small RGB-D sequences the tests write to disk themselves (the truth is known because it is
made here): a 7-Scenes folder with a corrupt frame and a broken pose, and a camera walking along a wall."""
from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np

from sg3d.ingest.readers import quaternion_to_matrix

W, H = 64, 48
K = np.array([[60.0, 0, 32.0], [0, 60.0, 24.0], [0, 0, 1]])


def colour_image(i: int) -> np.ndarray:
    rng = np.random.default_rng(i)
    return rng.integers(0, 255, size=(H, W, 3), dtype=np.uint8)


def depth_ramp_mm(i: int, w: int = W, h: int = H) -> np.ndarray:
    # a ramp: every column has its own depth, so registration shifts can be read off
    d = np.tile((1000 + 10 * np.arange(w) + i).astype(np.uint16), (h, 1))
    d[0, 0] = 0
    d[0, 1] = 65535
    return d


def pose_of(i: int) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = quaternion_to_matrix(np.array([0, 0, math.sin(0.05 * i), math.cos(0.05 * i)]))
    T[:3, 3] = (0.1 * i, 0.0, 0.5)
    return T


def write_7scenes(root: Path, n: int = 5, corrupt: int | None = 1, nan_pose: int | None = 2,
                  intrinsics: bool = True) -> Path:
    root.mkdir(parents=True, exist_ok=True)
    if intrinsics:
        np.savetxt(root / "camera-intrinsics.txt", K)
    for i in range(n):
        stem = root / f"frame-{i:06d}"
        if i == corrupt:
            Path(f"{stem}.color.png").write_bytes(b"not a png at all")
        else:
            cv2.imwrite(f"{stem}.color.png", colour_image(i))
        cv2.imwrite(f"{stem}.depth.png", depth_ramp_mm(i))
        pose = pose_of(i)
        if i == nan_pose:
            pose[0, 3] = np.nan
        np.savetxt(f"{stem}.pose.txt", pose)
    return root


WALK_W, WALK_H = 320, 240


def _textured(seed: int, contrast: float = 0.1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    tex = cv2.resize(rng.integers(0, 256, size=(60, 80), dtype=np.uint8), (WALK_W, WALK_H), interpolation=cv2.INTER_NEAREST)
    grey = (128 + (tex.astype(np.float64) - 128) * contrast).astype(np.uint8)
    return cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)


def write_walk(root: Path, n: int = 12, blurry: tuple[int, ...] = (6,)) -> Path:
    """A camera sliding along a textured wall 2 m away; frames in `blurry` get motion blur."""
    root.mkdir(parents=True)
    np.savetxt(root / "camera-intrinsics.txt", [[300.0, 0, 160.0], [0, 300.0, 120.0], [0, 0, 1]])
    kernel = np.full((1, 15), 1 / 15, np.float32)
    for i in range(n):
        img = _textured(0)
        if i in blurry:
            img = cv2.filter2D(img, -1, kernel)
        cv2.imwrite(str(root / f"frame-{i:06d}.color.png"), img)
        cv2.imwrite(str(root / f"frame-{i:06d}.depth.png"), np.full((WALK_H, WALK_W), 2000, np.uint16))
        pose = np.eye(4)
        pose[0, 3] = 0.25 * i        # 0.25 m per frame = 37.5 px of image motion
        np.savetxt(root / f"frame-{i:06d}.pose.txt", pose)
    return root


class UnposedSource:
    """A LiveSource over frames of a sequence on disk, with their poses removed (the frames'
    pixels are the reader's; `blank`: frames whose depth is replaced by zeros)."""

    seq = None

    def __init__(self, seq, n: int, blank: frozenset = frozenset()):
        self.source, self.n, self.blank = seq, n, blank

    def poll(self) -> int:
        return self.n

    def written_at(self, i: int) -> float:
        return 0.0

    def frame(self, i: int):
        from sg3d.ingest.readers.frames import Frame, FrameInfo

        f = self.source.frame(i)
        depth = np.zeros_like(f.depth) if i in self.blank else f.depth
        return Frame(i, f.color, depth, f.K, np.full((4, 4), np.nan), FrameInfo(f.timestamp, f.name))
