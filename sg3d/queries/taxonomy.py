"""The category taxonomy: COCO classes -> groups -> ... -> "object" (hierarchical counting, Sec. VI-A).

`queries/data/taxonomy.json` is the single source. `Taxonomy.load()` reads it for offline use
(parsing, planners, eval); `ensure_taxonomy(store)` mirrors it into the store as
`(:Category {name})-[:IS_A]->(:Category)` so Cypher can search it; `descendants`/`ancestors`
query the store. Semantics are the same in both places:
  descendants(name) -> the name itself and every category below it;
  ancestors(name)   -> every category above it, nearest first (the name itself excluded).
"""
from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data" / "taxonomy.json"


@dataclass(frozen=True)
class Taxonomy:
    parents: dict[str, str]
    root: str
    version: str

    @staticmethod
    @functools.cache
    def load(path: Path = DATA) -> "Taxonomy":
        raw = path.read_bytes()
        data = json.loads(raw)
        # the content hash is the version: any edit of the file reloads it into the store
        version = f"{data.get('version', 0)}-{hashlib.sha1(raw).hexdigest()[:12]}"
        return Taxonomy(parents=dict(data["parents"]), root=data["root"], version=version)

    @functools.cached_property
    def children(self) -> dict[str, list[str]]:
        out: dict[str, list[str]] = {}
        for child, parent in self.parents.items():
            out.setdefault(parent, []).append(child)
        return out

    @property
    def names(self) -> set[str]:
        return set(self.parents) | {self.root}

    @functools.cached_property
    def leaves(self) -> frozenset[str]:
        """The object classes (COCO categories): names nothing points to."""
        return frozenset(n for n in self.names if n not in self.children)

    @property
    def groups(self) -> set[str]:
        return self.names - self.leaves

    def parent(self, name: str) -> str | None:
        return self.parents.get(name)

    def ancestors(self, name: str) -> list[str]:
        out, node = [], self.parents.get(name)
        while node is not None:
            out.append(node)
            node = self.parents.get(node)
        return out

    def descendants(self, name: str) -> set[str]:
        if name not in self.names:
            return set()
        out, todo = {name}, [name]
        while todo:
            for child in self.children.get(todo.pop(), ()):
                if child not in out:
                    out.add(child)
                    todo.append(child)
        return out

    def labels_under(self, name: str) -> set[str]:
        """The object classes at or below `name` (what a hierarchical count counts)."""
        return self.descendants(name) & self.leaves

    def is_a(self, label: str, group: str) -> bool:
        return label == group or group in self.ancestors(label)


# stores (uri, database) known to hold the current version in this process
_loaded: set[tuple[str, str, str]] = set()


def _key(store, tax: Taxonomy) -> tuple[str, str, str]:
    return (str(getattr(store, "uri", id(store))), str(getattr(store, "database", "")), tax.version)


def ensure_taxonomy(store, taxonomy: Taxonomy | None = None, force: bool = False) -> bool:
    """Load the taxonomy into the store unless its version marker already matches.

    Cached per process; returns True when it (re)loaded. The only write `sg3d ask` makes.
    """
    tax = taxonomy or Taxonomy.load()
    key = _key(store, tax)
    if key in _loaded and not force:
        return False
    rows = store.read("taxonomy_version", root=tax.root)
    if rows and rows[0]["version"] == tax.version and not force:
        _loaded.add(key)
        return False
    from sg3d.graphdb import cypher

    names = sorted(tax.names)
    pairs = [{"child": c, "parent": p} for c, p in sorted(tax.parents.items())]

    def load(tx):
        # one transaction: a reader never sees a half-loaded taxonomy
        tx.run(cypher.load("taxonomy_clear")).consume()
        tx.run(cypher.load("taxonomy_nodes"), names=names).consume()
        tx.run(cypher.load("taxonomy_edges"), pairs=pairs).consume()
        tx.run(cypher.load("taxonomy_version_set"), root=tax.root, version=tax.version).consume()
        # what a category word names changed for every room: kept answers must not outlive it
        tx.run(cypher.load("room_bump_all")).consume()

    store.execute_write(load)
    _loaded.add(key)
    return True


def forget(store=None) -> None:
    """Drop the per-process cache (after a wipe of the store)."""
    _loaded.clear()


def descendants(store, name: str) -> set[str]:
    """The category and every category below it, searched in the store."""
    ensure_taxonomy(store)
    found = {r["name"] for r in store.read("taxonomy_descendants", category=name)}
    if not found and name in Taxonomy.load().names:
        # the store was wiped since this process loaded it: reload once
        ensure_taxonomy(store, force=True)
        found = {r["name"] for r in store.read("taxonomy_descendants", category=name)}
    return found


def ancestors(store, name: str) -> list[str]:
    """Every category above `name` in the store, nearest first."""
    ensure_taxonomy(store)
    rows = store.read("taxonomy_ancestors", category=name)
    if not rows and Taxonomy.load().parent(name) is not None:
        ensure_taxonomy(store, force=True)
        rows = store.read("taxonomy_ancestors", category=name)
    return [r["name"] for r in rows]
