"""Loading the Cypher templates of `sg3d/cypher/`: the only place statements come from.

A template that needs a relation type (Cypher cannot take one as a parameter) spells it
`REL_TYPE`, a valid identifier so the file still lints; `render` replaces it with a member of
the whitelist `sg3d.core.model.RELATION_TYPES` and nothing else.
"""
from __future__ import annotations

import functools
import os
import re
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from sg3d.core.model import RELATION_TYPES

if TYPE_CHECKING:
    from importlib.abc import Traversable

REL_TOKEN = "REL_TYPE"


def cypher_dir() -> Traversable:
    """The templates: package data of `sg3d` (in a checkout, an editable or a wheel install alike),
    or the folder SG3D_CYPHER_DIR names."""
    env = os.environ.get("SG3D_CYPHER_DIR")
    return Path(env) if env else resources.files("sg3d") / "cypher"


@functools.cache
def load(name: str) -> str:
    """The text of `cypher/<name>.cypher`, comments stripped."""
    if not re.fullmatch(r"[a-z0-9_]+", name):
        raise ValueError(f"bad template name {name!r}")
    path = cypher_dir() / f"{name}.cypher"
    text = path.read_text(encoding="utf-8")
    lines = [ln for ln in text.splitlines() if not ln.lstrip().startswith("//")]
    return "\n".join(lines).strip()


_COLLECTED = re.compile(r"\bRETURN\s+collect\(\{.*\}\)\s+AS\s+rows\s*$", re.S)


@functools.cache
def collected(name: str) -> bool:
    """Whether template `name` returns its rows as ONE row holding `rows`, a list of maps (its
    statement ends `RETURN collect({...}) AS rows`): a read hands back those maps as the rows."""
    return _COLLECTED.search(load(name)) is not None


def statements(name: str) -> list[str]:
    """A file of several statements separated by ';' (schema files)."""
    return [s.strip() for s in load(name).split(";") if s.strip()]


def render(name: str, rel_type: str) -> str:
    if rel_type not in RELATION_TYPES:
        raise ValueError(f"relation type {rel_type!r} is not in the whitelist")
    return load(name).replace(REL_TOKEN, rel_type)
