"""RGB-D odometry's checks (`sg3d.ingest.poses.tracking`) on hand-made depth: no motion is fitted here."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.poses.tracking import MIN_TEXTURE, MIN_TEXTURE_POINTS, Odometry, depth_agreement, image_agreement, reduce_factor

K = np.array([[100.0, 0, 79.5], [0, 100.0, 59.5], [0, 0, 1]])


def test_odometry_runs_about_320_pixels_wide():                         # TARGET_WIDTH
    assert [reduce_factor(w) for w in (320, 640, 1280)] == [1, 2, 4]


def test_a_frame_needs_a_tenth_of_its_depth_to_be_tracked():            # MIN_DEPTH_SHARE
    odometry = Odometry(K, (160, 120))
    gray = np.zeros((120, 160), np.uint8)

    def depth(rows):
        d = np.zeros((120, 160), np.float32)
        d[:rows] = 1.5
        return d
    assert odometry.view(0, depth(15), gray).index == 0                 # 12.5 % valid
    with pytest.raises(ValueError, match="of its depth is valid"):
        odometry.view(1, depth(9), gray)                                 # 7.5 %


def test_a_point_agrees_within_3_cm():                                  # INLIER_M
    source = np.full((120, 160), 1.5, np.float32)
    assert depth_agreement(source, source + 0.025, K, np.eye(4))[0] == 1.0
    assert depth_agreement(source, source + 0.035, K, np.eye(4))[0] == 0.0


def test_agreement_is_sampled_every_4th_pixel():                        # FIT_GRID
    source = np.full((120, 160), 1.5, np.float32)
    target = source + 1.0
    target[:, 4::8] = 1.5                  # only the columns 4, 12, 20, ... agree
    assert depth_agreement(source, target, K, np.eye(4))[0] == 0.5


def _wall(gray: np.ndarray):
    """A view of a flat wall 1.5 m away showing `gray`."""
    return Odometry(K, (160, 120)).view(0, np.full((120, 160), 1.5, np.float32), gray)


def _slid(metres: float) -> np.ndarray:
    motion = np.eye(4)
    motion[0, 3] = metres
    return motion


STRIPES = (np.arange(160)[None, :].repeat(120, 0) // 8 % 2 * 120 + 60).astype(np.uint8)   # 8-pixel bars


def test_the_images_judge_a_slide_along_a_plane_that_the_depth_cannot():    # image_agreement
    view = _wall(STRIPES)
    assert depth_agreement(view.depth, view.depth, K, _slid(0.12))[0] > 0.9   # the depth agrees either way
    assert image_agreement(view, view, K, np.eye(4)) > 0.99
    assert image_agreement(view, view, K, _slid(0.12)) < 0                    # 8 px: the bars swap places


def test_too_little_texture_or_too_few_points_leave_the_images_out():       # MIN_TEXTURE, MIN_TEXTURE_POINTS
    rng = np.random.default_rng(0)
    faint = (128 + rng.normal(0, MIN_TEXTURE * 0.5, (120, 160))).astype(np.uint8)
    plain = (128 + rng.normal(0, MIN_TEXTURE * 2, (120, 160))).astype(np.uint8)
    assert image_agreement(_wall(faint), _wall(faint), K, np.eye(4)) is None
    assert image_agreement(_wall(plain), _wall(plain), K, np.eye(4)) > 0.99
    view = _wall(STRIPES)
    depth = np.zeros((120, 160), np.float32)
    few, enough = int(np.sqrt(MIN_TEXTURE_POINTS)) - 1, int(np.sqrt(MIN_TEXTURE_POINTS)) + 1
    depth[:4 * few, :4 * few] = 1.5                       # (few)^2 sampled points: under the minimum
    view.depth = depth
    assert image_agreement(view, _wall(STRIPES), K, np.eye(4)) is None
    depth[:4 * enough, :4 * enough] = 1.5
    assert image_agreement(view, _wall(STRIPES), K, np.eye(4)) > 0.99
