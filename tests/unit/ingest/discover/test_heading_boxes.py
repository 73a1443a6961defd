"""Rule "a box along the room's heading" (`sg3d.ingest.discover.heading.along_heading`): a box
measured along the world's axes is measured again along the room's heading from the cloud's
points inside it; the floor and walls stay as found."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sg3d.core.geometry import horizontal_frame
from sg3d.core.model import ObjectObservation
from sg3d.ingest.discover.heading import ALONG_MIN_POINTS, ALONG_PERCENTILE, along_heading, points_off_planes
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import FLOOR_SLAB_M

UP = (0.0, 0.0, 1.0)


def turned(deg: float) -> np.ndarray:
    return np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg)), 0.0])


def top_points(w: float, d: float, h: float, deg: float, step: float = 0.01) -> np.ndarray:
    """A w x d top at height h, turned `deg` about up, its centre at (1, 2)."""
    a, b = np.meshgrid(np.arange(-w / 2, w / 2 + 1e-9, step), np.arange(-d / 2, d / 2 + 1e-9, step))
    e1, e2 = turned(deg), turned(deg + 90)
    return np.array([1.0, 2.0, h]) + a.reshape(-1, 1) * e1 + b.reshape(-1, 1) * e2


def cloud_of(points: np.ndarray) -> RoomCloud:
    return RoomCloud(points, np.tile([0.0, 0.0, 1.0], (len(points), 1)), np.zeros(len(points), int),
                     np.eye(3), 0.0, [SimpleNamespace(pose=np.eye(4))])


def world_box(points: np.ndarray, margin: float = 0.0) -> ObjectObservation:
    """The object as the world's axes measure it: the hull of its points (plus `margin` a side)."""
    lo, hi = points.min(axis=0) - margin, points.max(axis=0) + margin
    return ObjectObservation(local_id="a", labels=["object"], scores=[1.0], mean=tuple((lo + hi) / 2),
                             var=(0.01, 0.01, 0.01), n_points=len(points), size=tuple(hi - lo),
                             hist=np.zeros(1), box_centre=tuple((lo + hi) / 2))


def test_a_counter_turned_13_degrees_measures_its_own_size_along_the_heading():
    pts = top_points(1.6, 0.6, 0.9, 13.0)
    obj = world_box(pts)
    assert obj.size[:2] == pytest.approx((1.69, 0.94), abs=0.02)          # the world's hull
    along_heading(obj, pts, cloud_of(pts), horizontal_frame(UP, turned(13.0)))
    assert obj.size[:2] == pytest.approx((1.6, 0.6), abs=0.04)
    assert obj.box_centre == pytest.approx((1.0, 2.0, 0.9), abs=0.01)     # it stays where it stands


def test_a_box_is_the_extent_of_its_points_whatever_margin_the_world_box_had():
    pts = top_points(1.0, 0.5, 0.7, 20.0)
    obj = world_box(pts, margin=0.0125)                                    # a voxel box: half a voxel out
    along_heading(obj, pts, cloud_of(pts), horizontal_frame(UP, turned(20.0)))
    assert obj.size[:2] == pytest.approx((1.0, 0.5), abs=0.02)


def test_a_box_needs_20_points_inside_to_be_measured_again():               # ALONG_MIN_POINTS
    pts = top_points(1.0, 0.5, 0.7, 20.0, step=0.05)
    for n, moved in ((ALONG_MIN_POINTS, True), (ALONG_MIN_POINTS - 1, False)):
        few = pts[np.linspace(0, len(pts) - 1, n).round().astype(int)]
        obj = world_box(pts)
        before = obj.size
        along_heading(obj, few, cloud_of(few), horizontal_frame(UP, turned(20.0)))
        assert (obj.size != before) == moved


def test_a_stray_point_inside_the_box_does_not_widen_it():                 # ALONG_PERCENTILE
    pts = top_points(1.0, 0.5, 0.7, 20.0)
    obj = world_box(pts)
    corner = np.array([[obj.box_centre[0] + obj.size[0] / 2 - 1e-3, obj.box_centre[1] + obj.size[1] / 2 - 1e-3, 0.7]])
    stray = np.vstack([pts, np.repeat(corner, int(len(pts) * ALONG_PERCENTILE / 100 * 0.5), axis=0)])
    along_heading(obj, stray, cloud_of(stray), horizontal_frame(UP, turned(20.0)))
    assert obj.size[:2] == pytest.approx((1.0, 0.5), abs=0.04)


def test_the_floor_and_walls_stay_as_found_and_a_surface_is_turned():
    pts = top_points(1.6, 0.6, 0.9, 13.0)
    for label, kept in (("floor", True), ("wall", True), ("counter", False)):
        obj = world_box(pts)
        obj.labels, obj.layer = [label], "structure"
        before = obj.size
        along_heading(obj, pts, cloud_of(pts), horizontal_frame(UP, turned(13.0)))
        assert (obj.size == before) == kept


def test_the_points_a_box_holds_leave_the_floor_slab_out():                # FLOOR_SLAB_M
    pts = np.array([[0.0, 0.0, FLOOR_SLAB_M], [0.0, 0.0, FLOOR_SLAB_M + 1e-3]])
    assert points_off_planes(cloud_of(pts), []) == pytest.approx(pts[1:])
