"""The room's up and floor (`sg3d.ingest.poses.gravity`) from hand-rendered depth: cameras above planes."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.poses.gravity import depth_normals, estimate_gravity, floor_not_a_top, horizontal_span, level_camera_up
from sg3d.ingest.readers.frames import Frame, FrameInfo

FLOOR = ((0.0, 0.0, 1.0), 0.0, None)


def camera(pitch_deg: float, height: float) -> np.ndarray:
    """An OpenCV camera (x right, y down, z ahead) `height` above the floor at the origin, looking
    along world +y, pitched down by `pitch_deg` (world z is up)."""
    p = np.radians(pitch_deg)
    pose = np.eye(4)
    pose[:3, 0] = (1, 0, 0)
    pose[:3, 1] = (0, -np.sin(p), -np.cos(p))
    pose[:3, 2] = (0, np.cos(p), -np.sin(p))
    pose[:3, 3] = (0, 0, height)
    return pose


def frame(pose: np.ndarray, planes, size=(160, 120), f: float = 120.0) -> Frame:
    """Depth of the planes (normal, offset: n . X = offset, pixel mask or None), the nearest wins."""
    w, h = size
    K = np.array([[f, 0, (w - 1) / 2], [0, f, (h - 1) / 2], [0, 0, 1]])
    v, u = np.mgrid[0:h, 0:w]
    rays = np.stack([(u - K[0, 2]) / f, (v - K[1, 2]) / f, np.ones((h, w))], axis=-1) @ pose[:3, :3].T
    depth = np.full((h, w), np.inf)
    for n, c, mask in planes:
        n = np.asarray(n, float) / np.linalg.norm(n)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (c - pose[:3, 3] @ n) / (rays @ n)
        t = np.where((t > 0) & np.isfinite(t), t, np.inf)
        if mask is not None:
            t = np.where(mask(u, v), t, np.inf)
        depth = np.minimum(depth, t)
    depth = np.where(np.isfinite(depth), depth, 0.0).astype(np.float32)
    return Frame(0, np.zeros((h, w, 3), np.uint8), depth, K, pose, FrameInfo(0.0, "rendered"))


def test_up_is_sought_within_35_degrees_of_the_cameras_image_up():    # PRIOR_CONE_DEG
    assert estimate_gravity([frame(camera(30, 1.5), [FLOOR])]).up == pytest.approx((0, 0, 1), abs=1e-6)


def test_a_camera_looking_down_up_to_60_degrees_finds_the_level_it_looks_at():   # WIDE_CONE_DEG
    # pitched 40 or 58 degrees down, the floor's normals lie outside the 35-degree cone, within 60
    assert estimate_gravity([frame(camera(40, 1.5), [FLOOR])]).up == pytest.approx((0, 0, 1), abs=1e-6)
    assert estimate_gravity([frame(camera(58, 1.0), [FLOOR])]).up == pytest.approx((0, 0, 1), abs=1e-6)
    # pitched 62 degrees down, the prior stands
    assert estimate_gravity([frame(camera(62, 1.0), [FLOOR])]).n_normals == 0


def test_a_desk_and_the_wall_behind_it_the_level_one_square_to_the_cameras_x_axes_is_up():   # MODE_SHARE
    """Looking 45 degrees down at a desk top with a wall behind it, both lie 45 degrees from the
    image-up; the cameras turned a little left and right, and only the top is square to every
    image x-axis."""
    def turned(yaw_deg, pitch=45):
        pose = camera(pitch, 0.5)
        y = np.radians(yaw_deg)
        R = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
        pose[:3, :3] = R @ pose[:3, :3]
        return pose

    def scan(wall_from_row):
        wall = ((0, -1.0, 0), -0.9, lambda u, v: v < wall_from_row)       # 0.9 m ahead, the image's top rows
        return [frame(turned(yaw), [FLOOR, wall]) for yaw in (-12, -6, 0, 6, 12)]
    assert estimate_gravity(scan(60)).up == pytest.approx((0, 0, 1), abs=5e-3)
    assert estimate_gravity(scan(20)).up == pytest.approx((0, 0, 1), abs=5e-3)



def test_a_direction_with_under_half_the_densest_ones_normals_is_no_candidate():   # MODE_SHARE
    from types import SimpleNamespace

    prior = np.array([0.0, np.sqrt(0.5), np.sqrt(0.5)])              # 45 degrees from the top and the wall
    turned = np.eye(4)
    turned[:3, 0] = (np.cos(0.2), np.sin(0.2), 0.0)                   # its x-axis is not square to the wall
    frames = [SimpleNamespace(pose=np.eye(4)), SimpleNamespace(pose=turned)]

    def up_of(top: int, wall: int) -> np.ndarray:
        N = np.vstack([np.tile([0.0, 0.0, 1.0], (top, 1)), np.tile([0.0, 1.0, 0.0], (wall, 1))])
        return level_camera_up(prior, N, prior, frames)
    assert up_of(55, 100) == pytest.approx((0, 0, 1))
    assert up_of(45, 100) == pytest.approx((0, 1, 0))


def test_up_is_refined_over_the_normals_within_10_degrees():            # REFINE_CONE_DEG
    def with_ramp(tilt):                # a ramp tilted `tilt` degrees in the image's right 30 columns
        t = np.radians(tilt)
        ramp = ((0, np.sin(t), np.cos(t)), 0.3 * np.cos(t) + 1.5 * np.sin(t), lambda u, v: u >= 130)
        return estimate_gravity([frame(camera(30, 1.5), [FLOOR, ramp])]).n_normals
    assert with_ramp(8) == 412          # the floor's 372 normals and the ramp's 40
    assert with_ramp(12) == 372


def test_normals_are_taken_every_4th_pixel():                          # GRID_STRIDE
    assert len(depth_normals(frame(camera(30, 1.5), [FLOOR]))[1]) == 456   # (40 - 2) x (30 - 2), less the far rows


def test_normals_are_taken_within_5_m():                               # MAX_RANGE_M
    def wall(distance):
        return frame(camera(0, 1.0), [((0, -1, 0), -distance, None)])
    assert len(depth_normals(wall(4.9))[1]) == 1064
    assert len(depth_normals(wall(5.1))[1]) == 0


def test_the_floor_lies_15_cm_below_the_cameras_at_least():           # MIN_FLOOR_DROP
    assert estimate_gravity([frame(camera(20, 0.16), [FLOOR])]).floor_height == pytest.approx(0.0, abs=1e-6)
    assert estimate_gravity([frame(camera(20, 0.14), [FLOOR])]).floor_height is None


def level(span: float) -> np.ndarray:
    """Points of a horizontal level `span` long (x) and 0.6 m deep (y), 1 cm apart."""
    x, y = np.meshgrid(np.linspace(0, span / 0.96, 200), np.linspace(0, 0.6, 60))
    return np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)


def test_a_level_0_9_m_below_the_cameras_is_the_floor_however_small():   # HANDHELD_DROP_M
    up = np.array([0.0, 0.0, 1.0])
    assert floor_not_a_top(level(1.0), up, 0.91, 45.0)
    assert not floor_not_a_top(level(1.0), up, 0.89, 45.0)


def test_a_nearer_level_is_the_floor_when_it_spans_2_m():               # FLOOR_MIN_SPAN_M
    up = np.array([0.0, 0.0, 1.0])
    assert horizontal_span(level(2.05), up) == pytest.approx(2.05, abs=0.02)
    assert floor_not_a_top(level(2.05), up, 0.5, 45.0)
    assert not floor_not_a_top(level(1.95), up, 0.5, 45.0)


def test_a_nearer_level_is_the_floor_when_the_cameras_look_along_it():   # LEVEL_GAZE_DEG
    top = ((0, 0, 1.0), 0.0, lambda u, v: v >= 70)        # a level 0.5 m under the camera, its near part
    assert estimate_gravity([frame(camera(24, 0.5), [top])]).floor_height == pytest.approx(0.0, abs=1e-6)
    assert estimate_gravity([frame(camera(26, 0.5), [top])]).floor_height is None


def test_a_camera_held_half_a_metre_over_a_top_sees_no_floor():
    """A tabletop scan: the top fills the near half of the view, 0.5 m under the camera; a robot's
    camera 0.3 m over the floor sees the floor run on to the walls."""
    top = ((0, 0, 1.0), 0.0, lambda u, v: v >= 70)        # the top's far edge 0.9 m ahead
    assert estimate_gravity([frame(camera(30, 0.5), [top])]).floor_height is None
    assert estimate_gravity([frame(camera(20, 0.3), [FLOOR])]).floor_height == pytest.approx(0.0, abs=1e-6)


def test_a_level_below_the_floor_is_the_floor_when_it_holds_1_percent_of_the_flat_points():   # FLOOR_MIN_SHARE
    def hole(u, v):                     # a gap in the floor showing a level 30 cm lower (a step down)
        return (u >= 20) & (u < 36) & (v >= 40) & (v < 200)
    holed = frame(camera(30, 1.5), [((0, 0, 1.0), 0.0, lambda u, v: ~hole(u, v)), ((0, 0, 1.0), -0.3, hole)],
                  size=(320, 240), f=240.0)
    plain = frame(camera(30, 1.5), [FLOOR], size=(320, 240), f=240.0)
    # 56 of the about 3130 flat points of a frame see the lower level
    assert estimate_gravity([holed] * 5 + [plain] * 7).floor_height == pytest.approx(0.0, abs=1e-6)    # 0.75 %
    assert estimate_gravity([holed] * 8 + [plain] * 4).floor_height == pytest.approx(-0.3, abs=1e-6)   # 1.2 %


def test_the_floor_is_the_densest_level_within_5_bins_of_2_cm_above_the_lowest():   # FLOOR_BIN_M
    def levels(dz):                     # the floor in the left 60 columns, a larger level dz above it
        return frame(camera(30, 1.5), [((0, 0, 1.0), 0.0, lambda u, v: u < 60), ((0, 0, 1.0), dz, lambda u, v: u >= 60)])
    assert estimate_gravity([levels(0.07)]).floor_height == pytest.approx(0.07, abs=1e-3)
    assert estimate_gravity([levels(0.12)]).floor_height == pytest.approx(0.0, abs=1e-3)
