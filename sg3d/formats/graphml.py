"""GraphML of an exported scene graph: nodes with their scalar attributes, typed and scored edges."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from sg3d.core.stored import StoredGraph


def to_graphml(graph: StoredGraph) -> str:
    """The exported graph ({building, room, nodes, edges}) as a GraphML document."""
    root = ET.Element("graphml", xmlns="http://graphml.graphdrawing.org/xmlns")
    scalar = {"label": "string", "name": "string", "room_name": "string", "colour": "string", "x": "double", "y": "double",
              "z": "double", "volume": "double", "observations": "int", "layer": "string"}
    for name, kind in scalar.items():
        ET.SubElement(root, "key", id=name, attrib={"for": "node", "attr.name": name, "attr.type": kind})
    ET.SubElement(root, "key", id="type", attrib={"for": "edge", "attr.name": "type", "attr.type": "string"})
    ET.SubElement(root, "key", id="score", attrib={"for": "edge", "attr.name": "score", "attr.type": "double"})
    g = ET.SubElement(root, "graph", id=graph.building, edgedefault="directed")
    for node in graph.nodes:
        n = ET.SubElement(g, "node", id=node.id)
        for name in scalar:
            if getattr(node, name) is not None:
                ET.SubElement(n, "data", key=name).text = str(getattr(node, name))
    for i, edge in enumerate(graph.edges):
        e = ET.SubElement(g, "edge", id=f"e{i}", source=edge.s, target=edge.o)
        ET.SubElement(e, "data", key="type").text = edge.type
        ET.SubElement(e, "data", key="score").text = str(edge.score)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True)
