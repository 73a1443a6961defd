"""Aligning two rooms' frames from the objects they share.

Each room is built in its own world frame (its first camera pose), so the same doorway
cabinet seen from two rooms sits at two unrelated positions. Objects give the
correspondences: a pair is a candidate when the labels agree (Eq. 10 without the detector
score) and the colour histograms intersect well (Eq. 14). Many candidates are wrong (two
white chairs), so the rigid transform comes from RANSAC over 3-pair samples, refitted by
Kabsch on the inliers; the residual of that fit says how much to trust it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from scipy.optimize import linear_sum_assignment

from sg3d.core.errors import Sg3dError
from sg3d.graphdb.similarity import histogram_intersection, label_similarity_matrix
from sg3d.graphdb.values import unpack_hist

# A pair needs labels at least this similar (1 = a shared label; word-vector cosine else) ...
LABEL_MIN = 0.8
# ... and this much of the smaller histogram in common (Eq. 14), to be a candidate.
COLOUR_MIN = 0.5
# Object centres of two scans of one room differ by 10-30 cm (detector boxes, depth noise,
# partial views: measured on the 7-Scenes kitchen split in two halves), so a correspondence
# within 30 cm counts as agreeing with a model.
INLIER_M = 0.3
RANSAC_ITERS = 1000
# Three nearly collinear centres fix no rotation about their line: samples whose triangle is
# thinner than this (m^2) are skipped.
MIN_SAMPLE_AREA_M2 = 0.01


class AlignmentError(Sg3dError, ValueError):
    """The two rooms cannot be aligned (too few or degenerate correspondences)."""


@dataclass
class Alignment:
    """`T` maps room B's frame into room A's: p_A ≈ T @ [p_B, 1]."""
    T: np.ndarray
    residual_rms_m: float
    pairs: list[tuple[str, str]] = field(default_factory=list)   # (object in A, object in B), inliers
    candidates: int = 0                                           # label+colour pairs RANSAC saw


def estimate_rigid_transform(src_points, dst_points) -> np.ndarray:
    """Kabsch/Umeyama without scale: the 4x4 rigid T minimising Σ‖R src + t − dst‖².

    Needs ≥ 3 non-collinear pairs for a unique rotation; the sign correction keeps R a
    rotation (det +1) where the best orthogonal fit would be a reflection.
    """
    src = np.asarray(src_points, dtype=float).reshape(-1, 3)
    dst = np.asarray(dst_points, dtype=float).reshape(-1, 3)
    if len(src) != len(dst) or len(src) < 3:
        raise AlignmentError(f"need at least 3 point pairs, got {len(src)} and {len(dst)}")
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    cov = (dst - mu_d).T @ (src - mu_s)
    u, _, vt = np.linalg.svd(cov)
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    rot = u @ np.diag([1.0, 1.0, d]) @ vt
    T = np.eye(4)
    T[:3, :3] = rot
    T[:3, 3] = mu_d - rot @ mu_s
    return T


def apply(T: np.ndarray, points) -> np.ndarray:
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    return pts @ T[:3, :3].T + T[:3, 3]


def _triangle_area(p: np.ndarray) -> float:
    return 0.5 * float(np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0])))


def ransac_rigid(src, dst, iters: int = RANSAC_ITERS, inlier_m: float = INLIER_M,
                 rng: Optional[np.random.Generator] = None) -> tuple[np.ndarray, np.ndarray]:
    """Robust `estimate_rigid_transform` over putative pairs src[k] ↔ dst[k].

    Returns (T, inlier mask). The best model keeps the most inliers (ties: the smaller error)
    and is refitted on them twice, since the refit can pull in pairs the 3-point model missed.
    Samples whose pairwise distances disagree are rejected before the SVD: a rigid motion
    preserves distances, and this cheap test removes most wrong samples when labels repeat.
    """
    src = np.asarray(src, dtype=float).reshape(-1, 3)
    dst = np.asarray(dst, dtype=float).reshape(-1, 3)
    n = len(src)
    if n < 3:
        raise AlignmentError(f"need at least 3 candidate pairs for RANSAC, got {n}")
    rng = rng or np.random.default_rng(0)
    best_mask, best_key = None, (-1, np.inf)
    for _ in range(iters):
        k = rng.choice(n, size=3, replace=False)
        s, d = src[k], dst[k]
        ds = np.linalg.norm(s[[0, 0, 1]] - s[[1, 2, 2]], axis=1)
        dd = np.linalg.norm(d[[0, 0, 1]] - d[[1, 2, 2]], axis=1)
        if np.any(np.abs(ds - dd) > 2 * inlier_m) or _triangle_area(s) < MIN_SAMPLE_AREA_M2:
            continue
        T = estimate_rigid_transform(s, d)
        err = np.linalg.norm(apply(T, src) - dst, axis=1)
        mask = err < inlier_m
        key = (int(mask.sum()), float(np.sum(err[mask] ** 2)))
        if key[0] > best_key[0] or (key[0] == best_key[0] and key[1] < best_key[1]):
            best_mask, best_key = mask, key
    if best_mask is None or best_key[0] < 3:
        raise AlignmentError("no consistent, non-degenerate 3-object sample: the rooms share "
                             "too few objects (or they lie on one line)")
    mask = best_mask
    for _ in range(2):
        T = estimate_rigid_transform(src[mask], dst[mask])
        new_mask = np.linalg.norm(apply(T, src) - dst, axis=1) < inlier_m
        if new_mask.sum() < 3:
            break
        mask = new_mask
    return estimate_rigid_transform(src[mask], dst[mask]), mask


def room_objects(store, room_id: str) -> list[dict]:
    return store.read("building_room_objects", room=room_id)


def candidate_pairs(objs_a: list[dict], objs_b: list[dict], embedding=None,
                    label_min: float = LABEL_MIN, colour_min: float = COLOUR_MIN) -> list[tuple[int, int]]:
    """Index pairs (i in A, j in B) whose labels and colours agree (position is not used:
    the frames differ, which is the point)."""
    if not objs_a or not objs_b:
        return []
    if embedding is None:
        from sg3d.core.embedding import default_embedding
        embedding = default_embedding()
    # unit scores: Eq. 10 scales by the detector's confidence, which says nothing about
    # whether two stored objects are the same thing
    ones_a = [[1.0]] * len(objs_a)
    ones_b = [[1.0]] * len(objs_b)
    s_lab = label_similarity_matrix([o["labels"] or [o["label"]] for o in objs_a], ones_a,
                                    [o["labels"] or [o["label"]] for o in objs_b], ones_b, embedding)
    rows, cols = np.nonzero(s_lab >= label_min)
    if rows.size == 0:
        return []
    # histograms only for the label-compatible pairs: n×m×512 floats would not fit big rooms
    h_a = np.array([unpack_hist(o["hist"]) for o in objs_a])
    h_b = np.array([unpack_hist(o["hist"]) for o in objs_b])
    s_col = histogram_intersection(h_a[rows], h_b[cols])
    keep = s_col >= colour_min
    return [(int(i), int(j)) for i, j in zip(rows[keep], cols[keep])]


def positions(objs: list[dict]) -> np.ndarray:
    """Centres of the objects' 3-D boxes (steadier than the centre-patch mean for large objects
    seen in parts), the mean where a node has no box."""
    return np.array([o.get("box_centre") or [o["x"], o["y"], o["z"]] for o in objs],
                    dtype=float).reshape(-1, 3)


def one_to_one(pairs: list[tuple[int, int]], err: np.ndarray) -> list[int]:
    """Indices into `pairs` keeping each object in at most one pair, smallest errors first."""
    if not pairs:
        return []
    ia = sorted({i for i, _ in pairs})
    jb = sorted({j for _, j in pairs})
    cost = np.full((len(ia), len(jb)), 1e9)
    where = {}
    for k, (i, j) in enumerate(pairs):
        r, c = ia.index(i), jb.index(j)
        if err[k] < cost[r, c]:
            cost[r, c], where[(r, c)] = err[k], k
    rows, cols = linear_sum_assignment(cost)
    return sorted(where[(r, c)] for r, c in zip(rows, cols) if (r, c) in where)


def align_objects(objs_a: list[dict], objs_b: list[dict], embedding=None, iters: int = RANSAC_ITERS,
                  inlier_m: float = INLIER_M, seed: int = 0) -> Alignment:
    """`align_rooms` on already-fetched objects (dicts with id, label(s), x, y, z, hist)."""
    pairs = candidate_pairs(objs_a, objs_b, embedding)
    if len(pairs) < 3:
        raise AlignmentError(f"only {len(pairs)} object pair(s) match by label and colour; "
                             "at least 3 shared objects are needed (or give --transform)")
    pa, pb = positions(objs_a), positions(objs_b)
    src = pb[[j for _, j in pairs]]
    dst = pa[[i for i, _ in pairs]]
    T, mask = ransac_rigid(src, dst, iters, inlier_m, np.random.default_rng(seed))
    inl = [p for p, m in zip(pairs, mask) if m]
    err = np.linalg.norm(apply(T, pb[[j for _, j in inl]]) - pa[[i for i, _ in inl]], axis=1)
    keep = one_to_one(inl, err)
    if len(keep) < 3:
        raise AlignmentError("fewer than 3 distinct objects agree with any rigid transform")
    chosen = [inl[k] for k in keep]
    # final fit on one pair per object, so a repeated label cannot weigh twice
    T = estimate_rigid_transform(pb[[j for _, j in chosen]], pa[[i for i, _ in chosen]])
    err = np.linalg.norm(apply(T, pb[[j for _, j in chosen]]) - pa[[i for i, _ in chosen]], axis=1)
    return Alignment(T=T, residual_rms_m=float(np.sqrt(np.mean(err ** 2))),
                     pairs=[(objs_a[i]["id"], objs_b[j]["id"]) for i, j in chosen], candidates=len(pairs))


def align_rooms(store, room_a_id: str, room_b_id: str, embedding=None, iters: int = RANSAC_ITERS,
                inlier_m: float = INLIER_M, seed: int = 0) -> Alignment:
    """The rigid transform taking room B's frame into room A's, from their shared objects."""
    objs_a, objs_b = room_objects(store, room_a_id), room_objects(store, room_b_id)
    for rid, objs in ((room_a_id, objs_a), (room_b_id, objs_b)):
        if not objs:
            raise AlignmentError(f"room {rid!r} holds no objects")
    return align_objects(objs_a, objs_b, embedding, iters, inlier_m, seed)
