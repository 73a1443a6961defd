"""Rule "a move keeps its size" (sg3d.merge.rescan.same_size): both sides of its factor, and the
gate it puts on pairing an unmatched observation with a node whose place was seen empty."""
from __future__ import annotations

import numpy as np

from sg3d.core.embedding import default_embedding
from sg3d.core.model import ObjectObservation
from sg3d.merge.rescan import MOVE_MIN_EXTENT_M, MOVE_SIZE_RATIO, pair_moves, same_size
from sg3d.merge.histograms import pack_hist


def test_a_box_measured_from_other_views_is_the_same_size_a_sheet_is_not():
    mug = [0.10, 0.10, 0.12]
    assert same_size(np.array([mug]), np.array([[0.12, 0.09, 0.11]]))[0, 0]
    # either side of the factor, on the largest extent
    assert same_size(np.array([[0.2, 0.1, 0.1]]), np.array([[0.2 * MOVE_SIZE_RATIO * 0.95, 0.1, 0.1]]))[0, 0]
    assert not same_size(np.array([[0.2, 0.1, 0.1]]), np.array([[0.2 * MOVE_SIZE_RATIO * 1.05, 0.1, 0.1]]))[0, 0]
    # a 20 cm thing is never a 2 m sheet (what a partial re-scan once "moved" a grey box into)
    assert not same_size(np.array([[2.175, 0.175, 1.4]]), np.array([[0.15, 0.10, 0.20]]))[0, 0]
    # orientation does not matter: extents are compared largest first
    assert same_size(np.array([[0.6, 0.3, 0.9]]), np.array([[0.3, 0.9, 0.6]]))[0, 0]
    # a flat thing's thickness is depth noise: floored at MOVE_MIN_EXTENT_M
    assert same_size(np.array([[0.3, 0.2, 0.005]]), np.array([[0.3, 0.2, MOVE_MIN_EXTENT_M * 1.5]]))[0, 0]


def _obs(size) -> ObjectObservation:
    hist = np.full(512, 1 / 512)
    return ObjectObservation(local_id="n0", labels=["cup"], scores=[0.9], mean=(0.0, 0.0, 0.8),
                             var=(0.01, 0.01, 0.01), n_points=100, size=tuple(size), hist=hist.tolist(),
                             colour="white")


def _stored(size) -> dict:
    return {"id": "o-1", "labels": ["cup"], "hist": pack_hist(np.full(512, 1 / 512)), "size": size}


def test_only_a_node_of_the_same_size_is_paired_as_moved():
    words = default_embedding()       # "cup" ships with the package: no model is loaded
    assert pair_moves([_obs((0.1, 0.1, 0.12))], [_stored([0.11, 0.1, 0.12])], words) == {0: _stored([0.11, 0.1, 0.12])}
    assert pair_moves([_obs((1.1, 0.1, 0.8))], [_stored([0.11, 0.1, 0.12])], words) == {}
