"""Screens in view, left out of an object's surround: their boxes reach the border they were cut by."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from sg3d.ingest.discover.discovery import screens_in_view
from sg3d.ingest.discover.room_cloud import RoomCloud


def _camera_at_origin():
    K = np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]])
    return SimpleNamespace(pose=np.eye(4), K=K, size=(640, 480))


def test_a_screen_box_that_stops_just_short_of_the_border_runs_to_it():
    view = _camera_at_origin()
    cloud = RoomCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int), np.eye(3), 0.0, [view])
    # 2 m ahead: x from 0.2 to 1.16 m projects to u 370..610 (the image ends at 640)
    near_border = (np.array([0.2, -0.3, 2.0]), np.array([1.16, 0.1, 2.05]))
    inside = (np.array([-0.6, -0.3, 2.0]), np.array([-0.2, 0.1, 2.05]))
    (a, b) = screens_in_view([near_border, inside], cloud, view)
    assert a[2] == 640 and 360 <= a[0] <= 380
    assert 160 <= b[0] <= 175 and 265 <= b[2] <= 275      # well inside: kept as measured
