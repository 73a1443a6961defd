"""Walls the vote misses (`structure.fitted_walls`): few points with noisy normals, as a low-
resolution camera sees them. Each threshold on both sides."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import (Element, fitted_plane, fitted_walls, normals_agree, seen_face_area,
                                            walls)
from tests.unit.ingest.discover.clouds import room_of


def _sparse_wall(x: float, length: float, height: float, jitter_deg: float = 8.0, seed: int = 0):
    """A wall across x (facing the camera at the origin), one point per 5 cm cell, normals turned
    by up to +-jitter_deg at random (depth noise), so no vote bin reaches the vote rule's count."""
    rng = np.random.default_rng(seed)
    b, h = np.meshgrid(np.arange(-0.6, -0.6 + length - 1e-9, 0.05) + 0.025, np.arange(0.1, 0.1 + height - 1e-9, 0.05) + 0.025)
    pts = np.stack([np.full(b.size, x), b.ravel(), h.ravel()], axis=1)
    turn = np.radians(rng.uniform(-jitter_deg, jitter_deg, len(pts)))
    nrm = np.stack([-np.cos(turn), -np.sin(turn), np.zeros(len(pts))], axis=1)
    return pts, nrm


def _room(*planes) -> RoomCloud:
    return room_of(*planes, floor_step=0.05)


def _found_x(cloud, found=()) -> list[float]:
    return [round(float(e.plane[1]), 2) for e in fitted_walls(cloud, list(found))]


def test_the_vote_misses_a_sparse_noisy_wall_and_the_fit_finds_it():
    cloud = _room(_sparse_wall(1.5, 2.0, 1.2))
    assert walls(cloud) == []
    (wall,) = fitted_walls(cloud, [])
    assert wall.label == "wall"
    assert abs(np.degrees(wall.plane[0])) < 1.0 and wall.plane[1] == pytest.approx(1.5, abs=0.01)


def test_a_fitted_plane_is_pulled_from_its_vote_bin_onto_the_wall():
    pts, _ = _sparse_wall(1.5, 2.0, 1.2)
    theta, rho = fitted_plane(pts[:, :2], np.radians(4.0), 1.45)
    assert abs(np.degrees(theta)) < 0.5 and rho == pytest.approx(1.5, abs=0.005)


def test_a_wall_shows_a_square_metre_of_face():                          # WALL_FIT_MIN_AREA_M2
    assert seen_face_area(*_sparse_wall(1.5, 1.3, 0.8)[0][:, 1:].T) == pytest.approx(1.04)
    assert _found_x(_room(_sparse_wall(1.5, 1.3, 0.8))) == [1.5]
    assert _found_x(_room(_sparse_wall(1.5, 1.15, 0.8))) == []          # 0.92 m^2


def test_its_normals_agree_with_it_within_5_degrees():                  # WALL_NORMAL_AGREE_DEG
    def turned(deg):
        t = np.radians(deg)
        return np.tile([-np.cos(t), -np.sin(t), 0.0], (10, 1))
    assert normals_agree(turned(4.5), 0.0)
    assert not normals_agree(turned(5.5), 0.0)
    assert normals_agree(turned(180 - 4.5), 0.0)                        # a normal is a direction


def test_a_plane_25_cm_from_a_found_wall_is_that_wall():                # WALL_SAME_M
    found = Element("wall", np.zeros(3), np.ones(3), 100, 0, plane=(0.0, 1.5))
    assert _found_x(_room(_sparse_wall(1.72, 2.0, 1.2)), [found]) == []
    assert _found_x(_room(_sparse_wall(1.78, 2.0, 1.2)), [found]) == [1.78]


def test_a_plane_with_the_room_far_behind_it_is_no_wall():              # WALL_SURE_FAR
    wall = _sparse_wall(1.5, 2.0, 1.2)
    cloud = _room(wall)
    n = len(cloud.points)
    for share, expect in ((0.008, [1.5]), (0.012, [])):
        k = int(share * n / (1 - share)) + 1
        behind = (np.column_stack([np.full(k, 1.9), np.linspace(-0.5, 0.5, k), np.full(k, 0.5)]),
                  np.tile([0.0, 0.0, 1.0], (k, 1)))
        assert _found_x(_room(wall, behind)) == expect


def _front(x: float, length: float, height: float, jitter_deg: float, step: float, seed: int):
    """A furniture front across x near the camera (a bed's side seen from a robot's height): dense,
    its normals turned by up to +-jitter_deg at random, so its votes fill many angle bins."""
    b, h = np.meshgrid(np.arange(-0.6, -0.6 + length, step), np.arange(0.05, 0.05 + height, step))
    pts = np.stack([np.full(b.size, x), b.ravel(), h.ravel()], axis=1)
    turn = np.radians(np.random.default_rng(seed).uniform(-jitter_deg, jitter_deg, len(pts)))
    return pts, np.stack([-np.cos(turn), -np.sin(turn), np.zeros(len(pts))], axis=1)


def test_fronts_found_no_wall_vote_no_more_and_the_far_wall_behind_them_is_found():
    """Fronts with the room behind them are no walls; their noisy normals fill more vote bins than
    WALL_FIT_CANDIDATES, each fitting onto a front again: their points leave the vote
    (`rejected_votes`), so the far wall, its normals noisier still, is tried and found."""
    fronts = [_front(x, 1.0, 0.9, jitter_deg=45.0, step=0.01, seed=k) for k, x in enumerate((0.4, 0.7, 1.0))]
    assert _found_x(_room(*fronts, _sparse_wall(1.5, 2.0, 1.2, jitter_deg=20.0))) == [1.5]
    assert _found_x(_room(*fronts)) == []                               # the fronts alone are no wall


def _slanted_wall(turn_deg: float, through_b: float, b0: float, b1: float, height: float = 1.2):
    """A wall turned by `turn_deg` from x = const through (1.5, through_b), from b0 to b1 along b,
    one point per 5 cm cell, its normals its own."""
    t = np.radians(turn_deg)
    s, h = np.meshgrid(np.arange(b0, b1, 0.05) + 0.025, np.arange(0.1, 0.1 + height, 0.05) + 0.025)
    s = s.ravel() - through_b
    pts = np.stack([1.5 - s * np.sin(t), through_b + s * np.cos(t), h.ravel()], axis=1)
    return pts, np.tile([-np.cos(t), -np.sin(t), 0.0], (len(pts), 1))


def test_a_plane_slanted_across_a_found_wall_is_that_wall():           # WALL_SAME_DEG
    """Walls do not cross (`same_wall`): 8 degrees off a wall found at x = 1.5 and crossing it 1.5 m
    from the origin's foot on it, a plane is that wall's noisy remainder."""
    found = Element("wall", np.zeros(3), np.ones(3), 100, 0, plane=(0.0, 1.5))
    assert _found_x(_room(_slanted_wall(8.0, 3.0, 1.6, 3.6)), []) == [1.9]
    assert _found_x(_room(_slanted_wall(8.0, 3.0, 1.6, 3.6)), [found]) == []


@pytest.mark.parametrize("shift,same", [(0.32, True), (0.34, False)])
def test_a_slanted_plane_within_25_cm_of_a_found_wall_where_it_lies_is_that_wall(shift, same):   # WALL_SAME_M
    """Its nearest point (b = 3.575 m, 8 cm nearer than where it meets b = 3 m) lies shift - 8 cm
    from the found wall: 24 cm is that wall, 26 cm is a wall of its own."""
    found = Element("wall", np.zeros(3), np.ones(3), 100, 0, plane=(0.0, 1.5))
    pts, nrm = _slanted_wall(8.0, 3.0, 1.6, 3.6)
    assert float(np.min(pts[:, 0])) + shift - 1.5 == pytest.approx(shift - 0.08, abs=0.001)
    assert (_found_x(_room((pts + [shift, 0.0, 0.0], nrm)), [found]) == []) is same
