"""The 7-Scenes / 3DMatch layout: ``frame-NNNNNN.color.jpg|png``, ``.depth.png`` (uint16 mm),
``.pose.txt`` (4x4 camera-to-world), ``camera-intrinsics.txt`` (3x3, here or one folder up)."""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Optional

import cv2
import numpy as np

from sg3d.ingest.readers.base import Entry, Sequence, SequenceError, read_matrix
from sg3d.ingest.readers.image_checks import image_problem
from sg3d.ingest.readers.registration import REGISTRATION_PROBES, Registration, estimate_registration

SEVEN_SCENES_COLOUR = re.compile(r"^(frame-(\d+))\.color\.(jpg|jpeg|png)$", re.IGNORECASE)


class SevenScenesSequence(Sequence):
    layout = "7scenes"
    depth_scale = 1000.0
    registration_estimate: Optional[tuple[str, dict[str, float]]] = None
    sources: Optional[dict[str, str]] = None       # what the reader chose, in words (`sg3d frames`)

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "SevenScenesSequence":
        candidates = [path / "camera-intrinsics.txt", path.parent / "camera-intrinsics.txt"]
        intr = next((p for p in candidates if p.is_file()), None)
        if intr is None:
            raise SequenceError(f"missing intrinsics file {path / 'camera-intrinsics.txt'} "
                                f"(3x3 colour camera matrix; 7-Scenes' Kinect: fx=fy=585, cx=320, cy=240)")
        K = read_matrix(intr)
        # one listing answers which depth files exist (a followed folder is listed again as it
        # grows: a stat per frame made each listing of 1,000 frames cost twice as much)
        with os.scandir(path) as it:
            names = {e.name for e in it}
        found = []
        for name in names:
            m = SEVEN_SCENES_COLOUR.match(name)
            if m:
                found.append((int(m.group(2)), m.group(1), name))
        found.sort()
        entries, skipped = [], []
        for number, stem, color in found:
            depth = f"{stem}.depth.png"
            if depth not in names:
                skipped.append((stem, f"missing {depth}"))
                continue
            entries.append(Entry(stem, path / color, path / depth, timestamp=number / 30.0,  # Kinect v1 runs at 30 Hz
                                  pose_file=path / f"{stem}.pose.txt"))
        if not entries:
            raise SequenceError(f"no frame-NNNNNN.color.jpg|png with a .depth.png in {path}")
        estimate = None
        if registration is None:
            name, scores = estimate_registration(_probe_pairs(entries), K, CANDIDATES)
            registration, estimate = CANDIDATES[name], (name, scores)
        seq = cls(path, entries, K, registration, skipped)
        seq.registration_estimate = estimate
        if estimate is not None:
            seq.sources = {"depth registration": _describe(*estimate)}
        return seq


# What depth registration a 7-Scenes-layout folder may need: none (3DMatch scenes ship depth
# registered to colour) or the Kinect v1 rig's form (7-Scenes). The identity comes first: it wins ties.
CANDIDATES = {"identity": Registration(), "Kinect v1 form": Registration.kinect_v1()}


def _probe_pairs(entries: list[Entry]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Grey colour and depth (metres, depth pixels) of frames spread evenly over the sequence."""
    picks = sorted({int(i) for i in np.linspace(0, len(entries) - 1, REGISTRATION_PROBES)})
    pairs = []
    for i in picks:
        gray, raw = _quiet_read(entries[i].color, cv2.IMREAD_GRAYSCALE), _quiet_read(entries[i].depth, cv2.IMREAD_UNCHANGED)
        if gray is None or raw is None or raw.ndim != 2:
            continue                      # a bad frame is reported when the build reaches it
        depth = raw.astype(np.float32) / SevenScenesSequence.depth_scale
        depth[raw == 65535] = 0.0
        pairs.append((gray, depth))
    return pairs


def _quiet_read(path: Path, flags: int) -> Optional[np.ndarray]:
    """An image, or None when it is missing or damaged (checked before decoding: libjpeg and
    libpng would print their own complaint on stderr)."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if image_problem(data, path.suffix):
        return None
    return cv2.imdecode(np.frombuffer(data, np.uint8), flags)


def _describe(name: str, scores: dict[str, float]) -> str:
    others = ", ".join(f"{n} {s:.2f}" for n, s in scores.items() if n != name)
    return f"{name}, estimated (depth/colour edge agreement {scores[name]:.2f}; {others})"
