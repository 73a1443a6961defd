"""Re-scans (`sg3d.ingest.objects.rescan`): did a frame see a stored object's place empty? A camera at
the origin looking along +z (f = 500 px, 640 x 480), a 40 cm box 2 m ahead, hand-made depth."""
from __future__ import annotations

import numpy as np

from sg3d.core.model import KnownObject
from sg3d.ingest.objects.existence import View
from sg3d.ingest.objects.rescan import empty_places, place_seen_empty

K = np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]])
BASIS = np.array([[1.0, 0, 0], [0, 0, 1.0], [0, -1.0, 0]])     # e1 = x, e2 = z (away), up = -y
BOX = KnownObject("box", (0.0, 0.0, 2.0), (0.4, 0.4, 0.4))      # spans 1.8 - 2.2 m of depth


def view(depth_m: float = 3.0, rows=(), index: int = 0, pixels=None) -> View:
    """The camera's small (1/4) depth: `depth_m` everywhere, 2.0 m (something standing in the box)
    in the full-resolution image `rows` (v0, v1); or only the small `pixels` {(row, col): depth}."""
    d = np.full((120, 160), depth_m, np.float32)
    for v0, v1 in rows:
        d[v0 // 4:(v1 + 3) // 4] = 2.0
    if pixels is not None:
        d[:] = 0.0
        for (r, c), z in pixels.items():
            d[r, c] = z
    return View(index, K, np.eye(4), (640, 480), d)


def test_a_ray_passed_when_its_depth_reaches_2_cm_before_the_cores_far_side():
    # PASS_TOLERANCE_M, CORE_HORIZONTAL: the core is 60 % of the box across, so its far side is 2.12 m
    assert place_seen_empty(BOX, BASIS, view(2.105)) is True
    assert place_seen_empty(BOX, BASIS, view(2.095)) is False


def test_the_core_starts_30_percent_up_the_box():                     # CORE_BOTTOM, CORE_TOP
    # the box's lower part (image rows 255 down) holds something: not probed
    assert place_seen_empty(BOX, BASIS, view(rows=[(255, 300)])) is True
    # from 40 % of its height (row 236) down: the core's lower part is full
    assert place_seen_empty(BOX, BASIS, view(rows=[(236, 300)])) is False


def _told(passed: int, stopped: int) -> View:
    """Depth only at `passed` pixels that see through the box and `stopped` ones that hit it,
    all inside the core's image (small rows 52-62, columns 76-83)."""
    cells = [(r, c) for r in range(52, 63) for c in range(76, 84)]
    return view(pixels={cell: (3.0 if k < passed else 2.0) for k, cell in enumerate(cells[:passed + stopped])})


def test_a_frame_tells_with_6_rays():                                  # MIN_RAYS
    assert place_seen_empty(BOX, BASIS, _told(6, 0)) is True
    assert place_seen_empty(BOX, BASIS, _told(5, 0)) is None


def test_the_place_is_empty_when_80_percent_of_the_rays_passed():      # EMPTY_FRACTION
    assert place_seen_empty(BOX, BASIS, _told(17, 3)) is True
    assert place_seen_empty(BOX, BASIS, _told(15, 5)) is False


def test_objects_up_to_1_5_m_are_judged():                              # MAX_JUDGED_EXTENT_M
    def box(width):
        return KnownObject("b", (0.0, 0.0, 3.0), (width, 0.4, 0.4))
    assert place_seen_empty(box(1.45), BASIS, view(4.0)) is True
    assert place_seen_empty(box(1.55), BASIS, view(4.0)) is None


def test_a_place_is_gone_when_most_frames_that_could_tell_saw_it_empty():   # EMPTY_SHARE
    def frames(empty, full):
        return [view(3.0, index=i) for i in range(empty)] + [view(2.0, index=10 + i) for i in range(full)]
    assert empty_places([BOX], frames(8, 2), BASIS) == {"box": list(range(8))}
    assert empty_places([BOX], frames(7, 3), BASIS) == {}
    assert empty_places([BOX], frames(2, 2), BASIS) == {}      # half is not enough


def test_a_surface_point_is_hit_within_2_cm_plus_2_percent_of_its_range():   # SURFACE_NOISE_REL, PASS_TOLERANCE_M
    points = [(x, y, 2.0) for x in (-0.1, 0.0, 0.1) for y in (-0.1, 0.0, 0.1)]   # 2 m away: 6 cm
    thing = KnownObject("t", (0.0, 0.0, 2.0), (0.2, 0.01, 0.2), tuple(v for p in points for v in p))
    assert place_seen_empty(thing, BASIS, view(2.065)) is True      # seen through
    assert place_seen_empty(thing, BASIS, view(2.055)) is False     # seen on it
