"""The ROS bag options shared by `sg3d build` and `sg3d frames`, collected into one `bag` dict
(the keyword arguments of `sg3d.ingest.readers.open_sequence` for bags)."""
from __future__ import annotations

import functools

import click

_OPTIONS = [
    click.option("--color-topic", default=None, metavar="TOPIC",
                 help="ROS bag: colour Image/CompressedImage topic (default: the only one)."),
    click.option("--depth-topic", default=None, metavar="TOPIC",
                 help="ROS bag: depth Image (16UC1 mm, 32FC1 m) or compressedDepth topic (default: the only one)."),
    click.option("--info-topic", default=None, metavar="TOPIC",
                 help="ROS bag: CameraInfo topic (default: beside the colour topic, else the only one)."),
    click.option("--pose-topic", default=None, metavar="TOPIC|tf",
                 help="ROS bag: PoseStamped/Odometry topic of the camera, or 'tf' for /tf + /tf_static."),
    click.option("--camera-frame", default=None, metavar="FRAME",
                 help="ROS bag, /tf poses: the camera's optical frame (default: the colour images' frame_id)."),
    click.option("--world-frame", default=None, metavar="FRAME",
                 help="ROS bag, /tf poses: the world frame (default: the root of the camera's tf tree)."),
    click.option("--max-dt", type=click.FloatRange(0.0, min_open=True), default=None, metavar="SECONDS",
                 help="ROS bag: colour/depth/pose association tolerance [0.02]."),
]
KEYS = ("color_topic", "depth_topic", "info_topic", "pose_topic", "camera_frame", "world_frame", "max_dt")


def bag_options(fn):
    """Add the bag options to a click command; the command receives them as `bag` (a dict with
    only the options given)."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        kwargs["bag"] = {k: v for k in KEYS if (v := kwargs.pop(k)) is not None}
        return fn(*args, **kwargs)

    for option in reversed(_OPTIONS):
        wrapper = option(wrapper)
    return wrapper
