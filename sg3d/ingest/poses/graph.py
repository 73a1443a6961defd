"""Pose-graph optimisation with GTSAM: odometry and loop-closure edges between camera poses."""
from __future__ import annotations

import numpy as np

ROTATION_SIGMA = 0.01        # radians, per edge: what one RGB-D odometry fit is good to
TRANSLATION_SIGMA = 0.01     # metres


def optimise_pose_graph(initial: dict[int, np.ndarray], edges: list[tuple[int, int, np.ndarray, bool]],
                        anchor: int) -> dict[int, np.ndarray]:
    """Maximum-likelihood camera poses given relative measurements: minimise
    sum_e |Log(Z_e^-1 T_a^-1 T_b)|^2_Sigma over edges e = (a, b, Z_e), T_a camera-to-world, with
    the `anchor` pose held by a tight prior (the gauge). Loop-closure edges (flag True) carry a
    Huber kernel so one wrong closure cannot pull the whole trajectory. Levenberg-Marquardt."""
    import gtsam

    sigmas = np.array([ROTATION_SIGMA] * 3 + [TRANSLATION_SIGMA] * 3)
    noise = gtsam.noiseModel.Diagonal.Sigmas(sigmas)
    robust = gtsam.noiseModel.Robust.Create(gtsam.noiseModel.mEstimator.Huber.Create(1.345), noise)
    graph = gtsam.NonlinearFactorGraph()
    graph.add(gtsam.PriorFactorPose3(anchor, gtsam.Pose3(initial[anchor]),
                                     gtsam.noiseModel.Diagonal.Sigmas(sigmas * 1e-3)))
    for a, b, Z, loop in edges:
        graph.add(gtsam.BetweenFactorPose3(a, b, gtsam.Pose3(Z), robust if loop else noise))
    values = gtsam.Values()
    for k, T in initial.items():
        values.insert(k, gtsam.Pose3(T))
    params = gtsam.LevenbergMarquardtParams()
    params.setMaxIterations(50)
    result = gtsam.LevenbergMarquardtOptimizer(graph, values, params).optimize()
    return {k: result.atPose3(k).matrix() for k in initial}
