"""What a build did (`BuildSummary`), from its stages' counts and the room as the store holds it."""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Optional

from sg3d.graphdb.protocol import GraphStore


@dataclass
class BuildSummary:
    """What a build did, as `sg3d build` prints it and `--json` writes it (`as_dict`). The
    sections are the JSON's objects; `summary["graph"]` reads like the JSON."""
    sequence: str
    layout: str
    room: str
    building: str
    method: str
    quality: str
    detector: str
    interrupted: bool
    up: list[float]
    frames: dict                    # in_range, read, blurry, keyframes, ..., skipped, skipped_frames
    hypotheses: dict                # formed, kept, rejected (reason -> n)
    from_depth: dict                # found from depth, named by no detector: unnamed, structure
    graph: dict                     # chunk and object totals, room_objects, room_relations
    seconds: dict                   # per phase
    input_frames_per_second: float
    key: str
    scan: str
    placement: Optional[dict]
    poses: dict
    # "seen", or "not seen": the recording never saw the floor (a desk scan), so its tops are objects
    floor: str = "seen"
    rooms_found: Optional[dict] = None   # --rooms auto: `sg3d.app.places.write_walk_rooms`

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __getitem__(self, name: str):
        return getattr(self, name)

    def get(self, name: str, default=None):
        return getattr(self, name, default)


@dataclass(frozen=True)
class BuildFacts:
    """What the build knew when it ended, besides its stages' counts: the opened sequence and
    range, its poses and gravity, its keys, where the room was placed, the seconds per phase."""

    seq: Any
    stop: int
    up: Any
    floor_seen: bool
    poses: dict
    run: str
    scan: str
    placement: Optional[dict]
    seconds: dict
    wall: float


def summarize(store: GraphStore, rid: str, prepared: Any, facts: BuildFacts, chunks: Any) -> BuildSummary:
    """The summary of a build of room `rid` (`chunks`: the merged chunks' totals and stages' stats)."""
    from sg3d.core.model import RELATION_TYPES

    req, settings, seq = prepared.req, prepared.settings, facts.seq
    room_objects = store.read("object_count", room=rid)[0]["n"]
    room_relations = store.read("relation_count", room=rid, types=list(RELATION_TYPES))[0]["n"]
    skipped = [{"frame": name, "reason": reason} for name, reason in seq.skipped]
    counts = chunks.stats.as_dict()
    hyp = {"formed": counts.pop("hypotheses"), "kept": counts.pop("kept"), "rejected": counts.pop("rejected")}
    wall = facts.wall
    return BuildSummary(
        sequence=str(req.sequence), layout=seq.layout, room=req.room, building=req.building,
        method=settings.method.name, quality=settings.detect.quality, detector=settings.detect.detector,
        interrupted=chunks.interrupted, up=[round(float(v), 4) for v in facts.up],
        frames={"in_range": facts.stop - req.start, **{k: counts[k] for k in (
            "read", "blurry", "keyframes", "anchors", "coverage", "detected", "detections")},
            "skipped": len(skipped), "skipped_frames": skipped},
        hypotheses=hyp,
        from_depth={"unnamed": counts.get("unnamed", 0), "structure": counts.get("structure", 0)},
        graph={**chunks.totals, "room_objects": room_objects, "room_relations": room_relations},
        seconds={k: round(v, 3) for k, v in {**facts.seconds, **chunks.stats.seconds,
                                             "merge": chunks.merge_seconds, "total": wall}.items()},
        input_frames_per_second=round(counts["frames"] / wall, 2) if wall > 0 and counts["frames"] else 0.0,
        key=facts.run, scan=facts.scan, placement=facts.placement, poses=facts.poses,
        floor="seen" if facts.floor_seen else "not seen")
