"""One RGB-D frame, with its pixels decoded only when someone looks at them.

Most frames of a sequence die early (blurry, or redundant for the keyframe groups) and only
need a grey image or nothing but their pose. A `Frame` therefore keeps a `FrameSource` that
decodes colour, depth or a grey image on demand; readers that already hold the pixels (tests,
in-memory sequences) pass them straight in and no source is needed.
"""
from __future__ import annotations

import re
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Iterator, Optional, Protocol

import cv2
import numpy as np

from sg3d.core.errors import Sg3dError


class FrameError(Sg3dError):
    """A frame that cannot be used (corrupt or missing image, bad pose); it is skipped, not fatal."""

    def __init__(self, name: str, reason: str):
        super().__init__(f"{name}: {reason}")
        self.name = name
        self.reason = reason


class FrameSource(Protocol):
    """Decodes the pixels of one frame; raises FrameError naming the file when it cannot."""

    def color(self) -> np.ndarray: ...            # HxWx3 BGR uint8
    def depth(self) -> np.ndarray: ...            # HxW float32 metres, 0 = invalid, colour-registered
    def gray(self) -> np.ndarray: ...             # HxW uint8, same size as colour
    def preview(self, factor: int) -> np.ndarray: ...  # BGR uint8, about 1/factor of the colour size


@dataclass(frozen=True)
class FrameInfo:
    """What a frame is besides its pixels and camera: its time (s) and name in the recording, and
    for a lazily decoded frame its image size, the source decoding its pixels and who hears of a
    decoding failure (once)."""

    timestamp: float = 0.0
    name: str = ""
    size: Optional[tuple[int, int]] = None
    source: Optional[FrameSource] = None
    on_error: Optional[Callable[[str, str], None]] = None


class Frames(Protocol):
    """Anything that gives frame i: a recorded sequence, a live source."""

    def frame(self, i: int) -> "Frame": ...


class Frame:
    """An RGB-D frame: colour (BGR uint8), depth (float32 metres, 0 = invalid, registered to the
    colour image), K (3x3 colour intrinsics), pose (4x4 camera-to-world, float64).

    `color`, `depth` and `gray` decode on first access when the frame came from a lazy reader;
    `load()` decodes both now; `release()` drops the pixels again (the pose stays).
    A decoding failure raises FrameError and is reported once to the reader's `on_error`.
    """

    __slots__ = ("index", "K", "pose", "timestamp", "name", "_color", "_depth", "_gray",
                 "_source", "_on_error", "_size")

    def __init__(self, index: int, color: Optional[np.ndarray], depth: Optional[np.ndarray],
                 K: np.ndarray, pose: np.ndarray, info: FrameInfo = FrameInfo()):
        timestamp, name, size, source, on_error = info.timestamp, info.name, info.size, info.source, info.on_error
        self.index = int(index)
        self.K = np.asarray(K, dtype=np.float64)
        self.pose = np.asarray(pose, dtype=np.float64)
        self.timestamp = float(timestamp)
        self.name = name or f"frame {index}"
        self._color = color
        self._depth = depth
        self._gray: Optional[np.ndarray] = None
        self._source = source
        self._on_error = on_error
        self._size: Optional[tuple[int, int]] = (size[0], size[1]) if size is not None else None

    def __repr__(self) -> str:
        state = "loaded" if self.is_loaded else "lazy"
        return f"Frame({self.index}, {self.name!r}, {state})"

    # -- pixels -----------------------------------------------------------------------------
    def _decode(self, what: str) -> np.ndarray:
        if self._source is None:
            raise FrameError(self.name, f"no {what} image")
        return self._call(getattr(self._source, what))

    def _call(self, fn: Callable[[], np.ndarray]) -> np.ndarray:
        try:
            return fn()
        except FrameError as exc:
            if self._on_error is not None:
                self._on_error(exc.name, exc.reason)
                self._on_error = None  # count each bad frame once
            raise

    @property
    def color(self) -> np.ndarray:
        if self._color is None:
            self._color = self._decode("color")
        return self._color

    @property
    def depth(self) -> np.ndarray:
        if self._depth is None:
            self._depth = self._decode("depth")
        return self._depth

    @property
    def gray(self) -> np.ndarray:
        """Grey image at colour resolution (decoded straight from the file when possible: 3x
        cheaper than a colour decode, which is what blur rejection of every frame needs)."""
        if self._gray is None:
            if self._color is not None or self._source is None:
                self._gray = cv2.cvtColor(self.color, cv2.COLOR_BGR2GRAY)
            else:
                self._gray = self._decode("gray")
        return self._gray

    def preview(self, factor: int = 4) -> np.ndarray:
        """A small BGR image (about 1/factor per side), cheap to decode for contact sheets."""
        source = self._source
        if self._color is None and source is not None:
            return self._call(lambda: source.preview(factor))
        h, w = self.color.shape[:2]
        return cv2.resize(self.color, (max(1, w // factor), max(1, h // factor)), interpolation=cv2.INTER_AREA)

    @property
    def is_loaded(self) -> bool:
        return self._color is not None and self._depth is not None

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of the colour image, known without decoding it."""
        if self._size is None:
            for img in (self._color, self._gray, self._depth):
                if img is not None:
                    self._size = (img.shape[1], img.shape[0])
                    break
            else:
                self._size = (self.color.shape[1], self.color.shape[0])
        return self._size

    def decode_quietly(self, what: Iterable[str]) -> dict[str, np.ndarray]:
        """Decode the named images ("color", "depth", "gray") that are not decoded yet, without
        keeping them or reporting a failure (a failed one is left out): the work a reader thread
        can do ahead; `keep` hands the result back to the frame."""
        out: dict[str, np.ndarray] = {}
        if self._source is None:
            return out
        for name in what:
            if getattr(self, "_" + name) is not None or (name == "gray" and self._color is not None):
                continue
            try:
                out[name] = getattr(self._source, name)()
            except FrameError:
                pass   # raised and reported again when the frame's user asks for it
        return out

    def keep(self, decoded: dict[str, np.ndarray]) -> None:
        """Take images decoded by `decode_quietly` (those not decoded here in the meantime)."""
        for name, img in decoded.items():
            if getattr(self, "_" + name) is None:
                setattr(self, "_" + name, img)

    def load(self) -> "Frame":
        """Decode colour and depth now (raises FrameError); returns self."""
        _ = self.color, self.depth
        return self

    def release(self) -> None:
        """Drop decoded pixels that can be decoded again (keeps in-memory frames intact)."""
        if self._source is not None:
            self._color = self._depth = self._gray = None


_FRAME_NAME = re.compile(r"frame-\d+")
_FIGURE = re.compile(r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?")


def reason_kind(name: str, reason: str) -> str:
    """What kind of damage a skipped frame's reason names, the same for every frame it hits: the
    reason without the frame's name in its file names, other frames' names as "frame-N" and
    every figure as "N" ("frame-000059.depth.png is truncated" -> "depth.png is truncated")."""
    text = reason.replace(name + ".", "").replace(name, "frame-N")
    return _FIGURE.sub("N", _FRAME_NAME.sub("frame-N", text))


def ring_item(items: Any, count: int, i: int, name: str, ring: int) -> Any:
    """Frame i of a live source that keeps only its last `ring` frames (`items`, the newest last,
    `count` received so far): FrameError when it has not arrived or is no longer held."""
    first = count - len(items)
    if i >= count:
        raise FrameError(name, "has not arrived yet")
    if i < first:
        raise FrameError(name, f"no longer held (the last {ring} frames are kept in memory)")
    return items[i - first]


def decoded_ahead(frames: Iterable[Frame], what: tuple[str, ...], ahead: int = 4) -> Iterator[Frame]:
    """`frames` in order, with their `what` images decoded on a reader thread up to `ahead` frames
    before the caller reaches them (JPEG and PNG decoding release the GIL, so decoding overlaps
    the caller's work). Nothing else changes: a frame whose decoding failed comes back without
    that image, and the failure is raised and reported when the caller asks for it."""
    window: deque = deque()
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="sg3d-decode") as pool:
        for frame in frames:
            window.append((frame, pool.submit(frame.decode_quietly, what)))
            if len(window) > ahead:
                ready, decoded = window.popleft()
                ready.keep(decoded.result())
                yield ready
        while window:
            ready, decoded = window.popleft()
            ready.keep(decoded.result())
            yield ready
