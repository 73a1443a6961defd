"""The bounds every value that enters the store must keep: one place per kind, used by every
door (`POST /ingest`, `sg3d build --room`, the readers' poses, the store check).

A value outside them would be stored and then break every later read of its room (an infinite
coordinate cannot be written as JSON, a NaN `up` cannot be drawn), so they are refused at the door.
"""
from __future__ import annotations

import math
import os
import unicodedata
from typing import Iterable, Optional

from sg3d.core.model import WORLD_EXTENT_M  # noqa: E402,F401 - coordinates (m): a campus fits, 1e308 does not

# The largest object box edge (m) and positional variance (m^2) an observation may carry.
MAX_SIZE_M = 100.0
MAX_VAR_M2 = 10_000.0
# Points behind one object's position (a dense scan of a large object stays far below it).
MAX_POINTS = 1_000_000_000
# Frame numbers: non-negative, below this, and at most this many per object or graph.
MAX_FRAME = 100_000_000
MAX_FRAMES = 100_000
# Object ids, labels, room and building names, observation ids: characters.
MAX_ID_CHARS = 200
MAX_LABEL_CHARS = 64
MAX_NAME_CHARS = 100
# How far `up` may be from unit length before it is refused instead of normalised.
UP_NORM_TOLERANCE = 0.05
# Nesting of JSON bodies and PDDL goals.
MAX_JSON_DEPTH = 32
MAX_GOAL_DEPTH = 16
# Request bodies (bytes); `sg3d serve --max-body` changes it.
DEFAULT_MAX_BODY = 32 * 1024 * 1024
# Store calls `sg3d serve` runs at once (more wait their turn); `sg3d serve --threads` changes it.
DEFAULT_THREADS = 64
# Worker processes of `sg3d serve` (`--workers`) by default: `default_workers`. On the 2-core
# machines it was measured on, the store's JVM needs STORE_CORES of its own under load and a
# second worker gave no more answers per second; each worker holds its own label model and
# connection pool, so past MAX_DEFAULT_WORKERS more are a choice, not a default.
STORE_CORES = 2
CORES_PER_WORKER = 2
MAX_DEFAULT_WORKERS = 4
# Answers `sg3d serve` keeps per process (sg3d.app.answers): entries, and their approximate bytes.
ANSWER_CACHE_ENTRIES = 4096
ANSWER_CACHE_BYTES = 64 * 1024 * 1024
# A user's own Cypher statement (MCP `cypher`, `sg3d cypher`, `sg3d shell`): characters.
MAX_STATEMENT_CHARS = 20_000
# The embedded store's statement time limit lives with the store: sg3d.graphdb.embedded.STORE_TIMEOUT_S.

_SEPARATORS = ("/", "\\")


def default_workers(cores: Optional[int]) -> int:
    """Rule "workers from cores": one worker, plus one per CORES_PER_WORKER cores beyond the
    store's STORE_CORES, at most MAX_DEFAULT_WORKERS (one when the count is unknown)."""
    if not cores:
        return 1
    return max(1, min(MAX_DEFAULT_WORKERS, 1 + (cores - STORE_CORES) // CORES_PER_WORKER))


DEFAULT_WORKERS = default_workers(os.cpu_count())


def name_problem(name: object, what: str = "name") -> Optional[str]:
    """Why `name` cannot name a room or building, or None. Rule: 1..MAX_NAME_CHARS printable
    characters (any script: "küche", "my room"), no path separator, no "..", no leading or
    trailing space, not only dots and spaces ("." names the current folder wherever a name becomes
    a path or a listing). The value itself is never repeated in the reason."""
    problem = _text_problem(name, what, MAX_NAME_CHARS)
    if problem or not isinstance(name, str):     # no problem: it is a text
        return problem
    if any(sep in name for sep in _SEPARATORS) or ".." in name:
        return f"{what} must not contain '/', '\\' or '..'"
    if name != name.strip():
        return f"{what} must not start or end with a space"
    if not name.replace(".", "").strip():
        return f"{what} must hold more than dots"
    return None


def check_name(name: str, what: str = "name") -> str:
    """`name` if it can name a room or building (see `name_problem`), else ValueError."""
    problem = name_problem(name, what)
    if problem:
        raise ValueError(problem)
    return name


def label_problem(label: object) -> Optional[str]:
    """Why `label` cannot be an object label, or None: 1..MAX_LABEL_CHARS printable characters
    made of letters, digits, spaces, '-', '_', "'" and '.'."""
    if not isinstance(label, str) or not label.strip():
        return "labels must be non-empty words"
    if len(label) > MAX_LABEL_CHARS:
        return f"labels must be at most {MAX_LABEL_CHARS} characters"
    if not all(c.isalnum() or c in " -_'." or unicodedata.category(c) == "Mn" for c in label):
        return "labels may hold letters, digits, spaces and - _ ' . only"
    return None


def id_problem(value: object, what: str = "id") -> Optional[str]:
    """Why `value` cannot be an id, or None: 1..MAX_ID_CHARS printable characters."""
    return _text_problem(value, what, MAX_ID_CHARS)


def _text_problem(value: object, what: str, limit: int) -> Optional[str]:
    """Why `value` is not 1..`limit` printable characters, or None (the value is never repeated)."""
    if not isinstance(value, str) or not value:
        return f"{what} must be a non-empty text"
    if len(value) > limit:
        return f"{what} must be at most {limit} characters"
    if not value.isprintable():
        return f"{what} must be printable (no control characters, line breaks or NUL)"
    return None


def length_problem(fields: Iterable[tuple[str, object, int]]) -> Optional[str]:
    """Why one of the (what, value, limit) fields is no text of at most `limit` characters, or
    None; a field whose value is None was not given and passes. The reason names the length and
    the limit, never the value (a 5 MB value must not come back in an error)."""
    for what, value, limit in fields:
        if value is None:
            continue
        if not isinstance(value, str):
            return f"{what} must be a text"
        if len(value) > limit:
            return f"{what} is {len(value)} characters; at most {limit}"
    return None


def finite(values: Iterable[float]) -> bool:
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


def within_world(values: Iterable[float]) -> bool:
    """Every coordinate finite and within +-WORLD_EXTENT_M."""
    return all(isinstance(v, (int, float)) and math.isfinite(v) and abs(v) <= WORLD_EXTENT_M for v in values)


def unit_up(up: Iterable[float]) -> tuple[float, float, float]:
    """`up` scaled to unit length; ValueError unless it is three finite numbers whose length is
    within UP_NORM_TOLERANCE of 1 (a zero or NaN vector has no direction)."""
    v = tuple(float(x) for x in up)
    if len(v) != 3 or not finite(v):
        raise ValueError("up must be three finite numbers")
    norm = math.sqrt(sum(x * x for x in v))
    if abs(norm - 1.0) > UP_NORM_TOLERANCE:
        raise ValueError(f"up must be a unit vector (length within {UP_NORM_TOLERANCE} of 1)")
    return (v[0] / norm, v[1] / norm, v[2] / norm)


def nesting_depth(value) -> int:
    """How deeply lists and dicts nest in a parsed JSON value (iterative: no recursion limit)."""
    depth, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict):
            depth = max(depth, level)
            stack.extend((v, level + 1) for v in item.values() if isinstance(v, (dict, list)))
        elif isinstance(item, list):
            depth = max(depth, level)
            stack.extend((v, level + 1) for v in item if isinstance(v, (dict, list)))
    return depth


def paren_depth(text: str) -> int:
    """The deepest nesting of parentheses in `text` (a PDDL goal)."""
    depth = deepest = 0
    for c in text:
        if c == "(":
            depth += 1
            deepest = max(deepest, depth)
        elif c == ")":
            depth -= 1
    return deepest
