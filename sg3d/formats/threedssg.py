"""3DSSG / 3RScan scene-graph files (`objects.json`, `relationships.json`), so a graph can be
scored with the 3DSSG benchmark tools.

One scan per room, named by the room id ("building/room"). Objects get the integer ids 3DSSG
uses ("1", "2", ...) in the exported order, with their label and colour attribute (plus our id,
position and size under extra keys the benchmark ignores). Relations use 3DSSG's predicate list
(`RELATIONSHIPS`, the order of its relationships.txt, so the class id is the index):

ON -> "standing on", IN -> "inside", ABOVE -> "higher than", BELOW -> "lower than",
NEXT_TO and NEAR -> "close by", IN_FRONT_OF -> "front", BEHIND -> "behind", LEFT_OF -> "left",
RIGHT_OF -> "right", BIGGER_THAN -> "bigger than", SMALLER_THAN -> "smaller than";
UNDER and CONTAINS_OBJ have no 3DSSG predicate (their inverse, ON and IN, is exported).
"""
from __future__ import annotations

from sg3d.core.stored import StoredGraph

RELATIONSHIPS = (
    "none", "supported by", "left", "right", "front", "behind", "close by", "inside", "bigger than",
    "smaller than", "higher than", "lower than", "same symmetry as", "same as", "attached to", "standing on",
    "lying on", "hanging on", "connected to", "leaning against", "part of", "belonging to", "build in",
    "standing in", "cover", "lying in", "hanging in", "same color", "same material", "same texture",
    "same shape", "same state", "same object type", "messier than", "cleaner than", "fuller than",
    "more closed", "more open", "brighter than", "darker than", "more comfortable than",
)
PREDICATE = {"ON": "standing on", "IN": "inside", "ABOVE": "higher than", "BELOW": "lower than",
             "NEXT_TO": "close by", "NEAR": "close by", "IN_FRONT_OF": "front", "BEHIND": "behind",
             "LEFT_OF": "left", "RIGHT_OF": "right", "BIGGER_THAN": "bigger than", "SMALLER_THAN": "smaller than"}


def to_3dssg(graph: StoredGraph) -> tuple[dict, dict]:
    """The exported graph as 3DSSG's (objects.json, relationships.json)."""
    scans: dict[str, dict] = {}
    numbers: dict[str, tuple[str, int]] = {}
    for n in graph.nodes:
        scan = f"{graph.building}/{n.room_name or ''}"
        s = scans.setdefault(scan, {"objects": [], "relationships": [], "names": {}})
        k = len(s["objects"]) + 1
        numbers[n.id] = (scan, k)
        s["objects"].append({"id": str(k), "label": n.label or "object",
                             "attributes": {"color": [n.colour] if n.colour else []},
                             "affordances": [], "sg3d_id": n.id, "name": n.name,
                             "position": [n.x, n.y, n.z], "size": n.size})
        s["names"][str(k)] = n.label or "object"
    seen = set()
    for e in graph.edges:
        if e.type not in PREDICATE or e.s not in numbers or e.o not in numbers:
            continue
        (scan, a), (scan_b, b) = numbers[e.s], numbers[e.o]
        name = PREDICATE[e.type]
        if scan != scan_b or (scan, a, b, name) in seen:  # NEXT_TO and NEAR both give "close by"
            continue
        seen.add((scan, a, b, name))
        scans[scan]["relationships"].append([a, b, RELATIONSHIPS.index(name), name])
    objects = {"scans": [{"scan": scan, "objects": s["objects"]} for scan, s in scans.items()]}
    relationships = {"scans": [{"scan": scan, "split": 0, "objects": s["names"], "relationships": s["relationships"]}
                               for scan, s in scans.items()]}
    return objects, relationships
