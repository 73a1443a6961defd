"""The colour's grey levels brought into a depth camera's own pixels (`sg3d.ingest.readers.depth_pixels`)."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.readers.depth_pixels import grey_in_depth_pixels

K = np.array([[100.0, 0, 79.5], [0, 100.0, 59.5], [0, 0, 1]])
STRIPES = (np.arange(160)[None, :].repeat(120, 0) * 3 % 256).astype(np.uint8)    # grey = 3 x column


def test_one_camera_sees_its_own_grey():
    wall = np.full((120, 160), 2.0, np.float32)
    assert np.array_equal(grey_in_depth_pixels(wall, K, STRIPES, K, np.eye(4)), STRIPES)


def test_a_baseline_shifts_the_grey_by_its_parallax_at_the_point_s_depth():
    """Colour camera 10 cm to the depth camera's left (points move +0.1 m in x): a wall at 2 m
    lands f * 0.1 / 2 = 5 px to the right in colour, one at 1 m 10 px."""
    to_colour = np.eye(4)
    to_colour[0, 3] = 0.1
    for metres, px in ((2.0, 5), (1.0, 10)):
        wall = np.full((120, 160), metres, np.float32)
        grey = grey_in_depth_pixels(wall, K, STRIPES, K, to_colour).astype(int)
        assert np.array_equal(grey[:, 20:140], STRIPES[:, 20 + px:140 + px].astype(int))


def test_a_pixel_without_depth_takes_the_grey_of_the_point_a_metre_ahead():
    to_colour = np.eye(4)
    to_colour[0, 3] = 0.1
    hole = np.zeros((120, 160), np.float32)
    grey = grey_in_depth_pixels(hole, K, STRIPES, K, to_colour).astype(int)
    assert np.array_equal(grey[:, 20:140], STRIPES[:, 30:150].astype(int))              # 10 px: 1 m
