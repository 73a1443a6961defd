"""Build (or extend) a room's scene graph from a sequence: the one function every front end calls.

It opens the sequence (`sg3d.app.build_place`), runs the pipeline (`sg3d.ingest.pipeline.BuildPipeline`)
chunk by chunk and merges each chunk's local graph into the store as one transaction under a key
made of the build's identity and the chunk's frame range. A chunk whose key is already in the
store is not read again, so re-running a build, or `--resume` after a crash or Ctrl-C, merges
exactly what is missing and ends with the graph of one clean build. What is checked before the
store starts is `sg3d.app.build_request`; the summary, `sg3d.app.build_summary`.
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Optional

from sg3d.app.build_chunks import Chunks, DiskCheck
from sg3d.app.build_place import ProgressFn, merged_chunks, open_range, place_cameras, place_room, scan_key
from sg3d.app.build_request import (
    BuildError,
    BuildRequest,
    PreparedBuild,
    check_detector,
    check_frame_selection_options,
    check_names,
    prepare,
    validate,
)
from sg3d.app.build_summary import BuildFacts, BuildSummary, summarize
from sg3d.graphdb.protocol import GraphStore

__all__ = ["BuildError", "BuildRequest", "BuildSummary", "PreparedBuild", "build_room", "check_detector",
           "check_frame_selection_options", "check_names", "merged_chunks", "place_cameras", "place_room", "prepare",
           "run_build", "scan_key", "validate"]

def build_room(store: GraphStore, req: BuildRequest, settings: Any, detector: Any = None, embedding: Any = None,
               progress: Optional[ProgressFn] = None) -> BuildSummary:
    """Run the pipeline over `req.sequence` and merge each chunk into `store` (`prepare`, then
    `run_build`). `settings`: `sg3d.ingest.config.BuildConfig`."""
    return run_build(store, prepare(req, settings, detector), embedding, progress)


def run_build(store: GraphStore, prepared: PreparedBuild, embedding: Any = None, progress: Optional[ProgressFn] = None,
              disk_check: Optional[DiskCheck] = None) -> BuildSummary:
    """A prepared build: the sequence read, its camera poses and gravity, each chunk's local
    graph merged into `store`, the room placed. The room is held for the whole build (one writer
    per room: `sg3d.app.writers.writing`). KeyboardInterrupt between chunks keeps what was merged
    and returns a summary with `interrupted` set. `disk_check` (`sg3d.app.stores.disk_check`) is
    asked before every merge transaction: a disk below the store's minimum is refused, not written."""
    from sg3d.app.writers import Writer, writing
    from sg3d.core.embedding import default_embedding
    from sg3d.merge.similarity import SimilarityParams
    from sg3d.ingest.pipeline import BuildPipeline

    req = prepared.req
    seq, stop = open_range(req)
    store.ensure_schema()
    with writing(store, req.building, req.room, Writer("build", f"sg3d build {req.sequence}", wait=req.wait),
                 error=BuildError) as lease:
        t_start = time.perf_counter()
        poses = place_cameras(seq, req, stop, progress)
        three_d = prepared.settings.method.three_d
        chunks = Chunks(store, BuildPipeline(prepared.settings, prepared.detector, progress),
                         embedding or default_embedding(),
                         SimilarityParams() if three_d else SimilarityParams(threshold=float("inf")),
                         lease.fence, disk_check)
        return _run_held(chunks, prepared, seq, stop, poses, t_start)


def _run_held(chunks: Chunks, prepared: PreparedBuild, seq: Any, stop: int, poses: dict,
              t_start: float) -> BuildSummary:
    from sg3d.graphdb.values import room_id
    from sg3d.ingest.pipeline import run_key
    from sg3d.ingest.stages import find_ground

    req, store = prepared.req, chunks.store
    rid = room_id(req.building, req.room)
    # a build on estimated poses is another build than one on the recording's own poses
    identity = str(Path(req.sequence).resolve()) + (" (estimated poses)" if poses["source"] == "estimated" else "")
    run = run_key(identity, len(seq), prepared.settings, req.room, req.building)
    scan = scan_key(run, req.start, stop)
    chunks.done, chunks.totals["remerged_chunks"] = merged_chunks(store, rid, run, scan)
    try:
        grounded = find_ground(seq, (req.start, stop))
    except ValueError:
        raise BuildError(f"no frame of {req.sequence} has usable depth") from None
    ground = grounded.ground
    chunks.merge_all(seq, req, run, scan, ground, stop)
    placed = None if chunks.interrupted else place_room(store, req, prepared.placement)
    seconds = {**({"poses": poses["seconds"]} if "seconds" in poses else {}), **grounded.seconds}
    found = None
    if req.rooms == "auto" and not chunks.interrupted:
        from sg3d.app.places import Walk, write_walk_rooms

        t0 = time.perf_counter()
        # under the lease, as each merge: a build that lost the room writes no rooms
        found = write_walk_rooms(store, rid, Walk(seq, req.start, stop, ground.up, ground.floor), fence=chunks.fence)
        seconds["rooms"] = time.perf_counter() - t0
    facts = BuildFacts(seq, stop, ground.up, ground.floor is not None, poses, run, scan, placed, seconds,
                       time.perf_counter() - t_start)
    summary = summarize(store, rid, prepared, facts, chunks)
    summary.rooms_found = found
    return summary
