"""The evidence an alignment needs before `sg3d rooms link` stores it (`sg3d.merge.align`), on
hand-made alignments: both sides of every rule."""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.merge.align import (
    MAX_RESIDUAL_M,
    MAX_UP_ANGLE_DEG,
    MIN_EVIDENCE_PAIRS,
    MIN_INLIER_SHARE,
    SIZE_FLOOR_M,
    SIZE_RATIO_MAX,
    Alignment,
    evidence_problem,
    sizes_compatible,
    up_angle_deg,
)


def alignment(evidence: int, pairs: int = 10, matchable: int = 10, residual: float = 0.02) -> Alignment:
    return Alignment(T=np.eye(4), residual_rms_m=residual, pairs=[(f"a{k}", f"b{k}") for k in range(pairs)],
                     evidence=[(f"a{k}", f"b{k}") for k in range(evidence)], matchable=matchable)


def test_the_rules_are_what_the_comments_say():
    assert (MIN_EVIDENCE_PAIRS, MIN_INLIER_SHARE, MAX_RESIDUAL_M, MAX_UP_ANGLE_DEG) == (3, 0.3, 0.15, 10.0)
    assert (SIZE_RATIO_MAX, SIZE_FLOOR_M) == (2.0, 0.05)


def test_three_object_pairs_are_enough_two_are_not():                     # MIN_EVIDENCE_PAIRS
    assert evidence_problem(alignment(3, matchable=3)) is None
    why = evidence_problem(alignment(2, matchable=3))
    assert why is not None and "only 2 of the 10 pairs" in why and "at least 3" in why


def test_the_evidence_must_be_a_share_of_what_could_match():              # MIN_INLIER_SHARE
    assert evidence_problem(alignment(3, matchable=10)) is None           # 30 %
    why = evidence_problem(alignment(3, matchable=11))                    # 27 %
    assert why is not None and "3 of 11 objects" in why


def test_the_residual_bound():                                             # MAX_RESIDUAL_M
    assert evidence_problem(alignment(5, residual=0.149)) is None
    why = evidence_problem(alignment(5, residual=0.151))
    assert why is not None and "residual is 0.15 m" in why


def test_the_floors_must_agree_after_the_transform():                     # MAX_UP_ANGLE_DEG
    assert evidence_problem(alignment(5), up_angle=9.9) is None
    why = evidence_problem(alignment(5), up_angle=10.1)
    assert why is not None and "tilts" in why
    assert evidence_problem(alignment(5), up_angle=None) is None           # a room without an up


def test_up_angle_carries_room_bs_up_into_room_as_frame():
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("x", 90, degrees=True).as_matrix()
    assert abs(up_angle_deg(T, [0, 0, 1], [0, 1, 0])) < 1e-6              # y-up in B is z-up in A
    assert abs(up_angle_deg(T, [0, 0, 1], [0, -1, 0]) - 180.0) < 1e-6     # a room turned upside down
    assert abs(up_angle_deg(np.eye(4), [0, 0, 1], [0, 1, 0]) - 90.0) < 1e-6
    assert up_angle_deg(np.eye(4), None, [0, 0, 1]) is None
    assert up_angle_deg(np.eye(4), [0, 0, 0], [0, 0, 1]) is None


def test_sizes_agree_within_a_factor_of_two_per_sorted_extent():          # SIZE_RATIO_MAX
    chair = {"size": [0.5, 0.6, 0.9]}
    assert sizes_compatible(chair, {"size": [0.6, 0.5, 0.9]})              # the axes may swap between rooms
    assert sizes_compatible(chair, {"size": [0.99, 1.19, 1.79]})           # x1.99 each
    assert not sizes_compatible(chair, {"size": [1.01, 1.21, 1.81]})       # x2.02 each
    assert sizes_compatible(chair, {"size": None}) and sizes_compatible({}, chair)


def test_thin_extents_count_as_the_floor():                               # SIZE_FLOOR_M
    # a 1 mm and a 4 cm thick board: both read as 5 cm, so their thickness does not decide
    assert sizes_compatible({"size": [0.001, 0.8, 0.4]}, {"size": [0.04, 0.8, 0.4]})
    assert not sizes_compatible({"size": [0.001, 0.8, 0.4]}, {"size": [0.11, 0.8, 0.4]})
