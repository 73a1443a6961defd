"""The ground truth of a generated room, in the shared format of ../shared/eval (objects with
id, category, coco_category, count_confidence, colour, world_position; relations; questions),
with what only a generator knows exactly: each object's box and size in the gravity frame, its
support, whether it is flat, how much of it the frames saw, and the room's structure."""
from __future__ import annotations

import numpy as np

from benchmarks.synth.scene import ROOM_HEIGHT, Room

# An object counts as seen when the frames show this many of its pixels in all, in this many
# frames (a thing glimpsed at the edge of one frame cannot be asked of any method).
SEEN_PIXELS = 150
SEEN_FRAMES = 3
FRAME_PIXELS = 20
FLAT_MAX_M = 0.05


def ground_truth(room: Room, to_world: np.ndarray, pixels: np.ndarray, frames_seen: np.ndarray) -> dict:
    """`pixels[k]` and `frames_seen[k]`: pixels of room thing k over all frames, and the frames
    that showed at least FRAME_PIXELS of it."""
    index = {t.id: k for k, t in enumerate(room.things)}
    R, t = to_world[:3, :3], to_world[:3, 3]
    objects: list[dict] = []
    relations: list[dict] = []
    seen: dict[str, bool] = {}
    for thing in room.objects():
        k = index[thing.id]
        lo, hi = thing.box()
        seen[thing.id] = bool(pixels[k] >= SEEN_PIXELS and frames_seen[k] >= SEEN_FRAMES)
        centre = R @ ((lo + hi) / 2) + t
        objects.append({
            "id": thing.id, "category": thing.category, "coco_category": thing.coco, "count_confidence": "sure",
            "colour": thing.colour,
            "world_position": [round(float(v), 4) for v in centre] if seen[thing.id] else None,
            "frames": [], "notes": "generated",
            "box_gravity": {"min": [round(float(v), 4) for v in lo], "max": [round(float(v), 4) for v in hi]},
            "size": [round(float(v), 4) for v in hi - lo],
            "support": thing.support, "flat": bool(hi[2] - lo[2] <= FLAT_MAX_M),
            "seen": seen[thing.id], "pixels": int(pixels[k]), "frames_seen": int(frames_seen[k]),
        })
    for thing in room.objects():
        if thing.support != "floor" and seen[thing.id] and seen.get(thing.support, False):
            relations.append({"subject": thing.id, "predicate": "on", "object": thing.support, "frames": [],
                              "notes": "exact support"})
    floor_k = index["floor"]
    walls = [{"id": w.id, "seen": bool(pixels[index[w.id]] >= SEEN_PIXELS)} for w in room.things if w.category == "wall"]
    W, D = room.size
    return {
        "sequence": f"generated {room.kind} layout, seed {room.seed} (benchmarks.synth)",
        "coordinate_frame": "World frame of the poses (metres): the room frame (z up, floor top at z = 0) moved by "
                            "room_to_world; box_gravity and size are in the room frame.",
        "kind": room.kind, "seed": room.seed,
        "room_to_world": [[round(float(v), 6) for v in row] for row in to_world],
        "up": [round(float(v), 6) for v in R[:, 2]],
        "structure": {"floor": {"seen": bool(pixels[floor_k] >= SEEN_PIXELS), "pixels": int(pixels[floor_k]),
                                "height": 0.0},
                      "walls": walls, "ceiling_height": ROOM_HEIGHT},
        "room": {"size": [W, D, ROOM_HEIGHT], "door_x": list(room.door), "window_y": list(room.window),
                 "focus": room.focus},
        "objects": objects, "relations": relations, "questions": [],
    }
