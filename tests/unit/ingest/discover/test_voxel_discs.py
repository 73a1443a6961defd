"""The pixels projected voxels cover (`sg3d.ingest.discover.discovery.voxel_discs`)."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from sg3d.ingest.discover.discovery import VOXEL_DISC_M, voxel_discs


def _one_circle_at_a_time(u, v, z, focal, shape):
    mask = np.zeros(shape, np.uint8)
    for x, y, d in zip(u, v, z):
        cv2.circle(mask, (int(round(x)), int(round(y))), max(1, int(round(focal * VOXEL_DISC_M / d))), 1, -1)
    return mask


@pytest.mark.parametrize("seed", range(40))
def test_the_discs_are_cv2_circles_drawn_one_by_one(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(0, 1500))
    h, w = 120, 160
    spread = rng.choice([8.0, 60.0])                  # a segment's voxels, or scattered ones
    centre = rng.uniform((-30, -30), (w + 30, h + 30))
    u, v = centre[0] + rng.normal(0, spread, n), centre[1] + rng.normal(0, spread, n)
    z = rng.uniform(0.25, 6.0, n)
    focal = float(rng.uniform(100, 600))
    np.testing.assert_array_equal(voxel_discs(u, v, z, focal, (h, w)), _one_circle_at_a_time(u, v, z, focal, (h, w)))


def test_nothing_in_view_is_an_empty_mask():
    empty = np.zeros(0)
    assert not voxel_discs(empty, empty, empty, 500.0, (48, 64)).any()
    far = np.array([-100.0]), np.array([-100.0]), np.array([1.0])
    assert not voxel_discs(*far, 500.0, (48, 64)).any()


def test_a_near_voxel_covers_a_wider_disc_and_never_less_than_one_pixel():
    near = voxel_discs(np.array([32.0]), np.array([24.0]), np.array([0.5]), 500.0, (48, 64))
    far = voxel_discs(np.array([32.0]), np.array([24.0]), np.array([50.0]), 500.0, (48, 64))
    assert near.sum() > far.sum() >= 5            # radius 12 px against the 1 px floor (a cross of 5)
