"""The picture of an answer ("which cup is the biggest"): the stored thumbnail, written in the
format the file name asks for, at a size a person can see.

The store keeps a JPEG crop of at most 128 px on its long side (ingest decides that), often far
less (a cup seen from across the room is ~40 px). A tile that small is unreadable on a screen,
so it is decoded and upscaled with bicubic interpolation (cv2.INTER_CUBIC) until its long side is
at least `MIN_SIDE`: this adds no detail, it only makes the crop visible.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Optional

MIN_SIDE = 256
FORMATS = {".png": ".png", ".jpg": ".jpg", ".jpeg": ".jpg"}


def visible(image, min_side: int = MIN_SIDE):
    """Upscale (bicubic) so the long side is at least `min_side`; larger images are unchanged."""
    import cv2

    h, w = image.shape[:2]
    if max(h, w) >= min_side:
        return image
    f = min_side / max(h, w)
    return cv2.resize(image, (max(1, round(w * f)), max(1, round(h * f))), interpolation=cv2.INTER_CUBIC)


def write_picture(data: bytes, out: Optional[str] = None) -> str:
    """Decode the stored thumbnail, upscale it (`visible`) and write it as PNG or JPEG, as the
    extension of `out` names (default: a new temporary .png). ValueError for another extension
    or bytes that are no image."""
    import cv2
    import numpy as np

    if out is None:
        fd, out = tempfile.mkstemp(prefix="sg3d-answer-", suffix=".png")
        os.close(fd)
    ext = Path(out).suffix.lower()
    if ext not in FORMATS:
        raise ValueError(f"--out must end in .png, .jpg or .jpeg, not '{ext or Path(out).name}'")
    image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    if image is None:
        raise ValueError("the stored thumbnail is not a readable image")
    ok, buf = cv2.imencode(FORMATS[ext], visible(image))
    if not ok:
        raise ValueError(f"could not encode the picture as {ext}")
    Path(out).write_bytes(buf.tobytes())
    return str(out)
