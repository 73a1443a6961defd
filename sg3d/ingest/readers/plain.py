"""A plain folder, your own recording: ``color/*.png|jpg``, ``depth/*.png`` (uint16, registered to
colour) and a one-line ``intrinsics.txt`` (``fx fy cx cy`` [depth units per metre]); no poses."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np

from sg3d.ingest.readers.base import Entry, Sequence, SequenceError
from sg3d.ingest.readers.registration import Registration

PLAIN_INTRINSICS = ("intrinsics.txt", "camera-intrinsics.txt")
_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg")


class PlainSequence(Sequence):
    """``color/`` + ``depth/`` + a one-line ``intrinsics.txt``: what a RealSense or any RGB-D
    camera's recorder gives once the frames are saved as images. No poses."""

    layout = "plain"
    depth_scale = 1000.0

    @staticmethod
    def looks_like(path: Path) -> bool:
        """A color/ folder without ScanNet's intrinsic/ and pose/ (what else is missing is
        reported when it is opened)."""
        return (path / "color").is_dir() and not (path / "intrinsic").is_dir() and not (path / "pose").is_dir()

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "PlainSequence":
        intr = next((path / n for n in PLAIN_INTRINSICS if (path / n).is_file()), None)
        missing = []
        if not (path / "color").is_dir():
            missing.append("color/ (the colour images, .png or .jpg)")
        if not (path / "depth").is_dir():
            missing.append("depth/ (16-bit .png depth registered to colour, e.g. RealSense aligned depth)")
        if intr is None:
            missing.append("intrinsics.txt (one line: fx fy cx cy [depth units per metre]; from the "
                           "camera's calibration, e.g. `rs-enumerate-devices -c` for a RealSense)")
        if missing:
            raise SequenceError(f"{path} is missing " + "; ".join(missing))
        assert intr is not None
        K, scale = _plain_intrinsics(intr)
        colours = sorted(p for p in (path / "color").iterdir() if p.suffix.lower() in _IMAGE_SUFFIXES)
        depths = sorted(p for p in (path / "depth").iterdir() if p.suffix.lower() == ".png")
        by_stem = {p.stem: p for p in depths}
        if colours and all(c.stem in by_stem for c in colours[:5]):
            pairs = [(c, by_stem.get(c.stem)) for c in colours]
        elif len(colours) == len(depths):
            pairs = list(zip(colours, depths))      # named differently: paired in order
        else:
            raise SequenceError(f"cannot pair {len(colours)} colour and {len(depths)} depth images in {path}: "
                                f"name them alike (color/000123.png with depth/000123.png) or give as many of each")
        entries, skipped = [], []
        for k, (color, depth) in enumerate(pairs):
            if depth is None:
                skipped.append((color.stem, f"missing depth/{color.stem}.png"))
                continue
            stamp = float(color.stem) if _is_number(color.stem) and len(color.stem) > 6 else k / 30.0
            entries.append(Entry(color.stem, color, depth, timestamp=stamp))
        if not entries:
            raise SequenceError(f"no colour image in {path / 'color'} has a depth image")
        seq = cls(path, entries, K, registration, skipped)
        seq.depth_scale = scale
        return seq


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _plain_intrinsics(path: Path) -> tuple[np.ndarray, float]:
    """`fx fy cx cy [depth scale]` (or a 3x3 matrix) -> (K, depth units per metre)."""
    try:
        values = np.array(path.read_text().split(), dtype=np.float64)
    except ValueError:
        raise SequenceError(f"{path} is not a list of numbers (expected: fx fy cx cy [depth units per metre])") from None
    scale = 1000.0
    if values.size == 5:
        values, scale = values[:4], float(values[4])
        if not np.isfinite(scale) or scale <= 0:
            raise SequenceError(f"{path}: the depth scale (5th number) must be positive, e.g. 1000 for millimetres")
    if values.size not in (4, 9):
        raise SequenceError(f"{path} holds {values.size} numbers; expected fx fy cx cy [depth units per metre]")
    return _read_matrix_values(values, path), scale


def _read_matrix_values(values: np.ndarray, path: Path) -> np.ndarray:
    K = values.reshape(3, 3) if values.size == 9 else np.array(
        [[values[0], 0, values[2]], [0, values[1], values[3]], [0, 0, 1]])
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{path} does not hold valid intrinsics (focal lengths must be positive)")
    return K
