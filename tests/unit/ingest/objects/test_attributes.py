"""Per-object attributes on synthetic frames with known answers (gravity on the real kitchen:
tests/quality/kitchen/test_kitchen_ingest.py)."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from sg3d.core.model import COLOUR_NAMES, HIST_SIZE
from sg3d.ingest.objects.attributes import (
    dominant_colour,
    hsv_histogram,
    measure_object,
    object_size,
    position_gaussian,
    thumbnail,
    world_points,
)
from sg3d.ingest.readers import quaternion_to_matrix
from sg3d.ingest.readers.frames import Frame, FrameInfo

W, H = 160, 120
K = np.array([[100.0, 0, 80.0], [0, 100.0, 60.0], [0, 0, 1]])
BOX = (40, 20, 90, 70)        # the object fills it exactly
OBJECT_DEPTH, WALL_DEPTH = 1.5, 3.0


def _pose() -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = quaternion_to_matrix(np.array([0.2, 0.1, -0.3, 0.9]))
    T[:3, 3] = (0.4, -1.2, 2.0)
    return T


def _scene(depth_hook=None) -> Frame:
    depth = np.full((H, W), WALL_DEPTH, np.float32)
    x1, y1, x2, y2 = BOX
    depth[y1:y2, x1:x2] = OBJECT_DEPTH
    if depth_hook:
        depth_hook(depth)
    color = np.full((H, W, 3), 200, np.uint8)
    color[y1:y2, x1:x2] = (0, 0, 255)
    return Frame(0, color, depth, K, _pose(), FrameInfo(0.0, "synthetic"))


def _true_centre() -> np.ndarray:
    # the centre cell [60, 70) x [40, 50) is symmetric about pixel (64.5, 44.5)
    return world_points(np.array([64.5]), np.array([44.5]), np.array([OBJECT_DEPTH]), K, _pose())[0]


def test_position_recovers_the_3d_centre_with_a_posed_camera():
    pos = position_gaussian(_scene(), BOX)
    assert pos.region == "centre cell" and pos.n_points == 100
    np.testing.assert_allclose(pos.mean, _true_centre(), atol=1e-9)
    # a flat patch 10 px = 0.15 m wide: per-axis variance well under (0.15 m)^2
    assert max(pos.var) < 0.15 ** 2 and min(pos.var) >= 0
    assert pos.median_depth == pytest.approx(OBJECT_DEPTH)


def test_position_ignores_background_seen_through_the_centre():
    def hole(depth):
        depth[42:46, 61:66] = WALL_DEPTH  # 20 of 100 centre pixels see the wall behind
    pos = position_gaussian(_scene(hole), BOX)
    assert pos.n_points == 80
    assert np.linalg.norm(np.asarray(pos.mean) - _true_centre()) < 0.02


def test_position_falls_back_to_centre_3x3_then_none():
    def sparse(depth):
        depth[40:50, 60:70] = 0          # centre cell without depth
    pos = position_gaussian(_scene(sparse), BOX)
    assert pos.region == "centre 3x3" and pos.n_points == 30 * 30 - 100
    np.testing.assert_allclose(pos.mean, _true_centre(), atol=0.02)

    def blind(depth):
        depth[:] = 0
    assert position_gaussian(_scene(blind), BOX) is None
    assert measure_object(_scene(blind), BOX) is None


def test_size_keeps_the_object_not_the_wall_around_it():
    wide_box = (30, 10, 100, 80)  # 10 px of wall on every side
    up = -_pose()[:3, 1]          # the camera's image up
    w, d, h = object_size(_scene(), wide_box, up)
    true_w = (BOX[2] - BOX[0]) * OBJECT_DEPTH / K[0, 0]
    true_h = (BOX[3] - BOX[1]) * OBJECT_DEPTH / K[1, 1]
    # percentiles 5-95 keep 90 % of a uniform extent
    assert h == pytest.approx(0.9 * true_h, rel=0.05)
    assert np.hypot(w, d) == pytest.approx(0.9 * true_w, rel=0.1)


def test_histogram_sums_to_pixel_count_and_bins_hsv():
    rng = np.random.default_rng(0)
    img = rng.integers(0, 256, size=(H, W, 3), dtype=np.uint8)
    hist = hsv_histogram(img, BOX)
    assert hist.shape == (HIST_SIZE,)
    assert hist.sum() == (BOX[2] - BOX[0]) * (BOX[3] - BOX[1])
    red = np.zeros((10, 10, 3), np.uint8)
    red[:] = (0, 0, 255)             # HSV (0, 255, 255): bins (0, 7, 7)
    h = hsv_histogram(red)
    assert h[(0 * 8 + 7) * 8 + 7] == 100 and h.sum() == 100


@pytest.mark.parametrize("bgr,name", [
    ((0, 0, 220), "red"), ((255, 255, 255), "white"), ((10, 10, 10), "black"), ((128, 128, 128), "grey"),
    ((200, 60, 20), "blue"), ((40, 180, 40), "green"), ((0, 220, 240), "yellow"), ((0, 130, 255), "orange"),
    ((60, 100, 150), "brown"), ((180, 40, 130), "purple"), ((200, 170, 255), "pink"),
])
def test_dominant_colour_names(bgr, name):
    assert name in COLOUR_NAMES
    img = np.zeros((100, 100, 3), np.uint8)
    img[:] = (255, 255, 255) if name != "white" else (0, 0, 0)
    img[20:80, 20:80] = bgr          # the margin is background of another colour
    assert dominant_colour(img, (10, 10, 90, 90)) == name


def test_thumbnail_is_a_small_jpeg_of_the_box():
    img = np.zeros((400, 600, 3), np.uint8)
    img[100:300, 50:450] = (0, 255, 0)
    data = thumbnail(img, (50, 100, 450, 300))
    assert data[:2] == b"\xff\xd8"
    back = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    assert back.shape == (64, 128, 3)
    assert back[32, 64, 1] > 200 and back[32, 64, 2] < 60


def test_measure_object_bundles_everything():
    """The 50 x 50 px red patch at 1.5 m (0.75 m square, facing the camera) measured in full:
    every field against the scene as made."""
    a = measure_object(_scene(), BOX)       # up: the camera's image up
    np.testing.assert_allclose(a.mean, _true_centre(), atol=1e-9)
    assert a.n_points == 100 and max(a.var) < 0.15 ** 2
    side = (BOX[2] - BOX[0]) * OBJECT_DEPTH / K[0, 0]
    w, d, h = a.size
    # percentiles 5-95 keep 90 % of each extent; the patch is flat along the viewing direction,
    # which is horizontal, so its horizontal extent is shared between width and depth
    assert h == pytest.approx(0.9 * side, rel=0.05)
    assert np.hypot(w, d) == pytest.approx(0.9 * side, rel=0.1)
    np.testing.assert_allclose(a.centre, _true_centre(), atol=0.02)   # the patch is symmetric about it
    assert a.colour == "red"
    assert a.hist.sum() == 50 * 50 and a.hist[(0 * 8 + 7) * 8 + 7] == 50 * 50   # HSV (0, 255, 255)
    thumb = cv2.imdecode(np.frombuffer(a.thumbnail, np.uint8), cv2.IMREAD_COLOR)
    assert thumb.shape[:2] == (50, 50)
    assert thumb[..., 2].min() > 200 and thumb[..., :2].max() < 60     # the red box, nothing around it


# --------------------------------------------------------------------------- each threshold, on both sides

def test_the_centre_cell_is_used_from_10_depths_on():                 # MIN_CENTRE_POINTS
    def centre_cell_with(n):
        def hook(depth):
            cell = depth[40:50, 60:70].reshape(-1)
            cell[n:] = 0
            depth[40:50, 60:70] = cell.reshape(10, 10)
        return position_gaussian(_scene(hook), BOX).region
    assert centre_cell_with(10) == "centre cell"
    assert centre_cell_with(9) == "centre 3x3"


def test_the_extent_is_read_between_the_5th_and_95th_percentile():     # BOX_LOW/HIGH_PERCENTILE
    # the patch's 50 rows, 1.5 cm apart: rows 2 to 47 of them
    h = object_size(_scene(), BOX, -_pose()[:3, 1])[2]
    assert h == pytest.approx(45 * 0.015, abs=0.004)


def _step_mask(near: float, step: float) -> np.ndarray:
    """The object mask of a 50 x 20 box whose right 10 columns lie `step` behind the rest."""
    from sg3d.ingest.objects.attributes import object_mask

    depth = np.full((20, 50), near, np.float32)
    depth[:, 40:] = near + step
    return object_mask(depth, (0, 0, 50, 20))


def test_a_depth_step_under_4_cm_keeps_one_surface_at_1_m():           # DEPTH_JUMP_M
    assert _step_mask(1.0, 0.035).all()
    assert not _step_mask(1.0, 0.045)[:, 42:].any()


def test_a_depth_step_under_3_percent_keeps_one_surface_at_2_m():       # DEPTH_JUMP_REL
    assert _step_mask(2.0, 0.055).all()
    assert not _step_mask(2.0, 0.065)[:, 42:].any()


def test_a_box_is_sampled_on_about_6400_pixels():                      # MAX_BOX_SAMPLES
    from sg3d.ingest.objects.attributes import sample_stride

    assert sample_stride((0, 0, 80, 80)) == 1
    assert sample_stride((0, 0, 81, 80)) == 2


def test_a_boxs_colour_is_read_inside_a_margin_of_a_fifth():            # INNER_MARGIN
    img = np.zeros((100, 100, 3), np.uint8)
    img[:] = (0, 160, 0)                   # green out to 10 % of the box
    img[20:80, 20:80] = (200, 60, 20)      # blue from 20 %
    img[30:70, 30:70] = (0, 0, 220)        # a red core
    assert dominant_colour(img, (0, 0, 100, 100)) == "blue"


def _patchy_frame(valid_cols: int) -> tuple[Frame, tuple[int, int, int, int]]:
    """A 100 px box (sampled every 2 px: its inner region is 30 x 30 samples) with depth in the
    inner region's left `valid_cols` pixel columns only."""
    depth = np.zeros((100, 100), np.float32)
    depth[20:80, 20:20 + valid_cols] = 1.0
    color = np.full((100, 100, 3), 120, np.uint8)
    K = np.array([[100.0, 0, 50], [0, 100.0, 50], [0, 0, 1]])
    return Frame(0, color, depth, K, np.eye(4), FrameInfo(0.0, "synthetic")), (0, 0, 100, 100)


def test_a_colour_is_read_on_the_surface_depth_shows_when_it_covers_a_quarter_of_the_box():   # MIN_MASK_SHARE
    from sg3d.ingest.objects.attributes import colour_pixels

    frame, bounds = _patchy_frame(24)       # 280 of the 900 inner samples (31 %): those
    assert len(colour_pixels(frame, bounds)[0]) == 280
    frame, bounds = _patchy_frame(18)       # about a fifth: the whole inner region
    assert len(colour_pixels(frame, bounds)[0]) == 900


def test_an_objects_own_depths_lie_within_5_cm_of_its_centres_at_least():   # MIN_DEPTH_BAND
    from sg3d.ingest.objects.attributes import within_object_depth

    K = np.array([[500.0, 0, 5], [0, 500.0, 5], [0, 0, 1]])
    crop = np.ones((10, 10), np.float32)   # a 10 px box 1 m away: 1 cm wide, the band is its floor
    crop[0, 0], crop[0, 9] = 1.045, 1.055
    inside = within_object_depth(crop, (0, 0, 10, 10), K)
    assert inside[0, 0] and not inside[0, 9]


# --------------------------------------------------------------------------- a box measured off the floor

def _floor_scene() -> Frame:
    """A camera 1 m above a floor (world z up, looking along +y, tilted down 45 degrees) over a
    floor that runs across the whole image, and a 0.6 m wide, 0.6 m tall panel standing on it
    1 m ahead, in the middle of the image."""
    c, s = np.cos(np.radians(45)), np.sin(np.radians(45))
    # camera axes in world: x right = +x, y down = (0, -s... ), z forward = (0, c, -s)
    R = np.array([[1.0, 0, 0], [0, -s, c], [0, -c, -s]])
    pose = np.eye(4)
    pose[:3, :3] = R
    pose[:3, 3] = (0.0, 0.0, 1.0)
    v, u = np.mgrid[0:H, 0:W].astype(np.float64)
    rays = np.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], np.ones_like(u)], axis=-1) @ R.T
    depth = (-1.0 / rays[..., 2]).astype(np.float32)          # where each ray meets z = 0
    depth[depth < 0] = 0
    # the panel: |x| <= 0.3, 0 <= z <= 0.6 on the plane y = 1
    panel_depth = np.full((H, W), 0.0, np.float32)
    t = 1.0 / rays[..., 1]                                      # ray meets the plane y = 1
    hit = t * rays[..., 2] + 1.0
    on = (np.abs(t * rays[..., 0]) <= 0.3) & (hit >= 0.0) & (hit <= 0.6) & (t > 0)
    panel_depth[on] = (t * (rays @ R)[..., 2])[on]
    depth = np.where(on, panel_depth, depth)
    return Frame(index=0, color=np.full((H, W, 3), 128, np.uint8), depth=depth, pose=pose, K=K)


def test_floor_pixels_are_those_within_5_cm_of_the_floor():           # FLOOR_BAND_M
    from sg3d.core.geometry import Ground
    from sg3d.ingest.objects.attributes import floor_pixels

    frame = _floor_scene()
    crop = frame.depth
    up = (0.0, 0.0, 1.0)
    assert floor_pixels(crop, (0, 0, W, H), 1, frame, Ground(up, -0.04)).any()       # the floor 4 cm under
    assert not floor_pixels(crop, (0, 0, W, H), 1, frame, Ground(up, -0.06))[crop > 0].any()


def test_a_box_standing_on_the_floor_is_measured_without_the_floor():
    from sg3d.ingest.objects.attributes import object_box

    frame = _floor_scene()
    box = (45, 0, 115, 100)           # the panel and the floor around and in front of it
    with_floor = object_box(frame, box, (0.0, 0.0, 1.0))
    off_floor = object_box(frame, box, (0.0, 0.0, 1.0), floor=0.0)
    assert with_floor is not None and off_floor is not None
    assert with_floor[1][1] > 0.3                       # the floor before the panel deepens it
    assert off_floor[1][0] == pytest.approx(0.6 * 0.9, abs=0.04)   # 5th-95th percentile of 0.6 m
    assert off_floor[1][1] < 0.05                       # a panel is thin once the floor is left out


def test_a_thing_lying_flat_on_the_floor_keeps_its_floor_level():      # MIN_OFF_FLOOR_SHARE
    from sg3d.ingest.objects import attributes

    frame = _floor_scene()
    box = (0, 100, W, H)              # floor only
    whole = attributes.object_box(frame, box, (0.0, 0.0, 1.0))
    assert attributes.object_box(frame, box, (0.0, 0.0, 1.0), floor=0.0) == whole
