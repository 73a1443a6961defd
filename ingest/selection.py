"""The front of the pipeline: sequence -> blur rejection (ABIR) -> keyframe groups (KGE).

`FrameSelector.groups(seq)` yields `KeyframeGroup`s whose frames are decoded (colour + depth)
and ready for detection; everything else is dropped after its grey image (for ABIR) and its pose
(for KGE) were looked at. `stats` counts what happened, for reports and benchmarks.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from typing import Callable, Iterator, Optional

from ingest.abir import ABIR, AbirDecision
from ingest.frames import Frame, FrameError, decoded_ahead
from ingest.kge import KeyframeGroup, KeyframeGrouper
from ingest.readers import Sequence


@dataclass
class SelectionStats:
    frames: int = 0            # frames in the range asked for
    read: int = 0              # frames that reached ABIR with a readable image
    skipped: int = 0           # bad frames (see Sequence.skipped)
    blurry: int = 0
    keyframes: int = 0
    anchors: int = 0
    groups: int = 0
    seconds: float = 0.0

    @property
    def kept(self) -> int:
        """Frames passed on to detection: keyframes + anchors."""
        return self.keyframes + self.anchors

    @property
    def fraction_kept(self) -> float:
        return self.kept / self.read if self.read else 0.0

    @property
    def frames_per_second(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else 0.0

    def as_dict(self) -> dict:
        d = asdict(self)
        d.update(kept=self.kept, fraction_kept=round(self.fraction_kept, 4),
                 frames_per_second=round(self.frames_per_second, 1), seconds=round(self.seconds, 3))
        return d


# (frame, abir decision or None when the frame was bad, role: "blurry"|"keyframe"|"anchor"|"garbage"|"skipped")
FrameCallback = Callable[[Frame, Optional[AbirDecision], str], None]


@dataclass
class FrameSelector:
    abir: ABIR = field(default_factory=ABIR)
    grouper: KeyframeGrouper = field(default_factory=KeyframeGrouper)
    stats: SelectionStats = field(default_factory=SelectionStats)

    def groups(self, seq: Sequence, start: int = 0, stop: Optional[int] = None, step: int = 1,
               on_frame: Optional[FrameCallback] = None) -> Iterator[KeyframeGroup]:
        stats = self.stats
        t0 = time.perf_counter()
        skipped_before = len(seq.skipped)
        stop = len(seq) if stop is None else min(stop, len(seq))
        stats.frames += len(range(start, stop, step))
        try:
            for frame in decoded_ahead(seq.frames(start, stop, step, lazy=True), ("gray",)):
                try:
                    decision = self.abir.update(frame)
                    stats.read += 1
                    if decision.blurry:
                        stats.blurry += 1
                        role = "blurry"
                    else:
                        role = self.grouper.add(frame)
                except FrameError:
                    decision, role = None, "skipped"
                if role == "garbage" or role == "blurry":
                    frame.release()
                elif role == "keyframe":
                    stats.keyframes += 1
                elif role == "anchor":
                    stats.anchors += 1
                if on_frame is not None:
                    on_frame(frame, decision, role)
                while self.grouper.completed:
                    stats.groups += 1
                    stats.seconds = time.perf_counter() - t0
                    yield self.grouper.completed.pop(0)
            last = self.grouper.finish()
            if last is not None:
                stats.groups += 1
                yield last
        finally:
            stats.skipped += len(seq.skipped) - skipped_before
            stats.seconds = time.perf_counter() - t0


def select_frames(seq: Sequence, abir: Optional[ABIR] = None, grouper: Optional[KeyframeGrouper] = None,
                  **kwargs) -> tuple[list[KeyframeGroup], SelectionStats]:
    """All keyframe groups of a sequence at once (convenient for small sequences and tests)."""
    selector = FrameSelector(abir or ABIR(), grouper or KeyframeGrouper())
    groups = list(selector.groups(seq, **kwargs))
    return groups, selector.stats
