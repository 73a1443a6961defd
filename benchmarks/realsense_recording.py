"""A RealSense recording made from recorded frames by librealsense's own recorder (pyrealsense2's
software device), for `sg3d map realsense:FILE` without a camera: used by tests/e2e/test_map_sources.py
and `benchmarks.map_noposes --realsense`."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np


def colour_intrinsics(K: np.ndarray, K_depth: np.ndarray, registration) -> np.ndarray:
    """The colour camera's intrinsics that a camera's calibration would give, for a recording
    whose depth reaches colour pixels by `registration` (depth pixel = c + s (colour pixel - c) +
    o, both cameras on one optical axis): the colour ray of pixel u is the depth camera's ray of
    the depth pixel it maps to, so fx = fx_depth / s and cx = c - (o + c - cx_depth) / s."""
    if registration is None or registration.is_identity:
        return np.asarray(K, dtype=np.float64)
    out = np.array(K_depth, dtype=np.float64)
    centre = registration.center if registration.center is not None else (K[0, 2], K[1, 2])
    for axis in (0, 1):
        s, o, c = registration.scale[axis], registration.offset[axis], centre[axis]
        out[axis, axis] = K_depth[axis, axis] / s
        out[axis, 2] = c - (o + c - K_depth[axis, 2]) / s
    return out


def record_realsense(path: Path, folder: Path, n: int, colour_format: str = "bgr8", fps: int = 30) -> Path:
    """A RealSense recording made by librealsense's own recorder from a software device whose
    depth (z16, 1 mm units) and colour sensors are fed the first `n` frames of a recording (any layout sg3d reads) at
    `fps` (a RealSense streams at 6, 15, 30 or 60). librealsense 2.57+ records ROS 2 .db3 files (older ones: .bag).

    The recorder stamps each frame with the time it reached it, and playback follows those
    stamps: the frames are therefore fed at `fps` in real time (recording takes n / fps seconds).
    Fed as fast as they could be decoded, a quiet machine's recording played back at ~60 frames/s."""
    import cv2
    import pyrealsense2 as rs      # ImportError without it: pip install 'sg3d[live]'

    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(folder)
    first = seq.frame(0)
    h, w = first.color.shape[:2]
    K_depth = seq.depth_K
    K = colour_intrinsics(seq.K, K_depth, seq.registration)
    dh, dw = seq.pixels(0, registered=False).depth().shape

    def intrinsics(K, w, h):
        i = rs.intrinsics()
        i.width, i.height, i.fx, i.fy, i.ppx, i.ppy = w, h, K[0, 0], K[1, 1], K[0, 2], K[1, 2]
        i.model, i.coeffs = rs.distortion.none, [0.0] * 5
        return i

    def stream(kind, uid, fmt, bpp, K, w, h):
        s = rs.video_stream()
        s.type, s.index, s.uid, s.width, s.height, s.fps, s.bpp, s.fmt = kind, 0, uid, w, h, fps, bpp, fmt
        s.intrinsics = intrinsics(K, w, h)
        return s

    # depth in the depth camera's own pixels and intrinsics, as a camera streams it (the
    # recording's registration as the two cameras' intrinsics on one optical axis)
    device = rs.software_device()
    depth_sensor, colour_sensor = device.add_sensor("Depth"), device.add_sensor("Color")
    depth_profile = depth_sensor.add_video_stream(stream(rs.stream.depth, 0, rs.format.z16, 2, K_depth, dw, dh))
    depth_sensor.add_read_only_option(rs.option.depth_units, 0.001)
    fmt = rs.format.rgb8 if colour_format == "rgb8" else rs.format.bgr8
    colour_profile = colour_sensor.add_video_stream(stream(rs.stream.color, 1, fmt, 3, K, w, h))
    same = rs.extrinsics()
    same.rotation, same.translation = [1, 0, 0, 0, 1, 0, 0, 0, 1], [0, 0, 0]
    depth_profile.register_extrinsics_to(colour_profile, same)
    device.create_matcher(rs.matchers.default)
    recorder = rs.recorder(str(path), device)
    sync = rs.syncer()
    depth_sensor.open(depth_profile)
    colour_sensor.open(colour_profile)
    depth_sensor.start(sync)
    colour_sensor.start(sync)
    t0 = time.monotonic()
    for k in range(n):
        f = seq.frame(k)
        depth = np.ascontiguousarray(np.round(seq.pixels(k, registered=False).depth() * 1000).astype(np.uint16))
        colour = np.ascontiguousarray(cv2.cvtColor(f.color, cv2.COLOR_BGR2RGB) if colour_format == "rgb8" else f.color)
        for sensor, profile, pixels, bpp in ((depth_sensor, depth_profile, depth, 2),
                                             (colour_sensor, colour_profile, colour, 3)):
            frame = rs.software_video_frame()
            frame.pixels, frame.stride, frame.bpp = pixels, pixels.shape[1] * bpp, bpp
            frame.timestamp, frame.domain, frame.frame_number = k * 1000 / fps, rs.timestamp_domain.hardware_clock, k
            frame.profile = profile.as_video_stream_profile()
            if sensor is depth_sensor:
                frame.depth_units = 0.001
            sensor.on_video_frame(frame)
        time.sleep(max(0.002, t0 + (k + 1) / fps - time.monotonic()))
    for sensor in (depth_sensor, colour_sensor):
        sensor.stop()
        sensor.close()
    del recorder               # closes the file
    return path
