"""RGB-D odometry's checks (`sg3d.ingest.poses.tracking`) on hand-made depth: no motion is fitted here."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.poses.tracking import Odometry, depth_agreement, reduce_factor

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
