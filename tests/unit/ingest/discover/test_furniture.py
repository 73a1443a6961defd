"""Furniture named from its shape (sg3d.ingest.discover.furniture): each rule on both sides of its
thresholds, on small synthetic clouds and surfaces."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import ObjectObservation
from sg3d.ingest.discover import furniture
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import SURFACE_CELL_M, Element

CELL = SURFACE_CELL_M


def top(a0: float, a1: float, b0: float, b1: float, height: float) -> Element:
    """A horizontal surface whose footprint fills the rectangle [a0, a1] x [b0, b1] at `height`."""
    origin = np.array([a0, b0])
    shape = (int(round((a1 - a0) / CELL)), int(round((b1 - b0) / CELL)))
    fp = np.ones(shape, bool)
    return Element("surface", np.array([a0, b0, height - 0.03]), np.array([a1, b1, height]), 1000, 10,
                   height, fp, origin)


def grid(a0, a1, b0, b1, h0, h1, step=0.02) -> np.ndarray:
    a, b, h = np.meshgrid(np.arange(a0, a1, step), np.arange(b0, b1, step), np.arange(h0, h1 + 1e-9, step),
                          indexing="ij")
    return np.stack([a.ravel(), b.ravel(), h.ravel()], axis=1)


def cloud_of(*parts: np.ndarray) -> RoomCloud:
    pts = np.concatenate(parts) if parts else np.zeros((0, 3))
    return RoomCloud(pts, np.zeros_like(pts), np.zeros(len(pts), int), np.eye(3), 0.0, [])


def obj(label: str, labels=None) -> ObjectObservation:
    labels = labels or [label]
    return ObjectObservation("o", labels, [0.9] * len(labels), (0, 0, 0), (0.01, 0.01, 0.01), 10,
                             (0.5, 0.5, 0.5), np.ones(512))


@pytest.mark.parametrize("height,ok", [(0.58, False), (0.62, True), (0.72, True), (0.78, True), (0.82, False)])
def test_desk_top_height(height, ok):
    assert furniture.desk_shaped(height, 0.5, 0.9) is ok


@pytest.mark.parametrize("area,ok", [(0.12, False), (0.18, True)])
def test_desk_top_area(area, ok):
    assert furniture.desk_shaped(0.72, area, 0.9) is ok


@pytest.mark.parametrize("floor_share,ok", [(0.45, False), (0.55, True)])
def test_desk_needs_knee_space(floor_share, ok):
    assert furniture.desk_shaped(0.72, 0.5, floor_share) is ok


@pytest.mark.parametrize("height,floor_share,ok", [(0.49, 0.22, True), (0.49, 0.30, True), (0.49, 0.40, False),
                                                   (0.56, 0.10, True), (0.64, 0.10, False)])
def test_cabinet_is_a_low_top_that_hides_the_floor(height, floor_share, ok):
    assert furniture.cabinet_shaped(height, floor_share) is ok


def test_floor_seen_under_counts_footprint_cells_with_floor_below():
    desk = top(0.0, 1.0, 0.0, 0.5, 0.72)
    half_floor = grid(0.0, 0.5, 0.0, 0.5, 0.0, 0.0)          # the floor seen under the left half only
    elsewhere = grid(2.0, 3.0, 0.0, 0.5, 0.0, 0.0)           # floor away from the desk does not count
    share = furniture.floor_seen_under(desk, cloud_of(half_floor, elsewhere))
    assert share == pytest.approx(0.5, abs=0.06)
    assert furniture.floor_seen_under(desk, cloud_of(grid(0.0, 1.0, 0.0, 0.5, 0.3, 0.3))) == 0.0


@pytest.mark.parametrize("inside,ok", [(0.7, True), (0.55, True), (0.4, False)])
def test_a_level_mostly_inside_a_chair_box_is_its_seat(inside, ok):
    seat = top(0.0, 0.4, 0.0, 0.4, 0.42)
    box = (np.array([0.4 - inside * 0.4, -0.1, 0.0]), np.array([1.0, 0.5, 0.85]))   # covers `inside` of the seat
    assert furniture.part_of_furniture(seat, [box]) is ok


def test_a_level_above_the_box_is_not_its_seat():
    seat = top(0.0, 0.4, 0.0, 0.4, 0.95)
    box = (np.array([-0.1, -0.1, 0.0]), np.array([0.5, 0.5, 0.85]))
    assert not furniture.part_of_furniture(seat, [box])
    assert furniture.part_of_furniture(top(0.0, 0.4, 0.0, 0.4, 0.88), [box])    # within the 5 cm slack


def panel(a: float, height: float) -> np.ndarray:
    """A thin vertical panel across a 0.7 m deep top at `a`, from 0.1 m over the floor to 0.7 m above the top."""
    return grid(a, a + 0.03, 0.0, 0.7, 0.12, height + 0.7)


def test_a_worktop_is_cut_at_the_panel_that_crosses_it():
    row = top(0.0, 2.0, 0.0, 0.7, 0.70)
    parts = furniture.split_at_panels(row, cloud_of(panel(1.0, 0.70)))
    assert len(parts) == 2
    assert parts[0].lo[0] == pytest.approx(0.0) and parts[0].hi[0] == pytest.approx(1.0, abs=CELL)
    assert parts[1].hi[0] == pytest.approx(2.0)


def test_no_panel_or_one_above_the_top_only_keeps_the_worktop_whole():
    row = top(0.0, 2.0, 0.0, 0.7, 0.70)
    assert len(furniture.split_at_panels(row, cloud_of())) == 1
    screen = grid(1.0, 1.03, 0.0, 0.7, 0.75, 1.3)          # a monitor on the desk: above the top only
    assert len(furniture.split_at_panels(row, cloud_of(screen))) == 1


@pytest.mark.parametrize("at,cuts", [(0.35, 0), (0.6, 1)])
def test_a_panel_near_the_end_leaves_no_desk_narrower_than_half_a_metre(at, cuts):
    row = top(0.0, 2.0, 0.0, 0.7, 0.70)
    assert len(furniture.panel_cuts(row, cloud_of(panel(at, 0.70)))) == cuts


@pytest.mark.parametrize("depth,cuts", [(0.05, 0), (0.2, 1)])
def test_a_post_is_no_panel(depth, cuts):
    """A chair's back or a post fills a few cells of the slice; a panel fills a fair share of it."""
    row = top(0.0, 2.0, 0.0, 0.7, 0.70)
    post = grid(1.0, 1.03, 0.0, depth, 0.12, 1.4)
    assert len(furniture.panel_cuts(row, cloud_of(post))) == cuts


def test_a_table_named_by_the_detector_is_renamed_by_its_shape_and_keeps_the_detector_label():
    renamed = furniture.renamed_by_shape(obj("dining table", ["dining table", "bench"]), furniture.CABINET_LABEL)
    assert renamed.labels == ["cabinet", "dining table", "bench"]
    assert len(renamed.scores) == 3 and renamed.named_by == "shape"


def test_a_low_solid_top_makes_a_table_a_cabinet_but_not_a_chair():
    low = top(0.0, 1.0, 0.0, 0.5, 0.49)
    solid = cloud_of()                                          # no floor seen under it
    assert furniture.low_solid_top(obj("dining table"), low, solid)
    assert not furniture.low_solid_top(obj("chair"), low, solid)
    assert not furniture.low_solid_top(obj("dining table"), top(0.0, 1.0, 0.0, 0.5, 0.72), solid)
    open_below = cloud_of(grid(0.0, 1.0, 0.0, 0.5, 0.0, 0.0))
    assert not furniture.low_solid_top(obj("dining table"), low, open_below)


# --- couch: a seat level with a back or an arm longer than any chair's -----------------------

def slab(a0, a1, b0, b1, h0, h1, step=0.025) -> np.ndarray:
    """Voxel centres filling a box (gravity frame)."""
    return grid(a0, a1, b0, b1, h0, h1, step)


@pytest.mark.parametrize("height,ok", [(0.33, False), (0.37, True), (0.48, True), (0.52, False)])
def test_couch_seat_height(height, ok):
    assert furniture.couch_shaped(height, [1.0]) is ok


@pytest.mark.parametrize("length,ok", [(0.6, False), (0.75, False), (0.85, True), (1.4, True)])
def test_couch_back_or_arm_longer_than_a_chairs(length, ok):
    assert furniture.couch_shaped(0.42, [0.4, length]) is ok


def test_back_or_arm_rises_from_the_seat_and_stays_below_a_cabinets_top():
    arm = slab(0.0, 0.1, 0.0, 0.95, 0.20, 0.78)                # an arm 0.95 m deep, up to 0.8 m
    assert furniture.back_or_arm_length(arm, 0.42) == pytest.approx(0.925, abs=0.03)
    floating = slab(0.0, 0.1, 0.0, 0.95, 0.60, 0.70)           # a table's edge above the level
    assert furniture.back_or_arm_length(floating, 0.42) == 0.0
    assert furniture.back_or_arm_length(slab(0.0, 0.1, 0.0, 0.95, 0.20, 0.95), 0.42) > 0.8   # top 0.95 m
    assert furniture.back_or_arm_length(slab(0.0, 0.1, 0.0, 0.95, 0.20, 1.05), 0.42) == 0.0  # top 1.05 m
    low = slab(0.0, 0.1, 0.0, 0.95, 0.20, 0.55)                # not COUCH_RISE_M above the seat
    assert furniture.back_or_arm_length(low, 0.42) == 0.0


@pytest.mark.parametrize("gap,joined", [(0.0, True), (0.3, True), (0.4, False)])
def test_couch_parts_lie_within_a_cushions_depth_of_the_seat(gap, joined):
    seat = top(0.0, 0.5, 0.0, 0.5, 0.42)
    arm = (np.array([-0.15 - gap, 0.0, 0.2]), np.array([-gap, 0.9, 0.8]))
    cabinet = (np.array([0.5, 0.0, 0.0]), np.array([1.0, 0.5, 1.3]))   # beside it but taller
    assert (furniture.couch_parts(seat, [arm, cabinet]) == [0]) is joined


def test_couch_box_spans_seat_and_parts_from_the_floor():
    seat = top(0.0, 0.5, 0.0, 0.5, 0.42)
    lo, hi = furniture.couch_box(seat, [(np.array([-0.2, -0.1, 0.2]), np.array([-0.05, 0.9, 0.8]))])
    assert np.allclose(lo, [-0.2, -0.1, 0.0]) and np.allclose(hi, [0.5, 0.9, 0.8])


# --- a seat's base; a carrel's panel -------------------------------------------------------------

@pytest.mark.parametrize("base_top,ok", [(0.10, True), (0.15, True), (0.18, False)])
def test_a_low_piece_under_a_seat_is_its_base(base_top, ok):
    seat = (np.array([0.0, 0.0, 0.32]), np.array([0.5, 0.5, 0.92]))
    base = (np.array([-0.2, -0.2, 0.04]), np.array([0.7, 0.7, base_top]))
    assert furniture.base_under_seat(*base, [seat]) is ok


def test_a_low_piece_with_no_seat_over_it_stays():
    seat = (np.array([2.0, 2.0, 0.32]), np.array([2.5, 2.5, 0.92]))
    base = (np.array([-0.2, -0.2, 0.04]), np.array([0.7, 0.7, 0.12]))
    assert not furniture.base_under_seat(*base, [seat])
    assert not furniture.base_under_seat(*base, [])


WORKTOP = (np.array([0.0, 0.0, 0.0]), np.array([2.0, 0.7, 0.7]))


@pytest.mark.parametrize("thickness,ok", [(0.10, True), (0.18, True), (0.25, False)])
def test_carrel_panel_is_thin(thickness, ok):
    panel = (np.array([1.0, 0.75, 0.05]), np.array([1.0 + thickness, 1.0, 1.4]))
    assert furniture.carrel_panel(*panel, *WORKTOP) is ok


@pytest.mark.parametrize("gap,ok", [(0.05, True), (0.35, True), (0.45, False)])
def test_carrel_panel_stands_beside_the_worktop(gap, ok):
    panel = (np.array([1.0, 0.7 + gap, 0.05]), np.array([1.15, 1.0 + gap, 1.4]))
    assert furniture.carrel_panel(*panel, *WORKTOP) is ok


def test_carrel_panel_rises_above_the_top():
    assert not furniture.carrel_panel(np.array([1.0, 0.75, 0.05]), np.array([1.15, 1.0, 0.6]), *WORKTOP)


@pytest.mark.parametrize("gap,ok", [(0.09, True), (0.11, False)])
def test_a_base_reaches_10_cm_beyond_its_seat(gap, ok):                 # BASE_REACH_M
    seat = (np.array([0.0, 0.0, 0.32]), np.array([0.5, 0.5, 0.92]))
    base = (np.array([0.5 + gap, 0.0, 0.04]), np.array([1.2, 0.5, 0.12]))
    assert furniture.base_under_seat(*base, [seat]) is ok


# --- a solid kind open below ---------------------------------------------------------------------

@pytest.mark.parametrize("floor_share,ok", [(0.40, True), (0.30, False)])
def test_a_refrigerator_with_the_floor_seen_under_it_is_no_refrigerator(floor_share, ok):   # CABINET_FLOOR_SHARE
    lo, hi = np.array([0.0, 0.0, 0.05]), np.array([1.0, 1.0, 1.2])
    # floor points under the first `floor_share` of the footprint (along a)
    floor = grid(0.0, floor_share, 0.0, 1.0, 0.0, 0.0, step=0.025)
    cloud = cloud_of(floor, grid(0.0, 1.0, 0.0, 1.0, 0.5, 0.5))
    assert furniture.floor_seen_in_footprint(lo, hi, cloud) == pytest.approx(floor_share, abs=0.03)
    assert furniture.open_below("refrigerator", lo, hi, cloud) is ok
    assert furniture.open_below("oven", lo, hi, cloud) is ok
    assert not furniture.open_below("chair", lo, hi, cloud)         # a chair is open below anyway
