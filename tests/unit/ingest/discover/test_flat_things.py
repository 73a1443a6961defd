"""Flat things on a top, per view (`sg3d.ingest.discover.flat_things`): each rule and threshold on
both sides, and the whole chain on views rendered here of a top with things lying on it."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.discover import flat_things as ft
from sg3d.ingest.discover.room_cloud import room_cloud
from sg3d.ingest.discover.structure import Element
from sg3d.ingest.objects.existence import View

TOP_H = 0.75
GREY = (128, 128, 128)
K = np.array([[262.5, 0.0, 159.5], [0.0, 262.5, 119.5], [0.0, 0.0, 1.0]])


def _top(lo=(0.0, 0.0), hi=(1.2, 0.6)) -> Element:
    """A 1.2 x 0.6 m top at TOP_H (footprint cells of 5 cm)."""
    cells = (int(round((hi[0] - lo[0]) / 0.05)), int(round((hi[1] - lo[1]) / 0.05)))
    return Element("surface", np.array([*lo, TOP_H - 0.03]), np.array([*hi, TOP_H]), 1000, 10, TOP_H,
                   np.ones(cells, bool), np.array(lo, float))


def _view(index: int, centre, things, offset: float = 0.0, seed: int = 0) -> tuple[View, np.ndarray]:
    """A camera 0.55 m above the top at `centre` (a, b) looking straight down, the top grey and
    each thing (lo (a, b), hi (a, b), height, BGR) a box lying on it; depth with the sensor's noise
    (`depth_noise`), the pose moved up by `offset` (one view's pose error: the fused top spreads
    by it). Returns the view (small depth, 1/4 resolution) and its colour image."""
    w, h = 320, 240
    cam_h = TOP_H + 0.55
    v, u = np.mgrid[0:h, 0:w]
    rx, ry = (u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1]
    # camera x along a, camera y along -b, looking down -h
    a = centre[0] + rx * 0.55
    b = centre[1] - ry * 0.55
    surface_h = np.full((h, w), TOP_H)
    image = np.empty((h, w, 3), np.uint8)
    image[:] = GREY
    for lo, hi, height, bgr in things:
        on = (a >= lo[0]) & (a <= hi[0]) & (b >= lo[1]) & (b <= hi[1])
        surface_h[on] = TOP_H + height
        image[on] = bgr
    z = cam_h - surface_h
    z = z + np.random.default_rng(seed).normal(0.0, 1.0, z.shape) * ft.depth_noise(z)
    pose = np.eye(4)
    pose[:3, :3] = np.diag([1.0, -1.0, -1.0])
    pose[:3, 3] = [centre[0], centre[1], cam_h + offset]
    small = z[2::4, 2::4].astype(np.float32)
    return View(index, K, pose, (w, h), small), image


def _things_found(things, centres, offsets=None, taken=()):
    offsets = offsets if offsets is not None else [0.0] * len(centres)
    rendered = [_view(k, c, things, off, seed=k) for k, (c, off) in enumerate(zip(centres, offsets))]
    views = [v for v, _ in rendered]
    cloud = room_cloud(views, (0.0, 0.0, 1.0), 0.0)
    return ft.things_on_top(_top(), cloud, lambda k: ft.small_lab(rendered[k][1], views[k].depth.shape), list(taken))


CENTRES = [(0.45, 0.3), (0.55, 0.3), (0.65, 0.3), (0.5, 0.25), (0.6, 0.35), (0.55, 0.28)]
KEYBOARD = ((0.35, 0.2), (0.80, 0.34))


def test_a_keyboard_the_tops_colour_two_cm_high_is_found_though_the_fused_top_spreads():
    """Depth alone (grey on grey): each view's own plane shows the 2 cm rise, though the views'
    poses disagree by +-1 cm in height (the fused top spreads so: its slab takes the keyboard)."""
    found = _things_found([(*KEYBOARD, 0.02, GREY)], CENTRES, offsets=[0.01, -0.01, 0.0, 0.008, -0.008, 0.004])
    assert len(found) == 1
    size = found[0].size
    assert size[0] == pytest.approx(0.45, abs=0.03) and size[1] == pytest.approx(0.14, abs=0.03)
    assert size[2] == pytest.approx(0.02, abs=0.004)
    assert found[0].lo[2] == pytest.approx(TOP_H, abs=0.015)


def test_a_bump_of_a_few_millimetres_the_tops_colour_is_the_top():
    assert _things_found([(*KEYBOARD, 0.004, GREY)], CENTRES) == []


def test_a_sheet_of_another_colour_is_found_by_colour_alone():
    paper = ((0.5, 0.2), (0.71, 0.5))
    found = _things_found([(*paper, 0.001, (40, 40, 220))], CENTRES)
    assert len(found) == 1 and found[0].size[0] == pytest.approx(0.21, abs=0.03)


def test_a_thing_two_views_saw_is_not_enough_and_three_are():
    thing = [(*KEYBOARD, 0.02, (40, 40, 220))]
    assert _things_found(thing, CENTRES[:ft.MIN_LYING_VIEWS - 1]) == []
    assert len(_things_found(thing, CENTRES[:ft.MIN_LYING_VIEWS])) == 1


def test_a_thing_already_found_is_not_found_again():
    box = (np.array([0.34, 0.19, TOP_H]), np.array([0.81, 0.35, TOP_H + 0.02]))
    assert _things_found([(*KEYBOARD, 0.02, GREY)], CENTRES, taken=[box]) == []


# --------------------------------------------------------------------------- each threshold, on both sides

def test_rise_threshold_is_the_sensors_noise_at_range():
    # at desk range a centimetre stands out; at 2.5 m the noise (~1 cm) swallows it
    assert ft.rise_threshold(np.array(0.6)) == pytest.approx(ft.RISE_MIN_M)
    assert 0.01 >= ft.rise_threshold(np.array(0.6))
    assert 0.01 < ft.rise_threshold(np.array(2.5))
    assert ft.depth_noise(np.array(0.4)) == pytest.approx(ft.NOISE_A_M)


def test_colour_contrast_sees_paper_on_a_black_desk_not_the_desks_shading():
    black = np.array([5.0, 0.0, 0.0])
    assert ft.colour_distance(np.array([60.0, 0.0, 0.0]), black) >= ft.CONTRAST_DELTA_E     # grey paper
    assert ft.colour_distance(np.array([45.0, 60.0, 45.0]), black) >= ft.CONTRAST_DELTA_E   # a red keyboard
    assert ft.colour_distance(np.array([30.0, 2.0, -2.0]), black) < ft.CONTRAST_DELTA_E     # the desk, lit
    assert ft.colour_distance(np.array([5.0, 14.0, 10.0]), black) < ft.CONTRAST_DELTA_E     # a brownish cast


def _plane_points(n=2000, tilt=(0.0, 0.0), raised_share=0.0, seed=0):
    rng = np.random.default_rng(seed)
    ab = rng.uniform(0, 1, (n, 2))
    h = 0.75 + ab @ np.array(tilt)
    h[: int(raised_share * n)] += 0.02
    return np.c_[ab, h + rng.normal(0, 0.001, n)], np.full(n, 0.6)


def test_the_views_plane_is_the_lower_one_under_what_lies_on_it():
    pts, z = _plane_points(raised_share=0.4)
    coef, keep = ft.view_plane(pts, z, np.zeros(2))
    assert coef[2] == pytest.approx(0.75, abs=0.003)
    assert not keep[: int(0.4 * len(pts))].any() and keep[int(0.4 * len(pts)):].mean() > 0.9


def test_the_views_plane_tilts_with_the_fused_top_within_max_tilt():
    slope = np.tan(np.radians(ft.MAX_TILT_DEG))
    pts, z = _plane_points(tilt=(0.8 * slope, 0.0))
    assert ft.view_plane(pts, z, np.zeros(2)) is not None
    pts, z = _plane_points(tilt=(1.5 * slope, 0.0))
    assert ft.view_plane(pts, z, np.zeros(2)) is None
    assert ft.view_plane(pts, z, np.array([1.5 * slope, 0.0])) is not None


def test_faces_up_on_a_level_grid_not_on_a_wall():
    a, b = np.meshgrid(np.arange(10) * 0.01, np.arange(8) * 0.01)
    level = np.stack([a, b, np.full_like(a, 0.75)], axis=-1)
    wall = np.stack([a, np.zeros_like(a), 0.75 + b], axis=-1)
    assert ft.faces_up(level)[1:-1, 1:-1].all() and not ft.faces_up(level)[0].any()
    assert not ft.faces_up(wall)[1:-1, 1:-1].any()


def _cells(lying, seen, tall=None):
    shape = np.shape(lying)
    return ft.TopCells(np.zeros(2), np.asarray(seen), np.asarray(lying),
                       np.zeros(shape, int) if tall is None else np.asarray(tall), np.zeros((0, 5)), {})


def test_a_cell_lies_when_enough_views_and_their_share_say_so():
    block = np.zeros((12, 12), int)
    block[3:9, 3:9] = 1
    n = ft.MIN_LYING_VIEWS
    assert ft.lying_cells(_cells(block * n, block * n)).sum() == 36
    assert ft.lying_cells(_cells(block * (n - 1), block * (n - 1))).sum() == 0
    seen = int(np.ceil(n / ft.LYING_SHARE))
    assert ft.lying_cells(_cells(block * n, block * seen)).sum() == 36
    assert ft.lying_cells(_cells(block * n, block * (seen * 2 + 1))).sum() == 0


def test_what_lies_at_a_taller_things_foot_is_its_foot():
    lying = np.zeros((30, 12), int)
    lying[2:28, 3:9] = 5
    tall = np.zeros_like(lying)
    tall[0:2, 3:9] = 5          # a cup at one end
    near = ft.lying_cells(_cells(lying, lying, tall))
    reach = int(np.ceil(ft.TALL_CLEARANCE_M / ft.FLAT_CELL_M))
    assert not near[: 2 + reach].any() and near[2 + reach + 1:27, 3:9].all()


def test_flat_size_bounds():
    assert ft.flat_size(0.075, 0.15)                                   # a phone
    assert not ft.flat_size(ft.MIN_FLAT_SIDE_M - 0.01, 0.15)           # a pen
    assert ft.flat_size(ft.MAX_FLAT_SIDE_M, 0.3)
    assert not ft.flat_size(ft.MAX_FLAT_SIDE_M + 0.05, 0.3)            # a top's strip, not a thing
    assert not ft.flat_size(0.06, 0.06)                                 # under MIN_FLAT_AREA_M2


def test_a_far_views_pixel_covers_several_cells():
    idx = np.array([5 * 10 + 5])
    assert ft.splat(idx, (10, 10), ft.FLAT_CELL_M).sum() == 1
    assert ft.splat(idx, (10, 10), 1.7 * ft.FLAT_CELL_M).sum() == 9
    assert ft.splat(idx, (10, 10), 3 * ft.FLAT_CELL_M).sum() == 9


def test_a_region_inside_a_taken_box_is_taken():
    member = np.argwhere(np.ones((10, 4), bool))
    box = (np.array([0.0, 0.0, 0.75]), np.array([0.15, 0.06, 0.8]))
    assert ft.already_taken(member, np.zeros(2), [box])
    half = int(10 * ft.TAKEN_SHARE) - 2
    small = (np.array([0.0, 0.0, 0.75]), np.array([half * ft.FLAT_CELL_M - ft.FLAT_CELL_M, 0.06, 0.8]))
    assert not ft.already_taken(member, np.zeros(2), [small])


def test_a_thing_stands_on_the_top_and_the_tops_own_table_does_not():
    top = _top()
    cup = (np.array([0.1, 0.1, TOP_H]), np.array([0.18, 0.18, TOP_H + 0.1]))
    assert ft.stands_on(*cup, top)
    assert not ft.stands_on(cup[0], np.array([0.18, 0.18, TOP_H + ft.RISE_MIN_M / 2]), top)    # no higher than the top
    assert not ft.stands_on(np.array([0.1, 0.1, 0.0]), cup[1], top)                         # a chair from the floor
    table = (np.array([0.0, 0.0, TOP_H - 0.03]), np.array([1.2, 0.6, TOP_H + 0.02]))
    assert not ft.stands_on(*table, top)
    half = (np.array([0.0, 0.0, TOP_H]), np.array([1.2 * ft.TOP_SHARE * 0.9, 0.6, TOP_H + 0.05]))
    assert ft.stands_on(*half, top)
