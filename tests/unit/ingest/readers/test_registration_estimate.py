"""Depth-to-colour registration estimated per sequence (sg3d.ingest.readers.registration):
depth edges that fall on colour edges pick their registration, and the identity wins ties."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from sg3d.ingest.readers.registration import (
    MIN_EDGE_PIXELS,
    Registration,
    edge_agreement,
    estimate_registration,
)

W, H = 640, 480
K = np.array([[585.0, 0, 320.0], [0, 585.0, 240.0], [0, 0, 1]])
CANDIDATES = {"identity": Registration(), "kinect": Registration.kinect_v1()}


def scene(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A grey image of bright boxes on a dark wall, and the depth of the same boxes (1.2 m on a 3 m
    wall), both in colour pixels."""
    rng = np.random.default_rng(seed)
    gray = np.full((H, W), 40, np.uint8)
    depth = np.full((H, W), 3.0, np.float32)
    for _ in range(6):
        x, y = rng.integers(40, W - 160), rng.integers(40, H - 140)
        w, h = rng.integers(50, 120), rng.integers(50, 100)
        gray[y:y + h, x:x + w] = 200
        depth[y:y + h, x:x + w] = 1.2
    return gray, depth


def as_depth_camera(depth: np.ndarray, reg: Registration) -> np.ndarray:
    """The depth image a camera registered by `reg` records: colour pixel (u, v) is seen at the
    depth pixel `reg` maps it to."""
    mx, my = reg.depth_coordinates(K, (W, H))
    out = np.zeros_like(depth)
    u = np.clip(np.round(mx).astype(int), 0, W - 1)
    v = np.clip(np.round(my).astype(int), 0, H - 1)
    out[v, u] = depth
    return cv2.dilate(out, np.ones((3, 3), np.uint8))     # fill the gaps a scale > 1 leaves


@pytest.mark.parametrize("truth", ["identity", "kinect"])
def test_the_registration_the_camera_used_is_found(truth):
    pairs = []
    for seed in range(3):
        gray, depth = scene(seed)
        pairs.append((gray, as_depth_camera(depth, CANDIDATES[truth])))
    best, scores = estimate_registration(pairs, K, CANDIDATES)
    assert best == truth
    other = next(n for n in CANDIDATES if n != truth)
    assert scores[truth] > scores[other] + 0.3


def test_aligned_edges_score_high_and_shifted_ones_low():
    gray, depth = scene(1)
    aligned = edge_agreement(gray, depth)
    shifted = edge_agreement(gray, np.roll(depth, 15, axis=1))
    assert aligned > 2.0 and shifted < aligned - 0.5


def test_a_frame_without_depth_edges_says_nothing():
    gray, _ = scene(2)
    assert edge_agreement(gray, np.full((H, W), 2.0, np.float32)) == 0.0
    small = np.full((H, W), 2.0, np.float32)
    small[100:105, 100:105] = 1.0                      # fewer edge pixels than MIN_EDGE_PIXELS
    assert np.count_nonzero(small != 2.0) * 4 < MIN_EDGE_PIXELS * 2
    assert edge_agreement(gray, small) == 0.0


def test_a_tie_keeps_the_identity():
    flat = [(np.full((H, W), 90, np.uint8), np.full((H, W), 2.0, np.float32))]
    best, scores = estimate_registration(flat, K, CANDIDATES)
    assert best == "identity" and scores["identity"] == scores["kinect"] == 0.0
