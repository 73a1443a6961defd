"""Geometric relations on hand-made boxes (metres, z up unless stated)."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.geometry import horizontal_basis
from sg3d.core.model import RELATION_TYPES, ObjectObservation
from sg3d.ingest.relate.relations import (
    ObjectGeometry,
    floor_under_room,
    spatial_relations,
)

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


def test_two_chairs_side_by_side_are_next_to_stored_once():
    a = ObjectGeometry("c1", "chair", (0.0, 0.0, 0.45), (0.45, 0.5, 0.9))
    b = ObjectGeometry("c2", "chair", (0.65, 0.0, 0.45), (0.45, 0.5, 0.9))
    r = rels([b, a])
    # symmetric: one edge, subject = the smaller id, whatever order the objects come in
    assert ("c1", "NEXT_TO", "c2") in r and ("c2", "NEXT_TO", "c1") not in r
    assert ("c1", "ON", "c2") not in r
    # same size: no comparison edge
    assert not any(p in ("BIGGER_THAN", "SMALLER_THAN") for _, p, _ in r)
    far = rels([a, ObjectGeometry("c2", "chair", (3.0, 0.0, 0.45), (0.45, 0.5, 0.9))])
    assert ("c1", "NEXT_TO", "c2") not in far and ("c1", "NEAR", "c2") not in far


def test_viewpoint_relations_are_never_emitted():
    # IN_FRONT_OF/BEHIND from a keyframe camera flip with the viewpoint (one cup would be stored
    # both in front of and behind one table), so they are computed at ask time, never stored
    front = ObjectGeometry("front", "chair", (0.0, -0.8, 0.45), (0.5, 0.5, 0.9))
    back = ObjectGeometry("back", "refrigerator", (0.1, 0.5, 0.9), (0.7, 0.7, 1.8))
    for pose in (None, camera_looking_along_y(), camera_looking_along_y(position=(0.0, 3.0, 1.2))):
        r = rels([front, back], camera_pose=pose)
        assert not any(p in ("IN_FRONT_OF", "BEHIND", "LEFT_OF", "RIGHT_OF") for _, p, _ in r)
        assert ("back", "NEAR", "front") in r          # what holds from everywhere


def test_spoon_in_bowl_is_in():
    bowl = ObjectGeometry("bowl", "bowl", (0.0, 0.0, 0.83), (0.2, 0.2, 0.08))
    spoon = ObjectGeometry("spoon", "spoon", (0.02, 0.0, 0.82), (0.12, 0.03, 0.03))
    r = rels([bowl, spoon])
    assert ("spoon", "IN", "bowl") in r
    assert ("spoon", "ON", "bowl") not in r
    # a box inside a non-container (a book) is not IN it
    book = ObjectGeometry("bowl", "book", (0.0, 0.0, 0.83), (0.2, 0.2, 0.08))
    assert ("spoon", "IN", "bowl") not in rels([book, spoon])


def test_cup_on_table_vs_chair_tucked_under_it():
    # the chair's seat is under the table top, its back rises above it: "the chair at the table"
    chair = ObjectGeometry("chair", "chair", (0.0, 0.35, 0.45), (0.45, 0.45, 0.9))
    r = rels([table(), cup(), chair])
    assert ("cup", "ON", "table") in r
    assert ("chair", "NEXT_TO", "table") in r
    assert not any(k[1] in ("UNDER", "ON", "ABOVE", "BELOW", "IN") and {k[0], k[2]} == {"chair", "table"} for k in r)
    # the cup on the table is not next to the chair on the floor, and is above it? no: the
    # chair is not covered by the cup; nothing vertical between them
    assert not any({k[0], k[2]} == {"cup", "chair"} and k[1] in ("ON", "UNDER", "IN") for k in r)
    # a stool pushed right under the top is UNDER the table
    stool = ObjectGeometry("stool", "chair", (0.0, 0.1, 0.3), (0.35, 0.35, 0.6))
    r2 = rels([table(), stool])
    assert ("stool", "UNDER", "table") in r2
    assert ("table", "UNDER", "stool") not in r2 and ("stool", "NEXT_TO", "table") not in r2


def test_book_on_a_stack_of_magazines():
    low = ObjectGeometry("m1", "magazine", (0.0, 0.0, 0.76), (0.28, 0.21, 0.02))
    high = ObjectGeometry("m2", "magazine", (0.01, 0.0, 0.78), (0.28, 0.21, 0.02))
    book = ObjectGeometry("book", "book", (0.0, 0.01, 0.81), (0.24, 0.17, 0.04))
    r = rels([table(), low, high, book])
    assert ("book", "ON", "m2") in r
    assert ("m2", "ON", "m1") in r and ("m1", "ON", "m2") not in r
    assert ("m1", "ON", "table") in r and ("m2", "ON", "table") in r and ("book", "ON", "table") in r
    # not on the middle of the pile, and not "next to" it either
    assert ("book", "ON", "m1") not in r
    assert not any({k[0], k[2]} == {"book", "m1"} and k[1] in ("NEXT_TO", "NEAR") for k in r)


def test_tv_on_the_wall_above_a_shelf_and_a_tower_under_it():
    # wall at y = 0.3; the shelf sticks out 30 cm, the TV hangs flat 40 cm above it
    shelf = ObjectGeometry("shelf", "shelf", (0.0, 0.15, 0.95), (1.5, 0.3, 0.04))
    tv = ObjectGeometry("tv", "tv", (0.0, 0.26, 1.6), (1.0, 0.06, 0.6))
    tower = ObjectGeometry("tower", "computer", (-0.5, 0.1, 0.22), (0.2, 0.25, 0.44))
    r = rels([shelf, tv, tower])
    assert ("tv", "ABOVE", "shelf") in r and ("shelf", "BELOW", "tv") in r
    assert ("tv", "ON", "shelf") not in r and ("shelf", "ABOVE", "tv") not in r
    assert ("tower", "UNDER", "shelf") in r
    assert ("tower", "BELOW", "shelf") not in r and ("shelf", "ON", "tower") not in r


def test_sink_set_into_the_counter_is_in_it():
    # the basin's rim is flush with the counter top, its bottom 20 cm lower: it is held by the
    # counter, not standing on it (a sink "in the counter", as people and the kitchen GT say)
    counter = ObjectGeometry("counter", "counter", (0.0, 0.0, 0.45), (2.0, 0.6, 0.9))
    sink = ObjectGeometry("sink", "sink", (0.2, 0.0, 0.8), (0.5, 0.4, 0.2))
    r = rels([counter, sink])
    assert ("sink", "IN", "counter") in r
    assert ("sink", "ON", "counter") not in r and ("counter", "IN", "sink") not in r
    # a free-standing basin on the counter top is ON it
    basin = ObjectGeometry("sink", "sink", (0.2, 0.0, 1.0), (0.5, 0.4, 0.2))
    assert ("sink", "ON", "counter") in rels([counter, basin])


def test_cup_next_to_a_magazine_on_the_same_table():
    magazine = ObjectGeometry("mag", "magazine", (0.0, 0.0, 0.76), (0.28, 0.21, 0.02))
    beside = ObjectGeometry("cup", "cup", (0.20, 0.0, 0.80), (0.08, 0.08, 0.10))   # 6 cm gap
    r = rels([table(), magazine, beside])
    assert ("cup", "NEXT_TO", "mag") in r
    assert ("cup", "ON", "table") in r and ("mag", "ON", "table") in r
    # 40 cm away on the same table: near, not next to
    away = ObjectGeometry("cup", "cup", (0.54, 0.0, 0.80), (0.08, 0.08, 0.10))
    r2 = rels([table(), magazine, away])
    assert ("cup", "NEXT_TO", "mag") not in r2 and ("cup", "NEAR", "mag") in r2


def test_near_grows_with_object_size():
    # 70 cm gap: near for a table (1.6 m), not for two cups
    chair = ObjectGeometry("chair", "chair", (1.55, 0.0, 0.45), (0.45, 0.45, 0.9))
    assert ("chair", "NEAR", "table") in rels([table(), chair]) or ("chair", "NEXT_TO", "table") in rels([table(), chair])
    c1 = ObjectGeometry("c1", "cup", (0.0, 0.0, 0.8), (0.08, 0.08, 0.1))
    c2 = ObjectGeometry("c2", "cup", (0.78, 0.0, 0.8), (0.08, 0.08, 0.1))
    assert not rels([c1, c2])
    chair_far = ObjectGeometry("chair", "chair", (1.78, 0.0, 0.45), (0.45, 0.45, 0.9))
    r = rels([table(), chair_far])
    assert ("chair", "NEAR", "table") in r and ("chair", "NEXT_TO", "table") not in r


def test_near_only_without_a_more_specific_relation():
    bottle = ObjectGeometry("bottle", "bottle", (0.0, 0.0, 0.9), (0.08, 0.08, 0.3))
    vase = ObjectGeometry("vase", "vase", (0.4, 0.0, 1.2), (0.1, 0.1, 0.25))   # on a higher shelf
    r = rels([bottle, vase])
    assert ("bottle", "NEAR", "vase") in r and ("vase", "NEAR", "bottle") not in r
    r_on = rels([table(), cup()])
    assert not any(k[1] == "NEAR" for k in r_on)


def test_random_scenes_hold_no_contradiction():
    from sg3d.core.relation_rules import statement_of
    rng = np.random.default_rng(3)
    for _ in range(200):
        objs = [ObjectGeometry(f"o{i}", str(rng.choice(["cup", "bowl", "chair", "book", "sink"])),
                               tuple(rng.uniform([-1, -1, 0], [1, 1, 1.5])), tuple(rng.uniform(0.05, 0.8, 3)))
                for i in range(5)]
        per_pair = {}
        for r in spatial_relations(objs, UP):
            st = statement_of(r.subject, r.predicate, r.object)
            per_pair.setdefault((st.family, st.lo, st.hi), set()).add(st.form)
            if r.predicate in ("NEXT_TO", "NEAR"):
                assert r.subject < r.object
        assert all(len(forms) == 1 for forms in per_pair.values()), per_pair


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
    for r in spatial_relations(objs, UP):
        assert 0.0 < r.score <= 1.0


def test_cup_sunk_into_an_inflated_table_box_is_on_not_under():
    # the table's box reaches 0.95 m because the counter behind it fell into its 2-D box
    inflated = ObjectGeometry("table", "dining table", (0.0, 0.0, 0.475), (1.6, 0.9, 0.95))
    sunk = ObjectGeometry("cup", "cup", (0.2, 0.1, 0.87), (0.08, 0.08, 0.12))   # bottom 0.81, top 0.93
    r = rels([inflated, sunk])
    assert ("cup", "ON", "table") in r
    assert ("cup", "UNDER", "table") not in r


def test_flat_things_measured_into_a_thin_table_top_slab_are_on_it():
    # the kitchen's table box is often only its top slab (10 cm) and a book on it is measured a
    # few cm inside that slab: on the table, not under it
    slab = ObjectGeometry("table", "dining table", (0.0, 0.0, 0.72), (1.9, 0.9, 0.10))
    book = ObjectGeometry("book", "book", (0.2, 0.0, 0.71), (0.25, 0.24, 0.02))   # centre below the slab's
    r = rels([slab, book])
    assert ("book", "ON", "table") in r
    assert ("book", "UNDER", "table") not in r and ("table", "ON", "book") not in r


def test_a_cup_at_the_edge_of_a_partly_seen_table_top_is_left_to_other_views():
    # this frame sees only the right part of the table; the cup's footprint is half over it
    part = ObjectGeometry("table", "dining table", (0.3, 0.0, 0.72), (0.9, 0.6, 0.04))
    edge = ObjectGeometry("cup", "cup", (-0.17, 0.0, 0.78), (0.12, 0.12, 0.08))
    r = rels([part, edge])
    assert not any({k[0], k[2]} == {"cup", "table"} and k[1] in ("ON", "NEXT_TO", "NEAR") for k in r)
    # a cup beside a magazine (narrow, not a support surface) at the same height stays next to it
    magazine = ObjectGeometry("mag", "magazine", (0.0, 0.0, 0.76), (0.28, 0.21, 0.02))
    beside = ObjectGeometry("cup", "cup", (0.20, 0.0, 0.80), (0.08, 0.08, 0.10))
    assert ("cup", "NEXT_TO", "mag") in rels([magazine, beside])


def test_next_to_needs_one_support_across_the_sequence():
    from sg3d.core.model import RelationObservation as R
    from sg3d.ingest.relate.relations import side_by_side_on_one_support

    rels = [R("cup", "ON", "table"), R("book", "ON", "table"), R("cup", "NEXT_TO", "book"),
            R("chair", "NEXT_TO", "cup"), R("chair", "NEXT_TO", "table"), R("chair", "NEAR", "book")]
    kept = {(r.subject, r.predicate, r.object) for r in side_by_side_on_one_support(rels)}
    assert ("cup", "NEXT_TO", "book") in kept and ("chair", "NEXT_TO", "table") in kept
    assert ("chair", "NEXT_TO", "cup") not in kept
    assert ("chair", "NEAR", "book") in kept and len(kept) == 5


def test_a_flat_thing_filling_a_broad_support_slabs_height_is_on_it():
    # the fused table box is its top surface raised by what stands on it (8 cm); a magazine
    # measured from the same surface fills that height, its bottom a noisy 5 mm below the slab's:
    # on the table (the table is 15x its footprint)
    slab = ObjectGeometry("table", "dining table", (0.0, 0.0, 0.755), (1.8, 1.0, 0.07))   # 0.72-0.79
    magazine = ObjectGeometry("mag", "book", (0.2, 0.0, 0.735), (0.33, 0.36, 0.04))   # 0.715-0.755
    r = rels([slab, magazine])
    assert ("mag", "ON", "table") in r and ("table", "ON", "mag") not in r
    # two magazines of one size, one measured into the other: only the upper one is on the other
    lower = ObjectGeometry("a", "book", (0.0, 0.0, 0.73), (0.3, 0.3, 0.04))
    upper = ObjectGeometry("b", "book", (0.0, 0.0, 0.74), (0.3, 0.3, 0.04))          # bottoms 1 cm apart
    r = rels([lower, upper])
    assert ("b", "ON", "a") in r and ("a", "ON", "b") not in r
    same = rels([lower, ObjectGeometry("c", "book", (0.0, 0.0, 0.73), (0.3, 0.3, 0.04))])
    assert not any(k[1] == "ON" for k in same)          # level bottoms, same size: neither is on the other


def test_a_chair_at_the_end_of_a_table_is_next_to_it_whatever_its_box_height():
    # the table's box is its top slab; the end chair is seen down to the floor: their bottoms
    # are 0.7 m apart, but chairs and tables stand on the floor by their kind
    slab = ObjectGeometry("table", "dining table", (0.0, 0.0, 0.72), (1.9, 0.9, 0.08))
    chair = ObjectGeometry("chair", "chair", (1.2, 0.0, 0.45), (0.33, 0.5, 0.9))
    assert ("chair", "NEXT_TO", "table") in rels([slab, chair])
    # a box on the floor at the same spot is not at the table (it is no furniture)
    box = ObjectGeometry("box", "suitcase", (1.2, 0.0, 0.45), (0.33, 0.5, 0.9))
    assert not any({k[0], k[2]} == {"box", "table"} and k[1] == "NEXT_TO" for k in rels([slab, box]))


def test_a_chair_beyond_the_floor_seen_stands_on_the_floor():
    """The floor was seen only in front of the chair (the chair hides the floor under it): by
    its own box the chair is not over it, by the rule "the floor is under the whole room" it is."""
    floor = ObjectGeometry("floor", "floor", (0.0, 0.0, -0.005), (2.0, 2.0, 0.01))
    chair = ObjectGeometry("chair", "chair", (1.3, 0.0, 0.4), (0.45, 0.45, 0.8))
    assert ("chair", "ON", "floor") not in rels([floor, chair])
    whole = floor_under_room(floor, [chair], UP)
    assert whole.size[2] <= 0.02 and whole.center[2] == pytest.approx(-0.005)
    assert ("chair", "ON", "floor") in rels([whole, chair])
    # a picture on the wall is over the floor's footprint too, but does not rest on it
    picture = ObjectGeometry("picture", "object", (0.0, 1.5, 1.5), (0.4, 0.02, 0.3))
    assert ("picture", "ON", "floor") not in rels([floor_under_room(floor, [chair, picture], UP), picture])


# --------------------------------------------------------------------------- each threshold, on both sides
# Literal distances just inside and just outside today's thresholds (ON_TOLERANCE 8 cm, NEAR_MAX_GAP
# 1 m, ...): moving a threshold substantially moves one of them across it.

def box(local_id, label, lo, hi):
    """An ObjectGeometry from its corners (x, y, z up)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return ObjectGeometry(local_id, label, tuple((lo + hi) / 2), tuple(hi - lo))


def on_table(bottom, x=(0.0, 0.1), top=None, label="cup"):
    """A 10 cm cup over the table (top 0.75 m, 0.75 m tall) with its bottom at `bottom`."""
    return box("cup", label, (x[0], 0.0, bottom), (x[1], 0.1, top if top is not None else bottom + 0.1))


def flat_table():
    return box("table", "dining table", (-0.8, -0.45, 0.0), (0.8, 0.45, 0.75))


def test_on_allows_a_gap_of_under_8_cm():                      # ON_TOLERANCE
    assert ("cup", "ON", "table") in rels([flat_table(), on_table(0.75 + 0.07)])
    r = rels([flat_table(), on_table(0.75 + 0.09)])
    assert ("cup", "ON", "table") not in r and ("cup", "ABOVE", "table") in r


def test_on_allows_sinking_a_fifth_of_the_supports_height():  # ON_PENETRATION_FRACTION (0.2 x 0.75 m = 15 cm)
    assert ("cup", "ON", "table") in rels([flat_table(), on_table(0.75 - 0.14, top=0.95)])
    assert ("cup", "ON", "table") not in rels([flat_table(), on_table(0.75 - 0.16, top=0.95)])


def test_on_needs_half_the_footprint_over_the_support():      # ON_MIN_FOOTPRINT_OVERLAP
    # the table ends at x = 0.8; the 10 cm cup reaches 5.5 cm or 4.5 cm over it
    assert ("cup", "ON", "table") in rels([flat_table(), on_table(0.75, x=(0.745, 0.845))])
    assert ("cup", "ON", "table") not in rels([flat_table(), on_table(0.75, x=(0.755, 0.855))])


def test_a_flat_thing_filling_a_slab_is_on_it_only_when_the_slab_is_4x_its_footprint():
    # PILE_BASE_FOOTPRINT_RATIO: a 1 m^2 slab (0.72-0.79 m), a magazine measured into it from below
    slab = box("table", "dining table", (-0.5, -0.5, 0.72), (0.5, 0.5, 0.79))

    def magazine(side):
        return box("mag", "book", (-side / 2, -side / 2, 0.715), (side / 2, side / 2, 0.755))
    assert ("mag", "ON", "table") in rels([slab, magazine(0.4939)])      # slab = 4.1 x its footprint
    assert ("mag", "ON", "table") not in rels([slab, magazine(0.5064)])  # slab = 3.9 x


def test_a_thing_on_a_pile_is_on_the_furniture_under_it_only_when_that_is_4x_the_item_it_touches():
    # PILE_BASE_FOOTPRINT_RATIO in `_drop_pile_middles`: a book on a magazine on a board
    mag = box("m", "magazine", (-0.15, -0.1, 0.75), (0.15, 0.1, 0.77))     # 0.06 m^2
    book = box("b", "book", (-0.1, -0.08, 0.77), (0.1, 0.08, 0.80))

    def board(area):                                                      # 2 cm thick, square
        s = area ** 0.5 / 2
        return box("t", "shelf", (-s, -s, 0.73), (s, s, 0.75))
    assert ("b", "ON", "t") in rels([board(0.06 * 4.2), mag, book])
    r = rels([board(0.06 * 3.8), mag, book])
    assert ("b", "ON", "m") in r and ("b", "ON", "t") not in r


def test_above_reaches_up_to_2_m():                             # ABOVE_MAX_GAP
    shelf = box("shelf", "shelf", (-0.5, -0.2, 0.0), (0.5, 0.2, 0.05))

    def lamp(gap):
        return box("lamp", "lamp", (-0.1, -0.1, 0.05 + gap), (0.1, 0.1, 0.25 + gap))
    assert ("lamp", "ABOVE", "shelf") in rels([shelf, lamp(1.95)])
    assert ("lamp", "ABOVE", "shelf") not in rels([shelf, lamp(2.05)])


def test_a_thing_hanging_below_reaches_up_to_2_m():             # ABOVE_MAX_GAP in UNDER
    shelf = box("shelf", "shelf", (-0.5, -0.2, 2.5), (0.5, 0.2, 2.55))

    def box_below(gap):
        return box("box", "suitcase", (-0.1, -0.1, 2.3 - gap), (0.1, 0.1, 2.5 - gap))
    assert ("box", "UNDER", "shelf") in rels([shelf, box_below(1.95)])
    assert ("box", "UNDER", "shelf") not in rels([shelf, box_below(2.05)])


def test_above_needs_half_the_smaller_footprint_over_the_other():   # VERTICAL_MIN_FOOTPRINT_OVERLAP
    shelf = box("shelf", "shelf", (-0.5, -0.2, 0.0), (0.5, 0.2, 0.05))

    def lamp(x0):                                                       # 20 cm wide, 0.5 m up
        return box("lamp", "lamp", (x0, -0.1, 0.55), (x0 + 0.2, 0.1, 0.75))
    assert ("lamp", "ABOVE", "shelf") in rels([shelf, lamp(0.39)])      # 55 % over the shelf
    assert ("lamp", "ABOVE", "shelf") not in rels([shelf, lamp(0.41)])  # 45 %


def test_under_allows_the_lower_thing_to_rise_8_cm_above_the_top():   # UNDER_TOP_TOLERANCE
    table = box("table", "dining table", (-0.8, -0.45, 0.1), (0.8, 0.45, 0.85))   # seen down to 10 cm

    def stool(top):
        return box("stool", "chair", (-0.2, -0.2, 0.0), (0.2, 0.2, top))
    assert ("stool", "UNDER", "table") in rels([table, stool(0.85 + 0.07)])
    assert ("stool", "UNDER", "table") not in rels([table, stool(0.85 + 0.09)])


def test_side_by_side_needs_bottoms_within_15_cm():            # BASE_TOLERANCE
    a = box("a", "book", (0.0, 0.0, 0.5), (0.2, 0.2, 0.8))

    def b(bottom):
        return box("b", "book", (0.25, 0.0, bottom), (0.45, 0.2, bottom + 0.3))
    assert ("a", "NEXT_TO", "b") in rels([a, b(0.5 + 0.14)])
    assert ("a", "NEXT_TO", "b") not in rels([a, b(0.5 + 0.16)])


def test_in_needs_60_percent_inside():                          # IN_MIN_INSIDE_FRACTION
    bowl = box("bowl", "bowl", (-0.1, -0.1, 0.75), (0.1, 0.1, 0.85))

    def spoon(inside):                                           # 20 cm long, `inside` of it in the bowl
        x0 = 0.1 - inside * 0.2
        return box("spoon", "spoon", (x0, -0.015, 0.78), (x0 + 0.2, 0.015, 0.81))
    assert ("spoon", "IN", "bowl") in rels([bowl, spoon(0.65)])
    assert ("spoon", "IN", "bowl") not in rels([bowl, spoon(0.55)])


def test_side_by_side_allows_a_footprint_overlap_of_90_percent():   # NEXT_TO_MAX_FOOTPRINT_OVERLAP
    a = box("a", "chair", (0.0, 0.0, 0.0), (0.5, 0.5, 0.9))

    def b(overlap):
        x0 = 0.5 * (1 - overlap)
        return box("b", "chair", (x0, 0.0, 0.0), (x0 + 0.5, 0.5, 0.9))
    assert ("a", "NEXT_TO", "b") in rels([a, b(0.85)])
    assert ("a", "NEXT_TO", "b") not in rels([a, b(0.95)])


def test_a_cup_touching_the_edge_of_a_half_metre_support_is_left_to_other_views():   # SUPPORT_MIN_SIDE
    def board(width):                                            # 30 cm deep, top at 0.75
        return box("board", "shelf", (-width, 0.0, 0.71), (0.0, 0.3, 0.75))
    cup_beside = box("cup", "cup", (0.05, 0.1, 0.75), (0.13, 0.18, 0.85))   # 5 cm off its edge
    assert not any({k[0], k[2]} == {"cup", "board"} for k in rels([board(0.52), cup_beside]))
    assert ("board", "NEXT_TO", "cup") in rels([board(0.48), cup_beside])


def _pair(side, gap, label="book"):
    """Two `side`-square boxes on one level, `gap` apart along x."""
    return [box("a", label, (0.0, 0.0, 0.0), (side, side, 0.2)),
            box("b", label, (side + gap, 0.0, 0.0), (2 * side + gap, side, 0.2))]


def test_small_things_are_next_to_each_other_within_10_cm():    # NEXT_TO_MIN_GAP
    assert ("a", "NEXT_TO", "b") in rels(_pair(0.08, 0.09, "cup"))
    r = rels(_pair(0.08, 0.11, "cup"))
    assert ("a", "NEXT_TO", "b") not in r and ("a", "NEAR", "b") in r


def test_next_to_allows_one_mean_side_of_gap():                 # NEXT_TO_GAP_FRACTION
    assert ("a", "NEXT_TO", "b") in rels(_pair(0.3, 0.28))
    assert ("a", "NEXT_TO", "b") not in rels(_pair(0.3, 0.32))


def test_big_things_are_next_to_each_other_within_60_cm():      # NEXT_TO_MAX_GAP
    assert ("a", "NEXT_TO", "b") in rels(_pair(1.0, 0.58))
    assert ("a", "NEXT_TO", "b") not in rels(_pair(1.0, 0.62))


def test_near_reaches_at_least_40_cm():                         # NEAR_MIN_GAP
    assert ("a", "NEAR", "b") in rels(_pair(0.08, 0.38, "cup"))
    assert not rels(_pair(0.08, 0.42, "cup"))


def test_near_reaches_half_the_larger_objects_extent():         # NEAR_SIZE_FRACTION (1.4 m: 70 cm)
    def pair(gap):
        return [box("a", "couch", (0.0, 0.0, 0.0), (1.4, 0.8, 0.8)),
                box("b", "box", (1.4 + gap, 0.0, 0.0), (1.6 + gap, 0.2, 0.2))]
    assert ("a", "NEAR", "b") in rels(pair(0.67))
    assert not any(k[1] == "NEAR" for k in rels(pair(0.73)))


def test_near_reaches_no_farther_than_1_m():                    # NEAR_MAX_GAP (a 2.4 m bed)
    def pair(gap):
        return [box("a", "bed", (0.0, 0.0, 0.0), (2.4, 1.6, 0.5)),
                box("b", "box", (2.4 + gap, 0.0, 0.0), (2.6 + gap, 0.2, 0.2))]
    assert ("a", "NEAR", "b") in rels(pair(0.95))
    assert not any(k[1] == "NEAR" for k in rels(pair(1.05)))


def test_bigger_means_half_as_big_again():                      # BIGGER_VOLUME_RATIO
    def cups(ratio):
        return [box("c1", "cup", (0.0, 0.0, 0.0), (0.1, 0.1, 0.1 * ratio)),
                box("c2", "cup", (2.0, 0.0, 0.0), (2.1, 0.1, 0.1))]
    assert ("c1", "BIGGER_THAN", "c2") in rels(cups(1.55))
    assert not any(k[1] == "BIGGER_THAN" for k in rels(cups(1.45)))


def test_boxes_thinner_than_2_cm_are_padded_to_2_cm():           # MIN_EXTENT
    def sheets(t1, t2):                                          # two same-label sheets far apart
        return [box("p1", "paper", (0.0, 0.0, 0.0), (0.3, 0.2, t1)),
                box("p2", "paper", (3.0, 0.0, 0.0), (3.3, 0.2, t2))]
    assert not any(k[1] == "BIGGER_THAN" for k in rels(sheets(0.015, 0.001)))   # both read 2 cm
    assert ("p1", "BIGGER_THAN", "p2") in rels(sheets(0.031, 0.019))            # 3.1 cm vs 2 cm


def test_a_gap_exactly_at_a_limit_falls_on_one_side_whatever_its_last_bits():   # fixed_precision
    # boxes found from depth are whole 2.5 cm voxels: bottoms 0.15 m apart sit on BASE_TOLERANCE,
    # and another CPU's kernels leave other last bits in their centres
    def pair(nudge):
        a = ObjectGeometry("a", "object", (0.0, 0.0, np.nextafter(0.275, nudge)), (0.2, 0.2, 0.55))
        b = ObjectGeometry("b", "object", (0.3, 0.0, 0.25), (0.2, 0.2, 0.2))
        return rels([a, b], up=np.nextafter(np.array(UP), nudge))
    assert pair(-1.0) == pair(2.0)


def test_the_horizontal_frame_does_not_change_with_the_last_bits_of_up():
    up = np.array([0.0057479404968467694, -0.9051718177927078, -0.42500698988827196])
    for a, b in zip(horizontal_basis(up), horizontal_basis(np.nextafter(up, 1.0))):
        assert np.array_equal(a, b)


def test_a_stage_hands_on_metres_to_the_micrometre():            # METRES_DECIMALS
    from sg3d.core.geometry import fixed_precision

    assert fixed_precision(np.nextafter(0.15, 1.0)) == fixed_precision(np.nextafter(0.15, 0.0)) == 0.15
    assert fixed_precision(0.1500004) == 0.15 and fixed_precision(0.1500006) == 0.150001
