"""Loading the Cypher templates of `cypher/`: the only place statements come from.

A template that needs a relation type (Cypher cannot take one as a parameter) spells it
`REL_TYPE`, a valid identifier so the file still lints; `render` replaces it with a member of
the whitelist `core.model.RELATION_TYPES` and nothing else.
"""
from __future__ import annotations

import functools
import os
import re
from pathlib import Path

from core.model import RELATION_TYPES

REL_TOKEN = "REL_TYPE"


def cypher_dir() -> Path:
    env = os.environ.get("SG3D_CYPHER_DIR")
    return Path(env) if env else Path(__file__).resolve().parent.parent / "cypher"


@functools.cache
def load(name: str) -> str:
    """The text of `cypher/<name>.cypher`, comments stripped."""
    if not re.fullmatch(r"[a-z0-9_]+", name):
        raise ValueError(f"bad template name {name!r}")
    path = cypher_dir() / f"{name}.cypher"
    text = path.read_text()
    lines = [ln for ln in text.splitlines() if not ln.lstrip().startswith("//")]
    return "\n".join(lines).strip()


def statements(name: str) -> list[str]:
    """A file of several statements separated by ';' (schema files)."""
    return [s.strip() for s in load(name).split(";") if s.strip()]


def render(name: str, rel_type: str) -> str:
    if rel_type not in RELATION_TYPES:
        raise ValueError(f"relation type {rel_type!r} is not in the whitelist")
    return load(name).replace(REL_TOKEN, rel_type)
