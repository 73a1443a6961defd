"""The TUM RGB-D layout: ``rgb.txt``, ``depth.txt``, ``groundtruth.txt`` (t tx ty tz qx qy qz qw),
colour/depth/pose associated by nearest timestamp; depth scale 5000."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np

from sg3d.ingest.readers.base import (
    Entry,
    Sequence,
    SequenceError,
    quaternion_to_matrix,
    read_matrix,
)
from sg3d.ingest.readers.registration import Registration

# Published calibration of the TUM RGB-D Freiburg cameras (fx, fy, cx, cy).
TUM_FREIBURG = {
    "freiburg1": (517.3, 516.5, 318.6, 255.3),
    "freiburg2": (520.9, 521.0, 325.1, 249.7),
    "freiburg3": (535.4, 539.2, 320.1, 247.6),
}


def _read_list(path: Path, columns: int) -> list[list[str]]:
    rows = []
    for line in path.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split()
        if len(parts) >= columns:
            rows.append(parts)
    return rows


def _nearest(query: np.ndarray, reference: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the nearest reference timestamp for each query, and the absolute difference."""
    if reference.size == 0:
        return np.zeros(query.shape, int), np.full(query.shape, np.inf)
    order = np.argsort(reference)
    ref = reference[order]
    right = np.clip(np.searchsorted(ref, query), 0, ref.size - 1)
    left = np.clip(right - 1, 0, ref.size - 1)
    pick = np.where(np.abs(ref[left] - query) <= np.abs(ref[right] - query), left, right)
    return order[pick], np.abs(ref[pick] - query)


class TumSequence(Sequence):
    layout = "tum"
    depth_scale = 5000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None,
             max_dt: float = 0.02) -> "TumSequence":
        missing = [name for name in ("rgb.txt", "depth.txt") if not (path / name).is_file()]
        if missing:
            raise SequenceError(f"missing {', '.join(str(path / n) for n in missing)} (TUM RGB-D layout)")
        posed = (path / "groundtruth.txt").is_file()   # without it the poses are estimated
        K = cls._intrinsics(path)
        rgb = _read_list(path / "rgb.txt", 2)
        depth = _read_list(path / "depth.txt", 2)
        gt = _read_list(path / "groundtruth.txt", 8) if posed else []
        t_rgb = np.array([float(r[0]) for r in rgb])
        t_depth = np.array([float(r[0]) for r in depth])
        t_gt = np.array([float(r[0]) for r in gt])
        gt_values = np.array([[float(v) for v in r[1:8]] for r in gt]) if gt else np.zeros((0, 7))
        di, ddt = _nearest(t_rgb, t_depth)
        gi, gdt = _nearest(t_rgb, t_gt)
        entries, skipped = [], []
        for k, row in enumerate(rgb):
            name = Path(row[1]).stem
            if ddt[k] > max_dt:
                skipped.append((name, f"no depth image within {max_dt} s of {row[1]} in depth.txt"))
                continue
            if not posed:
                entries.append(Entry(name, path / row[1], path / depth[di[k]][1], float(t_rgb[k])))
                continue
            if gdt[k] > max_dt:
                skipped.append((name, f"no pose within {max_dt} s of {row[1]} in groundtruth.txt"))
                continue
            values = gt_values[gi[k]]
            pose = np.eye(4)
            if np.all(np.isfinite(values)) and np.linalg.norm(values[3:7]) > 0:
                pose[:3, :3] = quaternion_to_matrix(values[3:7])
                pose[:3, 3] = values[:3]
            else:
                pose[:] = np.nan  # reported as a non-finite pose when the frame is reached
            entries.append(Entry(name, path / row[1], path / depth[di[k]][1], float(t_rgb[k]), pose=pose))
        if not entries:
            raise SequenceError(f"no colour frame of {path / 'rgb.txt'} has depth and a pose within {max_dt} s")
        return cls(path, entries, K, registration, skipped)

    @staticmethod
    def _intrinsics(path: Path) -> np.ndarray:
        for name in ("camera-intrinsics.txt", "intrinsics.txt"):
            if (path / name).is_file():
                return read_matrix(path / name)
        for key, (fx, fy, cx, cy) in TUM_FREIBURG.items():
            if key in path.resolve().name:
                return np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])
        raise SequenceError(f"missing intrinsics file {path / 'camera-intrinsics.txt'} (3x3 colour camera "
                            f"matrix, or fx fy cx cy); only rgbd_dataset_freiburg1/2/3_* folders have a default")
