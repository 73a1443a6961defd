"""The 7-Scenes / 3DMatch layout: ``frame-NNNNNN.color.jpg|png``, ``.depth.png`` (uint16 mm),
``.pose.txt`` (4x4 camera-to-world), ``camera-intrinsics.txt`` (3x3, here or one folder up)."""
from __future__ import annotations

import re
from pathlib import Path
from typing import Optional

from sg3d.ingest.readers.base import Entry, Sequence, SequenceError, read_matrix
from sg3d.ingest.readers.registration import Registration

SEVEN_SCENES_COLOUR = re.compile(r"^(frame-(\d+))\.color\.(jpg|jpeg|png)$", re.IGNORECASE)


class SevenScenesSequence(Sequence):
    layout = "7scenes"
    depth_scale = 1000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "SevenScenesSequence":
        candidates = [path / "camera-intrinsics.txt", path.parent / "camera-intrinsics.txt"]
        intr = next((p for p in candidates if p.is_file()), None)
        if intr is None:
            raise SequenceError(f"missing intrinsics file {path / 'camera-intrinsics.txt'} "
                                f"(3x3 colour camera matrix; 7-Scenes' Kinect: fx=fy=585, cx=320, cy=240)")
        K = read_matrix(intr)
        found = []
        for p in path.iterdir():
            m = SEVEN_SCENES_COLOUR.match(p.name)
            if m:
                found.append((int(m.group(2)), m.group(1), p))
        found.sort()
        entries, skipped = [], []
        for number, stem, color in found:
            depth = path / f"{stem}.depth.png"
            if not depth.is_file():
                skipped.append((stem, f"missing {depth.name}"))
                continue
            entries.append(Entry(stem, color, depth, timestamp=number / 30.0,  # Kinect v1 runs at 30 Hz
                                  pose_file=path / f"{stem}.pose.txt"))
        if not entries:
            raise SequenceError(f"no frame-NNNNNN.color.jpg|png with a .depth.png in {path}")
        reg = Registration.seven_scenes() if registration is None else registration
        return cls(path, entries, K, reg, skipped)
