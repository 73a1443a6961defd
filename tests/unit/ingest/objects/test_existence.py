"""Does a hypothesis exist (`sg3d.ingest.objects.existence`): Bayes over detections and the views that
should have shown it, the size prior, tile artefacts, the visibility test (on real kitchen
frames: tests/quality/kitchen/test_kitchen_ingest.py)."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.detect.models import Detection
from sg3d.ingest.objects import existence


def test_existence_probability_is_bayes_over_two_binomials():
    k, n, pr, pf = 2, 10, 0.25, 0.10
    real, false = pr ** k * (1 - pr) ** (n - k), pf ** k * (1 - pf) ** (n - k)
    expected = real / (real + false)
    assert existence.existence_probability(k, n, pr, pf, 0.5) == pytest.approx(expected)
    # more detections among the same views, more belief; more silent views, less
    assert existence.existence_probability(5, 10) > existence.existence_probability(2, 10)
    assert existence.existence_probability(2, 40) < existence.existence_probability(2, 10)


def test_size_prior_relabels_or_rejects():
    assert existence.plausible_labels(["cell phone", "book"], [0.4, 0.2], (0.45, 0.36, 0.1)) == (["book"], [0.2])
    assert existence.plausible_labels(["cup"], [0.5], (1.5, 0.9, 0.8)) == ([], [])
    # what is left after the prior is a faint guess, not a reading of the object: rejected
    box = (0.36, 0.46, 0.1)
    assert existence.plausible_labels(["cell phone", "remote", "book"], [0.28, 0.10, 0.09], box) == ([], [])
    assert existence.plausible_labels(["cell phone", "remote", "book"], [0.28, 0.10, 0.14], box) == (["book"], [0.14])
    assert existence.size_plausible("chair", (0.5, 0.5, 0.9))


def test_size_prior_allows_for_the_percentile_box():
    """A table at the smallest plausible size, its points spread evenly, measures less than that
    size between the box percentiles; the prior still lets it be a table, not a much smaller box,
    and the upper bound stays the class's own."""
    from sg3d.ingest.objects.attributes import BOX_HIGH_PERCENTILE, BOX_LOW_PERCENTILE

    smallest, largest = existence.class_sizes()["dining table"]
    along = np.linspace(0.0, smallest, 2001)
    measured = float(np.percentile(along, BOX_HIGH_PERCENTILE) - np.percentile(along, BOX_LOW_PERCENTILE))
    assert measured < smallest
    assert existence.size_plausible("dining table", (measured, 0.3, 0.4))
    assert not existence.size_plausible("dining table", (0.8 * smallest, 0.3, 0.4))
    assert not existence.size_plausible("dining table", (largest * 1.01, 0.3, 0.4))


def test_an_object_only_tiles_named_though_big_enough_for_the_full_frame_is_a_tile_artefact():
    def det(side, full):
        return Detection((10, 10, 10 + side, 10 + side * 0.6), ["laptop"], [0.4], full)

    assert existence.tile_artefact([det(200, False), det(180, False), det(150, False)])
    assert not existence.tile_artefact([det(200, False), det(180, True)])      # the full frame named it once
    assert not existence.tile_artefact([det(90, False), det(60, False)])       # small: what tiles are for
    assert not existence.tile_artefact([])


# --------------------------------------------------------------------------- each threshold, on both sides

def _view(depth_m: float = 0.0):
    """A 640 x 480 camera at the origin looking along +z (f = 500 px), its small depth all `depth_m`."""
    K = np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]])
    return existence.View(0, K, np.eye(4), (640, 480), np.full((120, 160), depth_m, np.float32))


def _weight(centre, extent, depth_m=None):
    return existence.expected_in_view(centre, extent, _view(centre[2] if depth_m is None else depth_m))


def test_a_view_shows_what_lies_within_4_5_m():                    # MAX_RANGE_M
    assert _weight((0, 0, 4.4), 0.3) > 0
    assert _weight((0, 0, 4.6), 0.3) == 0.0


def test_a_view_shows_what_projects_5_percent_inside_its_border():  # BORDER_MARGIN
    def at(u):                                                        # 2 m away, at pixel column u
        return _weight(((u - 320) * 2.0 / 500.0, 0, 2.0), 0.3)
    assert at(0.06 * 640) > 0
    assert at(0.04 * 640) == 0.0


def test_a_view_shows_what_spans_24_pixels():                       # MIN_PIXELS (2 m away: 250 px per m)
    assert _weight((0, 0, 2.0), 0.100) > 0            # 25 px
    assert _weight((0, 0, 2.0), 0.092) == 0.0         # 23 px


def test_a_view_counts_fully_from_120_pixels_on():                  # FULL_VIEW_PIXELS
    assert _weight((0, 0, 2.0), 0.24) == pytest.approx(0.5)          # 60 px
    assert _weight((0, 0, 2.0), 0.52) == 1.0                          # 130 px


def test_a_surface_15_cm_before_the_objects_front_occludes_it():    # OCCLUSION_TOLERANCE_M
    # a 40 cm object 2 m away: its front at 1.8 m
    assert _weight((0, 0, 2.0), 0.4, depth_m=1.8 - 0.14) > 0
    assert _weight((0, 0, 2.0), 0.4, depth_m=1.8 - 0.16) == 0.0


def test_a_views_depth_is_kept_at_a_quarter_resolution_down_to_160_pixels():   # DEPTH_FACTOR, MIN_GRID_WIDTH
    from types import SimpleNamespace

    def grid(w, h):
        frame = SimpleNamespace(index=3, K=_view().K, pose=np.eye(4), size=(w, h), depth=np.ones((h, w), np.float32))
        return existence.View.of(frame).depth.shape

    assert grid(640, 480) == (120, 160)
    assert grid(1280, 720) == (180, 320)
    assert grid(320, 240) == (120, 160)
    assert grid(160, 120) == (120, 160)


def test_the_grid_shrinks_by_less_than_four_below_640_pixels():     # depth_factor
    assert existence.depth_factor(640) == 4 and existence.depth_factor(639) == 3
    assert existence.depth_factor(320) == 2 and existence.depth_factor(319) == 1
    assert existence.depth_factor(100) == 1


def test_only_tiles_naming_a_box_of_120_pixels_is_an_artefact():    # TILE_ONLY_MAX_PIXELS
    def tiles(side):
        return [Detection((0, 0, side, side * 0.5), ["laptop"], [0.4], False)] * 3
    assert existence.tile_artefact(tiles(125))
    assert not existence.tile_artefact(tiles(115))


def _exists(k: int, expected: float) -> bool:
    return existence.exists(existence.Evidence(k, expected, existence.existence_probability(k, expected)))


def test_two_detections_make_an_object_in_up_to_12_views():
    # P_DETECT_REAL 0.25, P_DETECT_FALSE 0.10, PRIOR_REAL 0.5 and EXISTENCE_THRESHOLD 0.5 put the
    # even odds of 2 detections at 12.05 expected views
    assert _exists(2, 11.5)
    assert not _exists(2, 12.5)


def test_an_object_needs_two_detections():                        # MIN_DETECTIONS
    assert existence.exists(existence.Evidence(2, 2.0, 0.99))
    assert not existence.exists(existence.Evidence(1, 1.0, 0.99))


def test_an_object_needs_even_odds():                             # EXISTENCE_THRESHOLD
    assert existence.exists(existence.Evidence(5, 10.0, 0.52))
    assert not existence.exists(existence.Evidence(5, 10.0, 0.48))


def test_a_label_the_size_prior_leaves_must_have_half_the_best_labels_evidence():   # RELABEL_MIN_SHARE
    box = (0.45, 0.36, 0.1)                                          # too big for a cell phone
    assert existence.plausible_labels(["cell phone", "book"], [0.4, 0.22], box) == (["book"], [0.22])
    assert existence.plausible_labels(["cell phone", "book"], [0.4, 0.18], box) == ([], [])


# --------------------------------------------------------------------------- the sizes the size prior judges

def _views(sizes, cut):
    from types import SimpleNamespace

    return [SimpleNamespace(attrs=SimpleNamespace(size=s, cut=c)) for s, c in zip(sizes, cut)]


def test_too_big_is_judged_on_the_median_view_not_the_union():
    # a chair seen in 5 views, 2 of whose boxes ran 1.7 m along the floor through its open base
    sizes = [(0.5, 0.5, 0.8)] * 3 + [(0.6, 1.7, 0.8)] * 2
    big, small = existence.judged_sizes(_views(sizes, [False] * 5), (0.6, 1.7, 0.8))
    assert existence.plausible_labels(["chair"], [0.9], big, small) == (["chair"], [0.9])
    sizes = [(0.5, 0.5, 0.8)] * 2 + [(0.6, 1.7, 0.8)] * 3     # most views that long: too big
    big, small = existence.judged_sizes(_views(sizes, [False] * 5), (0.6, 1.7, 0.8))
    assert existence.plausible_labels(["chair"], [0.9], big, small) == ([], [])


def test_an_object_cut_by_the_border_in_half_its_views_is_never_too_small():    # CUT_SHARE
    # a couch (at least 0.6 m) seen as 0.4 m: too small unless its views are cut
    sizes = [(0.4, 0.3, 0.3)] * 4
    for cut, ok in (([True, True, False, False], True), ([True, False, False, False], False)):
        big, small = existence.judged_sizes(_views(sizes, cut), (0.4, 0.3, 0.3))
        assert bool(existence.plausible_labels(["couch"], [0.9], big, small)[0]) is ok
    # ... while too big still counts in cut views
    big, small = existence.judged_sizes(_views([(5.0, 0.3, 0.3)] * 4, [True] * 4), (5.0, 0.3, 0.3))
    assert existence.plausible_labels(["couch"], [0.9], big, small) == ([], [])
