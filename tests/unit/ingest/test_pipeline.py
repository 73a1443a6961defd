"""The ingest pipeline's settings (`sg3d.ingest.pipeline`): how a long recording is cut into chunks."""
from __future__ import annotations

from sg3d.ingest.config import BuildConfig
from sg3d.ingest.pipeline import chunk_ranges


def test_a_recording_is_fused_in_chunks_of_3000_frames():             # DEFAULT_CHUNK_FRAMES
    assert chunk_ranges(0, 3000, BuildConfig().chunk_frames) == [(0, 3000)]            # a room: one chunk
    assert chunk_ranges(0, 7000, BuildConfig().chunk_frames) == [(0, 3000), (3000, 6000), (6000, 7000)]


def test_only_a_walk_finds_windows_and_a_build_without_them_keeps_its_merge_keys():
    """Windows cost a plane vote and every view's rays: a build that does not find the rooms of
    its walk never runs them, and its config's fingerprint (its merge keys) is the one it had
    before windows existed; a walk's (`--rooms auto`) finds them and is another build."""
    import json
    from dataclasses import replace

    from sg3d.app.places import walk_settings
    from sg3d.ingest.stages import depth_discovery, discover_from_depth, discover_with_windows

    plain = BuildConfig()
    assert walk_settings(plain, None) == plain and depth_discovery(plain) is discover_from_depth
    walk = walk_settings(plain, "auto")
    assert walk.discover.windows and depth_discovery(walk) is discover_with_windows
    assert "discover.windows" not in json.loads(plain.fingerprint())
    assert json.loads(walk.fingerprint())["discover.windows"] is True
    unwalked = replace(walk, discover=replace(walk.discover, windows=False))
    assert walk.fingerprint() != plain.fingerprint() == unwalked.fingerprint()
