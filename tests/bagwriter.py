"""Writes real ROS bags (rosbags' own writers: ROS1 .bag, ROS2 sqlite3 / MCAP, bare .mcap) from
frames of a folder sequence, so the bag reader can be compared with the folder reader."""
from __future__ import annotations

import shutil
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import cv2
import numpy as np
from scipy.spatial.transform import Rotation

T0 = 1_700_000_000  # seconds: a realistic stamp, far from 0


@dataclass
class BagFrame:
    colour: np.ndarray        # BGR uint8
    jpeg: bytes               # the original compressed colour file
    depth_mm: np.ndarray      # uint16, registered to colour
    pose: np.ndarray          # 4x4 camera-to-world
    K: np.ndarray
    t: float                  # seconds since T0


def frames_from(seq, indices) -> list[BagFrame]:
    out = []
    for k, i in enumerate(indices):
        f = seq.frame(i)
        depth = np.round(f.depth * 1000.0).astype(np.uint16)
        out.append(BagFrame(f.color, seq._entries[i].color.read_bytes(), depth, f.pose, f.K, k / 30.0))
    return out


def _typestore(ros1: bool):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    if "tf2_msgs/msg/TFMessage" not in ts.types:  # the ROS1 store lacks it
        ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    return ts


def _make(ts, msgtype: str, **values):
    cls = ts.types[msgtype]
    fields = [f for f in cls.__dataclass_fields__ if f != "__msgtype__"]
    lower = {f.lower(): f for f in fields}
    return cls(**{lower.get(k.lower(), k): v for k, v in values.items() if k.lower() in lower})


def _header(ts, t_ns: int, frame_id: str):
    stamp = _make(ts, "builtin_interfaces/msg/Time", sec=t_ns // 1_000_000_000, nanosec=t_ns % 1_000_000_000)
    return _make(ts, "std_msgs/msg/Header", seq=0, stamp=stamp, frame_id=frame_id)


def _pose_msgs(ts, T: np.ndarray):
    q = Rotation.from_matrix(T[:3, :3]).as_quat()
    quat = _make(ts, "geometry_msgs/msg/Quaternion", x=q[0], y=q[1], z=q[2], w=q[3])
    return T[:3, 3], quat


def write_bag(path: Path, frames: list[BagFrame], *, kind: str = "ros1", colour: str = "raw",
              poses: str = "topic", encoding: str = "rgb8", drop_tf: Optional[set] = None,
              depth_offset: float = 0.003, extra_colour_topic: bool = False, depth: bool = True,
              depth_format: str = "raw") -> Path:
    """kind: ros1 | sqlite3 | mcap | bare-mcap; colour: raw (Image `encoding`) | jpeg
    (CompressedImage); poses: topic (PoseStamped) | tf (/tf world->base_link, /tf_static
    base_link->camera_optical) | none; depth: False leaves the depth topic out; depth_format:
    raw (16UC1 Image) | compressedDepth (CompressedImage as image_transport's
    compressed_depth_image_transport writes it: a 12-byte header, then a PNG of 16-bit mm);
    drop_tf: frame indices whose /tf message is left out."""
    ros1 = kind == "ros1"
    ts = _typestore(ros1)
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    if ros1:
        from rosbags.rosbag1 import Writer

        writer = Writer(path)
    else:
        from rosbags.rosbag2 import StoragePlugin, Writer

        plugin = StoragePlugin.SQLITE3 if kind == "sqlite3" else StoragePlugin.MCAP
        writer = Writer(path, version=9, storage_plugin=plugin)
    cam = "camera_color_optical_frame"
    # a fixed mount of the camera on the robot, so /tf must be chained to give the camera pose
    mount = np.eye(4)
    mount[:3, :3] = Rotation.from_euler("xyz", [-90, 0, -90], degrees=True).as_matrix()
    mount[:3, 3] = (0.1, 0.02, 0.3)
    with writer:
        ctype = "sensor_msgs/msg/Image" if colour == "raw" else "sensor_msgs/msg/CompressedImage"
        c_colour = writer.add_connection("/camera/color/image_raw" if colour == "raw" else
                                         "/camera/color/image_raw/compressed", ctype, typestore=ts)
        c_extra = writer.add_connection("/camera/ir/image_raw", "sensor_msgs/msg/Image", typestore=ts) \
            if extra_colour_topic else None
        dtype = "sensor_msgs/msg/Image" if depth_format == "raw" else "sensor_msgs/msg/CompressedImage"
        c_depth = writer.add_connection("/camera/aligned_depth_to_color/image_raw" if depth_format == "raw" else
                                        "/camera/aligned_depth_to_color/image_raw/compressedDepth", dtype,
                                        typestore=ts) if depth else None
        c_info = writer.add_connection("/camera/color/camera_info", "sensor_msgs/msg/CameraInfo", typestore=ts)
        if poses == "topic":
            c_pose = writer.add_connection("/camera/pose", "geometry_msgs/msg/PoseStamped", typestore=ts)
        elif poses == "tf":
            c_tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=ts)
            c_static = writer.add_connection("/tf_static", "tf2_msgs/msg/TFMessage", typestore=ts)

        def tf_msg(t_ns, parent, child, T):
            p, q = _pose_msgs(ts, T)
            tr = _make(ts, "geometry_msgs/msg/Transform",
                       translation=_make(ts, "geometry_msgs/msg/Vector3", x=p[0], y=p[1], z=p[2]), rotation=q)
            stamped = _make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, t_ns, parent),
                            child_frame_id=child, transform=tr)
            return _make(ts, "tf2_msgs/msg/TFMessage", transforms=[stamped])

        t_first = T0 * 1_000_000_000
        if poses == "tf":
            writer.write(c_static, t_first, serialize(tf_msg(t_first, "base_link", cam, mount),
                                                      "tf2_msgs/msg/TFMessage"))
        for k, f in enumerate(frames):
            t = t_first + int(round(f.t * 1e9))
            h, w = f.colour.shape[:2]
            if colour == "raw":
                if encoding == "rgb8":
                    data = cv2.cvtColor(f.colour, cv2.COLOR_BGR2RGB)
                elif encoding == "bgr8":
                    data = f.colour
                else:  # an encoding the reader does not know
                    data = f.colour
                msg = _make(ts, "sensor_msgs/msg/Image", header=_header(ts, t, cam), height=h, width=w,
                            encoding=encoding, is_bigendian=0, step=w * 3,
                            data=np.ascontiguousarray(data).reshape(-1))
            else:
                msg = _make(ts, "sensor_msgs/msg/CompressedImage", header=_header(ts, t, cam), format="jpeg",
                            data=np.frombuffer(f.jpeg, dtype=np.uint8))
            writer.write(c_colour, t, serialize(msg, ctype))
            if c_extra is not None:
                ir = _make(ts, "sensor_msgs/msg/Image", header=_header(ts, t, "ir"), height=h, width=w,
                           encoding="mono8", is_bigendian=0, step=w,
                           data=cv2.cvtColor(f.colour, cv2.COLOR_BGR2GRAY).reshape(-1))
                writer.write(c_extra, t, serialize(ir, "sensor_msgs/msg/Image"))
            td = t + int(depth_offset * 1e9)
            if depth_format == "raw":
                dmsg = _make(ts, "sensor_msgs/msg/Image", header=_header(ts, td, cam), height=h, width=w,
                             encoding="16UC1", is_bigendian=0, step=w * 2,
                             data=np.ascontiguousarray(f.depth_mm).view(np.uint8).reshape(-1))
            else:  # header: int32 compression format (0 = 16UC1 as is), float32 depthQuantA, B (unused)
                ok, png = cv2.imencode(".png", f.depth_mm)
                assert ok, "cv2 cannot write a 16-bit PNG"
                dmsg = _make(ts, "sensor_msgs/msg/CompressedImage", header=_header(ts, td, cam),
                             format="16UC1; compressedDepth png",
                             data=np.frombuffer(struct.pack("<iff", 0, 0.0, 0.0) + png.tobytes(), dtype=np.uint8))
            if c_depth is not None:
                writer.write(c_depth, td, serialize(dmsg, dtype))
            if k == 0:
                K = f.K
                info = _make(ts, "sensor_msgs/msg/CameraInfo", header=_header(ts, t, cam), height=h, width=w,
                             distortion_model="plumb_bob", d=np.zeros(5), k=K.reshape(-1).astype(np.float64),
                             r=np.eye(3).reshape(-1),
                             p=np.hstack([K, np.zeros((3, 1))]).reshape(-1).astype(np.float64),
                             binning_x=0, binning_y=0,
                             roi=_make(ts, "sensor_msgs/msg/RegionOfInterest", x_offset=0, y_offset=0, height=0,
                                       width=0, do_rectify=False))
                writer.write(c_info, t, serialize(info, "sensor_msgs/msg/CameraInfo"))
            if poses == "topic":
                p, q = _pose_msgs(ts, f.pose)
                pmsg = _make(ts, "geometry_msgs/msg/PoseStamped", header=_header(ts, t, "world"),
                             pose=_make(ts, "geometry_msgs/msg/Pose",
                                        position=_make(ts, "geometry_msgs/msg/Point", x=p[0], y=p[1], z=p[2]),
                                        orientation=q))
                writer.write(c_pose, t, serialize(pmsg, "geometry_msgs/msg/PoseStamped"))
            elif poses == "tf" and (not drop_tf or k not in drop_tf):
                base = f.pose @ np.linalg.inv(mount)
                writer.write(c_tf, t, serialize(tf_msg(t, "world", "base_link", base), "tf2_msgs/msg/TFMessage"))
    if kind == "bare-mcap":
        inner = next(Path(path).glob("*.mcap"))
        bare = Path(str(path) + ".mcap")
        shutil.move(str(inner), bare)
        shutil.rmtree(path)
        return bare
    return Path(path)
