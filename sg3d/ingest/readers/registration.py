"""Depth-to-colour registration: which depth pixel lies behind each colour pixel.

Many RGB-D datasets store depth in the depth camera's own image (7-Scenes, ScanNet), while
everything downstream (boxes from the detector, colour histograms, Eq. 8 back-projection with
the colour intrinsics) works in colour pixels. We resample depth into the colour image once per
frame, with one vectorised `cv2.remap`, using an affine per-axis model

    u_d = c_u + s_u * (u - c_u) + o_u          v_d = c_v + s_v * (v - c_v) + o_v

where (u, v) is a colour pixel, (u_d, v_d) the depth pixel read for it, c the centre of the
scaling (the colour principal point unless given), s the scale (the ratio of the depth to the
colour focal length) and o an offset in depth pixels (the principal-point difference plus what
the baseline between the two cameras shifts at typical range). Nearest-neighbour sampling keeps
depth edges sharp (no invented depths between a foreground object and the wall behind it);
colour pixels whose depth pixel falls outside the depth image get 0 (= invalid).

Defaults per layout:
- 7-Scenes / 3DMatch: estimated per sequence (`estimate_registration`): the Kinect v1 rig's form,
  scale 1.09 and offset (+5, +1) about the principal point (measured on the red kitchen, whose depth
  edges lie 20-30 px off the colour edges without it), or the identity, whichever makes depth edges
  fall on colour edges best in a few frames spread over the sequence. 3DMatch scenes in the same
  layout ship depth already registered to colour (the study room): there the identity wins.
- ScanNet: from `intrinsic_depth.txt` and `intrinsic_color.txt` (s = f_d / f_c, o = c_d - c_c),
  which also handles the 640x480 depth under 1296x968 colour.
- TUM RGB-D: none (its depth is already registered to colour).
A plain resolution change without calibration maps pixel centres (`Registration.resample`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import cv2
import numpy as np


@dataclass(frozen=True)
class Registration:
    scale: tuple[float, float] = (1.0, 1.0)
    offset: tuple[float, float] = (0.0, 0.0)
    center: Optional[tuple[float, float]] = None  # None: the colour principal point

    @classmethod
    def kinect_v1(cls) -> "Registration":
        """The Kinect v1 rig's depth-to-colour form as 7-Scenes records it, measured on the red
        kitchen (ARCHITECTURE.md): depth = c + 1.09 (colour - c) + (5, 1). A candidate of
        `estimate_registration` for the 7-Scenes/3DMatch layout: the reader applies it when it scores best."""
        return cls(scale=(1.09, 1.09), offset=(5.0, 1.0))

    @classmethod
    def from_intrinsics(cls, K_color: np.ndarray, K_depth: np.ndarray) -> "Registration":
        """Registration implied by two pinhole intrinsics that share the optical axis."""
        sx = K_depth[0, 0] / K_color[0, 0]
        sy = K_depth[1, 1] / K_color[1, 1]
        return cls(scale=(float(sx), float(sy)),
                   offset=(float(K_depth[0, 2] - K_color[0, 2]), float(K_depth[1, 2] - K_color[1, 2])))

    @classmethod
    def resample(cls, color_size: tuple[int, int], depth_size: tuple[int, int]) -> "Registration":
        """Pure resolution change: pixel centres map onto pixel centres."""
        sx = depth_size[0] / color_size[0]
        sy = depth_size[1] / color_size[1]
        return cls(scale=(sx, sy), offset=(0.5 * sx - 0.5, 0.5 * sy - 0.5), center=(0.0, 0.0))

    @property
    def is_identity(self) -> bool:
        return self.scale == (1.0, 1.0) and self.offset == (0.0, 0.0)

    def depth_coordinates(self, K_color: np.ndarray, color_size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """Depth-image coordinates (map_x, map_y), float32 HxW, for every colour pixel."""
        w, h = color_size
        cu, cv = self.center if self.center is not None else (float(K_color[0, 2]), float(K_color[1, 2]))
        u = cu + self.scale[0] * (np.arange(w, dtype=np.float64) - cu) + self.offset[0]
        v = cv + self.scale[1] * (np.arange(h, dtype=np.float64) - cv) + self.offset[1]
        map_x = np.broadcast_to(u[None, :], (h, w)).astype(np.float32)
        map_y = np.broadcast_to(v[:, None], (h, w)).astype(np.float32)
        return map_x, map_y


class DepthRegistrar:
    """Applies a Registration to depth images of one size, with the remap tables built once."""

    def __init__(self, registration: Optional[Registration], K_color: np.ndarray, color_size: tuple[int, int]):
        self.registration = registration
        self.K_color = np.asarray(K_color, dtype=np.float64)
        self.color_size = (int(color_size[0]), int(color_size[1]))
        self._maps: dict[tuple[int, int], Optional[tuple[np.ndarray, np.ndarray]]] = {}

    def _maps_for(self, depth_size: tuple[int, int]) -> Any:
        if depth_size not in self._maps:
            reg = self.registration
            if reg is None or reg.is_identity:
                reg = None if depth_size == self.color_size else Registration.resample(self.color_size, depth_size)
            if reg is None:
                self._maps[depth_size] = None
            else:
                mx, my = reg.depth_coordinates(self.K_color, self.color_size)
                # fixed-point tables: the fastest form of remap for nearest-neighbour sampling
                self._maps[depth_size] = cv2.convertMaps(mx, my, cv2.CV_16SC2, nninterpolation=True)
        return self._maps[depth_size]

    def __call__(self, depth: np.ndarray) -> np.ndarray:
        """Depth (float32, any size) resampled into the colour image; outside = 0."""
        maps = self._maps_for((depth.shape[1], depth.shape[0]))
        if maps is None:
            return depth
        return cv2.remap(depth, maps[0], None, interpolation=cv2.INTER_NEAREST,  # type: ignore[call-overload]
                         borderMode=cv2.BORDER_CONSTANT, borderValue=0)


# A depth edge: the 3x3 Sobel of the log depth exceeds this (the Sobel weighs a step 4x, so a
# jump of about 5 % from one pixel to the next): an object's outline against what lies behind
# it, not a surface slanting away.
DEPTH_EDGE_LOG_JUMP = 0.2
# Too few depth-edge pixels (a frame of one flat wall) say nothing about the alignment.
MIN_EDGE_PIXELS = 100
# Frames scored per sequence, spread evenly over it (the median over them decides).
REGISTRATION_PROBES = 5


def edge_agreement(gray: np.ndarray, depth: np.ndarray) -> float:
    """How strongly colour edges lie where depth edges are, for depth already resampled into the
    colour image: the mean colour-gradient magnitude on depth-edge pixels over its mean on all
    pixels with depth (1 = no relation; a well registered pair scores 2-4). 0 when the frame has
    too few depth edges to judge."""
    valid = depth > 0
    log_depth = np.log(np.where(valid, depth, 1.0)).astype(np.float32)
    jump = np.hypot(cv2.Sobel(log_depth, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(log_depth, cv2.CV_32F, 0, 1, ksize=3))
    inner = cv2.erode(valid.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    edges = (jump > DEPTH_EDGE_LOG_JUMP) & inner
    if int(edges.sum()) < MIN_EDGE_PIXELS:
        return 0.0
    g = cv2.GaussianBlur(gray, (3, 3), 0).astype(np.float32)
    colour = np.hypot(cv2.Sobel(g, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(g, cv2.CV_32F, 0, 1, ksize=3))
    colour = cv2.dilate(colour, np.ones((3, 3), np.uint8))      # a 1-px miss is still a hit
    return float(colour[edges].mean() / (colour[inner].mean() + 1e-6))


def _registered_half(depth: np.ndarray, registration: "Registration", K: np.ndarray,
                     color_size: tuple[int, int]) -> np.ndarray:
    """Depth resampled into every second colour pixel (half resolution: 4x cheaper to score)."""
    mx, my = registration.depth_coordinates(K, color_size)
    return cv2.remap(depth, np.ascontiguousarray(mx[::2, ::2]), np.ascontiguousarray(my[::2, ::2]),
                     cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def estimate_registration(pairs: list[tuple[np.ndarray, np.ndarray]], K: np.ndarray,
                          candidates: dict[str, "Registration"]) -> tuple[str, dict[str, float]]:
    """The candidate registration under which depth edges fall on colour edges best.

    `pairs`: (grey colour image, depth in metres in the depth camera's pixels) of a few frames.
    Each candidate's score is the median `edge_agreement` over the frames; the first candidate
    (the identity, by convention) wins ties, so already registered depth is never moved.
    Returns the winner's name and every candidate's score."""
    scores: dict[str, float] = {}
    for name, reg in candidates.items():
        per_frame = [edge_agreement(gray[::2, ::2], _registered_half(depth, reg, K, (gray.shape[1], gray.shape[0])))
                     for gray, depth in pairs]
        scores[name] = float(np.median(per_frame)) if per_frame else 0.0
    best = max(scores, key=lambda n: (scores[n], n == next(iter(candidates))))
    return best, scores
