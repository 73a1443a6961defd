"""What the pictures draw (`sg3d show`, `sg3d eval --report`): the named graph of a room or a
building with each room's up direction and building transform, and a coloured point cloud
back-projected from a sequence (`sg3d.core.stored.Scene`, NumPy arrays); the drawing is in `render/`."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable, Optional

import numpy as np

from sg3d.app.errors import AppError, NotFound
from sg3d.core.stored import RoomFrame, Scene
from sg3d.graphdb.protocol import GraphStore

VOXEL_M = 0.01            # one cloud point per centimetre cube: frames overlap, so most are repeats
MAX_DEPTH_M = 4.0         # farther depth is noisy on a Kinect-class sensor


def fetch_scene(store: GraphStore, building: str, room: Optional[str] = None) -> Scene:
    """The graph of `fetch_named_graph` (every node with its readable name, as ask prints it), each
    node with its box centre (or None), and each room's frame (up, room-to-building as a 4x4 list).
    NotFound ("nothing to show ...") when it holds no objects."""
    from sg3d.app.graph import fetch_named_graph

    try:
        graph = fetch_named_graph(store, building, room)
    except NotFound:
        where = f"room {room!r} of building {building!r}" if room else f"building {building!r}"
        raise NotFound(f"nothing to show: {where} holds no objects") from None
    centres = {r["id"]: r["box_centre"] for r in store.read("show_boxes", building=building, room=room)}
    graph = replace(graph, nodes=[replace(n, box_centre=centres.get(n.id)) for n in graph.nodes])
    rooms = {
        r["room"]: RoomFrame(r["id"], list(r["up"]) if r.get("up") else None,
                             (np.asarray(r["to_building"], dtype=float).reshape(4, 4).tolist()
                              if r.get("to_building") else None))
        for r in store.read("show_rooms", building=building, room=room)}
    return Scene(graph, rooms)


@dataclass(frozen=True)
class Thinning:
    """How a sequence's cloud is thinned: every `stride`-th depth pixel, one point per `voxel_m`
    cube, a subsample seeded by `seed`."""

    stride: int = 4
    voxel_m: float = VOXEL_M
    seed: int = 0


def sequence_cloud(sequence_path: Any, frames: int = 8, max_points: int = 20000, thinning: Thinning = Thinning(),
                   progress: Optional[Callable[[int, int], None]] = None) -> tuple[np.ndarray, np.ndarray]:
    """(points N x 3 in the sequence's world frame, colours N x 3 uint8 RGB) from `frames` frames
    spread over the sequence: every `stride`-th depth pixel back-projected, reduced to one point
    per `voxel_m` cube (the frames see the same surfaces again and again), then at most
    `max_points` of them (a seeded uniform subsample). `progress(done, total)` after each frame."""
    from sg3d.ingest.readers import SequenceError, open_sequence

    stride, voxel_m, seed = thinning.stride, thinning.voxel_m, thinning.seed
    try:
        seq = open_sequence(sequence_path)
    except SequenceError as exc:
        raise AppError(str(exc)) from None
    picks = sorted({int(i) for i in np.linspace(0, len(seq) - 1, max(1, frames))})
    pts, cols = [], []
    for done, i in enumerate(picks, 1):
        if progress is not None and done > 1:
            progress(done - 1, len(picks))
        try:
            f = seq.frame(i)
            depth, colour, K, pose = f.depth, f.color, f.K, f.pose
        except Exception:  # noqa: BLE001 - a bad frame only thins the cloud
            continue
        d = depth[::stride, ::stride].astype(np.float64)
        v, u = np.mgrid[0:d.shape[0], 0:d.shape[1]] * stride
        ok = (d > 0) & (d < MAX_DEPTH_M) & np.isfinite(d)
        cam = np.stack([(u[ok] - K[0, 2]) / K[0, 0] * d[ok], (v[ok] - K[1, 2]) / K[1, 1] * d[ok], d[ok]], axis=1)
        pts.append(cam @ pose[:3, :3].T + pose[:3, 3])
        cols.append(colour[v[ok], u[ok]][:, ::-1])        # BGR -> RGB
    if progress is not None:
        progress(len(picks), len(picks))
    if not pts:
        return np.zeros((0, 3)), np.zeros((0, 3), np.uint8)
    P, C = np.vstack(pts), np.vstack(cols).astype(np.uint8)
    _, first = np.unique(np.floor(P / voxel_m).astype(np.int64), axis=0, return_index=True)
    first.sort()
    P, C = P[first], C[first]
    if len(P) > max_points:
        keep = np.sort(np.random.default_rng(seed).choice(len(P), max_points, replace=False))
        P, C = P[keep], C[keep]
    return P, C
