"""Store values: their JSON form (the one conversion the Cypher front ends and the eval report share)
and room ids (colour histograms' packed form: `sg3d.merge.histograms`)."""
from __future__ import annotations

import logging
import math
from typing import Any

from sg3d.core.stored import Row


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


def _finite_value(value: Any) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, (list, tuple)):
        if value and isinstance(value[0], (int, float)):
            try:
                return math.isfinite(math.fsum(value))   # one C pass; any NaN/inf (or overflow) fails
            except OverflowError:
                return False
            except TypeError:
                pass                                     # a mixed list: its floats one by one
        return all(math.isfinite(v) for v in value if isinstance(v, float))
    if isinstance(value, dict):
        return all(_finite_value(v) for v in value.values())
    return True


# values of these types hold no float: nothing to check
_NO_FLOATS = frozenset({str, int, bool, type(None), bytes})


def has_bad_number(row: dict) -> bool:
    """Whether a stored row holds a number no reader can use: NaN, +-Infinity (written around the
    ingest bounds, e.g. by a user's own Cypher); rows of such values are skipped, see `finite_rows`."""
    return not all(type(v) in _NO_FLOATS or _finite_value(v) for v in row.values())


def finite_rows(rows: list[Row], source: str) -> list[Row]:
    """`rows` without those holding a non-finite number, with one warning naming how many were
    skipped and how to repair the store."""
    good = [r for r in rows if not has_bad_number(r)]
    if len(good) != len(rows):
        logging.getLogger("sg3d.store").warning(
            "skipped %d stored record(s) of %s holding NaN or Infinity; `sg3d db check --repair` removes them",
            len(rows) - len(good), source)
    return good


def finite_or_none(value: Any) -> Any:
    """`value` with every NaN or +-Infinity float replaced by None (JSON has no such numbers)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, (list, tuple)):
        return [finite_or_none(v) for v in value]
    if isinstance(value, dict):
        return {k: finite_or_none(v) for k, v in value.items()}
    return value


def room_id(building: str, room: str) -> str:
    """A room's id, 'building/room'; a room given as a full id ('home/kitchen') is kept as is
    (room and building names never contain '/': build and the HTTP ingest refuse them)."""
    return room if "/" in room else f"{building}/{room}"
