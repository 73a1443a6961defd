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
from numpy.typing import ArrayLike
from scipy.optimize import linear_sum_assignment

from sg3d.core.embedding import LabelEmbedding
from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row
from sg3d.merge.similarity import histogram_intersection, label_similarity_matrix
from sg3d.merge.histograms import unpack_hist

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


# What an alignment must rest on before `sg3d rooms link` stores it (without --force). Two unrelated
# rooms always share a floor, walls and some unnamed blobs of one colour, and RANSAC fits three such
# pairs within centimetres (the 7-Scenes kitchen and the 3DMatch study room: a wall, a shelf level
# and two blobs 0.1 m and 2 m across, residual 0.03 m). So evidence is counted only on things:
# - at least this many distinct object pairs (never the structure layer: floor, walls, counters and
#   shelf levels match in any two rooms) agreeing on label, colour and size with the transform;
MIN_EVIDENCE_PAIRS = 3
# - those pairs at least this share of the things that could have matched (the label- and
#   colour-compatible things of the room with fewer of them): one room seen twice shares most,
#   two rooms that share a doorway cabinet and a chair still share a third of what could match;
MIN_INLIER_SHARE = 0.3
# - the residual of the fit on them at most half the inlier distance (INLIER_M);
MAX_RESIDUAL_M = 0.15
# - and, where both rooms know their up direction (the floor's normal, found independently of the
#   objects), the transform must carry one onto the other within this angle: gravity estimates of
#   one room differ by a degree or two, a wrong alignment tilts the room by tens of degrees.
MAX_UP_ANGLE_DEG = 10.0
# Two boxes are of a compatible size when each of their sorted extents agrees within this factor
# (partial views and depth noise: the same chair measures 0.56-0.61 m in two builds); extents under
# SIZE_FLOOR_M count as SIZE_FLOOR_M (a thin object's depth is mostly noise).
SIZE_RATIO_MAX = 2.0
SIZE_FLOOR_M = 0.05


class AlignmentError(Sg3dError, ValueError):
    """The two rooms cannot be aligned (too few or degenerate correspondences)."""


class WeakAlignment(AlignmentError):
    """An alignment was found but rests on too little independent evidence to be stored."""


@dataclass
class Alignment:
    """`T` maps room B's frame into room A's: p_A ≈ T @ [p_B, 1]."""
    T: np.ndarray
    residual_rms_m: float
    pairs: list[tuple[str, str]] = field(default_factory=list)   # (object in A, object in B), inliers
    candidates: int = 0                                           # label+colour pairs RANSAC saw
    evidence: list[tuple[str, str]] = field(default_factory=list)  # inliers that are things, not structure
    matchable: int = 0                  # things of the room with fewer that had a label+colour partner

    @property
    def share(self) -> float:
        """Evidence pairs over the things that could have matched (0 when none could)."""
        return len(self.evidence) / self.matchable if self.matchable else 0.0


def estimate_rigid_transform(src_points: ArrayLike, dst_points: ArrayLike) -> np.ndarray:
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


def apply(T: np.ndarray, points: ArrayLike) -> np.ndarray:
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    return pts @ T[:3, :3].T + T[:3, 3]


def _triangle_area(p: np.ndarray) -> float:
    return 0.5 * float(np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0])))


def ransac_rigid(src: np.ndarray, dst: np.ndarray, iters: int = RANSAC_ITERS, inlier_m: float = INLIER_M,
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


def candidate_pairs(objs_a: list[Row], objs_b: list[Row], embedding: Optional[LabelEmbedding] = None,
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
    return [(int(i), int(j)) for i, j in zip(rows[keep], cols[keep])
            if is_structure(objs_a[i]) or is_structure(objs_b[j]) or sizes_compatible(objs_a[i], objs_b[j])]


def is_structure(o: dict) -> bool:
    """Floor, walls, counters and shelf levels: every room has them, so they prove nothing."""
    return o.get("layer") == "structure"


def sizes_compatible(a: dict, b: dict, ratio: float = SIZE_RATIO_MAX) -> bool:
    """Whether two objects' boxes agree in size: each sorted extent within `ratio` of the other's
    (extents below SIZE_FLOOR_M raised to it); True when either has no size."""
    sa, sb = a.get("size"), b.get("size")
    if not sa or not sb or len(sa) != 3 or len(sb) != 3:
        return True
    ea = np.maximum(np.sort(np.asarray(sa, dtype=float)), SIZE_FLOOR_M)
    eb = np.maximum(np.sort(np.asarray(sb, dtype=float)), SIZE_FLOOR_M)
    return bool(np.all(np.maximum(ea / eb, eb / ea) <= ratio))


def positions(objs: list[Row]) -> np.ndarray:
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


def align_objects(objs_a: list[Row], objs_b: list[Row], embedding: Optional[LabelEmbedding] = None, iters: int = RANSAC_ITERS,
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
    things = [(i, j) for i, j in pairs if not is_structure(objs_a[i]) and not is_structure(objs_b[j])]
    matchable = min(len({i for i, _ in things}), len({j for _, j in things}))
    return Alignment(T=T, residual_rms_m=float(np.sqrt(np.mean(err ** 2))),
                     pairs=[(objs_a[i]["id"], objs_b[j]["id"]) for i, j in chosen], candidates=len(pairs),
                     evidence=[(objs_a[i]["id"], objs_b[j]["id"]) for i, j in chosen
                               if not is_structure(objs_a[i]) and not is_structure(objs_b[j])],
                     matchable=matchable)


def up_angle_deg(T: np.ndarray, up_a: Optional[ArrayLike], up_b: Optional[ArrayLike]) -> Optional[float]:
    """Angle (degrees) between room A's up and room B's up carried into A's frame by T; None when
    either room has no usable up."""
    if up_a is None or up_b is None:
        return None
    a, b = np.asarray(up_a, dtype=float), np.asarray(T, dtype=float)[:3, :3] @ np.asarray(up_b, dtype=float)
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    if not (np.isfinite(na) and np.isfinite(nb)) or na == 0 or nb == 0:
        return None
    return float(np.degrees(np.arccos(np.clip(a @ b / (na * nb), -1.0, 1.0))))


def evidence_problem(al: Alignment, up_angle: Optional[float] = None) -> Optional[str]:
    """Why `al` rests on too little independent evidence to be stored, in one clause, or None
    (rules: MIN_EVIDENCE_PAIRS, MIN_INLIER_SHARE, MAX_RESIDUAL_M, MAX_UP_ANGLE_DEG)."""
    n = len(al.evidence)
    if n < MIN_EVIDENCE_PAIRS:
        return (f"only {n} of the {len(al.pairs)} pairs it rests on are objects agreeing in label, colour and "
                f"size (floor, walls, counters and shelves match in any two rooms); at least "
                f"{MIN_EVIDENCE_PAIRS} are needed")
    if al.share < MIN_INLIER_SHARE:
        return (f"{n} of {al.matchable} objects that could match agree with it ({al.share:.0%}; at least "
                f"{MIN_INLIER_SHARE:.0%} are needed)")
    if al.residual_rms_m > MAX_RESIDUAL_M:
        return f"its residual is {al.residual_rms_m:.2f} m (at most {MAX_RESIDUAL_M:g} m)"
    if up_angle is not None and up_angle > MAX_UP_ANGLE_DEG:
        return (f"it tilts one room's floor {up_angle:.0f} deg against the other's (at most "
                f"{MAX_UP_ANGLE_DEG:g} deg)")
    return None
