"""Camera poses for RGB-D sequences recorded without them (RGB-D odometry, loop closures, pose graph)."""
from sg3d.ingest.poses.estimate import PoseEstimate, estimate_poses

__all__ = ["PoseEstimate", "estimate_poses"]
