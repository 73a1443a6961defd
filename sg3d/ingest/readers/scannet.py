"""The ScanNet layout (SensReader export): ``color/N.jpg``, ``depth/N.png`` (mm), ``pose/N.txt``,
``intrinsic/intrinsic_color.txt`` (4x4) and ``intrinsic_depth.txt``."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np

from sg3d.ingest.readers.base import (
    Entry,
    Sequence,
    SequenceError,
    numbered_images,
    read_matrix,
)
from sg3d.ingest.readers.registration import Registration


class ScanNetSequence(Sequence):
    layout = "scannet"
    depth_scale = 1000.0
    _depth_K: np.ndarray      # set by `open` when the export ships intrinsic_depth.txt (see `depth_K`)

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "ScanNetSequence":
        intr = path / "intrinsic" / "intrinsic_color.txt"
        if not intr.is_file():
            raise SequenceError(f"missing intrinsics file {intr} (ScanNet SensReader export)")
        K = read_matrix(intr)
        if registration is None and (path / "intrinsic" / "intrinsic_depth.txt").is_file():
            registration = Registration.from_intrinsics(K, read_matrix(path / "intrinsic" / "intrinsic_depth.txt"))
        if not (path / "color").is_dir():
            raise SequenceError(f"missing folder {path / 'color'} (ScanNet SensReader export)")
        entries, skipped = [], []
        for number, color in numbered_images(path / "color"):
            depth = path / "depth" / f"{color.stem}.png"
            if not depth.is_file():
                skipped.append((color.stem, f"missing depth/{depth.name}"))
                continue
            entries.append(Entry(color.stem, color, depth, timestamp=number / 30.0,
                                  pose_file=path / "pose" / f"{color.stem}.txt"))
        if not entries:
            raise SequenceError(f"no color/N.jpg with a depth/N.png in {path}")
        seq = cls(path, entries, K, registration, skipped)
        if (path / "intrinsic" / "intrinsic_depth.txt").is_file():
            seq._depth_K = read_matrix(path / "intrinsic" / "intrinsic_depth.txt")
        return seq
