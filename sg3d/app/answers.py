"""Answers kept by a long-lived server (`POST /ask` of `sg3d serve`), keyed by the store's revision.

Every merge, ingest and live publish bumps its room's revision in its own transaction
(cypher/room_ensure); `store_revision` reads the whole store's in one small query
(cypher/room_revisions). An answer is kept under (that revision, the normalised question, the
options), read BEFORE it was computed: what it says is at least as new as that revision, and the
next ask after any later commit reads another revision and misses. So a kept answer is never older
than the last merge or publish committed before the ask.

The key is the store's revision, not the asked room's alone: a question asked in one room may read
another ("how many cups are in the bedroom?" with room=kitchen, a misspelt room name read as
another), so a publish anywhere retires every kept answer. A room's placement in its building
bumps it too; other writes (`sg3d building` unlinking rooms, `sg3d db rebuild-tallies`, `db check
--repair`, a room deleted and another made the same millisecond) do not: restart the service
after them.
"""
from __future__ import annotations

import json
import threading
from collections import OrderedDict
from typing import Any, Optional

from sg3d.app import bounds
from sg3d.app.ask import ask
from sg3d.graphdb.protocol import GraphStore

_ENTRY_BYTES = 2048          # what an answer without a picture holds, roughly


def store_revision(store: GraphStore) -> tuple:
    """The store's content version: (rooms, sum of their revisions, latest room birth)."""
    row = store.read("room_revisions")[0]
    return row["rooms"], row["revisions"], row["born"]


class _Read:
    __slots__ = ("start", "done", "result", "failed")

    def __init__(self, start: int):
        self.start = start
        self.done = threading.Event()
        self.result: Optional[tuple] = None
        self.failed = False


class Revisions:
    """The store's revision for many concurrent asks with few reads (one round trip each). Rule
    "a read that began after the ask arrived": its result names every commit before the ask, so
    an ask takes the result of the read in progress when that read began after the ask arrived;
    otherwise it waits for that older read to end and then joins the next one or starts it. A
    hundred asks at once cost a few reads, each ask waiting at most about two of them."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._ticket = 0                 # rises with every arrival and every read begun
        self._latest: Optional[_Read] = None
        self.reads = 0                   # reads sent to the store

    def read(self, store: GraphStore) -> tuple:
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
    def _lead(read: _Read, store: GraphStore) -> tuple:
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


class AnswerCache:
    """A bounded LRU of answers (at most `entries`, and about `max_bytes`: a picture's base64
    counts its length), thread-safe; `hits` and `misses` count look-ups."""

    def __init__(self, entries: int = bounds.ANSWER_CACHE_ENTRIES, max_bytes: int = bounds.ANSWER_CACHE_BYTES):
        self.entries = entries
        self.max_bytes = max_bytes
        self._kept: OrderedDict[tuple, tuple[dict, int]] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0
        self.revisions = Revisions()

    def __len__(self) -> int:
        return len(self._kept)

    def get(self, *keys: tuple) -> Optional[dict]:
        """The answer kept under the first of `keys` that has one (one hit or one miss)."""
        with self._lock:
            for key in keys:
                kept = self._kept.get(key)
                if kept is not None:
                    self._kept.move_to_end(key)
                    self.hits += 1
                    return kept[0]
            self.misses += 1
            return None

    def put(self, key: tuple, answer: dict) -> None:
        size = _ENTRY_BYTES + len(answer.get("thumbnail_jpeg_base64") or "")
        if self.entries < 1 or size > self.max_bytes:
            return
        with self._lock:
            old = self._kept.pop(key, None)
            if old is not None:
                self._bytes -= old[1]
            self._kept[key] = (answer, size)
            self._bytes += size
            while len(self._kept) > self.entries or self._bytes > self.max_bytes:
                self._bytes -= self._kept.popitem(last=False)[1][1]


def ask_kept(store: GraphStore, cache: AnswerCache, question: str, room: Optional[str] = None,
             building: Optional[str] = None, viewpoint: Optional[dict] = None) -> tuple[dict, bool]:
    """(the JSON of `ask` with the picture inline, whether it came from `cache`). A refusal is kept
    under the question as asked (its text may quote it); an answer under the normalised question."""
    revision = cache.revisions.read(store)   # before the answer: the answer is at least this new
    options = (room, building, json.dumps(viewpoint, sort_keys=True) if viewpoint else None)
    key = (revision, normalised(question), options)
    kept = cache.get(key, (*key, question))
    if kept is not None:
        return {**kept, "question": question}, True
    data: dict[str, Any] = ask(store, question, room=room, building=building,
                               viewpoint=viewpoint).to_json(inline_thumbnail=True)
    cache.put(key if data.get("ok") else (*key, question), data)
    return data, False
