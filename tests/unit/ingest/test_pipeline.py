"""The ingest pipeline's settings (`sg3d.ingest.pipeline`): how a long recording is cut into chunks."""
from __future__ import annotations

from sg3d.ingest.pipeline import Settings, chunk_ranges


def test_a_recording_is_fused_in_chunks_of_3000_frames():             # DEFAULT_CHUNK_FRAMES
    assert chunk_ranges(0, 3000, Settings().chunk_frames) == [(0, 3000)]            # a room: one chunk
    assert chunk_ranges(0, 7000, Settings().chunk_frames) == [(0, 3000), (3000, 6000), (6000, 7000)]


def test_only_a_walk_finds_windows_and_a_build_without_them_keeps_its_merge_keys():
    """Windows cost a plane vote and every view's rays: a build that does not find the rooms of
    its walk never runs them, and its settings' fingerprint (its merge keys) is the one it had
    before windows existed; a walk's (`--rooms auto`) finds them and is another build."""
    import json
    from dataclasses import replace

    from sg3d.app.places import walk_settings
    from sg3d.ingest.pipeline import depth_discovery, discover_from_depth, discover_with_windows

    plain = Settings()
    assert walk_settings(plain, None) == plain and depth_discovery(plain) is discover_from_depth
    walk = walk_settings(plain, "auto")
    assert walk.windows and depth_discovery(walk) is discover_with_windows
    assert "windows" not in json.loads(plain.fingerprint())
    assert json.loads(walk.fingerprint())["windows"] is True
    assert walk.fingerprint() != plain.fingerprint() == replace(walk, windows=False).fingerprint()
