"""A camera's depth in its own pixels, with the colour image's grey levels brought into them: what
odometry reads (`sg3d.ingest.poses.online`). Aligning depth to colour resamples it (holes at
depth edges, nearest-neighbour steps) and, where the alignment is a fitted image-space map rather
than the rig's geometry, bends it; odometry's ICP works on the depth as the camera measured it."""
from __future__ import annotations

import cv2
import numpy as np


def grey_in_depth_pixels(depth: np.ndarray, K_depth: np.ndarray, grey: np.ndarray, K_colour: np.ndarray,
                         depth_to_colour: np.ndarray) -> np.ndarray:
    """Rule "each depth pixel sees the colour of its own 3-D point": every depth pixel with a
    depth is back-projected (`K_depth`), moved into the colour camera (`depth_to_colour`, 4x4) and
    projected there (`K_colour`); its grey level is the colour image's at that point (bilinear).
    A pixel without depth takes the grey level of the point 1 m ahead, where the parallax of a
    short baseline is small. Returns uint8 at the depth image's size."""
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w].astype(np.float32)
    z = np.where(depth > 0, depth, 1.0).astype(np.float32)
    x = (u - np.float32(K_depth[0, 2])) / np.float32(K_depth[0, 0]) * z
    y = (v - np.float32(K_depth[1, 2])) / np.float32(K_depth[1, 1]) * z
    R, t = depth_to_colour[:3, :3].astype(np.float32), depth_to_colour[:3, 3].astype(np.float32)
    xc = R[0, 0] * x + R[0, 1] * y + R[0, 2] * z + t[0]
    yc = R[1, 0] * x + R[1, 1] * y + R[1, 2] * z + t[1]
    zc = np.maximum(R[2, 0] * x + R[2, 1] * y + R[2, 2] * z + t[2], np.float32(1e-3))
    mx = (xc / zc * np.float32(K_colour[0, 0]) + np.float32(K_colour[0, 2])).astype(np.float32)
    my = (yc / zc * np.float32(K_colour[1, 1]) + np.float32(K_colour[1, 2])).astype(np.float32)
    return cv2.remap(grey, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
