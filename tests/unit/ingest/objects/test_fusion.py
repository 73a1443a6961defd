"""Whole-sequence fusion (`sg3d.ingest.objects.fusion`): association, consolidation, the fused box.

Hand-made sightings check the rules exactly (the existence test: test_existence.py beside this).
"""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import HIST_SIZE
from sg3d.ingest.detect.models import Detection
from sg3d.ingest.objects import fusion
from sg3d.ingest.objects.attributes import ObjectAttributes


def _sighting(frame: int, label: str, centre, size, score: float = 0.8, labels=None) -> fusion.Sighting:
    attrs = ObjectAttributes(mean=tuple(centre), var=(1e-4,) * 3, n_points=50, size=tuple(size),
                             hist=np.ones(HIST_SIZE), colour="white", thumbnail=b"jpg", centre=tuple(centre))
    names = labels or [label]
    det = Detection((0, 0, 10, 10), names, [score / (k + 1) for k in range(len(names))])
    return fusion.Sighting.of(frame, det, attrs, np.eye(3))


# --------------------------------------------------------------------------- association

def test_two_cups_side_by_side_stay_two_objects_and_later_views_join_them():
    s = [_sighting(0, "cup", (0.0, 0, 0), (0.1, 0.1, 0.1)), _sighting(0, "cup", (0.2, 0, 0), (0.1, 0.1, 0.1)),
         _sighting(5, "cup", (0.02, 0, 0), (0.1, 0.1, 0.1)), _sighting(9, "cup", (0.21, 0, 0), (0.1, 0.1, 0.1))]
    hyps = fusion.consolidate(fusion.associate(s))
    assert sorted(h.frames for h in hyps) == [[0, 5], [0, 9]]


def test_a_table_seen_in_two_parts_is_one_object():
    left = _sighting(0, "dining table", (-0.45, 0, 0), (1.1, 0.8, 0.05))
    right = _sighting(7, "dining table", (0.35, 0, 0), (1.7, 0.8, 0.05))    # centres 0.8 m apart
    hyps = fusion.consolidate(fusion.associate([left, right]))
    assert len(hyps) == 1 and hyps[0].frames == [0, 7]
    assert hyps[0].hi[0] - hyps[0].lo[0] > 1.3      # the box spans both parts


def test_a_differently_named_neighbour_does_not_join():
    chair = [_sighting(i, "chair", (0, 0, 0), (0.5, 0.5, 0.9)) for i in range(3)]
    vase = _sighting(3, "vase", (0.2, 0, 0.5), (0.1, 0.1, 0.2), labels=["vase", "cup"])
    hyps = fusion.associate(chair + [vase])
    assert sorted(h.label for h in hyps) == ["chair", "vase"]


def test_a_double_box_in_one_frame_is_suppressed():
    whole = _sighting(0, "chair", (0, 0, 0), (0.5, 0.5, 0.9), score=0.9)
    seat = _sighting(0, "chair", (0, 0, -0.1), (0.4, 0.4, 0.3), score=0.4)
    assert fusion.suppress_duplicates([seat, whole]) == [whole]


def test_label_evidence_accumulates_so_the_repeated_label_wins():
    s = [_sighting(0, "tv", (0, 0, 0), (0.3, 0.2, 0.05), score=0.9, labels=["tv", "book"])]
    s += [_sighting(i, "book", (0, 0, 0), (0.3, 0.2, 0.05), score=0.5, labels=["book", "tv"]) for i in range(1, 5)]
    hyp = fusion.consolidate(fusion.associate(s))
    assert len(hyp) == 1 and hyp[0].label == "book"


def test_fuse_labels_means_over_all_detections():
    from types import SimpleNamespace

    def seen(labels, scores):
        return SimpleNamespace(detection=Detection((0, 0, 1, 1), labels, scores))

    members = [seen(["cup", "bowl"], [0.6, 0.3]), seen(["cup"], [0.8]),
               seen(["bowl", "cup", "vase"], [0.9, 0.4, 0.2])]
    labels, scores = fusion.fuse_labels(members)
    assert labels == ["cup", "bowl", "vase"]
    assert scores == pytest.approx([(0.6 + 0.8 + 0.4) / 3, (0.3 + 0.9) / 3, 0.2 / 3])
    assert fusion.fuse_labels(members, top_k=1) == (["cup"], [pytest.approx(0.6)])
    assert fusion.fuse_labels([]) == ([], [])


def test_the_object_box_reaches_as_far_as_a_few_views_agree_but_heights_keep_the_core():
    # 60 views of the left part of a table, 4 (5 %) that also see its far right end, 1 shifted box
    views = [_sighting(i, "dining table", (0.0, 0, 0.72), (1.2, 0.8, 0.05)) for i in range(60)]
    views += [_sighting(60 + i, "dining table", (0.5, 0, 0.72), (2.2, 0.8, 0.05)) for i in range(4)]
    views += [_sighting(64, "dining table", (0.0, 0.5, 0.72), (1.2, 0.8, 0.05))]
    hyp = fusion.Hypothesis(0, views)
    lo, hi = fusion.object_box(hyp)
    assert hi[0] == pytest.approx(1.6)                 # the far end, seen by 4 views of 65
    assert hyp.hi[0] == pytest.approx(0.6)             # the association core does not reach it
    assert hi[1] == pytest.approx(0.4)                 # the one shifted box does not widen it
    assert (lo[2], hi[2]) == (hyp.lo[2], hyp.hi[2])    # heights: the percentile core
    obs = fusion.fuse("t", hyp, np.eye(3))
    assert obs.size[0] == pytest.approx(hi[0] - lo[0]) and obs.box_centre[0] == pytest.approx((lo[0] + hi[0]) / 2)
    # a mug is seen whole in every view: its outermost boxes (one took in the magazine) are noise
    mug = [_sighting(i, "cup", (0.0, 0, 0.8), (0.1, 0.1, 0.1)) for i in range(60)]
    mug += [_sighting(60 + i, "cup", (0.1, 0, 0.8), (0.3, 0.1, 0.1)) for i in range(4)]
    cup = fusion.Hypothesis(1, mug)
    lo, hi = fusion.object_box(cup)
    assert (list(lo), list(hi)) == (list(cup.lo), list(cup.hi)) and hi[0] == pytest.approx(0.05)


def test_a_chairs_back_and_base_boxed_in_different_tiles_are_one_chair():
    # tiles box the back (upper half) in some frames, the base in others, both in one frame:
    # their 3-D boxes barely overlap, but two chairs cannot stand in one place
    back = [_sighting(i, "chair", (0.4, 1.5, 0.15), (0.5, 0.7, 0.5)) for i in range(0, 12, 2)]
    base = [_sighting(i, "chair", (0.4, 1.5, -0.35), (0.6, 0.7, 0.5)) for i in range(1, 12, 2)]
    base.append(_sighting(4, "chair", (0.4, 1.5, -0.35), (0.6, 0.7, 0.5)))
    hyps = fusion.consolidate(fusion.associate(back + base))
    assert len(hyps) == 1 and hyps[0].n_frames == 12
    # two cups stacked in one place are two cups: only floor-standing furniture is exclusive
    low = [_sighting(i, "cup", (0, 0, 0.05), (0.1, 0.1, 0.1)) for i in range(4)]
    high = [_sighting(i, "cup", (0, 0, 0.35), (0.1, 0.1, 0.1)) for i in range(4)]
    assert len(fusion.consolidate(fusion.associate(low + high))) == 2


def test_a_part_read_as_another_label_folds_into_the_whole_only_when_seen_apart():
    tv = [_sighting(i, "tv", (1.6, 1.7, 0.6), (0.7, 0.2, 0.45), score=0.6) for i in range(10, 16)]
    corner = [_sighting(i, "book", (1.5, 1.7, 0.6), (0.4, 0.15, 0.4), score=0.3, labels=["book", "tv"])
              for i in range(0, 5)]
    hyps = fusion.consolidate(fusion.associate(tv + corner))
    assert len(hyps) == 1 and hyps[0].label == "tv" and hyps[0].n_frames == 11
    # a book that never lists "tv" stays a book; one seen with the TV in the same frames too
    book = [_sighting(i, "book", (1.5, 1.7, 0.6), (0.4, 0.15, 0.4), score=0.3) for i in range(0, 5)]
    assert sorted(h.label for h in fusion.consolidate(fusion.associate(tv + book))) == ["book", "tv"]
    together = [_sighting(i, "book", (1.5, 1.7, 0.6), (0.4, 0.15, 0.4), score=0.3, labels=["book", "tv"])
                for i in range(10, 15)]
    assert not fusion.part_read_as_other(fusion.Hypothesis(1, together), fusion.Hypothesis(0, tv))
    assert fusion.part_read_as_other(fusion.Hypothesis(1, corner), fusion.Hypothesis(0, tv))


def test_same_label_hypotheses_never_seen_together_that_share_space_are_one_object():
    """A TV seen from one side with the wall behind it in its box, and later from the other side
    with a wider box: the centres lie beyond the gate, but never in one frame and a quarter of
    the smaller box shared, they are one TV. Seen in the same frames, they are two."""
    first = [_sighting(i, "tv", (0.25, 0.0, 0.0), (0.49, 0.27, 0.39)) for i in range(0, 6)]
    later = [_sighting(i, "tv", (0.67, -0.08, 0.0), (0.78, 0.08, 0.40)) for i in range(10, 16)]
    hyps = fusion.consolidate(fusion.associate(first + later))
    assert len(hyps) == 1 and hyps[0].n_frames == 12
    together = [_sighting(i, "tv", (0.67, -0.08, 0.0), (0.78, 0.08, 0.40)) for i in range(0, 6)]
    assert len(fusion.consolidate(fusion.associate(first + together))) == 2


# --------------------------------------------------------------------------- each threshold, on both sides

def _n_objects(sightings) -> int:
    return len(fusion.associate(sightings))


def test_small_things_join_within_25_cm():                       # ASSOC_MAX_DISTANCE
    cup = (0.1, 0.1, 0.1)
    assert _n_objects([_sighting(0, "cup", (0, 0, 0), cup), _sighting(1, "cup", (0.24, 0, 0), cup)]) == 1
    assert _n_objects([_sighting(0, "cup", (0, 0, 0), cup), _sighting(1, "cup", (0.26, 0, 0), cup)]) == 2


def test_big_things_join_within_half_their_extent():             # ASSOC_EXTENT_FRACTION (a 1 m bench: 50 cm)
    bench = (1.0, 0.2, 0.2)
    assert _n_objects([_sighting(0, "bench", (0, 0, 0), bench), _sighting(1, "bench", (0, 0.48, 0), bench)]) == 1
    assert _n_objects([_sighting(0, "bench", (0, 0, 0), bench), _sighting(1, "bench", (0, 0.52, 0), bench)]) == 2


def test_another_best_label_costs_half_a_gate():                 # LABEL_MISMATCH_COST (gate 25 cm: 12.5 cm)
    def joined(bench_x: float) -> int:
        """The hypothesis a "bench" (listing "chair") 2 cm from a "chair" joins, with the bench at x."""
        first = [_sighting(0, "chair", (0, 0, 0), (0.1,) * 3, labels=["chair", "bench"]),
                 _sighting(0, "bench", (bench_x, 0, 0), (0.1,) * 3)]
        seen = _sighting(1, "bench", (0.02, 0, 0), (0.1,) * 3, labels=["bench", "chair"])
        return next(h.hid for h in fusion.associate(first + [seen]) if 1 in h.frames)
    assert joined(0.15) == 1          # the bench is 11 cm farther than the chair: the same label wins
    assert joined(0.18) == 0          # 14 cm farther: the chair, though named otherwise


def test_a_second_box_over_half_inside_another_in_one_frame_is_a_duplicate():   # PART_OVERLAP
    whole = _sighting(0, "chair", (0, 0, 0), (0.5, 0.5, 0.9), score=0.9)

    def part(x):                                        # a 40 cm cube reaching past the chair's side
        return _sighting(0, "chair", (x, 0, 0), (0.4, 0.4, 0.4), score=0.4)
    assert fusion.suppress_duplicates([whole, part(0.23)]) == [whole]     # 55 % of it inside
    assert len(fusion.suppress_duplicates([whole, part(0.27)])) == 2      # 45 %


def _apart(shift: float, first=range(0, 6), later=range(10, 16)):
    """A 50 cm TV seen in `first` frames and one `shift` further along x in `later` frames."""
    size = (0.5, 0.1, 0.4)
    return ([_sighting(i, "tv", (0.25, 0, 0), size) for i in first]
            + [_sighting(i, "tv", (0.25 + shift, 0, 0), size) for i in later])


def test_hypotheses_seen_apart_fold_when_they_share_a_quarter_of_the_smaller_box():   # APART_OVERLAP
    assert len(fusion.associate(_apart(0.35))) == 2                               # beyond the gate
    assert len(fusion.consolidate(fusion.associate(_apart(0.35)))) == 1           # 30 % shared
    assert len(fusion.consolidate(fusion.associate(_apart(0.40)))) == 2           # 20 %


def test_hypotheses_seen_together_in_a_tenth_of_their_frames_are_still_apart():   # MAX_SHARED_FRAMES
    def objects(shared: int) -> int:
        return len(fusion.consolidate(fusion.associate(
            _apart(0.35, range(0, 20), range(20 - shared, 40 - shared)))))
    assert objects(2) == 1            # 2 of 20 frames together
    assert objects(3) == 2            # 3 of 20


def test_a_part_named_otherwise_folds_when_70_percent_of_it_lies_inside_the_whole():   # NESTED_OVERLAP
    tv = fusion.Hypothesis(0, [_sighting(i, "tv", (0, 0, 0), (0.7, 0.2, 0.45)) for i in range(10, 16)])

    def corner(x):                  # a 40 cm "book" (listing "tv") reaching past the TV's side
        return fusion.Hypothesis(1, [_sighting(i, "book", (x, 0, 0), (0.4, 0.15, 0.4), labels=["book", "tv"])
                                     for i in range(0, 5)])
    assert fusion.part_read_as_other(corner(0.25), tv)          # 75 % inside
    assert not fusion.part_read_as_other(corner(0.29), tv)      # 65 %


def test_a_hypothesis_box_spans_the_20th_to_80th_percentile_of_its_sightings():   # BOX_LOW/HIGH_PERCENTILE
    hyp = fusion.Hypothesis(0, [_sighting(i, "cup", (0.1 * i, 0, 0), (0.1, 0.1, 0.1)) for i in range(10)])
    # lower bounds -0.05 .. 0.85, upper bounds 0.05 .. 0.95 in steps of 0.1
    assert hyp.lo[0] == pytest.approx(0.13) and hyp.hi[0] == pytest.approx(0.77)


def _table_views(n: int, reaching: int, width: float = 1.2):
    """n views of a table top `width` wide, `reaching` of them also seeing 1 m more of it."""
    views = [_sighting(i, "dining table", (0, 0, 0.72), (width, 0.3, 0.05)) for i in range(n - reaching)]
    views += [_sighting(n - reaching + i, "dining table", (0.5, 0, 0.72), (width + 1.0, 0.3, 0.05))
              for i in range(reaching)]
    return fusion.Hypothesis(0, views)


def test_the_object_box_reaches_as_far_as_three_views_agree():     # BOX_SUPPORT
    assert fusion.object_box(_table_views(20, 3))[1][0] == pytest.approx(1.6)
    assert fusion.object_box(_table_views(20, 2))[1][0] == pytest.approx(0.6)


def test_of_many_views_five_percent_must_agree():                  # BOX_SUPPORT_FRACTION
    assert fusion.object_box(_table_views(100, 5))[1][0] == pytest.approx(1.6)
    assert fusion.object_box(_table_views(100, 4))[1][0] == pytest.approx(0.6)


def test_only_objects_half_a_metre_wide_are_seen_in_parts():       # PART_VIEW_MIN_EXTENT
    assert fusion.object_box(_table_views(20, 3, width=0.52))[1][0] == pytest.approx(0.26 + 0.5 + 0.5)
    assert fusion.object_box(_table_views(20, 3, width=0.48))[1][0] == pytest.approx(0.24)
