"""The pure parts of the trust limits: the statement guard's measure and batching, the field
bounds of /ingest and /ask, 422 details that name a length instead of echoing a value, the
dispatcher's deadline and its daemon workers (no store, no server)."""
from __future__ import annotations

import asyncio
import base64
import threading
import time

import cv2
import numpy as np
import pytest
from pydantic import ValidationError

MIB = 1024 * 1024


def _jpeg(side: int = 32, seed: int = 0, quality: int = 90) -> bytes:
    noise = np.random.default_rng(seed).integers(0, 256, (side, side, 3), dtype=np.uint8)
    ok, buf = cv2.imencode(".jpg", noise, [cv2.IMWRITE_JPEG_QUALITY, quality])
    assert ok
    return buf.tobytes()


# -- the statement guard -------------------------------------------------------------------------
def test_encoded_bytes_counts_texts_bytes_numbers_and_nesting():
    from sg3d.graphdb.store import encoded_bytes

    assert encoded_bytes("a" * 100) == 105
    assert encoded_bytes("ü" * 100) == 205                    # UTF-8 bytes, not characters
    assert encoded_bytes(b"\x00" * 1000) == 1005
    assert encoded_bytes([1.0] * 512) == 5 + 9 * 512
    assert encoded_bytes(np.zeros(512)) == 5 + 9 * 512
    nested = {"rows": [{"thumbnail": b"x" * 1000, "hist": [0.5] * 10}] * 3}
    assert encoded_bytes(nested) > 3 * 1000
    deep: list = []
    for _ in range(5000):                                      # no recursion limit
        deep = [deep]
    assert encoded_bytes(deep) == 5 * 5001


def test_check_statement_refuses_past_the_bound_naming_the_parameter_not_its_value():
    from sg3d.graphdb.store import MAX_STATEMENT_BYTES, StatementTooLarge, check_statement

    check_statement("RETURN $x", {"x": "a" * (MAX_STATEMENT_BYTES - 1000)})
    with pytest.raises(StatementTooLarge) as refused:
        check_statement("RETURN $x", {"x": "secret" * (3 * MIB)})
    text = str(refused.value)
    assert "$x" in text and "nothing was sent" in text and "secret" not in text and len(text) < 300
    with pytest.raises(StatementTooLarge):                     # keyword parameters count too
        check_statement("RETURN $x", None, {"x": b"\x00" * (9 * MIB)})
    assert MAX_STATEMENT_BYTES <= 16 * MIB // 2                # well under what the store reads


def test_size_batches_keep_order_and_stay_under_the_budget():
    from sg3d.graphdb.store import encoded_bytes, size_batches

    rows = [{"i": i, "thumbnail": b"x" * (300_000 + 1000 * i)} for i in range(40)]
    batches = size_batches(rows, budget=MIB)
    assert [r["i"] for b in batches for r in b] == list(range(40))
    assert len(batches) > 1 and all(encoded_bytes(b) <= MIB + 5 for b in batches)
    huge = [{"i": 0}, {"i": 1, "thumbnail": b"x" * (2 * MIB)}, {"i": 2}]
    assert [[r["i"] for r in b] for b in size_batches(huge, budget=MIB)] == [[0], [1], [2]]
    assert size_batches([]) == []


# -- the /ingest schema ----------------------------------------------------------------------------
def _ingest(thumbnail: str) -> dict:
    from sg3d.testing import kitchen_body

    body = kitchen_body("t")
    body["graph"]["objects"][0]["thumbnail"] = thumbnail
    return body


def test_a_thumbnail_must_be_a_complete_small_jpeg():
    from sg3d.app.ingest import MAX_THUMBNAIL_BYTES, IngestRequest

    IngestRequest.model_validate(_ingest(base64.b64encode(_jpeg()).decode()))
    smuggled = b"\xff\xd8\xff\xe0" + b"\x00" * 1000 + b"\x00\x02\xb0\x0f\x00\x00"
    big = _jpeg(side=400, quality=100)
    assert len(big) > MAX_THUMBNAIL_BYTES
    for bad in (smuggled, _jpeg()[:-2], big, b"\x89PNG\r\n\x1a\n"):
        with pytest.raises(ValidationError) as refused:
            IngestRequest.model_validate(_ingest(base64.b64encode(bad).decode()))
        errors = refused.value.errors()
        assert errors[0]["loc"][-1] == "thumbnail", errors


def test_a_huge_thumbnail_is_refused_by_its_length_before_decoding():
    from sg3d.app.ingest import IngestRequest
    from sg3d.server.http import validation_details

    with pytest.raises(ValidationError) as refused:
        IngestRequest.model_validate(_ingest("A" * (20 * MIB)))
    details = validation_details(refused.value.errors())
    assert details[0]["type"] == "string_too_long" and str(20 * MIB) in details[0]["msg"]
    assert len(str(details)) < 1000


def test_ingest_lists_are_bounded():
    from sg3d.app.ingest import IngestRequest
    from sg3d.testing import kitchen_body

    body = kitchen_body("t")
    body["graph"]["frames"] = list(range(200_000))
    with pytest.raises(ValidationError):
        IngestRequest.model_validate(body)
    body = kitchen_body("t")
    body["graph"]["objects"][0]["labels"] = ["cup"] * 50
    with pytest.raises(ValidationError):
        IngestRequest.model_validate(body)


# -- /ask bounds -------------------------------------------------------------------------------------
def test_ask_refuses_an_oversize_room_before_touching_the_store():
    from sg3d.app.ask import MAX_SCOPE_CHARS, ask
    from sg3d.app.errors import AppError

    with pytest.raises(AppError) as refused:
        ask(None, "how many cups", room="k" * 6_000_000)   # type: ignore[arg-type] - never reached
    text = str(refused.value)
    assert text == f"room is 6000000 characters; at most {MAX_SCOPE_CHARS}"
    with pytest.raises(AppError, match="question is"):
        ask(None, "q" * 1_000_000)                          # type: ignore[arg-type]


def test_the_ask_body_is_bounded_and_its_errors_name_the_length():
    from sg3d.server.http import AskBody, PlanBody, validation_details

    for model, body, field in ((AskBody, {"question": "x", "room": "k" * 6_000_000}, "room"),
                               (AskBody, {"question": "x", "building": "b" * 5000}, "building"),
                               (PlanBody, {"command": "clean up", "room": "r" * 5000}, "room"),
                               (PlanBody, {"command": "clean up", "room": "r", "start": "s" * 5000}, "start")):
        with pytest.raises(ValidationError) as refused:
            model.model_validate(body)
        details = validation_details(refused.value.errors())
        assert details[0]["loc"] == [field] and "given)" in details[0]["msg"], details
        assert len(str(details)) < 500


# -- the dispatcher ----------------------------------------------------------------------------------
class _Watch:
    def __init__(self, down: bool):
        self.down = down
        self.calls = 0

    def raise_if_down(self, probe: bool = False):
        from sg3d.server.dispatch import StoreUnavailable

        self.calls += 1
        if self.down:
            raise StoreUnavailable("down")


def test_a_call_that_never_returns_is_503_by_its_deadline_and_the_loop_keeps_running():
    from sg3d.server.dispatch import Dispatcher, StoreUnavailable

    calls = Dispatcher(quick_timeout_s=0.5)
    never = threading.Event()
    ticks = []

    async def main():
        async def tick():
            while True:
                ticks.append(time.monotonic())
                await asyncio.sleep(0.05)
        ticker = asyncio.create_task(tick())
        t0 = time.monotonic()
        with pytest.raises(StoreUnavailable, match="did not answer within 0.5 s"):
            await calls.quick(never.wait)
        ticker.cancel()
        return time.monotonic() - t0

    took = asyncio.run(main())
    assert 0.45 < took < 2 and len(ticks) >= 5         # the event loop ran all along
    stuck = [t for t in threading.enumerate() if t.name == "sg3d-call" and t.is_alive()]
    assert stuck and all(t.daemon for t in stuck)     # a stuck call never keeps the process alive
    assert calls.in_flight == 0
    never.set()


def test_calls_run_off_the_event_loop_and_a_down_store_is_refused_without_calling():
    from sg3d.server.dispatch import Dispatcher, StoreUnavailable

    loop_thread = threading.get_ident()
    ran = []
    calls = Dispatcher(watch=_Watch(down=True))

    async def refused():
        with pytest.raises(StoreUnavailable):
            await calls.quick(lambda: ran.append(1))
    asyncio.run(refused())
    assert ran == []

    calls = Dispatcher(watch=_Watch(down=False))

    async def together(n):
        return await asyncio.gather(*(calls.quick(threading.get_ident) for _ in range(n)))
    assert loop_thread not in asyncio.run(together(5))

    async def fails():
        with pytest.raises(ValueError, match="no"):
            await calls.pooled(lambda: (_ for _ in ()).throw(ValueError("no")))
    asyncio.run(fails())
    assert calls.in_flight == 0


def test_store_failures_map_to_their_statuses():
    from sg3d.graphdb.store import StatementTooLarge
    from sg3d.server.dispatch import StoreUnavailable
    from sg3d.server.http import store_failure
    from sg3d.settings import Settings

    settings = Settings(uri="bolt://127.0.0.1:1")
    status, detail, headers = store_failure(StoreUnavailable("restarting"), settings)
    assert status == 503 and headers["Retry-After"] == "2"
    assert store_failure(StatementTooLarge("too big"), settings)[:2] == (413, "too big")


def test_workers_are_reused_and_kept_through_a_quiet_spell():
    from sg3d.server.dispatch import CallThreads

    workers = CallThreads(size=3)
    for _ in range(5):
        assert workers.submit(lambda: 7).future.result(5) == 7
    assert workers._threads == 1                       # one call at a time: one thread, reused
    gate = threading.Event()
    jobs = [workers.submit(gate.wait) for _ in range(10)]
    time.sleep(0.2)
    assert workers._threads == 3                       # a burst past the pool: it grows to its size, no more
    gate.set()
    assert all(j.future.result(5) for j in jobs)
    time.sleep(0.5)
    assert workers._threads == 3                       # kept: no thread ends for being idle
    assert [workers.submit(lambda i=i: i).future.result(5) for i in range(6)] == list(range(6))


def test_a_stuck_call_is_replaced_and_its_thread_ends_when_it_returns():
    from sg3d.server.dispatch import CallThreads

    workers = CallThreads(size=1)
    stuck = threading.Event()
    job = workers.submit(stuck.wait)
    time.sleep(0.1)
    waiting = workers.submit(lambda: "ran")            # queued behind the stuck call
    workers.abandon(job)
    assert waiting.future.result(5) == "ran"           # a replacement thread ran it
    assert workers._threads == 2 and workers._stuck == 1
    stuck.set()
    deadline = time.monotonic() + 5
    while workers._threads != 1 and time.monotonic() < deadline:
        time.sleep(0.02)
    assert workers._threads == 1 and workers._stuck == 0
    assert workers.submit(lambda: 9).future.result(5) == 9


def test_listing_filters_are_bounded_on_both_sides():
    from sg3d.app.ask import MAX_SCOPE_CHARS
    from sg3d.app.bounds import MAX_LABEL_CHARS
    from sg3d.app.rooms import filter_problem

    for what, limit in (("label", MAX_LABEL_CHARS), ("colour", MAX_LABEL_CHARS), ("building", MAX_SCOPE_CHARS),
                        ("room", MAX_SCOPE_CHARS)):
        assert filter_problem(**{what: "x" * limit}) is None
        assert filter_problem(**{what: "x" * (limit + 1)}) == f"{what} is {limit + 1} characters; at most {limit}"
        assert filter_problem(**{what: 5}) == f"{what} must be a text"
    assert MAX_LABEL_CHARS == 64 and MAX_SCOPE_CHARS == 201
    assert filter_problem() is None
