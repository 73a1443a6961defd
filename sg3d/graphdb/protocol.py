"""What the application layer needs of a graph store, as a protocol.

`sg3d.graphdb.store.Store` (the neo4j driver against Neo4j or the embedded ArcadeDB) satisfies it;
the app layer's functions take a `GraphStore`, so another handle with these methods (a pooled
one, a recording one) fits without being a `Store`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Optional, Protocol, TypeVar

from sg3d.core.stored import Row

if TYPE_CHECKING:                  # the driver's types only: importing this module stays cheap
    from neo4j import ManagedTransaction, Session


_T = TypeVar("_T")


class GraphStore(Protocol):
    """A connection to the graph store that runs the templates of cypher/ by name."""

    read_only: bool
    rooms_known: set[str]          # room ids this handle has created or seen created
    driver: Any                    # the neo4j driver (connectivity checks of the service)

    def read(self, name: str, **params: Any) -> list[Row]:
        """Run template `name` in a read transaction; its rows as dicts."""
        ...

    def reading(self, fn: Callable[[], _T]) -> _T:
        """`fn()` with every read of this handle within it sent in one read transaction."""
        ...

    def read_latest(self, name: str, **params: Any) -> list[Row]:
        """Run read template `name` where the latest commit is (a cluster's leader); later reads
        of this handle see at least as much."""
        ...

    def write(self, name: str, **params: Any) -> list[Row]:
        """Run template `name` in a write transaction; its rows as dicts."""
        ...

    def execute_write(self, fn: Callable[[ManagedTransaction], Any]) -> Any:
        """Run `fn(tx)` as one write transaction (retried on transient errors)."""
        ...

    def run_raw(self, text: str, params: Optional[dict] = None, write: bool = False) -> tuple[list[str], list[list]]:
        """A user's own statement: its keys and rows."""
        ...

    def session(self, **kw: Any) -> Session:
        """A driver session on the store's database (explicit transactions, EXPLAIN)."""
        ...

    def writer(self) -> GraphStore:
        """The store sg3d's own writes go to."""
        ...

    def ensure_schema(self) -> None:
        """Apply the schema once per handle (idempotent)."""
        ...

    def close(self) -> None:
        ...
