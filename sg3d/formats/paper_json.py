"""The paper's JSON form of an exported scene graph (Sec. VII-A.4)."""
from __future__ import annotations

import json

from sg3d.core.stored import StoredGraph


def to_json(graph: StoredGraph) -> str:
    """The exported graph ({building, room, nodes, edges}) as indented JSON."""
    return json.dumps(graph.as_json(), indent=1)
