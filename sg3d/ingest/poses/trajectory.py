"""Trajectories as arrays of 4x4 camera-to-world poses: interpolation, alignment, length, TUM files."""
from __future__ import annotations

from pathlib import Path
from typing import Sequence as Seq

import numpy as np
from scipy.spatial.transform import Rotation, Slerp


def interpolate_poses(known_t: Seq[float], known: np.ndarray, query_t: Seq[float]) -> np.ndarray:
    """Poses at `query_t` between the `known` ones (times increasing): translation linear in time,
    rotation by spherical linear interpolation (Slerp) of the two bracketing samples; times
    outside the known span take the nearest end pose."""
    times = np.asarray(known_t, dtype=np.float64)
    query = np.clip(np.asarray(query_t, dtype=np.float64), times[0], times[-1])
    out = np.tile(np.eye(4), (len(query), 1, 1))
    if len(times) == 1:
        out[:] = known[0]
        return out
    slerp = Slerp(times, Rotation.from_matrix(known[:, :3, :3]))
    out[:, :3, :3] = slerp(query).as_matrix()
    for axis in range(3):
        out[:, axis, 3] = np.interp(query, times, known[:, axis, 3])
    return out


def umeyama_alignment(source: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation R and translation t minimising sum |R s_i + t - t_i|^2 over point pairs (Nx3 each):
    Umeyama 1991, Eq. 40-42 without scale: R = U diag(1, 1, det(U V^T)) V^T from the SVD of the
    cross-covariance of the centred points, t = mean(target) - R mean(source)."""
    ms, mt = source.mean(axis=0), target.mean(axis=0)
    cov = (target - mt).T @ (source - ms) / len(source)
    U, _, Vt = np.linalg.svd(cov)
    S = np.eye(3)
    S[2, 2] = np.sign(np.linalg.det(U) * np.linalg.det(Vt)) or 1.0
    R = U @ S @ Vt
    return R, mt - R @ ms


def align_trajectory(estimate: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """The 4x4 transform that best maps the estimated camera positions onto the reference ones."""
    R, t = umeyama_alignment(estimate[:, :3, 3], reference[:, :3, 3])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    return T


def ate_rmse(estimate: np.ndarray, reference: np.ndarray) -> float:
    """Absolute trajectory error: RMSE of camera positions after the rigid alignment (Sturm et al.
    2012, the TUM RGB-D benchmark's ATE)."""
    T = align_trajectory(estimate, reference)
    moved = estimate[:, :3, 3] @ T[:3, :3].T + T[:3, 3]
    return float(np.sqrt(np.mean(np.sum((moved - reference[:, :3, 3]) ** 2, axis=1))))


def path_length(poses: np.ndarray) -> float:
    """Metres travelled by the camera: the sum of distances between consecutive positions."""
    if len(poses) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1).sum())


def write_tum(path: Path, timestamps: Seq[float], poses: np.ndarray) -> None:
    """TUM RGB-D trajectory file: one line per pose, `t tx ty tz qx qy qz qw` (camera-to-world)."""
    quats = Rotation.from_matrix(poses[:, :3, :3]).as_quat() if len(poses) else []  # x y z w
    lines = ["# timestamp tx ty tz qx qy qz qw (camera-to-world, estimated by sg3d)"]
    for t, T, q in zip(timestamps, poses, quats):
        lines.append(f"{t:.6f} " + " ".join(f"{v:.6f}" for v in (*T[:3, 3], *q)))
    Path(path).write_text("\n".join(lines) + "\n")


def read_tum(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(timestamps, Nx4x4 poses) of a TUM trajectory file."""
    rows = [line.split() for line in Path(path).read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    values = np.array(rows, dtype=np.float64)
    poses = np.tile(np.eye(4), (len(values), 1, 1))
    poses[:, :3, :3] = Rotation.from_quat(values[:, 4:8]).as_matrix()
    poses[:, :3, 3] = values[:, 1:4]
    return values[:, 0], poses
