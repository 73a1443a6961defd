"""Updating a global node with a matched observation (paper Sec. V-C.2, "Merge and Update")."""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from sg3d.core.model import TOP_K
from sg3d.ingest.objects.moments import combine_gaussians  # noqa: F401  (the update rule for positions)


def combine_labels(labels_o: Sequence[str], scores_o: Sequence[float],
                   labels_c: Sequence[str], scores_c: Sequence[float],
                   k: int = TOP_K) -> tuple[list[str], list[float]]:
    """The top-k labels with the maximum scores from C_o ∪ C_c (a label in both keeps its max)."""
    best: dict[str, float] = {}
    for label, score in list(zip(labels_o, scores_o)) + list(zip(labels_c, scores_c)):
        if score > best.get(label, -1.0):
            best[label] = float(score)
    ranked = sorted(best.items(), key=lambda kv: (-kv[1], kv[0]))[:k]
    return [lbl for lbl, _ in ranked], [s for _, s in ranked]


def combine_histograms(h_o: ArrayLike, h_c: ArrayLike) -> np.ndarray:
    """Histograms are pixel counts (Eq. 9), so combining the observations adds them."""
    return np.asarray(h_o, dtype=float) + np.asarray(h_c, dtype=float)


def combine_boxes(centre_o: ArrayLike, size_o: ArrayLike, centre_c: ArrayLike, size_c: ArrayLike,
                  basis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The box covering both boxes in the gravity frame (rows of `basis`: e1, e2, up): a node's
    extent grows as more of the object is seen (a table seen end by end) instead of averaging
    partial views (the paper leaves size open)."""
    co, cc = np.asarray(centre_o, float) @ basis.T, np.asarray(centre_c, float) @ basis.T
    lo = np.minimum(co - np.asarray(size_o, float) / 2, cc - np.asarray(size_c, float) / 2)
    hi = np.maximum(co + np.asarray(size_o, float) / 2, cc + np.asarray(size_c, float) / 2)
    return ((lo + hi) / 2) @ basis, hi - lo


def incoming_has_best_label(scores_o: Sequence[float], scores_c: Sequence[float]) -> bool:
    """The thumbnail is replaced when the label of maximum score comes from the new graph."""
    return max(scores_c, default=0.0) > max(scores_o, default=0.0)
