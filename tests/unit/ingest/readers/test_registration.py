"""Depth registration estimated per sequence (`sg3d.ingest.readers.registration`): depth edges against
colour edges on hand-made images, and the frames a 7-Scenes folder probes."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.readers import seven_scenes
from sg3d.ingest.readers.registration import edge_agreement
from tests.sequences import write_7scenes


def _step(log_jump: float):
    """A 200 px frame whose right half lies exp(log_jump) times farther, and is brighter."""
    depth = np.full((200, 200), 2.0, np.float32)
    depth[:, 100:] = 2.0 * np.exp(log_jump)
    gray = np.full((200, 200), 80, np.uint8)
    gray[:, 100:] = 160
    return gray, depth


def test_a_depth_edge_is_a_jump_of_about_5_percent_per_pixel():        # DEPTH_EDGE_LOG_JUMP (Sobel: 4x)
    assert edge_agreement(*_step(0.055)) > 2.0
    assert edge_agreement(*_step(0.045)) == 0.0


def test_a_frame_judges_the_alignment_with_100_edge_pixels():          # MIN_EDGE_PIXELS
    def square(side):                  # a nearer, brighter square: 8 edge pixels per side pixel
        depth = np.full((100, 100), 2.0, np.float32)
        depth[40:40 + side, 40:40 + side] = 1.5
        gray = np.full((100, 100), 80, np.uint8)
        gray[40:40 + side, 40:40 + side] = 160
        return gray, depth
    assert edge_agreement(*square(13)) > 2.0          # 104 edge pixels
    assert edge_agreement(*square(12)) == 0.0         # 96


def test_a_7scenes_folder_probes_5_frames_for_its_registration(tmp_path, monkeypatch):   # REGISTRATION_PROBES
    seen = []

    def estimate(pairs, K, candidates):
        seen.append(len(pairs))
        return "identity", {name: 1.0 for name in candidates}
    monkeypatch.setattr(seven_scenes, "estimate_registration", estimate)
    seven_scenes.SevenScenesSequence.open(write_7scenes(tmp_path / "seq", n=12, corrupt=None, nan_pose=None))
    assert seen == [5]
