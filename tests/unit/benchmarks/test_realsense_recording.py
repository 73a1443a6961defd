"""The colour intrinsics a recording made for `realsense:FILE` carries (`benchmarks.realsense_recording`)."""
from __future__ import annotations

import numpy as np

from benchmarks.realsense_recording import colour_intrinsics
from sg3d.ingest.readers.registration import Registration

K = np.array([[585.0, 0, 320.0], [0, 585.0, 240.0], [0, 0, 1]])


def test_a_colour_pixel_s_ray_is_the_ray_of_the_depth_pixel_the_registration_maps_it_to():
    reg = Registration.kinect_v1()
    K_colour = colour_intrinsics(K, K, reg)
    map_x, map_y = reg.depth_coordinates(K, (640, 480))
    for u, v in ((0, 0), (320, 240), (600, 30), (111, 470)):
        ray_colour = np.linalg.solve(K_colour, [u, v, 1.0])
        ray_depth = np.linalg.solve(K, [map_x[v, u], map_y[v, u], 1.0])
        assert np.allclose(ray_colour, ray_depth, atol=1e-9)
    assert K_colour[0, 0] < K[0, 0]                      # the colour camera sees wider (1.09)


def test_without_a_registration_the_colour_keeps_the_recording_s_intrinsics():
    assert np.array_equal(colour_intrinsics(K, K, None), K)
    assert np.array_equal(colour_intrinsics(K, K, Registration()), K)
