"""The room's heading (`sg3d.ingest.poses.gravity.manhattan_heading`) and the frame boxes are
measured in (`sg3d.core.geometry.horizontal_basis`): normals of vertical surfaces folded modulo 90
degrees; the world's axes when no two perpendicular directions stand out."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.geometry import Ground, horizontal_basis, horizontal_frame
from sg3d.ingest.poses.gravity import (
    HEADING_MIN_NORMALS,
    WALL_NORMAL_DEG,
    estimate_gravity,
    manhattan_heading,
)

from .test_gravity import FLOOR, camera, frame

UP = (0.0, 0.0, 1.0)


def normals_at(*angles_deg: float, tilt_deg: float = 0.0) -> np.ndarray:
    """Unit normals at these angles about z (from world x), tilted `tilt_deg` from horizontal."""
    a, t = np.radians(np.asarray(angles_deg, float)), np.radians(tilt_deg)
    return np.stack([np.cos(a) * np.cos(t), np.sin(a) * np.cos(t), np.full(a.shape, np.sin(t))], axis=1)


def angle_of(heading) -> float:
    return float(np.degrees(np.arctan2(heading[1], heading[0])))


def scattered(n: int, lo: float = 40.0, hi: float = 85.0) -> list[float]:
    """n directions spread evenly over [lo, hi) degrees of the folded circle (no pile)."""
    return list(np.linspace(lo, hi, n, endpoint=False))


def test_without_a_heading_the_frame_is_the_world_x_axis_made_horizontal():
    up = np.array([0.1, -0.3, 0.95]) / np.linalg.norm([0.1, -0.3, 0.95])
    e1, e2, u = horizontal_basis(up)
    x = np.array([1.0, 0.0, 0.0]) - up[0] * up
    assert e1 == pytest.approx(x / np.linalg.norm(x), abs=1e-12)
    assert e2 == pytest.approx(np.cross(up, e1), abs=1e-12)
    assert horizontal_frame(up, None) == pytest.approx(horizontal_frame(up), abs=0)


def test_a_heading_turns_the_horizontal_axes_and_keeps_up():
    h = (np.cos(np.radians(20)), np.sin(np.radians(20)), 0.3)     # made horizontal first
    e1, e2, u = horizontal_basis(UP, h)
    assert angle_of(e1) == pytest.approx(20.0, abs=1e-9) and e1[2] == 0.0
    assert angle_of(e2) == pytest.approx(110.0, abs=1e-9)
    assert u == pytest.approx(UP)
    # a 1.6 x 0.6 m top turned 20 degrees from the world measures 1.6 x 0.6 along its heading
    corners = np.array([[x, y, 0.0] for x in (-0.8, 0.8) for y in (-0.3, 0.3)]) @ horizontal_frame(UP, h)
    ground = Ground(UP, 0.0, h)
    local = corners @ ground.room_basis.T
    assert np.ptp(local, axis=0)[:2] == pytest.approx((1.6, 0.6), abs=1e-9)


def test_walls_normals_give_the_heading_folded_modulo_90_degrees():
    walls = normals_at(*([20.0] * 300 + [110.0] * 300 + [200.0] * 100 + [290.0] * 100))
    assert angle_of(manhattan_heading(walls, UP)) == pytest.approx(20.0, abs=1e-3)
    # the heading is the one of the four nearest the world's x axis: 70 degrees turns -20
    assert angle_of(manhattan_heading(normals_at(*[70.0] * 600), UP)) == pytest.approx(-20.0, abs=1e-3)


def test_the_heading_is_the_circular_mean_of_the_pile_and_the_same_after_any_shuffle():
    rng = np.random.default_rng(0)
    angles = list(rng.normal(12.0, 1.0, 800)) + scattered(200)
    N = normals_at(*angles)
    h = manhattan_heading(N, UP)
    assert angle_of(h) == pytest.approx(12.0, abs=0.2)
    assert np.array_equal(h, manhattan_heading(N[rng.permutation(len(N))], UP))


def test_a_normal_within_10_degrees_of_horizontal_is_a_vertical_surfaces():     # WALL_NORMAL_DEG
    n = HEADING_MIN_NORMALS
    assert manhattan_heading(normals_at(*[30.0] * n, tilt_deg=WALL_NORMAL_DEG - 0.5), UP) is not None
    assert manhattan_heading(normals_at(*[30.0] * n, tilt_deg=WALL_NORMAL_DEG + 0.5), UP) is None


def test_under_500_vertical_surface_normals_the_room_keeps_the_world_axes():   # HEADING_MIN_NORMALS
    assert manhattan_heading(normals_at(*[30.0] * 500), UP) is not None
    assert manhattan_heading(normals_at(*[30.0] * 499), UP) is None


def test_a_quarter_of_the_normals_must_pile_at_the_heading():                  # HEADING_MIN_SHARE
    assert manhattan_heading(normals_at(*([20.5] * 250 + scattered(750))), UP) is not None
    assert manhattan_heading(normals_at(*([20.5] * 240 + scattered(760))), UP) is None


def test_the_pile_holds_the_normals_within_5_degrees_of_its_bin():             # HEADING_PEAK_DEG
    def share_with_flanks(off: float):
        return normals_at(*([20.5] * 200 + [20.5 - off] * 30 + [20.5 + off] * 30 + scattered(740)))
    assert angle_of(manhattan_heading(share_with_flanks(4.9), UP)) == pytest.approx(20.5, abs=1e-3)
    assert manhattan_heading(share_with_flanks(5.1), UP) is None


def test_the_heading_is_kept_to_a_ten_thousandth_of_a_degree():                # HEADING_DECIMALS
    h = manhattan_heading(normals_at(*[20.123456] * 600), UP)
    assert angle_of(h) == pytest.approx(20.1235, abs=1e-9)


def test_a_floor_alone_leaves_the_world_axes_and_a_turned_wall_gives_its_heading():
    def turned(yaw_deg: float) -> np.ndarray:
        pose = camera(20, 1.5)
        y = np.radians(yaw_deg)
        R = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
        pose[:3, :3] = R @ pose[:3, :3]
        return pose

    wall_normal = (np.sin(np.radians(25)), -np.cos(np.radians(25)), 0.0)   # faces the camera, turned 25 degrees
    wall = (wall_normal, -2.0, None)
    assert estimate_gravity([frame(turned(y), [FLOOR]) for y in (20, 25, 30)]).heading is None
    g = estimate_gravity([frame(turned(y), [FLOOR, wall]) for y in (20, 25, 30)])
    assert angle_of(g.heading) == pytest.approx(25.0, abs=0.05)
    assert g.ground.room_basis == pytest.approx(horizontal_frame(g.up, g.heading))
    assert g.ground.basis == pytest.approx(horizontal_frame(g.up))            # the stages measure in the world's
