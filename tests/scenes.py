"""Hand-made rooms written to the real store, shared by the test modules: the house that `ask`
is tested on, the room `eval` scores against a hand-written ground truth, and the room `show` draws."""
from __future__ import annotations

import numpy as np
from click.testing import CliRunner

from sg3d.cli import cli
from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from tests.factories import graph, hist_of, obj

BROWN, GREY = "brown", "grey"


def _jpeg(w: int, h: int) -> bytes:
    """A real small JPEG (a stored thumbnail is at most 128 px)."""
    import cv2

    img = np.zeros((h, w, 3), np.uint8)
    img[:, : w // 2] = (0, 0, 255)
    return cv2.imencode(".jpg", img)[1].tobytes()


BOWL_JPEG = _jpeg(37, 49)


def build_house(store):
    """kitchen: 3 chairs (2 red), table, couch, 2 cups + 4 things on the table, 3 bowls, cutlery,
    monitor, sink; living room: 1 red chair, 1 couch, 1 tv. Returns local id -> global id."""
    kitchen = graph([
        obj("c1", "chair", (0, 0, 0), colour="red", size=(0.5, 0.5, 0.9)),
        obj("c2", "chair", (3, 0, 0), colour="red", size=(0.5, 0.5, 0.9)),
        obj("c3", "chair", (6, 0, 0), colour="blue", size=(0.5, 0.5, 0.9)),
        obj("t", "dining table", (0, 0, 3), colour=BROWN, size=(1.5, 0.8, 0.7)),
        obj("s", "couch", (6, 0, 6), colour=GREY, size=(2.0, 0.9, 0.8)),
        obj("u1", "cup", (0.2, 0.8, 3), colour="white"),
        obj("u2", "cup", (-0.3, 0.8, 3.1), colour="red", size=(0.12, 0.12, 0.12)),   # the bigger cup
        obj("b1", "bowl", (0.4, 0.8, 2.8), size=(0.2, 0.2, 0.1)),
        obj("b2", "bowl", (9, 0.9, 9.2), size=(0.3, 0.3, 0.15), thumbnail=BOWL_JPEG),
        obj("b3", "bowl", (12, 0.9, 12), size=(0.1, 0.1, 0.05)),
        obj("f1", "fork", (0.1, 0.8, 3.3)), obj("k1", "knife", (9, 0.8, 9.5)), obj("sp", "spoon", (15, 1, 1)),
        obj("m", "tv", (15, 1, 15), colour="black", size=(0.6, 0.1, 0.4)),
        obj("sk", "sink", (9, 0.9, 9.6), colour="grey", size=(0.6, 0.5, 0.2)),
    ], relations=[("u1", "ON", "t", 0.9), ("u2", "ON", "t", 0.8), ("b1", "ON", "t", 0.9), ("f1", "ON", "t", 0.7),
                  ("b2", "NEXT_TO", "sk", 0.8), ("k1", "IN", "sk", 0.9)], room="kitchen", building="home")
    living = graph([
        obj("c4", "chair", (0, 0, 0), colour="red", size=(0.5, 0.5, 0.9)),
        obj("s2", "couch", (4, 0, 0), colour="black", size=(2.0, 0.9, 0.8)),
        obj("tv", "tv", (8, 1, 0), colour="black", size=(1.0, 0.1, 0.6)),
    ], room="living room", building="home")
    ids = dict(merge_local_graph(store, kitchen).node_ids)
    ids.update(merge_local_graph(store, living).node_ids)
    return ids


class StoreSettings:
    """What a CLI command takes as its settings, over an open store (writer and reader alike)."""

    def __init__(self, store):
        self._store = store

    def store(self):
        return self._store

    reader = store


# A made-up room: a table with a cup on it, a chair beside it, a book nobody detected, a shelf
# no COCO detector can name, and a chair the annotator could not place.
EVAL_GT = {
    "sequence": "test room",
    "objects": [
        {"id": "T", "category": "table", "coco_category": "dining table", "count_confidence": "sure",
         "world_position": [0.0, 0.0, -0.5]},
        {"id": "C", "category": "mug", "coco_category": "cup", "count_confidence": "sure",
         "world_position": [0.0, 0.0, 0.0]},
        {"id": "H", "category": "chair", "coco_category": "chair", "count_confidence": "sure",
         "world_position": [3.0, 0.0, 0.0]},
        {"id": "B", "category": "booklet", "coco_category": "(book)", "count_confidence": "unsure",
         "world_position": [6.0, 0.0, 0.0]},
        {"id": "S", "category": "wall shelf", "coco_category": "(none)", "count_confidence": "sure",
         "world_position": [0.0, 3.0, 0.0]},
        {"id": "X", "category": "chair far away", "coco_category": "chair", "count_confidence": "unsure",
         "world_position": None},
    ],
    "relations": [
        {"subject": "C", "predicate": "on", "object": "T"},        # in the graph
        {"subject": "H", "predicate": "next to", "object": "T"},   # both ends matched, edge absent
        {"subject": "B", "predicate": "on", "object": "T"},        # B has no node
        {"subject": "S", "predicate": "above", "object": "C"},     # S is not a COCO object
        {"subject": "C", "predicate": "leaning on", "object": "T"},  # no such relation type
    ],
    "questions": [
        {"text": "How many cups are there?", "answer": 1, "kind": "counting", "sure": True},
        {"text": "Is there a tv?", "answer": "yes", "kind": "existence", "sure": True},
        {"text": "What colour is the cup?", "answer": "white", "kind": "attribute", "sure": True},
        {"text": "Where is the chair?", "answer": "beside the table", "kind": "relation", "sure": True},
        {"text": "How many books?", "answer": 1, "kind": "counting", "sure": False},
    ],
}

EVAL_ROOM, EVAL_BUILDING = "evalroom", "home"


def build_eval_room(store):
    """5 nodes: table, cup and chair match; a second chair repeats H; a tv matches nothing."""
    merge_local_graph(store, graph([
        obj("t", "dining table", (0.1, 0.0, -0.45), size=(1.5, 0.8, 0.7), hist=hist_of({30: 500}), colour="brown"),
        obj("c", "cup", (0.1, 0.05, 0.0)),
        obj("h", "chair", (3.2, 0.0, 0.0), hist=hist_of({200: 100}), colour="black"),
        obj("h2", "chair", (2.8, 0.2, 0.0), hist=hist_of({400: 100}), colour="red"),
        obj("tv", "tv", (10.0, 0.0, 0.0), hist=hist_of({300: 100}), colour="black"),
    ], relations=[("c", "ON", "t", 0.9), ("h", "NEXT_TO", "c", 0.8), ("c", "BIGGER_THAN", "t", 0.7)],
        room=EVAL_ROOM, building=EVAL_BUILDING))
    nodes = {r["o"]["label"] + ("@%.1f" % r["o"]["x"]): r["o"]["id"]
             for r in store.read("object_all", room=room_id(EVAL_BUILDING, EVAL_ROOM))}
    assert len(nodes) == 5, nodes
    return nodes


SHOW_ROOM, SHOW_BUILDING = "showroom", "home"
UP = np.array([0.0058, -0.9052, -0.4249])       # tilted, like the real kitchen's world frame
UP = UP / np.linalg.norm(UP)


def floor_basis(up):
    """Two horizontal unit vectors, made here independently of the renderer (any pair works:
    the checks below only use distances)."""
    a = np.cross(up, [0.0, 0.0, 1.0])
    a /= np.linalg.norm(a)
    return a, np.cross(up, a)


A, B = floor_basis(UP)
# (floor a, floor b, height) of each object: the table, a cup and a book on it, a chair beside it
PLACES = {"t": (0.0, 0.0, 0.4), "c": (0.2, 0.1, 0.8), "b": (-0.4, -0.2, 0.8), "h": (1.4, 0.0, 0.45)}


def world(a, b, h):
    return tuple(a * A + b * B + h * UP)


def build_show_room(store, room=SHOW_ROOM, up=UP, places=PLACES):
    g = graph([
        obj("t", "dining table", world(*places["t"]), size=(1.5, 0.8, 0.7), colour="brown"),
        obj("c", "cup", world(*places["c"]), colour="white"),
        obj("b", "book", world(*places["b"]), colour="red"),
        obj("h", "chair", world(*places["h"]), colour="black"),
    ], relations=[("c", "ON", "t", 0.9), ("b", "ON", "t", 0.9), ("h", "NEXT_TO", "t", 0.8),
                  ("t", "BIGGER_THAN", "c", 0.9), ("t", "BIGGER_THAN", "h", 0.9)],
        room=room, building=SHOW_BUILDING)
    g.up = tuple(up)
    merge_local_graph(store, g)


def run_show(home, *args, room=SHOW_ROOM):
    room_args = ["--room", room] if room else []
    return CliRunner().invoke(cli, ["--home", str(home), "show", *room_args, "--building", SHOW_BUILDING, *args])
