"""The places layer of a walk: the floor map (free, occupied, unknown) and the rooms and doorways
segmented from it (`floor_map`, `rooms`)."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.places.floor_map import FloorMap, PlacesConfig, floor_map, walk_points
from sg3d.ingest.places.rooms import Passage, Place, Places, room_at, rooms_bounded, segment_rooms

__all__ = ["FloorMap", "Passage", "Place", "Places", "PlacesConfig", "floor_map", "room_at", "rooms_bounded",
           "rooms_of_walk", "segment_rooms", "walk_points"]


def rooms_of_walk(points: np.ndarray, cameras: np.ndarray, cfg: PlacesConfig = PlacesConfig()) -> Places:
    """Rooms and doorways of gravity-frame points (a, b, h above the floor) and camera positions."""
    return segment_rooms(floor_map(points, cameras, cfg), cfg)
