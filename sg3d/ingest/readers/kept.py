"""Frames a live source keeps past its ring, so that the end of a map can still read them.

A camera's source holds only its last few seconds of frames (`RealSenseSource`, `McapFollower`:
`ring`), while a map tracked on two cores judges a frame now and may detect it only at the end
(`sg3d.ingest.live.LiveMapper.finish`: the coverage choice over every sharp frame judged). The
frames mapping judged sharp are therefore kept here, encoded as a folder recording stores them
(colour JPEG at `JPEG_QUALITY`, depth as 16-bit PNG in millimetres, a RealSense's own depth
unit), within a memory budget (`KEPT_MIB`; the oldest go first): about 0.3 MB a frame at
640x480, so the default holds some 1,700 judged frames, a quarter of an hour of mapping on two
cores. Encoding costs 5-10 ms a frame (OpenCV, outside the interpreter lock).
"""
from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any, Optional

import cv2
import numpy as np

from sg3d.ingest.readers.frames import Frame, FrameError, FrameInfo, ring_item

KEPT_MIB = 512               # memory the kept frames may take
JPEG_QUALITY = 95            # colour kept as a camera's JPEG would store it (detection sees no difference)
PNG_LEVEL = 1                # fast PNG compression: 3x less memory than raw depth for ~5 ms a frame
DEPTH_UNIT_M = 0.001         # depth kept in millimetres (uint16: up to 65 m)


class _Encoded:
    """A kept frame's pixels, decoded on demand (a `FrameSource`)."""

    def __init__(self, name: str, colour: bytes, depth: bytes):
        self.name, self._colour, self._depth = name, colour, depth

    @property
    def nbytes(self) -> int:
        return len(self._colour) + len(self._depth)

    def _image(self, data: bytes, flags: int) -> np.ndarray:
        img = cv2.imdecode(np.frombuffer(data, np.uint8), flags)
        if img is None:
            raise FrameError(self.name, "kept image cannot be decoded")
        return img

    def color(self) -> np.ndarray:
        return self._image(self._colour, cv2.IMREAD_COLOR)

    def depth(self) -> np.ndarray:
        return self._image(self._depth, cv2.IMREAD_UNCHANGED).astype(np.float32) * np.float32(DEPTH_UNIT_M)

    def gray(self) -> np.ndarray:
        return self._image(self._colour, cv2.IMREAD_GRAYSCALE)

    def preview(self, factor: int) -> np.ndarray:
        img = self.color()
        h, w = img.shape[:2]
        return cv2.resize(img, (max(1, w // factor), max(1, h // factor)), interpolation=cv2.INTER_AREA)


def encode_frame(frame: Frame) -> _Encoded:
    """Rule "a kept frame is stored as a recording stores it": colour as JPEG (`JPEG_QUALITY`),
    depth as 16-bit PNG in millimetres (`DEPTH_UNIT_M`; beyond 65.5 m, and NaN, read as none)."""
    ok_c, colour = cv2.imencode(".jpg", frame.color, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
    depth = np.nan_to_num(frame.depth, nan=0.0, posinf=0.0, neginf=0.0) / DEPTH_UNIT_M
    mm = np.where((depth > 0) & (depth < 65535.5), np.rint(depth), 0).astype(np.uint16)
    ok_d, png = cv2.imencode(".png", mm, [cv2.IMWRITE_PNG_COMPRESSION, PNG_LEVEL])
    if not (ok_c and ok_d):
        raise FrameError(frame.name, "cannot be encoded to be kept")
    return _Encoded(frame.name, colour.tobytes(), png.tobytes())


class KeptFrames:
    """Encoded frames by index within `budget_mib` of memory, the oldest dropped first (module
    doc); `dropped` counts those dropped for memory."""

    def __init__(self, budget_mib: float = KEPT_MIB):
        self.budget = int(budget_mib * (1 << 20))
        self.bytes = 0
        self.dropped = 0
        self._frames: OrderedDict[int, tuple[_Encoded, np.ndarray, np.ndarray, float]] = OrderedDict()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._frames)

    def __contains__(self, i: object) -> bool:
        return i in self._frames

    def keep(self, frame: Frame) -> None:
        """Keep `frame`'s pixels, K, pose and time (a tracker gives a tracked frame its current
        pose again: loop closure moves it); a frame kept already stays as it is."""
        if frame.index in self._frames:
            return
        encoded = encode_frame(frame)
        with self._lock:
            self._frames[frame.index] = (encoded, frame.K.copy(), frame.pose.copy(), frame.timestamp)
            self.bytes += encoded.nbytes
            while self.bytes > self.budget and len(self._frames) > 1:
                _, (old, *_) = self._frames.popitem(last=False)
                self.bytes -= old.nbytes
                self.dropped += 1

    def frame(self, i: int) -> Optional[Frame]:
        """Kept frame i as it was kept, its pixels decoded when looked at; None if not kept."""
        with self._lock:
            held = self._frames.get(i)
        if held is None:
            return None
        encoded, K, pose, stamp = held
        return Frame(i, None, None, K, pose.copy(), FrameInfo(stamp, encoded.name, source=encoded))


def ring_or_kept(items: Any, count: int, i: int, name: str, ring: int, kept: KeptFrames) -> tuple[Any, Optional[Frame]]:
    """Frame i of a live source with a ring of its last `ring` frames (`ring_item`) and the frames
    kept past it: (its ring item, None) while the ring holds it, else (None, the kept frame);
    the ring's FrameError when neither holds it."""
    try:
        return ring_item(items, count, i, name, ring), None
    except FrameError:
        frame = kept.frame(i)
        if frame is None:
            raise
        return None, frame
