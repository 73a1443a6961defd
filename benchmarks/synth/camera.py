"""Camera paths people record, as camera-to-world poses in the room frame (OpenCV camera: x right,
y down, z forward). Each path is a list of (eye, target) pairs; poses whose eye lies inside or
too near a thing are dropped by the caller."""
from __future__ import annotations

import numpy as np

from benchmarks.synth.scene import Room


def look_at(eye, target, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    if np.linalg.norm(x) < 1e-6:            # looking straight down: any heading
        x = np.cross(z, (0.0, 1.0, 0.0))
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = x, y, z, eye
    return pose


def walk(room: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """A loop around the room at 1.2-1.7 m, looking across it at the far side's furniture."""
    W, D = room.size
    c = np.array([W / 2, D / 2])
    phase = rng.uniform(0, 2 * np.pi)
    out = []
    for i in range(n):
        a = phase + 2 * np.pi * i / n
        e = c + np.array([(W / 2 - 0.7) * np.cos(a), (D / 2 - 0.7) * np.sin(a)])
        h = 1.45 + 0.25 * np.sin(3 * a + phase)
        t = c - 0.55 * (e - c)
        out.append((np.r_[e, h], np.r_[t, 0.55 + 0.1 * np.cos(2 * a)]))
    return out


def robot(room: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """A robot's camera 0.3 m above the floor on a loop through the room, looking level, inwards."""
    W, D = room.size
    c = np.array([W / 2, D / 2])
    phase = rng.uniform(0, 2 * np.pi)
    out = []
    for i in range(n):
        a = phase + 2 * np.pi * i / n
        e = c + np.array([(W / 2 - 0.9) * np.cos(a), (D / 2 - 0.8) * np.sin(a)])
        t = c - 0.8 * (e - c)
        out.append((np.r_[e, 0.3], np.r_[t, 0.3 + 0.15 * np.sin(2 * a)]))
    return out


def desk_scan(room: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """Handheld 0.3-0.7 m above a desk's top, sweeping left and right over it, looking steeply
    down at the top (the floor stays out of view)."""
    lo, hi = room.by_id(room.focus or "").box()
    top = float(hi[2])
    w, d = hi[0] - lo[0], hi[1] - lo[1]
    out = []
    for i in range(n):
        s = 0.5 - 0.5 * np.cos(2 * np.pi * 2 * i / n)      # two sweeps, left-right-left
        x = lo[0] + 0.35 * w + 0.3 * w * s
        y = lo[1] + 0.04 * d + 0.06 * d * np.sin(2 * np.pi * 3 * i / n)
        h = top + 0.5 + 0.2 * np.sin(2 * np.pi * i / n + 0.7)
        tx = x + 0.12 * w * np.sin(2 * np.pi * 2 * i / n)
        out.append((np.array([x, y, h]), np.array([tx, lo[1] + 0.75 * d, top])))
    return out


def shelf_sweep(room: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """Along a bookcase 1.1-1.5 m in front of it, at 1.0-1.5 m, aiming at its boards in turn."""
    lo, hi = room.by_id(room.focus or "").box()
    cx, top = (lo[0] + hi[0]) / 2, float(hi[2])
    out = []
    for i in range(n):
        s = np.sin(2 * np.pi * i / n)
        x = cx + (hi[0] - lo[0]) * 0.8 * s
        y = lo[1] - 1.3 - 0.2 * np.cos(2 * np.pi * 2 * i / n)
        h = 1.25 + 0.25 * np.sin(2 * np.pi * 3 * i / n)
        tz = top * (0.5 + 0.35 * np.sin(2 * np.pi * 3 * i / n))
        out.append((np.array([x, y, h]), np.array([cx + 0.4 * (x - cx), hi[1], tz])))
    return out


def corner(room: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """The north-west corner from one side: a short arc 2.5-3 m from it at 1.4-1.6 m."""
    W, D = room.size
    c = np.array([0.0, D])
    out = []
    for i in range(n):
        a = np.radians(-60 + 30 * np.sin(2 * np.pi * i / n))     # from the south-east of the corner
        r = min(2.9, W - 0.6, D - 0.6) - 0.2 * np.cos(2 * np.pi * 2 * i / n)
        e = c + r * np.array([np.cos(a), np.sin(a)])
        out.append((np.r_[e, 1.5 + 0.1 * np.sin(2 * np.pi * 3 * i / n)], np.array([1.2, D - 1.2, 0.45])))
    return out


PATHS = {"room": walk, "robot": robot, "desk": desk_scan, "shelf": shelf_sweep, "corner": corner}
