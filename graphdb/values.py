"""Store values as JSON: the one conversion the Cypher front ends and the eval report share."""
from __future__ import annotations

from typing import Any


def jsonable(value: Any) -> Any:
    """A driver or answer value as JSON: bytes as '<n bytes>', nodes and relationships as their
    properties, temporal values in ISO form, anything else without a JSON form as its text."""
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, (bytes, bytearray)):
        return f"<{len(value)} bytes>"
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, dict) or hasattr(value, "items"):
        return {str(k): jsonable(v) for k, v in value.items()}
    if hasattr(value, "iso_format"):          # neo4j temporal types
        return value.iso_format()
    return str(value)
