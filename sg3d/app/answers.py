"""Answers kept by a long-lived server (`POST /ask` of `sg3d serve`), keyed by the revisions of
the rooms each answer read.

Every write that changes what an answer over a room can read bumps that room's revision inside its
own transaction: a merge, ingest or live publish (cypher/room_ensure), a room placed in its building
(building_set_transform), rooms linked or unlinked (room_bump), an up cleared by `db check
--repair` (room_up_clear), a tally recount, a taxonomy load or a user's writing statement (every
room: room_bump_all). A room made or deleted changes the room list. `store_revision` reads every
room's revision and the room list in one small query (cypher/room_revisions).

An answer is kept under (the room list, the revision of every room it read, the normalised
question, the options), the revisions read BEFORE it was computed: what it says is at least as new
as them, and the next ask after a later commit to a room it read reads another revision and misses.
So a kept answer is never older than the last write committed before the ask to a room it read, and
an answer over one room outlives writes to the others. Which rooms an answer read is taken from the
statements it sent (`rooms_read`); an answer that read past any one room (a count over the whole
store, a size compared with every room's) is keyed by every room's revision.
"""
from __future__ import annotations

import json
import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional

from sg3d.app import bounds
from sg3d.app.ask import ask
from sg3d.core.stored import Row
from sg3d.graphdb.protocol import GraphStore

_ENTRY_BYTES = 2048          # what an answer without a picture holds, roughly

# Statements that read only the room list (ids, names, buildings): the key always holds that list.
ROOM_LIST_READS = frozenset({"vqa_room_named", "vqa_rooms", "vqa_room_names", "eval_room_exists"})
# A statement that finds objects by their id (already found by a read over their rooms) or reads
# the taxonomy names one of FINDERS and nothing past NO_ROOM_PARAMS: it reads no room of its own.
FINDERS = frozenset({"id", "ids", "category", "root"})
NO_ROOM_PARAMS = FINDERS | {"types", "incoming"}
EVERY_ROOM = None            # what `rooms_read` answers for a statement that may read any room


@dataclass(frozen=True)
class Snapshot:
    """Every room's (born, revision) and the room list, as one read of cypher/room_revisions saw them."""
    revisions: Mapping[str, tuple] = field(default_factory=dict)
    listing: tuple = ()

    def key(self, rooms: Optional[frozenset]) -> tuple:
        """The part of a cache key for an answer that read `rooms` (None: every room)."""
        ids = sorted(self.revisions) if rooms is None else sorted(rooms)
        return self.listing, tuple((rid, self.revisions.get(rid)) for rid in ids)


def store_revision(store: GraphStore) -> Snapshot:
    """Every room's revision and the room list (one round trip), read where the latest commit is:
    on a cluster the leader, and the answer's own reads, sent to replicas, then wait until they
    hold as much (the store's bookmarks), so an answer is at least as new as the key it is kept under."""
    rows = store.read_latest("room_revisions")
    return Snapshot({r["id"]: (r["born"], r["revision"]) for r in rows},
                    tuple((r["id"], r["name"], r["building"], r["born"]) for r in rows))


def rooms_read(name: Optional[str], params: Mapping[str, Any], known: Mapping[str, Any]) -> Optional[frozenset]:
    """Rule "the rooms a statement reads", from its template `name` and parameters: none for a
    read of the room list only (ROOM_LIST_READS) or of objects by id or the taxonomy (FINDERS,
    nothing past NO_ROOM_PARAMS); the rooms of a `rooms` list or a `room` id when each is a room in `known`;
    EVERY_ROOM (None) otherwise: a statement not scoped to known rooms may read any of them."""
    if name in ROOM_LIST_READS:
        return frozenset()
    scoped = params.get("rooms", params.get("room")) if ("rooms" in params or "room" in params) else None
    if isinstance(scoped, str):
        scoped = [scoped]
    if isinstance(scoped, (list, tuple)) and all(isinstance(r, str) and r in known for r in scoped):
        return frozenset(scoped)
    if set(params) <= NO_ROOM_PARAMS and set(params) & FINDERS:
        return frozenset()
    return EVERY_ROOM


def _lower(text: Any) -> Any:
    return text.lower() if isinstance(text, str) else None


def room_list_rows(name: str, params: Mapping[str, Any], listing: tuple) -> Optional[list[Row]]:
    """Rule "a room-list read is answered from the room list the revision read brought": the
    rows cypher/vqa_room_named, vqa_rooms and vqa_room_names would return (id, name, building of
    the rooms that match, ordered by id as the listing is), taken from `listing` ((id, name,
    building, born) per room, cypher/room_revisions), which the answer's key holds anyway; None
    for any other read. One round trip fewer for every question scoped to a room."""
    building = params.get("building")
    if name == "vqa_room_named":
        names = params.get("names") or ()
        return [{"id": i, "name": n, "building": b} for i, n, b, _ in listing
                if n in names and (building is None or _lower(b) == building)]
    if name == "vqa_rooms":
        room = params.get("room")
        return [{"id": i, "name": n, "building": b} for i, n, b, _ in listing
                if (room is None or _lower(n) == room) and (building is None or _lower(b) == building)]
    if name == "vqa_room_names":
        return [{"id": i, "name": n, "building": b} for i, n, b, _ in listing
                if building is None or _lower(b) == building]
    return None


class _ReadTx:
    """A transaction whose statements are noted by `_Recorder` (the relation reads of an answer)."""

    def __init__(self, tx, seen: "_Recorder"):
        self._tx, self._seen = tx, seen

    def run(self, query, parameters=None, **kw):
        self._seen.note(None, {**(parameters or {}), **kw})
        return self._tx.run(query, parameters, **kw)

    def __getattr__(self, name):
        return getattr(self._tx, name)


class _ReadSession:
    def __init__(self, session, seen: "_Recorder"):
        self._session, self._seen = session, seen

    def __enter__(self):
        self._session.__enter__()
        return self

    def __exit__(self, *exc):
        return self._session.__exit__(*exc)

    def execute_read(self, fn, *args, **kw):
        return self._session.execute_read(lambda tx, *a, **k: fn(_ReadTx(tx, self._seen), *a, **k), *args, **kw)

    def __getattr__(self, name):
        return getattr(self._session, name)


class _Recorder:
    """The store as one answer reads it, noting which rooms its statements read (`rooms_read`);
    a read of the room list is answered from `snapshot`'s (`room_list_rows`)."""

    def __init__(self, store: GraphStore, snapshot: Snapshot):
        self._store, self._known, self._listing = store, snapshot.revisions, snapshot.listing
        self.rooms: Optional[frozenset] = frozenset()

    def note(self, name: Optional[str], params: Mapping[str, Any]) -> None:
        if self.rooms is EVERY_ROOM:
            return
        more = rooms_read(name, params, self._known)
        self.rooms = EVERY_ROOM if more is EVERY_ROOM else self.rooms | more

    def read(self, name: str, **params: Any) -> list[Row]:
        self.note(name, params)
        listed = room_list_rows(name, params, self._listing)
        return listed if listed is not None else self._store.read(name, **params)

    def session(self, **kw: Any):
        return _ReadSession(self._store.session(**kw), self)

    def __getattr__(self, name):
        return getattr(self._store, name)


class _Read:
    __slots__ = ("start", "done", "result", "failed")

    def __init__(self, start: int):
        self.start = start
        self.done = threading.Event()
        self.result: Optional[Snapshot] = None
        self.failed = False


class Revisions:
    """Every room's revision for many concurrent asks with few reads (one round trip each). Rule
    "a read that began after the ask arrived": its result names every commit before the ask, so
    an ask takes the result of the read in progress when that read began after the ask arrived;
    otherwise it waits for that older read to end and then joins the next one or starts it. A
    hundred asks at once cost a few reads, each ask waiting at most about two of them."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._ticket = 0                 # rises with every arrival and every read begun
        self._latest: Optional[_Read] = None
        self.reads = 0                   # reads sent to the store

    def read(self, store: GraphStore) -> Snapshot:
        with self._lock:
            self._ticket += 1
            arrived = self._ticket
        while True:
            with self._lock:
                read = self._latest
                if read is None or (read.done.is_set() and read.start < arrived):
                    self._ticket += 1
                    read = self._latest = _Read(self._ticket)
                    leads = True
                else:
                    leads = False
            if leads:
                self.reads += 1
                return self._lead(read, store)
            read.done.wait()
            if read.start > arrived:     # began after this ask arrived: its result will do
                if read.failed or read.result is None:
                    return store_revision(store)
                return read.result

    @staticmethod
    def _lead(read: _Read, store: GraphStore) -> Snapshot:
        try:
            read.result = store_revision(store)
            return read.result
        except BaseException:
            read.failed = True
            raise
        finally:
            read.done.set()


def normalised(question: str) -> str:
    """The question as the cache keys it: lower case, runs of white space as one space."""
    return " ".join(question.split()).lower()


_UNSEEN = object()


class AnswerCache:
    """A bounded LRU of answers (at most `entries`, and about `max_bytes`: a picture's base64
    counts its length), thread-safe; `hits` and `misses` count look-ups. An answer is found by its
    question and options (`base`), which name the rooms it read, whose revisions end its key."""

    def __init__(self, entries: int = bounds.ANSWER_CACHE_ENTRIES, max_bytes: int = bounds.ANSWER_CACHE_BYTES):
        self.entries = entries
        self.max_bytes = max_bytes
        self._kept: OrderedDict[tuple, tuple[dict, int]] = OrderedDict()
        self._read: OrderedDict[tuple, Optional[frozenset]] = OrderedDict()   # base -> rooms read
        self._bytes = 0
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0
        self.revisions = Revisions()

    def __len__(self) -> int:
        return len(self._kept)

    def get(self, snapshot: Snapshot, *bases: tuple) -> Optional[dict]:
        """The answer kept for the first of `bases` whose rooms are at the revisions of `snapshot`
        (one hit or one miss)."""
        with self._lock:
            for base in bases:
                rooms = self._read.get(base, _UNSEEN)
                if rooms is _UNSEEN:
                    continue
                key = (*snapshot.key(rooms), *base)    # type: ignore[arg-type]
                kept = self._kept.get(key)
                if kept is not None:
                    self._kept.move_to_end(key)
                    self._read.move_to_end(base)
                    self.hits += 1
                    return kept[0]
            self.misses += 1
            return None

    def put(self, snapshot: Snapshot, rooms: Optional[frozenset], base: tuple, answer: dict) -> None:
        """Keep `answer`, which read `rooms` (None: every room) as `snapshot` names them."""
        size = _ENTRY_BYTES + len(answer.get("thumbnail_jpeg_base64") or "")
        if self.entries < 1 or size > self.max_bytes:
            return
        key = (*snapshot.key(rooms), *base)
        with self._lock:
            old = self._kept.pop(key, None)
            if old is not None:
                self._bytes -= old[1]
            self._kept[key] = (answer, size)
            self._read[base] = rooms
            self._read.move_to_end(base)
            self._bytes += size
            while len(self._kept) > self.entries or self._bytes > self.max_bytes:
                self._bytes -= self._kept.popitem(last=False)[1][1]
            while len(self._read) > self.entries:
                self._read.popitem(last=False)


def _bases(question: str, room: Optional[str], building: Optional[str],
           viewpoint: Optional[dict]) -> tuple[tuple, tuple]:
    """(the key part of an answer: the normalised question and the options; that of a refusal:
    the question as asked)."""
    options = (room, building, json.dumps(viewpoint, sort_keys=True) if viewpoint else None)
    return (normalised(question), options), (question, *options, "as asked")


def kept_answer(cache: AnswerCache, snapshot: Snapshot, question: str, room: Optional[str] = None,
                building: Optional[str] = None, viewpoint: Optional[dict] = None) -> Optional[dict]:
    """The JSON of `ask` kept in `cache` for this question and these options at the revisions of
    `snapshot` (read before this call, see `store_revision`), or None (one hit or one miss)."""
    kept = cache.get(snapshot, *_bases(question, room, building, viewpoint))
    return None if kept is None else {**kept, "question": question}


@dataclass(frozen=True)
class Asking:
    """A question and where it is asked: its room, building and viewpoint (None: not given)."""

    question: str
    room: Optional[str] = None
    building: Optional[str] = None
    viewpoint: Optional[dict] = None


def answer_and_keep(store: GraphStore, cache: AnswerCache, snapshot: Snapshot, asking: Asking) -> dict:
    """The JSON of `ask` with the picture inline, kept in `cache` under `snapshot` (read before
    this call: the answer is at least this new). A refusal is kept under the question as asked
    (its text may quote it); an answer under the normalised question."""
    question, room, building, viewpoint = asking.question, asking.room, asking.building, asking.viewpoint
    seen = _Recorder(store, snapshot)
    data: dict[str, Any] = ask(seen, question, room=room, building=building,
                               viewpoint=viewpoint).to_json(inline_thumbnail=True)
    base, as_asked = _bases(question, room, building, viewpoint)
    cache.put(snapshot, seen.rooms, base if data.get("ok") else as_asked, data)
    return data


def ask_kept(store: GraphStore, cache: AnswerCache, question: str, room: Optional[str] = None,
             building: Optional[str] = None, viewpoint: Optional[dict] = None) -> tuple[dict, bool]:
    """(the JSON of `ask` with the picture inline, whether it came from `cache`): the revisions
    read (`cache.revisions`, shared by concurrent asks), then `kept_answer`, else `answer_and_keep`."""
    snapshot = cache.revisions.read(store)   # before the answer: the answer is at least this new
    kept = kept_answer(cache, snapshot, question, room, building, viewpoint)
    if kept is not None:
        return kept, True
    return answer_and_keep(store, cache, snapshot, Asking(question, room, building, viewpoint)), False
