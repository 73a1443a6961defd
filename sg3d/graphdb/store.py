"""One store handle over the official neo4j driver: the embedded ArcadeDB by default, Neo4j 5 with --uri."""
from __future__ import annotations

import functools
import logging
import threading
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any, Callable, Iterable, Iterator, Optional, TypeVar, cast

from neo4j import GraphDatabase, ManagedTransaction, Query, RoutingControl, Session, unit_of_work
from neo4j.graph import Node, Path, Relationship

from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.values import finite_rows

# 2: an Object's histogram and thumbnail live on its (:Appearance {id}) node; 3: (:Scan) nodes and
# the re-scan fields of an Object (first/last seen, removed_at, history_*), see cypher/schema.cypher
SCHEMA_VERSION = 3
MIGRATION_BATCH = 2000   # objects moved per transaction by a schema migration

_GRAPH_TYPES = (Node, Relationship, Path)
_PLAIN_TYPES = frozenset({str, int, float, bool, type(None), list, dict, bytes})
_T = TypeVar("_T")

# the driver logs every retry of a refused connection; the CLI reports the final failure once
logging.getLogger("neo4j").setLevel(logging.ERROR)
log = logging.getLogger("sg3d.store")


_BOOKMARKS: dict[tuple[str, str], Any] = {}
_BOOKMARKS_LOCK = threading.Lock()


def shared_bookmarks(uri: str, database: str) -> Any:
    """The one bookmark manager of this process for a database (`uri`, `database`)."""
    with _BOOKMARKS_LOCK:
        if (uri, database) not in _BOOKMARKS:
            _BOOKMARKS[(uri, database)] = GraphDatabase.bookmark_manager()
        return _BOOKMARKS[(uri, database)]


def plain_rows(result: Any) -> list[Row]:
    """The rows of `result` as dicts, what `Result.data()` gives, without its walk through every
    list element (a quarter of a scene read's time in the driver): sg3d's templates return
    numbers, texts, bytes, lists and maps, so only a row holding a node, relationship or path is
    converted by the driver."""
    keys = result.keys()
    rows = []
    for record in result:
        values = record.values()
        # a value of a plain type is no node (an isinstance check against the driver's graph
        # types goes through the ABC machinery: 2 us a value, 1 ms an answer)
        plain = all(type(v) in _PLAIN_TYPES for v in values)
        rows.append(record.data() if not plain and any(isinstance(v, _GRAPH_TYPES) for v in values)
                    else dict(zip(keys, values)))
    return rows


class ReadOnlyStoreError(Sg3dError, RuntimeError):
    """A write was asked of a store opened for reading."""


# -- the message guard -------------------------------------------------------------------------
# ArcadeDB's Bolt plugin reads a message of at most 16 MiB. Of a longer one it reads part, answers
# FAILURE and then parses the rest of the bytes as NEW messages, so a parameter holding Bolt bytes
# after 16 MiB of padding runs a statement of the caller's choosing (and a plain long parameter
# leaves the driver waiting forever; measured on 26.10: a 16.1 MiB string hangs, 15.9 MiB works).
# Every statement sg3d sends is measured first and refused above this bound, well under 16 MiB.
MAX_STATEMENT_BYTES = 8 * 1024 * 1024
# What the rows of one batched statement may take (merges split their rows to fit, leaving room
# for the statement's other parameters).
BATCH_BYTES = MAX_STATEMENT_BYTES // 2
_SCALARS = frozenset({int, float, bool, type(None)})
_MIB = 1024 * 1024


class StatementTooLarge(Sg3dError, ValueError):
    """A statement whose text and parameters would not fit in one message the store reads whole;
    nothing of it was sent."""


def encoded_bytes(value: Any, stop_above: Optional[int] = None) -> int:
    """An upper bound of `value`'s size as a Bolt (PackStream) parameter: 9 bytes a number, 5 of
    header a text, byte string, list or map, plus their contents. Iterative (no recursion limit);
    with `stop_above`, it returns as soon as the count passes it."""
    total, stack = 0, [value]
    while stack:
        v = stack.pop()
        t = type(v)
        if t in _SCALARS:
            total += 9
        elif isinstance(v, str):
            total += 5 + (len(v) if v.isascii() else len(v.encode("utf-8", "surrogatepass")))
        elif isinstance(v, (bytes, bytearray)):
            total += 5 + len(v)
        elif isinstance(v, memoryview):
            total += 5 + v.nbytes
        elif isinstance(v, dict):
            total += 5
            stack.extend(v.keys())
            stack.extend(v.values())
        elif isinstance(v, (list, tuple, set, frozenset)):
            total += 5
            if set(map(type, v)) <= _SCALARS:      # a list of numbers (a histogram): no walk
                total += 9 * len(v)
            else:
                stack.extend(v)
        elif getattr(v, "dtype", None) is not None and getattr(v.dtype, "kind", "") in "biuf":
            total += 5 + 9 * int(v.size)         # a numeric numpy array or scalar
        elif hasattr(v, "tolist"):
            stack.append(v.tolist())
        else:                                    # dates, times, points: small fixed structures
            total += 64
        if stop_above is not None and total > stop_above:
            return total
    return total


def check_statement(query: Any, parameters: Optional[dict] = None, more: Optional[dict] = None) -> None:
    """StatementTooLarge, before anything is sent, when the statement's text and parameters
    (`parameters` and keyword parameters `more`) may exceed MAX_STATEMENT_BYTES."""
    text = getattr(query, "text", query)
    size = len(text.encode("utf-8", "surrogatepass")) if isinstance(text, str) else encoded_bytes(text)
    params = {**(parameters or {}), **(more or {})}
    size += encoded_bytes(params, stop_above=MAX_STATEMENT_BYTES)
    if size <= MAX_STATEMENT_BYTES:
        return
    biggest = max(params, key=lambda k: encoded_bytes(params[k]), default=None)
    what = f" (${biggest}: {encoded_bytes(params[biggest]) / _MIB:.1f} MiB)" if biggest is not None else ""
    raise StatementTooLarge(
        f"a statement of more than {size / _MIB:.1f} MiB{what} exceeds the {MAX_STATEMENT_BYTES // _MIB} MiB "
        f"sg3d sends to the store in one message; nothing was sent")


def size_batches(rows: Iterable[Any], budget: int = BATCH_BYTES) -> list[list]:
    """`rows` cut, in order, into batches of at most `budget` encoded bytes each (a row larger
    than the budget alone in its batch, which the guard then refuses): how a statement that
    takes many rows at once (UNWIND $rows) stays under MAX_STATEMENT_BYTES."""
    batches: list[list] = []
    current: list = []
    used = 0
    for row in rows:
        size = encoded_bytes(row)
        if current and used + size > budget:
            batches.append(current)
            current, used = [], 0
        current.append(row)
        used += size
    if current:
        batches.append(current)
    return batches


# -- the transaction time limit ------------------------------------------------------------------
# A caller with a deadline (the MCP server) sets it for the calls of its thread: every transaction
# sg3d then opens carries it as the Bolt transaction timeout (`tx_timeout`), which Neo4j enforces
# (it stops the statement). ArcadeDB's Bolt plugin ignores it (26.10: BEGIN and RUN read only `db`
# and `mode`); there the store-wide statement limit (`sg3d.graphdb.embedded.store_timeout_s`) stops it.
_TX_TIMEOUT: ContextVar[Optional[float]] = ContextVar("sg3d_tx_timeout", default=None)


@contextmanager
def transaction_timeout(seconds: Optional[float]) -> Iterator[None]:
    """Within the block (this thread or task), every transaction sg3d opens asks the store to stop
    it after `seconds` (None: the store's default)."""
    token = _TX_TIMEOUT.set(seconds)
    try:
        yield
    finally:
        _TX_TIMEOUT.reset(token)


def current_transaction_timeout() -> Optional[float]:
    return _TX_TIMEOUT.get()


def _timed(fn: Callable) -> Callable:
    """`fn` as a unit of work with the current transaction timeout (if any and none of its own)."""
    seconds = _TX_TIMEOUT.get()
    if seconds is None or getattr(fn, "timeout", None) is not None:
        return fn
    return unit_of_work(timeout=seconds)(fn)


# Called once for every statement sg3d sends (a round trip to the store): `sg3d serve` counts them
# for /metrics. One slot, not a list: a process that builds several apps installs the same counter.
_on_statement: Optional[Callable[[], None]] = None


def on_statement(hook: Optional[Callable[[], None]]) -> None:
    """Call `hook()` for every statement sent to the store from now on (None: stop)."""
    global _on_statement
    _on_statement = hook


def _sent() -> None:
    hook = _on_statement
    if hook is not None:
        hook()


class _GuardedTransaction:
    """A driver transaction whose `run` passes `check_statement` first; the rest is the driver's."""

    def __init__(self, tx: Any) -> None:
        self._tx = tx

    def run(self, query: Any, parameters: Optional[dict] = None, **kwparameters: Any) -> Any:
        check_statement(query, parameters, kwparameters)
        _sent()
        return self._tx.run(query, parameters, **kwparameters)

    def __enter__(self) -> _GuardedTransaction:
        self._tx.__enter__()
        return self

    def __exit__(self, *exc: Any) -> Any:
        return self._tx.__exit__(*exc)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._tx, name)


def _guarded_work(fn: Callable) -> Callable:
    @functools.wraps(fn)     # keeps a @unit_of_work's timeout and metadata
    def work(tx: Any, *args: Any, **kwargs: Any) -> Any:
        return fn(_GuardedTransaction(tx), *args, **kwargs)
    return work


# The read transaction that a block's reads share (`Store.reading`): (the store, its transaction).
_SHARED_READ: ContextVar[Optional[tuple]] = ContextVar("sg3d_shared_read", default=None)


def _shared_read(store: Any) -> Optional[Any]:
    """The transaction `store.reading` holds open in this thread (or task), or None."""
    shared = _SHARED_READ.get()
    return shared[1] if shared is not None and shared[0] is store else None


class _GuardedSession:
    """A driver session through which every statement passes `check_statement`: auto-commit
    `run`, explicit transactions and transaction functions alike. A read transaction function
    run while its store's `reading` holds one open runs in that one."""

    def __init__(self, session: Session, owner: Any = None):
        self._session = session
        self._owner = owner

    def run(self, query: Any, parameters: Optional[dict] = None, **kwargs: Any) -> Any:
        check_statement(query, parameters, kwargs)
        seconds = _TX_TIMEOUT.get()
        if seconds is not None and isinstance(query, str):
            query = Query(query, timeout=seconds)
        _sent()
        return self._session.run(query, parameters, **kwargs)

    def begin_transaction(self, *args: Any, **kwargs: Any) -> _GuardedTransaction:
        seconds = _TX_TIMEOUT.get()
        if seconds is not None and not args and kwargs.get("timeout") is None:
            kwargs["timeout"] = seconds
        return _GuardedTransaction(self._session.begin_transaction(*args, **kwargs))

    def execute_read(self, fn: Callable[..., _T], *args: Any, **kwargs: Any) -> _T:
        shared = _shared_read(self._owner)
        if shared is not None:
            return fn(shared, *args, **kwargs)
        return self._session.execute_read(_guarded_work(_timed(fn)), *args, **kwargs)

    def execute_write(self, fn: Callable[..., _T], *args: Any, **kwargs: Any) -> _T:
        return self._session.execute_write(_guarded_work(_timed(fn)), *args, **kwargs)

    def __enter__(self) -> _GuardedSession:
        self._session.__enter__()
        return self

    def __exit__(self, *exc: Any) -> Any:
        return self._session.__exit__(*exc)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._session, name)


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
        # every session of the process's handles on this database (a server's reader and writer)
        # starts after the last transaction any of them ended: on a cluster (a neo4j:// routing
        # URI) a read sent to a replica waits until it holds what the process wrote or read last
        # (causal consistency); one node ignores them
        self.bookmarks = shared_bookmarks(uri, database)
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

    def __exit__(self, *exc: object) -> None:
        self.close()

    def session(self, **kw: Any) -> Session:
        """A session on the store's database whose every statement is measured before it is sent
        (`check_statement`: StatementTooLarge above MAX_STATEMENT_BYTES, nothing sent). Every
        statement of sg3d goes through here; use it, never `driver.session`."""
        if "bookmarks" not in kw:
            kw.setdefault("bookmark_manager", self.bookmarks)
        return cast(Session, _GuardedSession(self.driver.session(database=self.database, **kw), self))

    def reading(self, fn: Callable[[], _T]) -> _T:
        """`fn()` with every read of this handle within it (`read`, a session's `execute_read`)
        sent in ONE read transaction: one BEGIN and one COMMIT for all of them instead of one
        each (an answer sends 3 to 6 reads, so a third of its round trips, and each of them
        a connection taken from the pool and given back), and every read sees the same committed
        state. Retried whole on a transient error like any read transaction (`fn` must only
        read: writes go through `write`/`execute_write`, in their own transactions); a call
        within another joins it."""
        if _shared_read(self) is not None:
            return fn()

        def work(tx: ManagedTransaction) -> _T:
            token = _SHARED_READ.set((self, tx))
            try:
                return fn()
            finally:
                _SHARED_READ.reset(token)

        with self.session() as s:
            return s.execute_read(work)

    # -- running templates -----------------------------------------------------------------
    def read(self, name: str, **params: Any) -> list[Row]:
        """Run template `name` in a read transaction; rows as dicts (of a template that collects
        them into one, `cypher.collected`, the maps it collected), without rows holding a stored
        NaN or Infinity (skipped with a warning: `sg3d.graphdb.values.finite_rows`)."""
        text = cypher.load(name)
        shared = _shared_read(self)
        if shared is not None:
            rows = plain_rows(shared.run(text, params))
        else:
            with self.session() as s:
                rows = s.execute_read(lambda tx: plain_rows(tx.run(text, params)))
        if cypher.collected(name):           # one row holding the list of rows (see cypher.collected)
            rows = rows[0]["rows"] if rows else []
        return finite_rows(rows, name)

    def read_latest(self, name: str, **params: Any) -> list[Row]:
        """Run read template `name` where the latest commit is: in a write transaction, which a
        routing driver sends to the cluster's leader (it writes nothing); its bookmark then makes
        this handle's later reads, sent to replicas, wait until they hold as much. One node: `read`.
        Sent through the driver's `execute_query`, which sends BEGIN with the statement (one round
        trip fewer than a transaction function), retried on transient errors alike."""
        text = cypher.load(name)
        check_statement(text, params)
        seconds = _TX_TIMEOUT.get()
        _sent()
        rows = self.driver.execute_query(Query(text, timeout=seconds) if seconds is not None else text, params,
                                         routing_=RoutingControl.WRITE, database_=self.database,
                                         bookmark_manager_=self.bookmarks, result_transformer_=plain_rows)
        return finite_rows(rows, name)

    def writer(self) -> "Store":
        """The store sg3d's own writes go to: itself, or the writer behind a read-only store."""
        if not self.read_only:
            return self
        if self._writes_via is None:
            raise ReadOnlyStoreError("this store was opened read-only")
        return self._writes_via()

    def write(self, name: str, **params: Any) -> list[Row]:
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

        def work(tx: ManagedTransaction) -> tuple[list[str], list[list]]:
            result = tx.run(text, params or {})
            keys = list(result.keys())
            rows = [list(r.values()) for r in result]
            if write:      # what a user's statement changed is unknown: every room's answers retire
                tx.run(cypher.load("room_bump_all")).consume()
            return keys, rows

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
