"""One store handle over the official neo4j driver: Neo4j in production, ArcadeDB embedded here."""
from __future__ import annotations

import logging
from typing import Any, Callable, Optional

from neo4j import GraphDatabase, ManagedTransaction

from graphdb import cypher

SCHEMA_VERSION = 1

# the driver logs every retry of a refused connection; the CLI reports the final failure once
logging.getLogger("neo4j").setLevel(logging.ERROR)


class Store:
    def __init__(self, uri: str, auth: tuple[str, str], database: str):
        self.uri = uri
        self.database = database
        self.driver = GraphDatabase.driver(uri, auth=auth, connection_timeout=10,
                                           max_transaction_retry_time=30)
        self._schema_checked = False
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

    def session(self, **kw):
        return self.driver.session(database=self.database, **kw)

    # -- running templates -----------------------------------------------------------------
    def read(self, name: str, **params: Any) -> list[dict]:
        """Run template `name` in a read transaction; rows as dicts."""
        text = cypher.load(name)
        with self.session() as s:
            return s.execute_read(lambda tx: tx.run(text, params).data())

    def write(self, name: str, **params: Any) -> list[dict]:
        text = cypher.load(name)
        with self.session() as s:
            return s.execute_write(lambda tx: tx.run(text, params).data())

    def execute_write(self, fn: Callable[[ManagedTransaction], Any]) -> Any:
        """Run `fn(tx)` as ONE write transaction (retried on transient errors)."""
        with self.session() as s:
            return s.execute_write(fn)

    def run_raw(self, text: str, params: Optional[dict] = None, write: bool = False) -> tuple[list[str], list[list]]:
        """A user's own statement (the `cypher` command and shell): keys and rows."""
        def work(tx: ManagedTransaction):
            result = tx.run(text, params or {})
            keys = list(result.keys())
            return keys, [list(r.values()) for r in result]

        with self.session() as s:
            return (s.execute_write if write else s.execute_read)(work)

    # -- schema ------------------------------------------------------------------------------
    def ensure_schema(self) -> None:
        """Apply cypher/schema.cypher once per store (idempotent statements)."""
        if self._schema_checked:
            return
        rows = self.read("schema_version")
        if not rows or rows[0]["version"] != SCHEMA_VERSION:
            with self.session() as s:
                for stmt in cypher.statements("schema"):
                    s.run(stmt).consume()
            self.write("schema_version_set", version=SCHEMA_VERSION)
        self._schema_checked = True

    def wipe(self) -> None:
        """Delete every node and edge (tests, `sg3d db reset`)."""
        self.write("wipe")
        self._schema_checked = False
