"""Same-node detection (paper Sec. V-C.1): label, position and colour similarity, Eq. 10-15.

Scoring is done in Python (NumPy/SciPy) inside the merge transaction function rather than in
Cypher: the normal CDF, histogram intersections over 512 bins and label vectors are clearer and
faster here, and the candidates were already fetched by one indexed, windowed read.

Two readings of the printed equations, both documented where they are made:
- Eq. 10 multiplies the score by the *count* of shared labels, which is unbounded (k shared
  labels give k·score) and would let the label term alone pass the threshold for any two
  objects of one class anywhere in the room. We divide the count by the smaller label-set
  size, so s_label stays in [0, 1] and the weights of Eq. 15 keep their meaning.
- Eq. 14 as printed is the histogram intersection, a similarity (1 = same colours); taking
  s_color = 1 − d_h would score identical histograms 0. We use the intersection as s_color.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import ndtr

from sg3d.core.embedding import LabelEmbedding

WEIGHTS = {"label": 0.375, "color": 0.25, "position": 0.375}
THRESHOLD = 0.7
# A Gaussian fitted to a few centre-region points can be a few millimetres wide, far tighter
# than the centimetres that depth noise and pose drift move an object between views; the floor
# keeps two views of one cup comparable. The cap keeps a huge table from matching across a room.
SIGMA_FLOOR_M = 0.08
SIGMA_CAP_M = 0.75
# The centre-patch Gaussian says where the patch is, not where a large object ends: a 2 m table
# seen from either end gives two patches a metre apart. Between views that share a label, σ is
# also floored at this fraction of the stored object's largest extent (sg3d.graphdb.merge).
# In-sample: chosen on the kitchen (its table seen from either end). On the living room a fresh
# default build keeps one chair, one tv and at most three objects (tests/quality/test_quality.py), so
# its views merge there without duplicates; with no living-room ground truth, that floor cannot
# show the widening is not too loose there (two chairs merged into one would pass it too).
SIGMA_SIZE_FRACTION = 0.5
# Extents above this are not trusted to widen the candidate window (a runaway box union).
MAX_EXTENT_M = 3.0


@dataclass(frozen=True)
class SimilarityParams:
    w_label: float = WEIGHTS["label"]
    w_color: float = WEIGHTS["color"]
    w_position: float = WEIGHTS["position"]
    threshold: float = THRESHOLD
    sigma_floor: float = SIGMA_FLOOR_M
    sigma_cap: float = SIGMA_CAP_M
    sigma_size_fraction: float = SIGMA_SIZE_FRACTION

    def min_position_similarity(self) -> float:
        """The s_position below which a pair cannot reach the threshold even with perfect
        label and colour scores (both are at most 1)."""
        return max(0.0, (self.threshold - self.w_label - self.w_color) / self.w_position)

    def window_margin(self) -> float:
        """How far (m, per axis) a candidate can be and still reach the threshold.

        With perfect label and colour scores a pair needs s_position ≥ p_min; Eq. 13 falls
        below p_min beyond z* standard deviations, and σ is capped, so nothing farther than
        z*·σ_cap on any axis can match: the candidate query may ignore it safely.
        """
        return float(max_tail_z(self.min_position_similarity()) * self.sigma_cap)


def _two_sided_tail(z: ArrayLike) -> np.ndarray:
    """1 − Φ(z) + Φ(−z): the mass of the standard normal beyond ±z."""
    z = np.abs(z)
    return 1.0 - ndtr(z) + ndtr(-z)


def _tail_inverse(p: float) -> float:
    from scipy.special import ndtri

    return float(-ndtri(p / 2.0))


def max_tail_z(p_min: float) -> float:
    """The largest z at which one axis of Eq. 13 (1, or the tail ratio beyond ±σ) is still
    ≥ p_min. Every axis factor is ≤ 1, so a pair with any axis beyond it scores below p_min."""
    if p_min <= 0:
        return float("inf")
    return _tail_inverse(p_min * float(_two_sided_tail(1.0)))


def _tail_factors(z: np.ndarray) -> np.ndarray:
    """Eq. 13 per axis: 1 inside ±σ (z < 1), else the normal tail ratio."""
    return np.where(z < 1.0, 1.0, _two_sided_tail(z) / _two_sided_tail(1.0))


def label_score(scores_o: Sequence[float], scores_c: Sequence[float]) -> float:
    """Eq. 11: score = max over both candidate sets of the score of any of their labels."""
    return float(max(max(scores_o, default=0.0), max(scores_c, default=0.0)))


def label_similarity(labels_o: Sequence[str], scores_o: Sequence[float],
                     labels_c: Sequence[str], scores_c: Sequence[float],
                     word_similarity: float) -> float:
    """Eq. 10: shared top-k labels times the score, else (1 − d_wv(l_o, l_c)) times the score.

    `word_similarity` is 1 − d_wv of the two best labels (cosine of their vectors), only used
    when the sets share nothing. The shared count is normalised by the smaller set (module doc).
    """
    score = label_score(scores_o, scores_c)
    common = len(set(labels_o) & set(labels_c))
    if common > 0:
        return score * common / max(1, min(len(set(labels_o)), len(set(labels_c))))
    return max(0.0, float(word_similarity)) * score


def _label_indicators(labels_c: Sequence[Sequence[str]], labels_o: Sequence[Sequence[str]]) -> tuple[np.ndarray, np.ndarray]:
    """0/1 matrices (row per object, column per label of the union vocabulary)."""
    vocab = {lbl: i for i, lbl in enumerate(sorted({lbl for ls in (*labels_c, *labels_o) for lbl in ls}))}

    def indicator(sets: Sequence[Sequence[str]]) -> np.ndarray:
        mat = np.zeros((len(sets), len(vocab)))
        for r, ls in enumerate(sets):
            mat[r, [vocab[lbl] for lbl in ls]] = 1.0
        return mat

    return indicator(labels_c), indicator(labels_o)


def shared_labels(labels_c: Sequence[Sequence[str]], labels_o: Sequence[Sequence[str]]) -> np.ndarray:
    """Number of top-k labels each (new, stored) pair has in common, shape (n_c, n_o)."""
    if not labels_c or not labels_o:
        return np.zeros((len(labels_c), len(labels_o)))
    a, b = _label_indicators(labels_c, labels_o)
    return a @ b.T


def label_similarity_matrix(labels_c: Sequence[Sequence[str]], scores_c: Sequence[Sequence[float]],
                            labels_o: Sequence[Sequence[str]], scores_o: Sequence[Sequence[float]],
                            embedding: LabelEmbedding) -> np.ndarray:
    """Eq. 10-11 for every (new, stored) pair at once, shape (len(labels_c), len(labels_o)).

    Same numbers as `label_similarity`, vectorised: shared-label counts as a product of
    label-indicator matrices, word similarities as a product of unit label vectors.
    """
    n, m = len(labels_c), len(labels_o)
    if n == 0 or m == 0:
        return np.zeros((n, m))
    a, b = _label_indicators(labels_c, labels_o)
    common = a @ b.T
    smaller = np.minimum.outer(a.sum(1), b.sum(1))
    score = np.maximum.outer([max(s, default=0.0) for s in scores_c], [max(s, default=0.0) for s in scores_o])
    vecs = embedding.vectors([ls[0] for ls in (*labels_c, *labels_o)])
    vc = np.array([vecs[ls[0]] for ls in labels_c])
    vo = np.array([vecs[ls[0]] for ls in labels_o])
    word = np.clip(vc @ vo.T, 0.0, None)
    return np.where(common > 0, score * common / np.maximum(smaller, 1.0), word * score)


def position_similarity(mean_o: ArrayLike, var_o: ArrayLike, mean_c: ArrayLike, sigma_floor: ArrayLike = SIGMA_FLOOR_M,
                        sigma_cap: float = SIGMA_CAP_M) -> np.ndarray:
    """Eq. 12-13: product over x, y, z of I^j; 1 inside ±σ_o, else the normal tail ratio.

    Broadcasts: mean_o/var_o (..., 3) against mean_c (..., 3); returns (...). `sigma_floor`
    may be an array broadcasting like var_o (a per-object floor, see SIGMA_SIZE_FRACTION).
    """
    return np.prod(_tail_factors(_position_z(mean_o, var_o, mean_c, sigma_floor, sigma_cap)), axis=-1)


def _position_z(mean_o: ArrayLike, var_o: ArrayLike, mean_c: ArrayLike, sigma_floor: ArrayLike,
                sigma_cap: float) -> np.ndarray:
    """|mean_c − mean_o| / σ_o per axis, σ_o clipped to [sigma_floor, sigma_cap] (Eq. 13's z)."""
    mean_o = np.asarray(mean_o, dtype=float)
    mean_c = np.asarray(mean_c, dtype=float)
    sigma = np.sqrt(np.maximum(np.asarray(var_o, dtype=float), 0.0))
    sigma = np.minimum(np.maximum(sigma, sigma_floor), sigma_cap)
    return np.abs(mean_c - mean_o) / sigma


def position_may_pass(mean_o: ArrayLike, var_o: ArrayLike, mean_c: ArrayLike, p_min: float,
                      sigma_floor: ArrayLike = SIGMA_FLOOR_M,
                      sigma_cap: float = SIGMA_CAP_M) -> np.ndarray:
    """Whether `position_similarity` can be ≥ p_min (every axis within `max_tail_z`), without
    evaluating the normal tail: the cheap test that spares a batched merge the tails of
    pairs across the room. Never False where the similarity is ≥ p_min."""
    z = _position_z(mean_o, var_o, mean_c, sigma_floor, sigma_cap)
    return np.all(z <= max_tail_z(p_min) * (1 + 1e-9), axis=-1)


def box_position_similarity(centre_o: ArrayLike, size_o: ArrayLike, centre_c: ArrayLike, size_c: ArrayLike,
                            basis: np.ndarray,
                            sigma: float = SIGMA_FLOOR_M) -> np.ndarray:
    """Our extension of Eq. 12-13 for objects seen in parts: per gravity-frame axis, 1 while the
    two 3-D boxes overlap (or their gap is under σ, the depth noise), else the same normal tail
    ratio applied to gap/σ; product over the axes.

    A 2 m table seen from either end gives two centre patches a metre apart (Eq. 13 scores them
    as different places) but two boxes that overlap. `basis`: rows e1, e2, up (sizes are along
    them). Broadcasts like `position_similarity`.
    """
    return np.prod(_tail_factors(_box_z(centre_o, size_o, centre_c, size_c, basis, sigma)), axis=-1)


def _box_z(centre_o: ArrayLike, size_o: ArrayLike, centre_c: ArrayLike, size_c: ArrayLike, basis: np.ndarray,
           sigma: float) -> np.ndarray:
    """Per gravity-frame axis: the gap between the two boxes (0 while they overlap) over σ."""
    d = (np.asarray(centre_c, float) - np.asarray(centre_o, float)) @ basis.T
    half = (np.asarray(size_o, float) + np.asarray(size_c, float)) / 2.0
    return np.maximum(np.abs(d) - half, 0.0) / sigma


def box_may_pass(centre_o: ArrayLike, size_o: ArrayLike, centre_c: ArrayLike, size_c: ArrayLike, basis: np.ndarray,
                 p_min: float,
                 sigma: float = SIGMA_FLOOR_M) -> np.ndarray:
    """Whether `box_position_similarity` can be ≥ p_min, without the normal tail (see
    `position_may_pass`)."""
    z = _box_z(centre_o, size_o, centre_c, size_c, basis, sigma)
    return np.all(z <= max_tail_z(p_min) * (1 + 1e-9), axis=-1)


def histogram_intersection(h_i: ArrayLike, h_j: ArrayLike) -> np.ndarray:
    """Eq. 14: Σ min(h_i, h_j) / min(|h_i|, |h_j|) over the 3-D HSV bins (broadcasts on rows)."""
    h_i = np.asarray(h_i, dtype=float)
    h_j = np.asarray(h_j, dtype=float)
    inter = np.minimum(h_i, h_j).sum(axis=-1)
    norm = np.minimum(h_i.sum(axis=-1), h_j.sum(axis=-1))
    return np.where(norm > 0, inter / np.maximum(norm, 1e-12), 0.0)


def total_similarity(s_label: np.ndarray, s_color: np.ndarray, s_position: np.ndarray,
                     params: SimilarityParams = SimilarityParams()) -> np.ndarray:
    """Eq. 15: s_total = Σ w_i s_i over {label, color, position}."""
    return params.w_label * s_label + params.w_color * s_color + params.w_position * s_position
