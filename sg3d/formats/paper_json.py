"""The paper's JSON form of an exported scene graph (Sec. VII-A.4)."""
from __future__ import annotations

import json


def to_json(graph: dict) -> str:
    """The exported graph ({building, room, nodes, edges}) as indented JSON."""
    return json.dumps(graph, indent=1)
