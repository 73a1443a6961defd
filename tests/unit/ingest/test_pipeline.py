"""The ingest pipeline's settings (`sg3d.ingest.pipeline`): how a long recording is cut into chunks."""
from __future__ import annotations

from sg3d.ingest.config import BuildConfig
from sg3d.ingest.pipeline import chunk_ranges


def test_a_recording_is_fused_in_chunks_of_3000_frames():             # DEFAULT_CHUNK_FRAMES
    assert chunk_ranges(0, 3000, BuildConfig().chunk_frames) == [(0, 3000)]            # a room: one chunk
    assert chunk_ranges(0, 7000, BuildConfig().chunk_frames) == [(0, 3000), (3000, 6000), (6000, 7000)]
