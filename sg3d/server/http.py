"""`sg3d serve`: the HTTP API (FastAPI) over the application layer. Routes only translate:
request -> `app` call -> JSON. OpenAPI at /openapi.json, docs at /docs.

Every route but /health needs `Authorization: Bearer <token>` (see `sg3d.server.auth`). Every
field a caller sends has a bound (here, in `sg3d.app.ingest` and `sg3d.app.ask`): a value past it is
a 422 naming the field and its length, never echoing it. Routes are async and hand their
application call to `sg3d.server.dispatch.Dispatcher`, which runs it in a worker thread with a
deadline and answers 503 + Retry-After at once while `sg3d.server.watch.StoreWatch` sees the store
down (restarting a dead embedded store in the background), so the event loop is never held by the
store. Requests share one Store per process (a driver with a connection pool) through
`sg3d.app.stores.StoreHandle`, which also survives a restart of the embedded store.

Every route declares its response model (`sg3d.server.schemas`) for /openapi.json but returns
JSON encoded once (`json_response`, where the call ran), which FastAPI sends as it is.
"""
from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Optional

from fastapi import Depends, FastAPI, HTTPException, Query, Request
from fastapi import Path as PathParam
from fastapi.exceptions import RequestValidationError
from fastapi.responses import Response
from fastapi.routing import APIRoute
from pydantic import BaseModel, ConfigDict, Field

from sg3d import __version__
from sg3d.app import answers as app_answers
from sg3d.app import ask as app_ask
from sg3d.app import bounds
from sg3d.app import graph as app_graph
from sg3d.app import ingest as app_ingest
from sg3d.app import mapping as app_mapping
from sg3d.app import plan as app_plan
from sg3d.app import rooms as app_rooms
from sg3d.app.errors import AppError, NotFound, Refused, RoomBusy
from sg3d.app.stores import StoreHandle
from sg3d.core.stored import Row
from sg3d.server import metrics, schemas
from sg3d.server.auth import token_matches
from sg3d.server.dispatch import (
    LONG_TIMEOUT_S,
    MAX_THREADS,
    QUICK_TIMEOUT_S,
    RETRY_AFTER_S,
    Dispatcher,
    SharedRead,
    StoreUnavailable,
    CallThreads,
)
from sg3d.server.guard import PARSED, TOKEN_HINT, Guard
from sg3d.server.schemas import ROUTE_ERRORS
from sg3d.server.watch import STOPPED, UP, StoreWatch

if TYPE_CHECKING:
    from sg3d.settings import Settings

_log = logging.getLogger("sg3d.server")

# names a request may carry: a room or building name, or a building/room id
NAME_CHARS = app_ask.MAX_SCOPE_CHARS
HEALTH_TIMEOUT_S = 3.0


class Viewpoint(BaseModel):
    """One of: a 4x4 camera-to-world pose, a point, or an object's name (the room's world frame)."""
    model_config = ConfigDict(extra="forbid")
    pose: Optional[list[list[float]]] = Field(None, min_length=4, max_length=4)
    position: Optional[list[float]] = Field(None, min_length=3, max_length=3)
    object: Optional[str] = Field(None, min_length=1, max_length=bounds.MAX_ID_CHARS)


class AskBody(BaseModel):
    model_config = ConfigDict(extra="forbid")
    question: str = Field(min_length=1, max_length=app_ask.MAX_QUESTION_CHARS,
                          examples=["how many cups are on the table?"])
    room: Optional[str] = Field(None, max_length=NAME_CHARS, description="only this room (its name)")
    building: Optional[str] = Field(None, max_length=NAME_CHARS, description="only this building")
    viewpoint: Optional[Viewpoint] = Field(None, description="where 'in front of / behind / left of / right "
                                                          "of' are seen from (e.g. the robot's pose)")


class PlanBody(BaseModel):
    model_config = ConfigDict(extra="forbid")
    command: Optional[str] = Field(None, max_length=2000, examples=["clean up the table"])
    goal: Optional[str] = Field(None, max_length=2000, description="a PDDL goal instead of a command "
                                                                   f"(parentheses nested at most {bounds.MAX_GOAL_DEPTH} deep)")
    room: str = Field(min_length=1, max_length=NAME_CHARS, description="room name or id (building/room)")
    building: Optional[str] = Field(None, max_length=NAME_CHARS)
    start: Optional[str] = Field(None, max_length=bounds.MAX_ID_CHARS,
                                 description="where the robot starts (a surface or receptacle name)")


class _ParsedRequest(Request):
    """A request whose JSON body the door (`Guard`) parsed already, in a worker thread: FastAPI
    would parse it a second time, on the event loop."""

    async def json(self) -> Any:
        if PARSED in self.scope:
            return self.scope[PARSED]
        return await super().json()


class _Route(APIRoute):
    """FastAPI's route, handing the endpoint a `_ParsedRequest`."""

    def get_route_handler(self):
        handler = super().get_route_handler()

        async def handle(request: Request) -> Response:
            return await handler(_ParsedRequest(request.scope, request.receive))
        return handle


def _status(exc: AppError) -> int:
    if isinstance(exc, RoomBusy):
        return 409
    return 404 if isinstance(exc, NotFound) else 403 if isinstance(exc, Refused) else 400


def store_failure(exc: Exception, settings: Settings) -> tuple[int, str, dict]:
    """Status, detail and headers for a failure that is not the caller's: an explicit stop is 503
    with the way out; a store that is restarting, briefly unreachable or past a call's deadline is
    503 with Retry-After; a full disk is 507 naming it; a statement too large for one message to
    the store (refused before it was sent) is 413; anything else 500 with the exception's type only."""
    from neo4j.exceptions import (
        AuthError,
        ServiceUnavailable,
        SessionExpired,
        TransientError,
    )

    from sg3d.graphdb.embedded import (
        EmbeddedStoreError,
        StoreLost,
        StoreStopped,
        disk_full_message,
        store_dir,
    )
    from sg3d.graphdb.store import StatementTooLarge

    if isinstance(exc, (StoreStopped, StoreLost)):     # no retry helps: the way out is in the detail
        return 503, str(exc), {}
    if isinstance(exc, StatementTooLarge):
        return 413, str(exc), {}
    if getattr(settings, "embedded", False):
        full = disk_full_message(store_dir(Path(settings.embedded_home()).expanduser().resolve()))
        if full:
            return 507, full, {}
    if isinstance(exc, StoreUnavailable):
        return 503, str(exc), {"Retry-After": str(exc.retry_after)}
    if isinstance(exc, (ServiceUnavailable, SessionExpired, TransientError, AuthError, EmbeddedStoreError)):
        return 503, "the graph store is unreachable or restarting; retry shortly", {"Retry-After": str(RETRY_AFTER_S)}
    return 500, f"internal error: {type(exc).__name__}", {}


def _json_default(value):
    """numpy scalars and arrays, and anything else `sg3d.graphdb.values.jsonable` knows."""
    if hasattr(value, "tolist"):
        return value.tolist()
    from sg3d.graphdb.values import jsonable

    return jsonable(value)


def json_response(data, status_code: int = 200) -> Response:
    """`data` as a JSON response, encoded once by the standard library's C encoder (FastAPI's own
    path walks the whole answer through `jsonable_encoder` first, the largest cost of a small
    request); a NaN that slipped through becomes null rather than invalid JSON."""
    import json

    try:
        body = json.dumps(data, separators=(",", ":"), ensure_ascii=False, allow_nan=False, default=_json_default)
    except ValueError:
        from sg3d.graphdb.values import finite_or_none

        body = json.dumps(finite_or_none(data), separators=(",", ":"), ensure_ascii=False, default=_json_default)
    return Response(body.encode(), status_code=status_code, media_type="application/json")


def _near(text: Optional[str]):
    if text is None:
        return None
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise AppError("near must be x,y,z (three numbers, metres)") from None


def validation_details(errors) -> list[Row]:
    """Pydantic's errors naming each field and the rule it broke, never the value it was sent
    (a 100 MB question must not come back as a 100 MB answer): a value too long is named by its
    length."""
    details = []
    for e in list(errors)[:20]:
        msg = str(e.get("msg", ""))[:300]
        value = e.get("input")
        if e.get("type") in ("string_too_long", "too_long", "bytes_too_long") and hasattr(value, "__len__"):
            msg += f" ({len(value)} given)"
        loc = [p if isinstance(p, int) else str(p)[:100] for p in e.get("loc", ())]   # a field name may be the caller's
        details.append({"loc": loc, "msg": msg, "type": e.get("type", "")})
    return details


def create_app(settings: Settings, token: str, handle: Optional[StoreHandle] = None,
               max_body: int = bounds.DEFAULT_MAX_BODY, quick_timeout_s: float = QUICK_TIMEOUT_S,
               long_timeout_s: float = LONG_TIMEOUT_S, max_threads: int = MAX_THREADS,
               answer_cache: int = bounds.ANSWER_CACHE_ENTRIES) -> FastAPI:
    """The FastAPI application for `settings`' store; `token` is the bearer token callers send;
    request bodies above `max_body` bytes are refused (413) before they are read; a read that has
    not answered within `quick_timeout_s` (a plan, export or ingest: `long_timeout_s`) is a 503;
    at most `max_threads` calls run at once (more wait their turn, within their deadline); `/ask`
    keeps up to `answer_cache` answers (`sg3d.app.answers`; 0: none)."""
    stores = handle or StoreHandle(settings)
    api = FastAPI(title="sg3d", version=__version__,
                  description="3-D scene graphs of rooms: ask, plan, list rooms and objects, export, ingest.")
    api.router.route_class = _Route

    async def authorised(request: Request) -> None:
        # the Guard has checked already; this keeps the requirement visible in the OpenAPI document
        # (async: a plain function dependency would cost every request a thread-pool hop)
        if not token_matches(token, request.headers.get("authorization")):
            raise HTTPException(401, TOKEN_HINT, headers={"WWW-Authenticate": "Bearer"})

    _add_error_handlers(api, settings)
    watch = StoreWatch(settings, restart=lambda: _reconnect(stores))
    calls = Dispatcher(watch, CallThreads(max_threads), quick_timeout_s=quick_timeout_s, long_timeout_s=long_timeout_s)
    _add_health_route(api, stores, settings, calls, watch)
    _add_metrics_route(api, calls)
    auth = [Depends(authorised)]
    answers = app_answers.AnswerCache(answer_cache)
    _add_read_routes(api, stores, calls, auth, answers)
    _add_write_routes(api, stores, calls, auth)
    # only the routes that take a body are sent one (the rest refuse it before it is read)
    body_paths = frozenset(r.path for r in api.routes
                           if isinstance(r, APIRoute) and (r.methods or set()) & {"POST", "PUT", "PATCH"})
    api.add_middleware(Failures, settings=settings)
    api.add_middleware(Guard, token=token, max_body=max_body, body_paths=body_paths)
    api.add_middleware(metrics.RequestMetrics, routes=lambda: api.routes)
    metrics.count_store_statements()
    api.state.stores = stores
    api.state.watch = watch
    api.state.answers = answers
    return api


def _reconnect(stores: StoreHandle) -> None:
    """Drop the drivers of a dead store and open new ones, which starts the embedded store again
    the normal way (`StoreWatch` runs this in the background when the daemon died)."""
    stores.close()
    stores.get()
    stores.get(write=True)


def _add_error_handlers(api: FastAPI, settings: Settings) -> None:
    # async: Starlette runs a plain handler in the thread pool
    @api.exception_handler(AppError)
    async def _app_error(request: Request, exc: AppError):
        return json_response({"detail": str(exc)}, status_code=_status(exc))

    @api.exception_handler(RequestValidationError)
    async def _invalid(request: Request, exc: RequestValidationError):
        return json_response({"detail": validation_details(exc.errors())}, status_code=422)

    async def _store_error(request: Request, exc: Exception):
        status, detail, headers = store_failure(exc, settings)
        response = json_response({"detail": detail}, status_code=status)
        response.headers.update(headers)
        return response

    from sg3d.graphdb.embedded import EmbeddedStoreError
    from sg3d.graphdb.store import StatementTooLarge

    # the failures sg3d names itself are answered as they are; any other one by `Failures`
    for known in (StoreUnavailable, EmbeddedStoreError, StatementTooLarge):
        api.add_exception_handler(known, _store_error)


class Failures:
    """ASGI middleware for a failure no handler names: it is logged with its traceback and
    answered by `store_failure` (503, 507, 500, ...), and the exchange then ends normally, so the
    kept-alive connection serves the client's next request. (Starlette's catch-all handler answers
    and then re-raises, and uvicorn closes the connection of an exception raised after its answer:
    the client's next request on it met a reset.)"""

    def __init__(self, app, settings: Settings):
        self.app = app
        self.settings = settings

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        started = False

        async def sending(message):
            nonlocal started
            started = started or message["type"] == "http.response.start"
            await send(message)

        try:
            await self.app(scope, receive, sending)
        except Exception as exc:
            _log.error("%s %s failed", scope.get("method"), str(scope.get("path"))[:200], exc_info=exc)
            if started:         # half an answer went: the connection cannot carry another
                raise
            status, detail, headers = store_failure(exc, self.settings)
            response = json_response({"detail": detail}, status_code=status)
            response.headers.update(headers)
            await response(scope, receive, send)


DISK_FULL = "disk full"


def disk_full(settings: Settings) -> Optional[str]:
    """Why the embedded store's disk counts as full (less free space in its folder than
    `sg3d.graphdb.embedded.min_free_mb()`, SG3D_MIN_FREE_MB), or None (also for a --uri store)."""
    if not getattr(settings, "embedded", False):
        return None
    from sg3d.graphdb.embedded import disk_full_message, store_dir

    return disk_full_message(store_dir(Path(settings.embedded_home()).expanduser().resolve()))


def _add_health_route(api: FastAPI, stores: StoreHandle, settings: Settings, calls: Dispatcher, watch: StoreWatch) -> None:
    def check() -> Optional[str]:
        watch.raise_if_down(probe=True)     # the daemon's process and port, without the driver
        stores.call(lambda s: s.driver.verify_connectivity())
        return disk_full(settings)          # up, but a write may fail any moment

    @api.get("/health", tags=["service"], response_model=schemas.Health,
             responses={503: {"model": schemas.Health, "description": "the store is down, restarting or stopped "
                                                                      "(Retry-After unless stopped)"},
                        507: {"model": schemas.Health, "description": "the store's disk is full"}})
    async def health():
        """Whether the store answers (`state`: up, down, stopped, disk full), and the version. No
        token needed; answers within a few seconds whatever the store does. A store whose disk
        has less free space than SG3D_MIN_FREE_MB (default 64 MB) is 507, state "disk full"."""
        try:
            full = await calls.run(check, HEALTH_TIMEOUT_S)
        except Exception as exc:  # noqa: BLE001 - any failure means not reachable; named by store_failure
            code, detail, headers = store_failure(exc, settings)
            state = STOPPED if watch.state() == STOPPED else DISK_FULL if code == 507 else "down"
            response = json_response({"status": detail, "store": False, "state": state, "version": __version__},
                                     status_code=code)
            response.headers.update(headers)
            return response
        if full:
            return json_response({"status": full, "store": True, "state": DISK_FULL, "version": __version__},
                                 status_code=507)
        return json_response({"status": "ok", "store": True, "state": UP, "version": __version__})


def _add_metrics_route(api: FastAPI, calls: Dispatcher) -> None:
    @api.get("/metrics", tags=["service"], response_class=Response,
             responses={200: {"content": {metrics.CONTENT_TYPE: {}}, "description": "the Prometheus text format"}})
    async def scrape():
        """Request counts and latency histograms per route, answer-cache hits and misses, statements
        sent to the store, in the Prometheus text format (every worker's). No token needed, as for
        /health: it names routes and counts, never a room, an object or a question."""
        body = await calls.run(metrics.exposition, HEALTH_TIMEOUT_S, watched=False)
        return Response(body, media_type=metrics.CONTENT_TYPE)


def _add_read_routes(api: FastAPI, stores: StoreHandle, calls: Dispatcher, auth: list,
                     answers: app_answers.AnswerCache) -> None:
    read = stores.call
    opts: dict[str, Any] = {"dependencies": auth, "tags": ["read"], "responses": ROUTE_ERRORS}
    revisions: SharedRead[app_answers.Snapshot] = SharedRead(lambda: calls.quick(lambda: read(app_answers.store_revision)))

    @api.post("/ask", response_model=schemas.AskAnswer, **opts)
    async def ask(body: AskBody):
        """The JSON of `sg3d ask --json`, plus the answer's picture as base64 JPEG when it has one.
        A question it cannot answer gives ok: false and the reason in answer (still 200)."""
        viewpoint = body.viewpoint.model_dump(exclude_none=True) if body.viewpoint else None
        if viewpoint is not None and len(viewpoint) != 1:
            raise AppError("viewpoint takes exactly one of pose, position and object")
        # the revisions first (one read for the asks that arrive together), then a kept answer is
        # looked up on the event loop: only a miss takes a worker thread
        snapshot = await revisions.get()
        kept = app_answers.kept_answer(answers, snapshot, body.question, body.room, body.building, viewpoint)
        metrics.count_cache(kept is not None)
        if kept is not None:
            return json_response(kept)
        return await calls.quick(lambda: json_response(read(lambda s: app_answers.answer_and_keep(
            s, answers, snapshot, app_answers.Asking(body.question, body.room, body.building, viewpoint)))))

    @api.post("/plan", response_model=schemas.Plan, **opts)
    async def plan(body: PlanBody):
        """A validated plan: steps in words and as PDDL actions, the goal, domain and problem PDDL."""
        return await calls.pooled(lambda: json_response(read(lambda s: app_plan.plan_json(
            s, body.command, goal=body.goal, room=body.room, building=body.building, start=body.start))))

    @api.get("/rooms", response_model=list[schemas.Room], **opts)
    async def rooms(building: Optional[str] = Query(None, max_length=NAME_CHARS)):
        """Rooms (of one building, or all) with object counts, transforms and adjacent rooms."""
        return await calls.quick(lambda: json_response(read(lambda s: app_rooms.list_rooms(s, building))))

    @api.get("/rooms/{building}/{room}", response_model=schemas.RoomState, **opts)
    async def room(building: str = PathParam(max_length=NAME_CHARS), room: str = PathParam(max_length=NAME_CHARS)):
        """One room: objects, placement, neighbours, and `mapping` while `sg3d map` builds it
        (state live/done, since when, frames so far, last publish; null when never mapped live)."""
        return await calls.quick(lambda: json_response(read(lambda s: app_mapping.room_state(s, building, room))))

    @api.get("/rooms/{building}/{room}/objects", response_model=list[schemas.RoomObject], **opts)
    async def objects(building: str = PathParam(max_length=NAME_CHARS), room: str = PathParam(max_length=NAME_CHARS),
                      label: Optional[str] = Query(None, max_length=bounds.MAX_LABEL_CHARS),
                      colour: Optional[str] = Query(None, max_length=bounds.MAX_LABEL_CHARS),
                      near: Optional[str] = Query(None, max_length=200,
                                                  description="x,y,z in the room's frame: sort by distance"),
                      radius: Optional[float] = Query(None, description="metres from `near`")):
        """A room's objects with readable names, filtered by label, colour and distance to a point."""
        point = _near(near)
        return await calls.quick(lambda: json_response(read(lambda s: app_rooms.room_objects(
            s, building, room, app_rooms.ObjectFilter(label, colour, point, radius)))))

    @api.get("/graph", response_model=schemas.Graph, dependencies=auth, tags=["read"],
             responses={**ROUTE_ERRORS, 200: {"content": {"application/graphml+xml": {}},
                                            "description": "the graph; GraphML for format=graphml"}})
    async def graph(building: str = Query("default", max_length=NAME_CHARS),
                    room: Optional[str] = Query(None, max_length=NAME_CHARS),
                    format: Literal["json", "graphml", "spark-dsg", "3dssg"] = "json", thumbnails: bool = False,
                    histograms: bool = False):
        """The graph of a room or a building: the paper's JSON form, GraphML, spark_dsg JSON or 3DSSG
        ({objects, relationships})."""
        spark = format == "spark-dsg"

        def fetch() -> Response:
            g = read(lambda s: app_graph.fetch_named_graph(s, building, room, thumbnails, histograms or spark,
                                                           room_transforms=spark))
            if format == "json":
                return json_response(g.as_json())
            return Response(app_graph.render_graph(g, format),
                            media_type="application/graphml+xml" if format == "graphml" else "application/json")
        return await calls.pooled(fetch)


def _add_write_routes(api: FastAPI, stores: StoreHandle, calls: Dispatcher, auth: list) -> None:
    @api.post("/ingest", dependencies=auth, tags=["write"], response_model=schemas.IngestResult,
              responses=ROUTE_ERRORS)
    async def ingest(body: app_ingest.IngestRequest):
        """Merge a robot's local scene graph (same-node detection, one transaction); the same
        observation_id is merged once. A body that does not validate is a 422 naming the field."""
        return await calls.pooled(lambda: json_response(stores.call(lambda s: app_ingest.ingest_graph(s, body),
                                                                    write=True)))


def is_loopback(host: str) -> bool:
    import ipaddress

    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False
