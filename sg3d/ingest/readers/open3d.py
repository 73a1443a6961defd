"""The Open3D reconstruction system (Redwood) layout: ``image/NNNNN.jpg|png``, ``depth/NNNNN.png``
(mm, registered to colour), ``trajectory.log`` and an intrinsics JSON."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np

from sg3d.ingest.readers.base import Entry, Sequence, SequenceError, numbered_images
from sg3d.ingest.readers.registration import Registration


def read_trajectory_log(path: Path) -> dict[int, np.ndarray]:
    """Redwood/Open3D ``trajectory.log``: blocks of a metadata line ``i j n`` and four rows of a
    4x4 camera-to-world matrix; frame i -> pose. A block that is not 16 numbers is a
    SequenceError naming its line (the file as a whole is unusable then)."""
    lines = [line.split() for line in path.read_text().splitlines() if line.strip()]
    if len(lines) % 5:
        raise SequenceError(f"{path} has {len(lines)} non-empty lines; a trajectory.log holds blocks of 5")
    poses = {}
    for b in range(0, len(lines), 5):
        try:
            index = int(lines[b][0])
            pose = np.array([[float(v) for v in row] for row in lines[b + 1:b + 5]], dtype=np.float64)
        except (ValueError, IndexError):
            raise SequenceError(f"{path} line {b + 1}: expected 'i j n' and four rows of 4 numbers") from None
        if pose.shape != (4, 4):
            raise SequenceError(f"{path} line {b + 2}: a pose needs four rows of 4 numbers")
        poses[index] = pose
    return poses


def _open3d_intrinsics(path: Path) -> np.ndarray:
    import json

    try:
        data = json.loads(path.read_text())
        values = np.asarray(data["intrinsic_matrix"], dtype=np.float64)
    except (ValueError, KeyError, TypeError):
        raise SequenceError(f"{path} is not an Open3D intrinsics JSON (needs 'intrinsic_matrix')") from None
    if values.size != 9:
        raise SequenceError(f"{path}: intrinsic_matrix holds {values.size} numbers, expected 9")
    K = values.reshape(3, 3).T  # Open3D writes the matrix column-major
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{path} does not hold valid intrinsics (focal lengths must be positive)")
    return K


class Open3dSequence(Sequence):
    layout = "open3d"
    depth_scale = 1000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "Open3dSequence":
        intrinsics = sorted(p for p in path.glob("*.json") if "intrinsic_matrix" in p.read_text(errors="replace"))
        if not intrinsics:
            raise SequenceError(f"missing intrinsics JSON in {path} (Open3D PinholeCameraIntrinsic "
                                f"with 'intrinsic_matrix', e.g. camera_primesense.json)")
        K = _open3d_intrinsics(intrinsics[0])
        # without trajectory.log the poses are estimated (see sg3d.ingest.poses)
        posed = (path / "trajectory.log").is_file()
        poses = read_trajectory_log(path / "trajectory.log") if posed else {}
        colour_dir = path / "image" if (path / "image").is_dir() else path / "color"
        entries, skipped = [], []
        for number, color in numbered_images(colour_dir):
            depth = path / "depth" / f"{color.stem}.png"
            if not depth.is_file():
                skipped.append((color.stem, f"missing depth/{depth.name}"))
                continue
            if posed and number not in poses:
                skipped.append((color.stem, f"no pose for frame {number} in trajectory.log"))
                continue
            entries.append(Entry(color.stem, color, depth, timestamp=number / 30.0, pose=poses.get(number)))
        if not entries:
            raise SequenceError(f"no {colour_dir.name}/NNNNN.jpg with a depth/NNNNN.png and a pose in {path}")
        return cls(path, entries, K, registration, skipped)
