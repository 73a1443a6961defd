"""One store handle over the official neo4j driver: the embedded ArcadeDB by default, Neo4j 5 with --uri."""
from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any, Callable, Optional

from neo4j import GraphDatabase, ManagedTransaction, Session

from sg3d.core.errors import Sg3dError
from sg3d.graphdb import cypher
from sg3d.graphdb.values import finite_rows

# 2: an Object's histogram and thumbnail live on its (:Appearance {id}) node; 3: (:Scan) nodes and
# the re-scan fields of an Object (first/last seen, removed_at, history_*), see cypher/schema.cypher
SCHEMA_VERSION = 3
MIGRATION_BATCH = 2000   # objects moved per transaction by a schema migration

# the driver logs every retry of a refused connection; the CLI reports the final failure once
logging.getLogger("neo4j").setLevel(logging.ERROR)
log = logging.getLogger("sg3d.store")


class ReadOnlyStoreError(Sg3dError, RuntimeError):
    """A write was asked of a store opened for reading."""


class Store:
    """A connection to the graph store.

    `read_only=True` marks a store opened with a reader's credentials (the embedded store's
    reader user, whose group may only read; a Neo4j reader role). A user's own statement
    (`run_raw`) on it always runs as that reader, so the SERVER refuses any write. sg3d's own
    fixed-template writes that a read path may need (the taxonomy mirror that `ask` keeps) go to
    `writes_via()`, the writer store, when one is given; without it they raise.
    """

    def __init__(self, uri: str, auth: tuple[str, str], database: str, *, read_only: bool = False,
                 writes_via: Optional[Callable[[], "Store"]] = None):
        self.uri = uri
        self.database = database
        self.read_only = read_only
        self._writes_via = writes_via
        self.driver = GraphDatabase.driver(uri, auth=auth, connection_timeout=10,
                                           max_transaction_retry_time=30)
        self._schema_checked = False
        # rooms this handle has created or seen created (sg3d.graphdb.merge skips create_room for them)
        self.rooms_known: set[str] = set()
        try:
            self.driver.verify_connectivity()
        except Exception:
            self.driver.close()
            raise

    def close(self) -> None:
        self.driver.close()

    def __enter__(self) -> "Store":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def session(self, **kw: Any) -> Session:
        return self.driver.session(database=self.database, **kw)

    # -- running templates -----------------------------------------------------------------
    def read(self, name: str, **params: Any) -> list[dict]:
        """Run template `name` in a read transaction; rows as dicts, without rows holding a stored
        NaN or Infinity (skipped with a warning: `sg3d.graphdb.values.finite_rows`)."""
        text = cypher.load(name)
        with self.session() as s:
            rows = s.execute_read(lambda tx: tx.run(text, params).data())
        return finite_rows(rows, name)

    def writer(self) -> "Store":
        """The store sg3d's own writes go to: itself, or the writer behind a read-only store."""
        if not self.read_only:
            return self
        if self._writes_via is None:
            raise ReadOnlyStoreError("this store was opened read-only")
        return self._writes_via()

    def write(self, name: str, **params: Any) -> list[dict]:
        if self.read_only:
            return self.writer().write(name, **params)
        text = cypher.load(name)
        with self.session() as s:
            return s.execute_write(lambda tx: tx.run(text, params).data())

    def execute_write(self, fn: Callable[[ManagedTransaction], Any]) -> Any:
        """Run `fn(tx)` as ONE write transaction (retried on transient errors)."""
        if self.read_only:
            return self.writer().execute_write(fn)
        with self.session() as s:
            return s.execute_write(fn)

    def run_raw(self, text: str, params: Optional[dict] = None, write: bool = False) -> tuple[list[str], list[list]]:
        """A user's own statement (the `cypher` command and shell): keys and rows.

        On a read-only store it runs as the reader whatever `write` says: never via the writer."""
        if write and self.read_only:
            raise ReadOnlyStoreError("a write was asked of a store opened read-only (use the writer)")

        def work(tx: ManagedTransaction):
            result = tx.run(text, params or {})
            keys = list(result.keys())
            return keys, [list(r.values()) for r in result]

        with self.session() as s:
            return (s.execute_write if write else s.execute_read)(work)

    # -- schema ------------------------------------------------------------------------------
    def ensure_schema(self) -> None:
        """Apply cypher/schema.cypher once per store (idempotent statements), then migrate the
        data of an older schema (`migrate_appearance`, tallies recounted) before recording the
        new version."""
        if self._schema_checked:
            return
        if self.read_only:
            self.writer().ensure_schema()
            self._schema_checked = True
            return
        rows = self.read("schema_version")
        if not rows or rows[0]["version"] != SCHEMA_VERSION:
            with self.session() as s:
                for stmt in cypher.statements("schema"):
                    s.run(stmt).consume()
            moved = self.migrate_appearance()
            from sg3d.graphdb.tally import rebuild_tallies

            tallies = rebuild_tallies(self)
            self.write("schema_version_set", version=SCHEMA_VERSION)
            if rows and (moved or tallies):
                # an existing store was upgraded in place: say so once (stderr), nothing to rebuild
                log.warning("upgraded the store from schema %s to %s: moved %d objects' histograms and "
                            "thumbnails to Appearance nodes, recounted %d tallies",
                            rows[0]["version"], SCHEMA_VERSION, moved, tallies)
        self._schema_checked = True

    def migrate_appearance(self) -> int:
        """Schema 1 -> 2: move every Object's hist/thumbnail onto its Appearance node, in batches
        (each its own transaction; an interrupted migration resumes where it stopped, since the
        version is recorded only after the last batch). Returns the objects moved."""
        moved = 0
        while True:
            n = self.write("schema_migrate_appearance", batch=MIGRATION_BATCH)[0]["n"]
            moved += n
            if n == 0:
                return moved

    def wipe(self) -> None:
        """Delete every node and edge (tests, `sg3d db reset`)."""
        if self.read_only:
            raise ReadOnlyStoreError("wipe needs the writer")
        self.write("wipe")
        self._schema_checked = False
        self.rooms_known.clear()


if TYPE_CHECKING:
    from sg3d.graphdb.protocol import GraphStore

    def _satisfies_the_protocol(store: Store) -> GraphStore:   # checked by mypy, never called
        return store
