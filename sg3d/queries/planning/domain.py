"""The household domain as parsed by the `pddl` package, with the little a checker needs:
predicate signatures and the type hierarchy."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

from sg3d.queries.planning.rules import DOMAIN_FILE


@dataclass(frozen=True)
class Domain:
    parsed: Any                             # pddl.core.Domain (pddl ships no type hints)
    predicates: dict[str, tuple[str, ...]]  # name -> parameter types
    parents: dict[str, Optional[str]]       # type -> parent type (None = object)
    path: Path

    def is_subtype(self, type_: str, wanted: str) -> bool:
        seen = set()
        t: Optional[str] = type_
        while t is not None and t not in seen:
            if t == wanted:
                return True
            seen.add(t)
            t = self.parents.get(t)
        return wanted == "object"

    def action(self, name: str):
        return next((a for a in self.parsed.actions if a.name == name), None)

    def text(self) -> str:
        return self.path.read_text()


def _one_type(tags) -> str:
    tags = sorted(str(t) for t in tags)
    return tags[0] if tags else "object"


@functools.cache
def load_domain(path: Optional[str] = None) -> Domain:
    from pddl import parse_domain

    domain_path = Path(path or DOMAIN_FILE)
    parsed = parse_domain(str(domain_path))
    predicates = {str(p.name): tuple(_one_type(t.type_tags) for t in p.terms) for p in parsed.predicates}
    parents = {str(k): (str(v) if v else None) for k, v in parsed.types.items()}
    return Domain(parsed=parsed, predicates=predicates, parents=parents, path=domain_path)
