"""Hand-made observations for store tests (the truth is known because we made it)."""
from __future__ import annotations

import numpy as np

from core.model import HIST_SIZE, LocalGraph, ObjectObservation, RelationObservation


def hist_of(bins: dict[int, float]) -> np.ndarray:
    h = np.zeros(HIST_SIZE)
    for b, v in bins.items():
        h[b] = v
    return h


def obj(local_id, label, mean, *, labels=None, scores=None, var=(0.01, 0.01, 0.01), n_points=100,
        size=(0.1, 0.1, 0.1), hist=None, colour="white", frame=0, thumbnail=b"\xff\xd8jpeg") -> ObjectObservation:
    return ObjectObservation(
        local_id=local_id, labels=labels or [label], scores=scores or [0.9], mean=tuple(mean),
        var=tuple(var), n_points=n_points, size=tuple(size),
        hist=hist if hist is not None else hist_of({7: 80, 100: 20}), colour=colour,
        thumbnail=thumbnail, first_frame=frame, last_frame=frame)


def graph(objects, relations=(), room="kitchen", building="home", key=None) -> LocalGraph:
    return LocalGraph(room=room, building=building, objects=list(objects),
                      relations=[RelationObservation(*r) for r in relations], key=key)
