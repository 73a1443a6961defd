"""CPU rendering of a room with Open3D's ray caster (Embree): per pixel the depth, the world normal
and the id of the thing hit; colour from the thing's albedo with Lambert shading; then the
faults of a consumer RGB-D sensor.

Sensor faults (all drawn from the layout's seed, so a layout renders the same every time):
- axial depth noise growing with distance, sigma(z) = 1.2 mm + 1.9 mm * (z - 0.4 m)^2 (the
  Kinect model of Nguyen, Izadi and Lovell, 3DIMPVT 2012);
- holes at depth edges (EDGE_HOLE of the edge pixels) and flying pixels between the two sides
  of an edge (EDGE_FLYING of them, at a random depth between the near and the far side);
- holes on dark surfaces (albedo luminance under DARK_LUMA: DARK_HOLE of their pixels, in blobs);
- no depth nearer than MIN_RANGE_M or beyond MAX_RANGE_M, nor where a ray leaves the room (door,
  window);
- exposure: a gain that drifts between frames, plus colour noise and a horizontal motion blur on
  every BLUR_EVERY-th frame.
"""
from __future__ import annotations

import numpy as np

from benchmarks.synth.scene import Room, Thing

MIN_RANGE_M = 0.2
MAX_RANGE_M = 6.0
EDGE_JUMP = 0.04                 # relative depth jump between neighbours that makes an edge
EDGE_HOLE = 0.5
EDGE_FLYING = 0.2
DARK_LUMA = 0.12
DARK_HOLE = 0.35
BLUR_EVERY = 9
LIGHT = np.array([0.3, -0.4, 1.0]) / np.linalg.norm([0.3, -0.4, 1.0])


def thing_mesh(thing: Thing):
    import open3d as o3d

    mesh = o3d.geometry.TriangleMesh()
    for p in thing.parts:
        if p.kind == "box":
            ext = np.maximum(p.hi - p.lo, 1e-4)
            m = o3d.geometry.TriangleMesh.create_box(*ext)
            m.translate(p.lo)
            if p.yaw:
                m.rotate(o3d.geometry.get_rotation_matrix_from_xyz((0.0, 0.0, p.yaw)), center=(p.lo + p.hi) / 2)
        else:
            r, h = float(p.hi[0]), float(p.hi[2])
            m = o3d.geometry.TriangleMesh.create_cylinder(radius=r, height=h, resolution=32, split=1)
            m.translate(p.lo + np.array([0.0, 0.0, h / 2]))
        mesh += m
    return o3d.t.geometry.TriangleMesh.from_legacy(mesh)


class Scene:
    """The ray-casting scene of a room; `index[g]` is the room thing of Open3D geometry id g."""

    def __init__(self, room: Room):
        import open3d as o3d

        self.room = room
        self.scene = o3d.t.geometry.RaycastingScene()
        self.index = {}
        for k, t in enumerate(room.things):
            self.index[int(self.scene.add_triangles(thing_mesh(t)))] = k
        self.albedo = np.array([t.albedo for t in room.things] + [(0.0, 0.0, 0.0)], np.float32)

    def cast(self, pose: np.ndarray, K: np.ndarray, w: int, h: int):
        """(depth z in metres, inf where nothing is hit; thing index per pixel, -1 for none;
        world normals) for a camera-to-world pose."""
        import open3d as o3d

        v, u = np.mgrid[0:h, 0:w].astype(np.float32)
        d = np.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], np.ones_like(u)], axis=-1)
        d_world = d @ pose[:3, :3].T.astype(np.float32)
        rays = np.concatenate([np.broadcast_to(pose[:3, 3].astype(np.float32), d_world.shape), d_world], axis=-1)
        hit = self.scene.cast_rays(o3d.core.Tensor.from_numpy(np.ascontiguousarray(rays, dtype=np.float32)))
        z = hit["t_hit"].numpy()                      # the ray's z is 1, so t is the depth
        gid = hit["geometry_ids"].numpy().astype(np.int64)
        lut = np.full(max(self.index) + 2, -1, np.int64)
        for g, k in self.index.items():
            lut[g] = k
        thing = np.where(np.isfinite(z), lut[np.clip(gid, 0, len(lut) - 1)], -1)
        return z, thing, hit["primitive_normals"].numpy(), d_world


def shade(scene: Scene, thing: np.ndarray, normals: np.ndarray, rays: np.ndarray, gain: float) -> np.ndarray:
    """Lambert shading of each pixel's albedo under a ceiling light and a weak headlight, RGB 0..1."""
    n = normals.copy()
    r = rays / np.linalg.norm(rays, axis=-1, keepdims=True)
    flip = np.sum(n * r, axis=-1) > 0
    n[flip] *= -1
    lam = 0.35 + 0.45 * np.clip(n @ LIGHT, 0, None) + 0.25 * np.clip(-np.sum(n * r, axis=-1), 0, None)
    rgb = scene.albedo[thing] * lam[..., None] * gain
    rgb[thing < 0] = 0.0
    return rgb


def depth_faults(z: np.ndarray, thing: np.ndarray, albedo: np.ndarray, rng) -> np.ndarray:
    """The true depth with the sensor's faults (module docstring), metres, 0 = no depth."""
    import cv2

    ok = np.isfinite(z) & (z > MIN_RANGE_M) & (z < MAX_RANGE_M)
    zz = np.where(ok, z, 0.0).astype(np.float32)
    sigma = 0.0012 + 0.0019 * (zz - 0.4) ** 2
    noisy = zz + rng.normal(0.0, 1.0, zz.shape).astype(np.float32) * sigma
    far = np.where(ok, zz, MAX_RANGE_M).astype(np.float32)
    hi = cv2.dilate(far, np.ones((3, 3), np.uint8))
    lo = cv2.erode(far, np.ones((3, 3), np.uint8))
    edge = ok & ((hi - lo) > EDGE_JUMP * zz)
    draw = rng.random(zz.shape)
    flying = edge & (draw >= EDGE_HOLE) & (draw < EDGE_HOLE + EDGE_FLYING)
    noisy[flying] = (lo + rng.random(zz.shape).astype(np.float32) * (np.minimum(hi, MAX_RANGE_M) - lo))[flying]
    luma = albedo[thing] @ np.array([0.3, 0.59, 0.11], np.float32)
    blobs = cv2.resize(rng.random((zz.shape[0] // 8, zz.shape[1] // 8)).astype(np.float32), zz.shape[::-1],
                       interpolation=cv2.INTER_LINEAR)
    dark = ok & (thing >= 0) & (luma < DARK_LUMA) & (blobs < DARK_HOLE)
    keep = ok & ~(edge & (draw < EDGE_HOLE)) & ~dark
    return np.where(keep, noisy, 0.0)


def colour_faults(rgb: np.ndarray, i: int, rng) -> np.ndarray:
    """8-bit BGR with colour noise and, every BLUR_EVERY-th frame, a 7-pixel horizontal blur."""
    import cv2

    rgb = np.clip(rgb + rng.normal(0.0, 0.012, rgb.shape), 0, 1)
    bgr = (rgb[..., ::-1] * 255).round().astype(np.uint8)
    if i % BLUR_EVERY == BLUR_EVERY // 2:
        bgr = cv2.blur(bgr, (7, 1))
    return bgr


def exposure(n: int, rng) -> np.ndarray:
    """A gain per frame drifting between about 0.75 and 1.25 (auto exposure chasing the view)."""
    phase = rng.uniform(0, 2 * np.pi)
    return 1.0 + 0.2 * np.sin(phase + np.arange(n) * 2 * np.pi / max(n / 2.5, 1)) + rng.normal(0, 0.02, n)
