"""The frame selection a build uses (`sg3d.ingest.select.selection`): its own KGE anchor threshold."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.readers.frames import Frame, FrameInfo
from sg3d.ingest.select.selection import SelectionParams

W, H = 100, 50
K = np.array([[50.0, 0, 49.5], [0, 50.0, 24.5], [0, 0, 1]])


def _slide(i: int) -> Frame:
    """A camera 1 m from a wall, moved sideways 7 px of image motion per frame."""
    pose = np.eye(4)
    pose[0, 3] = i * 7 / K[0, 0]
    return Frame(i, np.zeros((H, W, 3), np.uint8), np.ones((H, W), np.float32), K, pose, FrameInfo(i / 30.0, f"s-{i}"))


def test_a_build_anchors_a_frame_below_90_percent_overlap():          # BUILD_T_ANCHOR
    # frames 1 apart overlap 93 %, 2 apart 86 %: every second frame is an anchor
    grouper = SelectionParams().selector().grouper
    grouper.n_points = W * H
    groups = [[f.index for f in g.frames] for g in grouper.feed(_slide(i) for i in range(14))]
    assert groups == [[0, 2, 4, 6, 8, 10], [12]]
