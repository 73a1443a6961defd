"""Geometric relations on hand-made boxes (metres, z up unless stated)."""
from __future__ import annotations

import numpy as np
import pytest

from ingest.model import ObjectObservation, RELATION_TYPES
from ingest.relations import ObjectGeometry, horizontal_basis, spatial_relations

UP = (0.0, 0.0, 1.0)


def rels(objects, up=UP, camera_pose=None):
    return {(r.subject, r.predicate, r.object): r.score for r in spatial_relations(objects, up, camera_pose)}


def table():
    return ObjectGeometry("table", "dining table", (0.0, 0.0, 0.375), (1.6, 0.9, 0.75))


def cup(x=0.2, y=0.1, z=0.75 + 0.05):
    return ObjectGeometry("cup", "cup", (x, y, z), (0.08, 0.08, 0.10))


def camera_looking_along_y(position=(0.0, -3.0, 1.2)):
    """OpenCV camera (x right, y down, z forward) at `position` looking along world +y."""
    pose = np.eye(4)
    pose[:3, 0] = (1, 0, 0)
    pose[:3, 1] = (0, 0, -1)
    pose[:3, 2] = (0, 1, 0)
    pose[:3, 3] = position
    return pose


def test_horizontal_basis_is_orthonormal_and_right_handed():
    e1, e2, u = horizontal_basis((0.1, -0.95, 0.2))
    m = np.stack([e1, e2, u])
    assert m @ m.T == pytest.approx(np.eye(3))
    assert np.linalg.det(m) == pytest.approx(1.0)


def test_cup_resting_on_table_is_on_not_under():
    r = rels([table(), cup()])
    assert ("cup", "ON", "table") in r
    assert r[("cup", "ON", "table")] > 0.9
    assert ("cup", "UNDER", "table") not in r
    assert ("table", "ON", "cup") not in r
    assert ("cup", "ABOVE", "table") not in r          # touching: ON, not ABOVE
    assert all(p in RELATION_TYPES for _, p, _ in r)


def test_cup_on_table_with_noisy_gap_and_penetration():
    assert ("cup", "ON", "table") in rels([table(), cup(z=0.75 + 0.05 + 0.05)])
    assert ("cup", "ON", "table") in rels([table(), cup(z=0.75 + 0.05 - 0.05)])
    far = rels([table(), cup(z=0.75 + 0.05 + 0.3)])
    assert ("cup", "ON", "table") not in far
    assert ("cup", "ABOVE", "table") in far and ("table", "BELOW", "cup") in far


def test_cup_beside_table_is_not_on_it():
    r = rels([table(), cup(x=1.2)])
    assert ("cup", "ON", "table") not in r


def test_same_scene_in_a_tilted_world_frame():
    # rotate the whole scene about x by 30 degrees: relations must not change
    a = np.deg2rad(30)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    objs = [table(), cup()]
    e1, e2, _ = horizontal_basis(rot @ np.array(UP))
    # sizes must be expressed along the new frame's horizontal axes: rotate e1/e2 back
    assert abs(abs((rot.T @ e1) @ [1, 0, 0]) - 1) < 1e-9
    tilted = [ObjectGeometry(o.local_id, o.label, tuple(rot @ np.array(o.center)), o.size) for o in objs]
    r = rels(tilted, up=tuple(rot @ np.array(UP)))
    assert ("cup", "ON", "table") in r
    assert ("table", "ON", "cup") not in r


def test_table_bigger_than_cup():
    r = rels([table(), cup()])
    assert ("table", "BIGGER_THAN", "cup") in r
    assert ("cup", "SMALLER_THAN", "table") in r
    assert ("cup", "BIGGER_THAN", "table") not in r
    assert r[("table", "BIGGER_THAN", "cup")] > 0.9


def test_two_chairs_side_by_side_are_next_to():
    a = ObjectGeometry("c1", "chair", (0.0, 0.0, 0.45), (0.45, 0.5, 0.9))
    b = ObjectGeometry("c2", "chair", (0.65, 0.0, 0.45), (0.45, 0.5, 0.9))
    r = rels([a, b])
    assert ("c1", "NEXT_TO", "c2") in r and ("c2", "NEXT_TO", "c1") in r
    assert ("c1", "ON", "c2") not in r
    # same size: no comparison edge
    assert not any(p in ("BIGGER_THAN", "SMALLER_THAN") for _, p, _ in r)
    far = rels([a, ObjectGeometry("c2", "chair", (3.0, 0.0, 0.45), (0.45, 0.5, 0.9))])
    assert ("c1", "NEXT_TO", "c2") not in far and ("c1", "NEAR", "c2") not in far


def test_box_in_front_of_another_relative_to_camera():
    front = ObjectGeometry("front", "chair", (0.0, -0.8, 0.45), (0.5, 0.5, 0.9))
    back = ObjectGeometry("back", "refrigerator", (0.1, 0.5, 0.9), (0.7, 0.7, 1.8))
    r = rels([front, back], camera_pose=camera_looking_along_y())
    assert ("front", "IN_FRONT_OF", "back") in r
    assert ("back", "BEHIND", "front") in r
    assert ("back", "IN_FRONT_OF", "front") not in r
    # seen from the other side the order flips
    flipped = camera_looking_along_y(position=(0.0, 3.0, 1.2))
    flipped[:3, 2] *= -1
    flipped[:3, 0] *= -1
    r2 = rels([front, back], camera_pose=flipped)
    assert ("back", "IN_FRONT_OF", "front") in r2
    # no camera: no view-dependent relation
    assert not any(p in ("IN_FRONT_OF", "BEHIND") for _, p, _ in rels([front, back]))
    # laterally apart: not in front
    aside = ObjectGeometry("front", "chair", (2.0, -0.8, 0.45), (0.5, 0.5, 0.9))
    assert ("front", "IN_FRONT_OF", "back") not in rels([aside, back], camera_pose=camera_looking_along_y())


def test_spoon_in_bowl_is_in():
    bowl = ObjectGeometry("bowl", "bowl", (0.0, 0.0, 0.83), (0.2, 0.2, 0.08))
    spoon = ObjectGeometry("spoon", "spoon", (0.02, 0.0, 0.82), (0.12, 0.03, 0.03))
    r = rels([bowl, spoon])
    assert ("spoon", "IN", "bowl") in r
    assert ("spoon", "ON", "bowl") not in r
    # a box inside a non-container (a book) is not IN it
    book = ObjectGeometry("bowl", "book", (0.0, 0.0, 0.83), (0.2, 0.2, 0.08))
    assert ("spoon", "IN", "bowl") not in rels([book, spoon])


def test_chair_tucked_under_table_is_under():
    chair = ObjectGeometry("chair", "chair", (0.0, 0.1, 0.4), (0.45, 0.45, 0.8))
    r = rels([table(), chair])
    assert ("chair", "UNDER", "table") in r
    assert ("table", "UNDER", "chair") not in r


def test_near_only_without_a_more_specific_relation():
    bottle = ObjectGeometry("bottle", "bottle", (0.0, 0.0, 0.9), (0.08, 0.08, 0.3))
    vase = ObjectGeometry("vase", "vase", (0.4, 0.0, 1.2), (0.1, 0.1, 0.25))   # on a higher shelf
    r = rels([bottle, vase])
    assert ("bottle", "NEAR", "vase") in r and ("vase", "NEAR", "bottle") in r
    r_on = rels([table(), cup()])
    assert ("cup", "NEAR", "table") not in r_on


def test_comparisons_are_limited_to_related_pairs_or_same_label():
    far_cup = ObjectGeometry("cup", "cup", (5.0, 5.0, 0.8), (0.08, 0.08, 0.1))
    r = rels([table(), far_cup])
    assert not any(p in ("BIGGER_THAN", "SMALLER_THAN") for _, p, _ in r)
    big = ObjectGeometry("c1", "cup", (0.0, 0.0, 0.8), (0.12, 0.12, 0.15))
    small = ObjectGeometry("c2", "cup", (5.0, 5.0, 0.8), (0.06, 0.06, 0.08))
    assert ("c1", "BIGGER_THAN", "c2") in rels([big, small])


def test_from_points_and_from_observation():
    rng = np.random.default_rng(0)
    pts = rng.uniform([-0.5, -0.25, 0.0], [0.5, 0.25, 0.7], size=(5000, 3))
    g = ObjectGeometry.from_points("t", "dining table", pts, UP)
    assert g.center == pytest.approx((0.0, 0.0, 0.35), abs=0.03)
    assert g.size == pytest.approx((1.0, 0.5, 0.7), abs=0.05)
    obs = ObjectObservation("o1", ["cup"], [0.9], (1.0, 2.0, 3.0), (0.0, 0.0, 0.0), 10,
                            (0.1, 0.1, 0.12), np.zeros(512))
    g2 = ObjectGeometry.from_observation(obs)
    assert (g2.local_id, g2.label, g2.center, g2.size) == ("o1", "cup", (1.0, 2.0, 3.0), (0.1, 0.1, 0.12))


def test_scores_in_unit_interval():
    objs = [table(), cup(), ObjectGeometry("c1", "chair", (0.0, -0.8, 0.45), (0.45, 0.5, 0.9))]
    for r in spatial_relations(objs, UP, camera_looking_along_y()):
        assert 0.0 < r.score <= 1.0


def test_cup_sunk_into_an_inflated_table_box_is_on_not_under():
    # the table's box reaches 0.95 m because the counter behind it fell into its 2-D box
    inflated = ObjectGeometry("table", "dining table", (0.0, 0.0, 0.475), (1.6, 0.9, 0.95))
    sunk = ObjectGeometry("cup", "cup", (0.2, 0.1, 0.87), (0.08, 0.08, 0.12))   # bottom 0.81, top 0.93
    r = rels([inflated, sunk])
    assert ("cup", "ON", "table") in r
    assert ("cup", "UNDER", "table") not in r
