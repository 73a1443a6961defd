"""Same-node similarity (paper Eq. 10-15) and the update rules, on hand-computed numbers."""
from __future__ import annotations

import math

import numpy as np

from sg3d.merge.similarity import (
    SimilarityParams,
    histogram_intersection,
    label_score,
    label_similarity,
    position_similarity,
    total_similarity,
)
from sg3d.merge.update import combine_gaussians, combine_labels


def phi(z):  # standard normal CDF, written out so the test does not share SciPy's path
    return 0.5 * (1 + math.erf(z / math.sqrt(2)))


def test_label_score_is_the_max_over_both_sets():
    assert label_score([0.2, 0.7], [0.5]) == 0.7


def test_label_similarity_shared_labels_and_word_distance():
    assert label_similarity(["cup", "bowl"], [0.8, 0.1], ["cup", "vase"], [0.6, 0.2], 0.1) == 0.8 * 1 / 2
    assert label_similarity(["cup"], [0.8], ["cup"], [0.9], 0.0) == 0.9
    assert math.isclose(label_similarity(["cup"], [0.8], ["mug"], [0.5], 0.71), 0.71 * 0.8)


def test_position_similarity_is_one_inside_sigma_and_a_tail_ratio_outside():
    mean_o, var_o = (0.0, 0.0, 0.0), (0.25, 0.25, 0.25)  # sigma 0.5
    assert position_similarity(mean_o, var_o, (0.4, -0.4, 0.1)) == 1.0
    z = 1.0 / 0.5
    expected = (1 - phi(z) + phi(-z)) / (1 - phi(1) + phi(-1))
    assert math.isclose(position_similarity(mean_o, var_o, (1.0, 0.0, 0.0)), expected, rel_tol=1e-9)
    assert position_similarity(mean_o, var_o, (5.0, 0.0, 0.0)) < 1e-6


def test_histogram_intersection_normalises_by_the_smaller_histogram():
    a = np.array([10, 0, 5, 5], float)
    b = np.array([5, 5, 0, 0], float)
    assert histogram_intersection(a, b) == 5 / 10
    assert histogram_intersection(a, a) == 1.0


def test_total_similarity_uses_the_papers_weights():
    p = SimilarityParams()
    assert math.isclose(total_similarity(1.0, 1.0, 1.0, p), 1.0)
    assert math.isclose(total_similarity(0.0, 1.0, 1.0, p), 0.625)
    assert total_similarity(0.0, 1.0, 1.0, p) < p.threshold


def test_window_margin_excludes_only_candidates_that_cannot_match():
    p = SimilarityParams()
    margin = p.window_margin()
    # a candidate just outside the margin, with the largest sigma and perfect label/colour
    just_out = position_similarity((0, 0, 0), (p.sigma_cap ** 2,) * 3, (margin * 1.01, 0, 0))
    just_in = position_similarity((0, 0, 0), (p.sigma_cap ** 2,) * 3, (margin * 0.99, 0, 0))
    assert total_similarity(1.0, 1.0, just_out, p) < p.threshold <= total_similarity(1.0, 1.0, just_in, p)


def test_combine_labels_keeps_top_k_by_max_score():
    labels, scores = combine_labels(["cup", "bowl"], [0.5, 0.4], ["bowl", "vase"], [0.9, 0.1], k=2)
    assert labels == ["bowl", "cup"] and scores == [0.9, 0.5]


def test_combine_gaussians_equals_recomputing_over_all_points():
    rng = np.random.default_rng(0)
    a, b = rng.normal(1, 0.2, (50, 3)), rng.normal(1.3, 0.1, (150, 3))
    mean, var, n = combine_gaussians(a.mean(0), a.var(0), 50, b.mean(0), b.var(0), 150)
    both = np.vstack([a, b])
    assert n == 200
    assert np.allclose(mean, both.mean(0)) and np.allclose(var, both.var(0))


def test_label_similarity_matrix_matches_the_pairwise_equation():
    from sg3d.core.embedding import default_embedding, similarity
    from sg3d.merge.similarity import label_similarity_matrix

    emb = default_embedding()
    new = [(["cup", "bowl"], [0.8, 0.1]), (["couch"], [0.6])]
    old = [(["cup", "vase"], [0.5, 0.2]), (["mug"], [0.9]), (["chair", "couch"], [0.7, 0.4])]
    mat = label_similarity_matrix([lbl for lbl, _ in new], [s for _, s in new],
                                  [lbl for lbl, _ in old], [s for _, s in old], emb)
    for i, (lc, sc) in enumerate(new):
        for j, (lo, so) in enumerate(old):
            word = max(0.0, similarity(emb, lo[0], lc[0]))
            assert math.isclose(mat[i, j], label_similarity(lo, so, lc, sc, word), rel_tol=1e-5)


def test_box_similarity_is_one_for_overlapping_boxes_and_falls_off_with_the_gap():
    from sg3d.merge.similarity import box_position_similarity

    basis = np.eye(3)
    # two halves of a 2 m table, centres 1 m apart: overlapping boxes
    assert box_position_similarity((0, 0, 0), (1.2, 0.8, 0.1), (1.0, 0, 0), (1.2, 0.8, 0.1), basis) == 1.0
    # two chairs 0.9 m apart, 0.4 m wide: a 0.5 m gap is not the same place
    assert box_position_similarity((0, 0, 0), (0.4, 0.4, 0.4), (0.9, 0, 0), (0.4, 0.4, 0.4), basis) < 1e-6
    gap, sigma = 0.2, 0.08
    z = gap / sigma
    expected = (1 - phi(z) + phi(-z)) / (1 - phi(1) + phi(-1))
    got = box_position_similarity((0, 0, 0), (0.4, 0.4, 0.4), (0.6, 0, 0), (0.4, 0.4, 0.4), basis, sigma)
    assert math.isclose(got, expected, rel_tol=1e-9)


def test_combine_boxes_covers_both_boxes():
    from sg3d.merge.update import combine_boxes

    centre, size = combine_boxes((0, 0, 0), (1, 1, 1), (1.5, 0, 0), (1, 1, 1), np.eye(3))
    assert np.allclose(centre, (0.75, 0, 0)) and np.allclose(size, (2.5, 1, 1))


def test_the_cheap_position_tests_never_drop_a_pair_that_reaches_the_threshold():
    """position_may_pass / box_may_pass let a batched merge skip the normal tails of far pairs:
    they must be True wherever the exact similarity is ≥ p_min, and False for most far pairs."""
    from sg3d.merge.similarity import (
        box_may_pass,
        box_position_similarity,
        position_may_pass,
    )

    rng = np.random.default_rng(3)
    p_min = SimilarityParams().min_position_similarity()
    mean_o, mean_c = rng.uniform(0, 4, (400, 1, 3)), rng.uniform(0, 4, (1, 300, 3))
    var_o = rng.uniform(0, 0.5, (400, 1, 3)) ** 2
    exact = position_similarity(mean_o, var_o, mean_c)
    cheap = position_may_pass(mean_o, var_o, mean_c, p_min)
    assert (exact >= p_min).sum() > 50 and not ((exact >= p_min) & ~cheap).any()
    assert (~cheap).mean() > 0.5
    basis = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    size_o, size_c = rng.uniform(0.05, 1.5, (400, 1, 3)), rng.uniform(0.05, 1.5, (1, 300, 3))
    exact = box_position_similarity(mean_o, size_o, mean_c, size_c, basis)
    cheap = box_may_pass(mean_o, size_o, mean_c, size_c, basis, p_min)
    assert (exact >= p_min).sum() > 50 and not ((exact >= p_min) & ~cheap).any()
    assert (~cheap).mean() > 0.3
