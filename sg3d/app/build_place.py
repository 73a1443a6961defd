"""Where a build stands: its camera poses (given or estimated), its scan's key, the room placed in
its building."""
from __future__ import annotations

from typing import Any, Callable, Optional

from sg3d.app.build_request import BuildError, BuildRequest
from sg3d.graphdb.protocol import GraphStore

ProgressFn = Callable[[str, int, int], None]   # (phase, done, total)


def place_cameras(seq: Any, req: BuildRequest, stop: int, progress: Optional[ProgressFn] = None) -> dict:
    """Camera poses for the build: the recording's own, or estimated from its images when it has
    none or `req.estimate_poses` asks; the summary's "poses" section."""
    if not req.estimate_poses and seq.has_poses():
        if req.trajectory_out is not None:
            raise BuildError(f"--trajectory-out writes estimated poses, and {req.sequence} has its own; "
                             f"add --estimate-poses to estimate them anyway")
        return {"source": "given"}
    from sg3d.ingest.poses.sequence import (
        estimate_sequence_poses,
        estimate_summary,
        write_trajectory,
    )

    est = estimate_sequence_poses(seq, req.start, stop,
                                  progress=(lambda done, total: progress("poses", done, total)) if progress else None)
    if not est.poses:
        raise BuildError(f"no camera pose could be estimated for {req.sequence}: "
                         + "; ".join(sorted({why for why in est.unplaced.values()})[:3]))
    if req.trajectory_out is not None:
        try:
            write_trajectory(req.trajectory_out, seq, est)
        except OSError as exc:
            raise BuildError(f"cannot write --trajectory-out {req.trajectory_out}: {exc.strerror}")
    return estimate_summary(seq, est, str(req.trajectory_out) if req.trajectory_out else None)


def scan_key(run: str, start: int, stop: int) -> str:
    """A build's scan id: the build's identity and its frame range (the same build re-run or
    resumed is the same scan; another range of the same sequence is another scan)."""
    return f"{run}@{start}-{stop}"


def place_room(store: GraphStore, req: BuildRequest, transform: Any) -> Optional[dict]:
    """Give the room its room-to-building transform; a building's first room is its reference."""
    import numpy as np

    from sg3d.merge.align import AlignmentError
    from sg3d.graphdb.building import link_rooms, list_rooms, set_room_transform
    from sg3d.graphdb.values import room_id

    rid = room_id(req.building, req.room)
    try:
        if req.align_to:
            report = link_rooms(store, room_id(req.building, req.align_to), rid)
            return {"how": f"aligned to {req.align_to}", "residual_m": round(report.residual_rms_m, 4),
                    "pairs": report.pairs, "same_as": len(report.same_as)}
        if transform is not None:
            set_room_transform(store, rid, transform)
            return {"how": "transform file"}
        placed = [r for r in list_rooms(store, req.building) if r["id"] != rid and r["to_building"] is not None]
        if req.shared_frame or not placed:
            set_room_transform(store, rid, np.eye(4))
            return {"how": "shared frame" if req.shared_frame else "reference room of the building"}
    except AlignmentError as exc:
        raise BuildError(f"the graph was built, but placing it in the building failed: {exc}")
    return {"how": "not placed yet: `sg3d rooms link`, or build with --align-to/--transform/--shared-frame"}


def open_range(req: BuildRequest) -> tuple[Any, int]:
    """The sequence and the end of the frame range, refusing an empty sequence or range."""
    from sg3d.ingest.readers import SequenceError, open_sequence

    try:
        seq = open_sequence(req.sequence, req.layout, **(req.bag_options or {}))
    except SequenceError as exc:
        raise BuildError(str(exc)) from None
    if len(seq) == 0:
        raise BuildError(f"no frames found in {req.sequence}")
    if req.start >= len(seq):
        raise BuildError(f"--start {req.start} is past the end of the sequence ({len(seq)} frames)")
    return seq, len(seq) if req.stop is None else min(req.stop, len(seq))


def merged_chunks(store: GraphStore, rid: str, run: str, scan: str) -> tuple[set, int]:
    """The keys of this build's chunks already merged (not read again), and how many logged chunks
    were forgotten: rule "a merge log without its objects is no merge". When the build's logs say
    it created objects and the room holds none this build's scan saw (someone deleted them), its
    logs are removed and every chunk merges again, and the summary and stderr say so."""
    import logging

    rows = store.read("merge_log_run", prefix=run + ":")
    created = sum(int(r["created"] or 0) for r in rows)
    if not rows or created == 0 or store.read("scan_object_count", room=rid, scan=scan)[0]["n"]:
        return {r["key"] for r in rows}, 0
    store.write("merge_log_forget", prefix=run + ":")
    logging.getLogger("sg3d.build").warning(
        "room %s holds none of the %d objects this build merged before (its %d chunks are logged as merged): "
        "merging every chunk again", rid, created, len(rows))
    return set(), len(rows)
