"""Hand-made observations whose truth is known because they are made here: a builder for objects
and local graphs, and a small kitchen (ten objects, seven relations) as a local graph and as the
JSON body of `POST /ingest`, for trying the service and for the tests and benchmarks."""
from __future__ import annotations

import numpy as np

from sg3d.core.model import (
    HIST_SIZE,
    LocalGraph,
    ObjectObservation,
    RelationObservation,
)


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


def kitchen_objects():
    """Three cups and a bowl on a dining table, a bottle in a microwave, a sink, a chair by the
    table and a tv. Same-label objects get distinct colour histograms so they stay separate nodes."""
    return [
        obj("table", "dining table", (0.0, 0.0, 0.70), size=(1.6, 0.9, 0.7), hist=hist_of({30: 500}), colour="brown"),
        obj("cupA", "cup", (-0.30, 0.0, 0.76), hist=hist_of({1: 100})),
        obj("cupB", "cup", (0.00, 0.0, 0.76), hist=hist_of({200: 100}), colour="red"),
        obj("cupC", "cup", (0.30, 0.0, 0.76), hist=hist_of({400: 100}), colour="blue"),
        obj("bowl", "bowl", (0.10, 0.25, 0.75), hist=hist_of({60: 100})),
        obj("sink", "sink", (2.0, 0.0, 0.90), size=(0.6, 0.5, 0.2), hist=hist_of({300: 100}), colour="gray"),
        obj("micro", "microwave", (2.6, 0.0, 1.00), size=(0.5, 0.4, 0.3), hist=hist_of({500: 100}), colour="black"),
        obj("bottle", "bottle", (2.6, 0.0, 1.02), hist=hist_of({120: 100}), colour="green"),
        obj("chair", "chair", (0.0, 0.9, 0.45), size=(0.5, 0.5, 0.9), hist=hist_of({31: 100}), colour="brown"),
        obj("tv", "tv", (4.5, 0.0, 1.20), size=(1.0, 0.1, 0.6), hist=hist_of({511: 100}), colour="black"),
    ]


KITCHEN_RELATIONS = [
    ("cupA", "ON", "table", 0.9), ("cupB", "ON", "table", 0.9), ("cupC", "ON", "table", 0.8),
    ("bowl", "ON", "table", 0.85), ("bottle", "IN", "micro", 0.8), ("chair", "NEXT_TO", "table", 0.7),
    ("cupA", "NEAR", "bowl", 0.6),
]


def kitchen_body(observation_id: str = "obs-1", building: str = "home", room: str = "kitchen") -> dict:
    """Ten objects and seven relations (`kitchen_objects`, `KITCHEN_RELATIONS`) as local graph JSON."""
    objects = [{"id": o.local_id, "labels": o.labels, "scores": o.scores, "mean": list(o.mean),
                "var": list(o.var), "n_points": o.n_points, "size": list(o.size),
                "hist": [float(v) for v in o.hist], "colour": "grey" if o.colour == "gray" else o.colour,
                "frames": [3, 4, 9]} for o in kitchen_objects()]
    relations = [{"subject": s, "predicate": p, "object": o, "score": sc} for s, p, o, sc in KITCHEN_RELATIONS]
    return {"building": building, "room": room, "observation_id": observation_id,
            "graph": {"objects": objects, "relations": relations, "frames": [3, 4, 9]}}
