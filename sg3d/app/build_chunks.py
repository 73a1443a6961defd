"""A build's chunks: each one's local graph made by the pipeline and merged into the store as one
transaction under its key (a chunk already merged is not read again)."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable, Optional

from sg3d.app.build_request import BuildError, BuildRequest
from sg3d.graphdb.protocol import GraphStore

# None when the store's disk has room, else the line saying it is full (`sg3d.app.stores.disk_check`).
DiskCheck = Callable[[], Optional[str]]

_TOTALS = ("chunks", "merged_chunks", "skipped_chunks", "objects_created", "objects_updated", "objects_moved",
           "objects_removed", "objects_folded", "relations")
# the merge report's field behind each total it adds to
_REPORTED = {"objects_created": "created", "objects_updated": "updated", "relations": "relations",
             "objects_moved": "moved", "objects_removed": "removed", "objects_folded": "absorbed"}


@dataclass
class Chunks:
    """The build's chunks, each a local graph merged as one transaction under its key; a chunk
    whose key is already merged (`done`) is not read again."""
    store: GraphStore
    pipeline: Any                           # sg3d.ingest.pipeline.BuildPipeline
    embedding: Any
    params: Any                             # sg3d.merge.similarity.SimilarityParams
    fence: Any = None                       # the room lease's check, first in each merge transaction
    disk_check: Optional[DiskCheck] = None
    done: set = field(default_factory=set)
    totals: dict = field(default_factory=lambda: dict.fromkeys(_TOTALS, 0))
    merge_seconds: float = 0.0
    interrupted: bool = False

    @property
    def stats(self) -> Any:
        return self.pipeline.stats

    def merge_all(self, seq: Any, req: BuildRequest, run: str, scan_id: str, ground: Any, stop: int) -> None:
        from sg3d.core.model import ScanInfo
        from sg3d.graphdb.rescan import known_objects
        from sg3d.graphdb.values import room_id
        from sg3d.ingest.pipeline import Target, chunk_ranges

        scan_at = time.time()
        ranges = chunk_ranges(req.start, stop, self.pipeline.config.chunk_frames)
        try:
            for a, b in ranges:
                self.totals["chunks"] += 1
                key = f"{run}:{a}-{b}"
                if key in self.done:
                    self.totals["skipped_chunks"] += 1
                    continue
                self.check_disk()
                # the room as it stands before this chunk: what a re-scan may find moved or gone
                known = known_objects(self.store, room_id(req.building, req.room))
                scan = ScanInfo(scan_id, scan_at, closes=(a, b) == ranges[-1])
                self.merge(self.pipeline.run(seq, (a, b), ground, Target(req.room, req.building, key, scan, known)))
        except KeyboardInterrupt:
            self.interrupted = True

    def check_disk(self) -> None:
        """BuildError when the store's disk is below its minimum (checked before every merge
        transaction, not only when the store starts: a build must not write past it)."""
        full = self.disk_check() if self.disk_check is not None else None
        if full:
            raise BuildError(f"{full}; {self.totals['merged_chunks']} chunks were merged and are kept, nothing "
                             f"more was written: free space and run the same command again")

    def merge(self, graph: Any) -> None:
        from sg3d.graphdb.merge import merge_local_graph

        self.check_disk()
        t0 = time.perf_counter()
        report = merge_local_graph(self.store, graph, self.embedding, self.params, fence=self.fence)
        self.merge_seconds += time.perf_counter() - t0
        self.totals["merged_chunks"] += 0 if report.skipped else 1
        self.totals["skipped_chunks"] += 1 if report.skipped else 0
        for total, name in _REPORTED.items():
            self.totals[total] += getattr(report, name)
