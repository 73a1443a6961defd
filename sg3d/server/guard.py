"""The door of `sg3d serve`, before any route runs: the token is checked before a byte of the
body is read; a route that takes no body (every route but the POST ones: /health, /docs,
/openapi.json, /rooms, ...) is sent none, or the request is refused with 413 before its body is
read; a body larger than `max_body` is refused with 413 without being kept; and a JSON body must
be strict JSON (no NaN/Infinity literals) nested at most `bounds.MAX_JSON_DEPTH` deep.

A pure ASGI middleware: it buffers at most `max_body` bytes, then hands the same bytes to the
application, so routes see the body unchanged. The JSON of a body over INLINE_PARSE_BYTES is
parsed and its depth walked in a worker thread, never on the event loop (a 15 MB body took
8-10 s there, and every other request waited); the parsed value rides in the request's scope
(`PARSED`) so that the route reads it without parsing it again (`sg3d.server.http`'s request class).
"""
from __future__ import annotations

import json
from typing import Optional

import anyio

from sg3d.app import bounds
from sg3d.server.auth import token_matches

PARSED = "sg3d.json"          # the scope key of a body the door parsed already
# A body this small is parsed on the event loop (tens of microseconds, less than the hop to a
# worker thread and back, which a question's body would otherwise pay on every request)
INLINE_PARSE_BYTES = 16 * 1024
OPEN_PATHS = frozenset({"/health", "/metrics", "/openapi.json", "/docs", "/docs/oauth2-redirect", "/redoc"})
TOKEN_HINT = ("missing or wrong token: send Authorization: Bearer <token> "
              "(the token is in $SG3D_HOME/api-token; `sg3d serve` prints where)")


def _reject_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


def parse_json(body: bytes) -> tuple[object, Optional[str]]:
    """(the parsed value, None) for acceptable JSON, else (None, why not): strict JSON nested at
    most `bounds.MAX_JSON_DEPTH` deep."""
    try:
        value = json.loads(body, parse_constant=_reject_constant)
    except RecursionError:
        return None, f"the JSON body nests deeper than {bounds.MAX_JSON_DEPTH} levels"
    except ValueError as exc:   # JSONDecodeError is a ValueError; its message names a position only
        return None, f"the body is not valid JSON: {str(exc)[:120]}"
    if bounds.nesting_depth(value) > bounds.MAX_JSON_DEPTH:
        return None, f"the JSON body nests deeper than {bounds.MAX_JSON_DEPTH} levels"
    return value, None


def _joined_and_parsed(chunks: list[bytes]) -> tuple[bytes, object, Optional[str]]:
    body = b"".join(chunks)
    return (body, *parse_json(body))


class Guard:
    """ASGI middleware: authentication, then whether the route takes a body at all
    (`body_paths`), then the body size limit, then strict JSON, parsed off the event loop."""

    def __init__(self, app, token: str, max_body: int = bounds.DEFAULT_MAX_BODY,
                 body_paths: frozenset = frozenset()):
        self.app = app
        self.token = token
        self.max_body = max_body
        self.body_paths = body_paths

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", ())}
        if scope["path"] not in OPEN_PATHS and not token_matches(self.token, headers.get("authorization")):
            return await _reply(send, 401, TOKEN_HINT, [(b"www-authenticate", b"Bearer")])
        declared = headers.get("content-length")
        if declared is not None and not declared.isdigit():
            return await _reply(send, 400, "Content-Length must be a number")
        if scope["path"] not in self.body_paths:
            if (declared is not None and int(declared) > 0) or "transfer-encoding" in headers:
                return await _reply(send, 413, "this route takes no request body")
            return await self.app(scope, receive, send)
        if declared is not None and int(declared) > self.max_body:
            return await _reply(send, 413, self._too_large())
        if scope["method"] not in ("POST", "PUT", "PATCH"):
            return await self.app(scope, receive, send)
        chunks, size = [], 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                return
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > self.max_body:
                return await _reply(send, 413, self._too_large())
            chunks.append(chunk)
            if not message.get("more_body", False):
                break
        if size and "json" in headers.get("content-type", "json"):
            if size <= INLINE_PARSE_BYTES:
                body, value, problem = _joined_and_parsed(chunks)
            else:
                body, value, problem = await anyio.to_thread.run_sync(_joined_and_parsed, chunks)
            if problem:
                return await _reply(send, 422, problem)
            scope[PARSED] = value
        else:
            body = b"".join(chunks)
        return await self.app(scope, _replay(body, receive), send)

    def _too_large(self) -> str:
        return f"the request body is larger than {self.max_body} bytes (sg3d serve --max-body)"


def _replay(body: bytes, receive):
    sent = False

    async def again():
        nonlocal sent
        if sent:
            return await receive()
        sent = True
        return {"type": "http.request", "body": body, "more_body": False}
    return again


async def _reply(send, status: int, detail: str, extra_headers=()) -> None:
    payload = json.dumps({"detail": detail}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"),
                            (b"content-length", str(len(payload)).encode()),
                            (b"connection", b"close"), *extra_headers]})
    await send({"type": "http.response.body", "body": payload})
